"""The pre-test check of a controlled run: the motion, and the VS basemat motion, against the limits.

Before a tracking or MIL test the input motion is checked against the
table's capacity with the specimen on it (report Section 8.2,
:func:`impedance_mil.signals.check_motion`).  For a MIL test the stroke and
velocity the table will need to follow the VS basemat are predicted too,
with the specimen taken as a rigid mass (:func:`basemat_check`), and compared
with the lab's interlocks.

:func:`pretest` returns a :class:`Pretest`; :meth:`Pretest.findings` says
whether the motion must be refused (and what would make it fit) and what to
warn about.  The library decides nothing for the user: the caller refuses or
runs (``imil simulate --force``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from ..errors import ConfigError
from ..plant import TableParameters
from ..plant.lti_table import LTITable
from ..signals import GroundMotion, MotionCheck, TableLimits, check_motion
from ..units import G0, weight_to_mass
from ..virtual.excitation import rigid_article_response
from .setup import SafetyLimits


def check_dict(check: MotionCheck) -> dict:
    """JSON form of a :class:`~impedance_mil.signals.MotionCheck` (peaks and limits in their ``unit``)."""
    return {
        "ok": check.ok,
        "exceeded": check.exceeded,
        "checks": [
            {
                "name": c.name,
                "peak": c.peak,
                "limit": c.limit,
                "unit": c.unit,
                "ok": c.ok,
                "ratio": c.ratio,
                "time_s": c.time_s,
            }
            for c in check.checks
        ],
        "suggested_time_scale": check.suggested_time_scale,
        "max_pga_g": check.max_pga_g,
    }


def overruns(check: MotionCheck) -> str:
    """``"stroke 9.70 in > 3.2 in at t = 5.10 s, ..."`` for the exceeded limits."""
    return ", ".join(
        f"{c.name} {c.peak:.3g} {c.unit} > {c.limit:.3g} {c.unit} at t = {c.time_s:.2f} s"
        for c in check.checks
        if not c.ok
    )


@dataclass(frozen=True)
class PretestFindings:
    """What the pre-test check found.

    Attributes
    ----------
    refusal : str or None
        Why the motion exceeds the table's limits (None: it fits).
    time_scale : float or None
        Total time compression that would fix stroke, velocity and flow.
    pga_g : float or None
        Largest PGA [g] the force limit allows, when the force is exceeded.
    warnings : tuple of str
        Warnings for a run that goes ahead (the basemat prediction).
    basemat_fit_pga_g : float or None
        MIL, when the predicted basemat stroke exceeds the interlock: the PGA [g]
        at which it would just fit (the stroke scales with the PGA).
    """

    refusal: str | None
    time_scale: float | None
    pga_g: float | None
    warnings: tuple[str, ...]
    basemat_fit_pga_g: float | None = None


@dataclass(frozen=True)
class Pretest:
    """Pre-test check of a motion against the table's limits (report Section 8.2).

    Attributes
    ----------
    limits : TableLimits
        Capacity of the table with the specimen.
    input : MotionCheck
        The input motion (what the table follows when tracking).
    basemat : MotionCheck or None
        MIL only: stroke and velocity of the VS basemat motion the table must
        follow, predicted with the specimen as a rigid mass (:func:`basemat_check`).
    """

    limits: TableLimits
    input: MotionCheck
    basemat: MotionCheck | None = None

    def to_dict(self) -> dict:
        out = {"moving_weight_lbf": self.limits.moving_mass * G0, "input": check_dict(self.input)}
        if self.basemat is not None:
            out["basemat_predicted"] = check_dict(self.basemat)
        return out

    def findings(self, motion: GroundMotion, time_scale: float) -> PretestFindings:
        """Refusal, remedies and warnings for ``motion`` (run at ``time_scale``, the compression applied)."""
        refusal = scale = pga = None
        if not self.input.ok:
            refusal = f"the motion exceeds the table's limits: {overruns(self.input)}"
            if self.input.suggested_time_scale is not None:
                scale = time_scale * self.input.suggested_time_scale
            if not self.input.check("force").ok:
                pga = self.input.max_pga_g
        warnings = []
        fit_pga = None
        if self.basemat is not None and not self.basemat.ok:
            stroke = self.basemat.check("stroke")
            fit = ""
            if not stroke.ok:
                fit_pga = motion.pga_g * stroke.limit / stroke.peak
                fit = f"; at about {fit_pga:.2f} g it would fit"
            warnings.append(
                "the VS basemat motion the table must follow (specimen taken as rigid) "
                f"exceeds the lab's interlocks: {overruns(self.basemat)}; the run will "
                f"probably be stopped{fit}"
            )
        return PretestFindings(refusal, scale, pga, tuple(warnings), fit_pga)


def basemat_check(
    vs,
    motion: GroundMotion,
    params: TableParameters | LTITable,
    limits: TableLimits,
    specimen_weight_lbf: float,
    interlocks: SafetyLimits,
) -> MotionCheck:
    """Stroke and velocity the table needs to follow the VS basemat in a MIL run (a prediction).

    The basemat's absolute acceleration comes from the VS model carrying the
    specimen (``specimen_weight_lbf`` [lbf]) as a rigid mass
    (``virtual.excitation.rigid_article_response``), at the loop time; it is
    checked *without* baseline correction (``check_motion(...,
    baseline_correct=False)``), as the loop integrates it from rest (a
    correction misjudges an excerpt that ends mid-shaking).  The limits are
    the lab's ``interlocks`` where they are tighter than the table's capacity.
    """
    gm = motion.resampled(params.loop_time)
    response = rigid_article_response(vs, gm.accel, gm.time_step, weight_to_mass(specimen_weight_lbf))
    basemat = GroundMotion(gm.time_step, response.z_vs, "VS basemat")
    lab = replace(
        limits,
        stroke_in=min(limits.stroke_in, interlocks.stroke),
        velocity_in_s=min(limits.velocity_in_s, interlocks.velocity),
    )
    # stroke and velocity only: the flow check of 1.2 million samples (600 s at 500 us) took 0.05 s
    full = check_motion(basemat, lab, baseline_correct=False, flow=False)
    checks = [full.check("stroke"), full.check("velocity")]
    return MotionCheck(all(c.ok for c in checks), checks, None, full.max_pga_g)


def table_limits(
    params: TableParameters | LTITable, specimen_weight_lbf: float, interlocks: SafetyLimits
) -> TableLimits:
    """The capacity of the table with the article: of its physical parameters, or an LTI table's stated one.

    An LTI table (:mod:`impedance_mil.plant.capacity`) has no valve for the
    flow check; its stroke and velocity are its stated ones, else the lab's
    interlocks; its force capacity is the stated stall force, else the lab's
    actuator-force interlock; its moving mass must be stated.

    Raises
    ------
    ConfigError
        An LTI table without ``capacity.mass``, or without ``capacity.force``
        and an actuator-force interlock.
    """
    if not isinstance(params, LTITable):
        return TableLimits.from_table(params, specimen_weight=specimen_weight_lbf)
    c = params.capacity
    force = c.force if c.force is not None else interlocks.actuator_force
    if c.mass is None:
        raise ConfigError("capacity.mass", "the LTI table's moving mass (the pre-test check needs it)")
    if force is None:
        raise ConfigError(
            "capacity.force",
            "the LTI table's stall force, or a limits.actuator_force (the pre-test check needs one)",
        )
    return TableLimits(
        stroke_in=interlocks.stroke if c.stroke is None else c.stroke,
        velocity_in_s=interlocks.velocity if c.velocity is None else c.velocity,
        force_lbf=float(force),
        moving_mass=c.mass + weight_to_mass(specimen_weight_lbf),
    )


def pretest(
    params: TableParameters | LTITable,
    specimen_weight_lbf: float,
    motion: GroundMotion,
    interlocks: SafetyLimits,
    vs=None,
) -> Pretest:
    """Check the input motion (and, with a VS, the predicted basemat motion) against the table.

    Parameters
    ----------
    params : TableParameters or LTITable
        The table (:func:`table_limits`).
    specimen_weight_lbf : float
        Weight of the test article on the table [lbf] (0 for the bare table).
    motion : GroundMotion
        Input motion [in/s^2], as it will be run.
    interlocks : SafetyLimits
        The lab's interlocks (they bound the basemat prediction).
    vs : VirtualSystem, optional
        The VS of a MIL run.
    """
    limits = table_limits(params, specimen_weight_lbf, interlocks)
    basemat = (
        None if vs is None else basemat_check(vs, motion, params, limits, specimen_weight_lbf, interlocks)
    )
    return Pretest(limits, check_motion(motion, limits), basemat)
