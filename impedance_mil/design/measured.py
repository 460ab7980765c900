"""Design checks on a measured FRF: constraints I and III with no fitted model (issue 13, item 3).

A designed MIL controller (``u = H_uz r + H_uw w``, :mod:`.forms`) is
evaluated on the table's measured responses ``H_zu``, ``H_zw``
(:class:`~impedance_mil.plant.frf_table.FRFTable`) with the algebra of
:class:`~impedance_mil.design.constraints.ControlledTable`, the measured
responses standing for the model's ``H_zu^st``, ``H_zw^st`` (every form
uses the table's own ``H_zu``, ``H_zw`` there)::

    H_wu = H_uw + H_uz Z          (Z the VS target, standardized form; H_wu = H_uw otherwise)
    H_c  = H_zw + H_zu H_wu       (controlled impedance, Eq 6-5)
    H_vw = H_c / (j 2 pi f)       (force-velocity, Eq 9-2)

The controller and the VS target are evaluated as continuous transfer
functions at ``s = j 2 pi f`` (the design's own model of them).

Constraints, at the measured frequencies only (no interpolation):

I   ``e_I = max |H_c/H_zw^vs - 1|`` (tracking: ``max |H_c/H_zw|``) over the
    points inside the band of interest ``DesignCriteria.band_hz``;
II  copied from the design's model-based result: it depends on the
    controller (and the VS target) only, not on the table;
III passivity: ``margin = min (90 - |phase H_vw|)`` [deg] over the points
    from ``passivity_low_hz`` to the Nyquist frequency, as
    :mod:`.passivity` defines it.  A measured FRF holds the true loop delay,
    so there is no delay-model error to credit: by default
    (``tolerance="none"``) the verdict uses the raw margin plus only
    ``passivity_extra_tolerance_deg``.  ``tolerance="delay-model"`` credits
    the design's first-order delay-model tolerance as well
    (:func:`~impedance_mil.design.passivity.delay_model_tolerance_deg`), for
    comparing with the model-based verdict on an FRF sampled from that model.

Coverage: each check is asked over a band; the data cover the part of it
between their lowest and highest frequency.

* ``full``: the data span the whole band; the verdict is True or False.
* ``partial``: the data cover part of it.  A violation on the covered part is
  a violation (False); no violation there gives no verdict (None): the
  constraint is not shown to hold where nothing was measured.  The metric and
  ``holds_on_covered`` say what the covered part shows.
* ``none``: fewer than :data:`MIN_POINTS` points inside the band: no verdict
  (None) and no metric.

Stability cannot be judged from an FRF alone (the poles of ``H_vw`` are not
measured): the result says so (``stability``) and III is the phase condition
of passivity only, never a stability verdict.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from ..errors import ConfigError
from ..plant.frf_table import FRFTable
from ..systems import TransferFunction
from ..units import TWO_PI
from .constraints import ConstraintResult, DesignCriteria, target_impedance
from .controller import ControllerDesign, filter_controller
from .forms import TableModel, VirtualModel, environment, ideal_controller
from .passivity import delay_model_tolerance_deg

#: Fewest measured points inside a band for a check to be made there.
MIN_POINTS = 2

#: Relative slack on a band's edges when deciding full coverage (frequencies written to a file).
EDGE_RTOL = 1e-6

#: Passivity tolerances on measured data (see the module docstring).
TOLERANCES = ("none", "delay-model")

#: How the controller's response is evaluated (see :func:`controller_frequency_hz`).
CONTROLLER_MODELS = ("continuous", "tustin")

#: What the result says of stability.
STABILITY = "not judged (model-free)"

#: Relative difference of loop times above which an FRF does not belong to a design.
LOOP_TIME_RTOL = 1e-6


class ControllerPaths(Protocol):
    """Anything with the filtered controller paths (``ControllerDesign``, ``FilteredPaths``)."""

    @property
    def H_uz(self) -> TransferFunction: ...

    @property
    def H_uw(self) -> TransferFunction: ...


@dataclass(frozen=True)
class Coverage:
    """How much of one check's band the measured frequencies cover.

    Attributes
    ----------
    asked_hz : (float, float)
        The band the check is asked over [Hz].
    covered_hz : (float, float) or None
        The lowest and highest measured frequency inside it [Hz]; None when
        fewer than :data:`MIN_POINTS` points fall inside.
    status : str
        ``"full"``, ``"partial"`` or ``"none"``.
    n_points : int
        Measured frequencies inside the band.
    """

    asked_hz: tuple[float, float]
    covered_hz: tuple[float, float] | None
    status: str
    n_points: int

    def to_dict(self) -> dict:
        return {
            "asked_hz": [float(x) for x in self.asked_hz],
            "covered_hz": None if self.covered_hz is None else [float(x) for x in self.covered_hz],
            "status": self.status,
            "n_points": int(self.n_points),
        }


def coverage(frf: FRFTable, band_hz: tuple[float, float]) -> Coverage:
    """The coverage of ``band_hz`` [Hz] by the frequencies of ``frf``."""
    lo, hi = float(band_hz[0]), float(band_hz[1])
    f = frf.frequency_hz[frf.in_band((lo, hi))]
    if f.size < MIN_POINTS:
        return Coverage((lo, hi), None, "none", int(f.size))
    data_lo, data_hi = frf.range_hz
    full = data_lo <= lo * (1 + EDGE_RTOL) and data_hi >= hi * (1 - EDGE_RTOL)
    return Coverage((lo, hi), (float(f[0]), float(f[-1])), "full" if full else "partial", int(f.size))


def _verdict(cov: Coverage, holds: bool | None) -> bool | None:
    """True only on full coverage; a violation on any covered part is False; otherwise None."""
    if holds is None:
        return None
    if not holds:
        return False
    return True if cov.status == "full" else None


@dataclass(frozen=True)
class MeasuredChecks:
    """Constraints I, II, III of one controller on a measured FRF (see the module docstring).

    Attributes
    ----------
    fc_hz : float
        Cut-off of the controller [Hz].
    frequency_range_hz : (float, float)
        Lowest and highest measured frequency [Hz].
    coverage_I, coverage_III : Coverage
        Coverage of the band of interest (I) and of the passivity band (III).
    I, III : bool or None
        Verdicts; None when not judged (no coverage, or a pass on a partial coverage).
    II : bool
        The design's verdict (controller only).
    holds_on_covered_I, holds_on_covered_III : bool or None
        Whether the constraint holds on the covered part (None: no coverage).
    performance_error : float or None
        ``e_I`` on the covered part (dimensionless), peaking at ``performance_worst_hz`` [Hz].
    effort_ratio : float
        ``e_II`` of the design (dimensionless), peaking at ``effort_worst_hz`` [Hz].
    passivity_margin_deg : float or None
        ``min (90 - |phase H_vw|)`` [deg] on the covered part, at ``passivity_worst_hz`` [Hz].
    passivity_tolerant_margin_deg : float or None
        Margin after the tolerance [deg] at ``passivity_tolerant_worst_hz`` [Hz]; III uses it.
    passivity_tolerance : str
        ``"none"`` or ``"delay-model"`` (:data:`TOLERANCES`).
    passivity_extra_tolerance_deg : float
        Extra tolerance [deg] credited at every frequency.
    controller_model : str
        ``"continuous"`` or ``"tustin"`` (:data:`CONTROLLER_MODELS`).
    min_coherence_zu, min_coherence_zw : float or None
        Smallest coherence of each path over the points used (None when not measured).
    stability : str
        Always :data:`STABILITY`: an FRF does not show the poles.
    """

    fc_hz: float
    frequency_range_hz: tuple[float, float]
    coverage_I: Coverage
    coverage_III: Coverage
    I: bool | None  # noqa: E741 (the report names constraint I)
    II: bool
    III: bool | None
    holds_on_covered_I: bool | None
    holds_on_covered_III: bool | None
    performance_error: float | None
    performance_worst_hz: float | None
    effort_ratio: float
    effort_worst_hz: float
    passivity_margin_deg: float | None
    passivity_worst_hz: float | None
    passivity_tolerant_margin_deg: float | None
    passivity_tolerant_worst_hz: float | None
    passivity_tolerance: str
    passivity_extra_tolerance_deg: float
    controller_model: str
    min_coherence_zu: float | None
    min_coherence_zw: float | None
    stability: str = STABILITY

    def to_dict(self) -> dict:
        """The ``measured`` block of ``imil design --frf --json`` (the design's key names)."""

        def num(x):
            return None if x is None else float(x)

        return {
            "fc_hz": float(self.fc_hz),
            "frequency_range_hz": [float(x) for x in self.frequency_range_hz],
            "coverage": {
                "I": self.coverage_I.status,
                "II": "controller only",
                "III": self.coverage_III.status,
            },
            "frequency_bands": {"I": self.coverage_I.to_dict(), "III": self.coverage_III.to_dict()},
            "I": self.I,
            "II": bool(self.II),
            "III": self.III,
            "holds_on_covered": {"I": self.holds_on_covered_I, "III": self.holds_on_covered_III},
            "performance_error": num(self.performance_error),
            "performance_worst_hz": num(self.performance_worst_hz),
            "effort_ratio": float(self.effort_ratio),
            "effort_worst_hz": float(self.effort_worst_hz),
            "passivity_margin_deg": num(self.passivity_margin_deg),
            "passivity_worst_hz": num(self.passivity_worst_hz),
            "passivity_tolerant_margin_deg": num(self.passivity_tolerant_margin_deg),
            "passivity_tolerant_worst_hz": num(self.passivity_tolerant_worst_hz),
            "passivity_tolerance": self.passivity_tolerance,
            "passivity_extra_tolerance_deg": float(self.passivity_extra_tolerance_deg),
            "controller_model": self.controller_model,
            "min_coherence": {"zu": num(self.min_coherence_zu), "zw": num(self.min_coherence_zw)},
            "stability": self.stability,
        }

    def lines(self) -> list[str]:
        """Text lines for the human output: verdicts, metrics and coverage."""
        mark = {True: "ok", False: "NO", None: "--"}

        def band(c: Coverage) -> str:
            got = "none" if c.covered_hz is None else f"{c.covered_hz[0]:.4g}-{c.covered_hz[1]:.4g} Hz"
            return f"{c.status} ({got} of {c.asked_hz[0]:.4g}-{c.asked_hz[1]:.4g} Hz)"

        perf = "-" if self.performance_error is None else f"{self.performance_error:.3f}"
        margin = (
            "-"
            if self.passivity_margin_deg is None
            else f"{self.passivity_margin_deg:.2f} deg at {self.passivity_worst_hz:.4g} Hz"
        )
        lo, hi = self.frequency_range_hz
        return [
            f"  measured FRF at fc = {self.fc_hz:.4g} Hz (data {lo:.4g}-{hi:.4g} Hz; stability {self.stability}):",
            f"    I   {mark[self.I]:>3}  perf.err {perf}; coverage {band(self.coverage_I)}",
            f"    II  {mark[self.II]:>3}  effort {self.effort_ratio:.3g} (the design's: controller only)",
            f"    III {mark[self.III]:>3}  margin {margin} (tolerance {self.passivity_tolerance}); "
            f"coverage {band(self.coverage_III)}",
        ]


def measured_checks(
    frf: FRFTable,
    controller: ControllerPaths,
    model: ConstraintResult,
    *,
    form: str,
    vs: VirtualModel | None = None,
    criteria: DesignCriteria | None = None,
    tolerance: str = "none",
    controller_model: str = "continuous",
) -> MeasuredChecks:
    """Evaluate one filtered controller on a measured FRF.

    Parameters
    ----------
    frf : FRFTable
        The measured ``H_zu`` [in/s**2 per in], ``H_zw`` [in/s**2 per lbf].
    controller : ControllerDesign or FilteredPaths
        ``H_uz`` [in per in/s**2], ``H_uw`` [in per lbf] (sign convention of :mod:`.forms`).
    model : ConstraintResult
        The design's model-based result at the same cut-off: gives ``fc_hz`` and constraint II.
    form : str
        The controller's form; ``standardized`` closes ``w -> z_vs -> u`` through the VS target.
    vs : VirtualModel, optional
        The VS the design answers to (None: tracking, the rigid environment).
    criteria : DesignCriteria, optional
        Thresholds and bands; the defaults when omitted.
    tolerance : str
        ``"none"`` (default: a measurement has no delay-model error) or
        ``"delay-model"`` (credit the design's first-order delay tolerance).
    controller_model : str
        ``"continuous"`` (default: the design's controller at ``s = j 2 pi f``,
        as the model-based checks evaluate it) or ``"tustin"`` (its Tustin
        discretization at the loop time, the implementation step's default,
        :func:`controller_frequency_hz`); the VS target at the true frequency.

    Returns
    -------
    MeasuredChecks

    Raises
    ------
    ConfigError
        Unknown ``tolerance`` or ``controller_model``.
    """
    if tolerance not in TOLERANCES:
        raise ConfigError("tolerance", "one of " + ", ".join(TOLERANCES), tolerance)
    if controller_model not in CONTROLLER_MODELS:
        raise ConfigError("controller_model", "one of " + ", ".join(CONTROLLER_MODELS), controller_model)
    c = criteria or DesignCriteria()
    env = environment(form, vs)
    tracking = env.H_zw.is_zero
    target = None if tracking or form not in ("standardized", "tracking") else target_impedance(env, form)
    reference = None if tracking else (target if target is not None else target_impedance(env, "general"))

    def controlled(mask: np.ndarray) -> np.ndarray:
        f = frf.frequency_hz[mask]
        f_c = controller_frequency_hz(f, frf.loop_time_s, controller_model)
        H_wu = controller.H_uw.frequency_response(f_c)
        if target is not None:  # the VS model runs at the true frequency (integrated, not Tustin)
            H_wu = H_wu + controller.H_uz.frequency_response(f_c) * target.frequency_response(f)
        return frf.H_zw[mask] + frf.H_zu[mask] * H_wu

    cov_I = coverage(frf, c.band_hz)
    perf, perf_hz, holds_I = None, None, None
    mask_I = frf.in_band(c.band_hz)
    if cov_I.covered_hz is not None:
        f_I = frf.frequency_hz[mask_I]
        if reference is None:  # tracking: the share of the measured H_zw left uncompensated
            err = np.abs(controlled(mask_I) / frf.H_zw[mask_I])
        else:
            err = np.abs(controlled(mask_I) / reference.frequency_response(f_I) - 1.0)
        i = int(np.argmax(err))
        perf, perf_hz = float(err[i]), float(f_I[i])
        holds_I = perf <= c.performance_max

    band_III = (c.passivity_low_hz, frf.nyquist_hz)
    cov_III = coverage(frf, band_III)
    mask_III = frf.in_band(band_III)
    pas = None
    if cov_III.covered_hz is not None:
        pas = _passivity(frf, controlled(mask_III), mask_III, c, tolerance)
    used = mask_I | mask_III
    return MeasuredChecks(
        fc_hz=float(model.fc_hz),
        frequency_range_hz=frf.range_hz,
        coverage_I=cov_I,
        coverage_III=cov_III,
        I=_verdict(cov_I, holds_I),
        II=bool(model.II),
        III=_verdict(cov_III, None if pas is None else pas.holds),
        holds_on_covered_I=holds_I,
        holds_on_covered_III=None if pas is None else pas.holds,
        performance_error=perf,
        performance_worst_hz=perf_hz,
        effort_ratio=float(model.effort_ratio),
        effort_worst_hz=float(model.effort_worst_hz),
        passivity_margin_deg=None if pas is None else pas.margin_deg,
        passivity_worst_hz=None if pas is None else pas.worst_hz,
        passivity_tolerant_margin_deg=None if pas is None else pas.tolerant_margin_deg,
        passivity_tolerant_worst_hz=None if pas is None else pas.tolerant_worst_hz,
        passivity_tolerance=tolerance,
        passivity_extra_tolerance_deg=float(c.passivity_extra_tolerance_deg),
        controller_model=controller_model,
        min_coherence_zu=_min_coherence(frf, "H_zu", used),
        min_coherence_zw=_min_coherence(frf, "H_zw", used),
    )


def controller_frequency_hz(f_hz: np.ndarray, loop_time_s: float, controller_model: str) -> np.ndarray:
    """The frequency [Hz] at which a continuous controller gives the response of its model at ``f_hz`` [Hz].

    ``"continuous"``: ``f_hz`` itself.  ``"tustin"``: the warped frequency
    ``tan(pi f T)/(pi T)``, so that ``H(j 2 pi f_w) = H_d(exp(j 2 pi f T))`` for
    the Tustin discretization ``H_d`` at the loop time ``T`` [s] (no prewarping).
    """
    f = np.asarray(f_hz, dtype=float)
    if controller_model == "continuous":
        return f
    return np.tan(np.pi * f * loop_time_s) / (np.pi * loop_time_s)


@dataclass(frozen=True)
class MeasuredPassivity:
    """The passivity margin at the measured points of the passivity band (internal result)."""

    margin_deg: float
    worst_hz: float
    tolerant_margin_deg: float
    tolerant_worst_hz: float
    holds: bool


def _passivity(
    frf: FRFTable, H_c: np.ndarray, mask: np.ndarray, c: DesignCriteria, tolerance: str
) -> MeasuredPassivity:
    """``90 - |phase H_vw|`` [deg] at the measured points, raw and with the tolerance."""
    f = frf.frequency_hz[mask]
    margin = 90.0 - np.abs(np.degrees(np.angle(H_c / (1j * TWO_PI * f))))
    tol = np.full(f.shape, c.passivity_extra_tolerance_deg)
    if tolerance == "delay-model":
        tol = tol + delay_model_tolerance_deg(f, frf.loop_time_s)
    i, j = int(np.argmin(margin)), int(np.argmin(margin + tol))
    tolerant = float(margin[j] + tol[j])
    return MeasuredPassivity(float(margin[i]), float(f[i]), tolerant, float(f[j]), tolerant >= 0.0)


def _min_coherence(frf: FRFTable, path: str, mask: np.ndarray) -> float | None:
    coh = frf.coherence(path)
    return None if coh is None or not mask.any() else float(np.min(coh[mask]))


def check_loop_time(frf: FRFTable, loop_time_s: float) -> None:
    """Refuse an FRF measured at another loop time than the design's [s] (its Nyquist band differs).

    Raises
    ------
    ConfigError
        Key ``loop_time``: the FRF's and the design's loop times differ.
    """
    if not np.isclose(frf.loop_time_s, loop_time_s, rtol=LOOP_TIME_RTOL, atol=0.0):
        raise ConfigError(
            "loop_time",
            f"the design's loop time {loop_time_s:g} s in the FRF table "
            f"({frf.source or 'FRF'}; a controller runs at the loop rate it was designed for)",
            f"{frf.loop_time_s:g} s",
        )


def design_measured_checks(
    design: ControllerDesign,
    frf: FRFTable,
    *,
    table: TableModel | None = None,
    vs: VirtualModel | None = None,
    criteria: DesignCriteria | None = None,
    tolerance: str = "none",
    controller_model: str = "continuous",
) -> tuple[MeasuredChecks, ...]:
    """Every cut-off of a design (``design.constraints``) evaluated on a measured FRF.

    Parameters
    ----------
    design : ControllerDesign
        From :func:`~impedance_mil.design.controller.design_controller` or a design file.
    frf : FRFTable
        Measured at the design's loop time.
    table : TableModel, optional
        The model the design was made on; needed to rebuild the filtered paths
        of the cut-offs other than ``design.fc_hz`` (without it, or for an
        optimized design, only the design's own cut-off is evaluated).
    vs : VirtualModel, optional
        The VS of the design (None for tracking).
    criteria, tolerance, controller_model
        See :func:`measured_checks`.

    Raises
    ------
    ConfigError
        The FRF's loop time is not the design's (key ``loop_time``), a design
        made for a VS given without ``vs`` (key ``vs``), or an unknown
        ``tolerance`` or ``controller_model``.
    """
    check_loop_time(frf, design.loop_time_s)
    if vs is None and design.vs is not None and design.form != "tracking":
        name = design.vs.get("name") or design.vs.get("kind")
        raise ConfigError(
            "vs", f"the VS model of the design ({name}); without it the checks would be tracking's"
        )
    if not design.constraints:
        raise ConfigError("constraints", "a design with its constraints evaluated")
    kw: dict[str, Any] = dict(
        form=design.form, vs=vs, criteria=criteria, tolerance=tolerance, controller_model=controller_model
    )
    out = [measured_checks(frf, design, design.constraints[0], **kw)]
    if table is None or design.optimization is not None:
        return tuple(out)
    ideal = None
    for result in design.constraints[1:]:
        if ideal is None:
            ideal = ideal_controller(design.form, table, environment(design.form, vs))
        spec = design.filter
        order = spec.order_z if spec.order_z == spec.order_w else None  # one order given, or the defaults
        paths = filter_controller(ideal, result.fc_hz, spec.family, order, spec.ripple_db)
        out.append(measured_checks(frf, paths, result, **kw))
    return tuple(out)
