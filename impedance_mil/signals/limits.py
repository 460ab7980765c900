"""Pre-test feasibility check: does a ground motion fit the shake table?

Four limits of the servo-hydraulic table (report Sections 3.4, 4.3.2, 4.3.5):

stroke
    Peak displacement of the baseline-corrected motion against the mid-stroke
    position x_m (3.2 in: +-3.2 in of dynamic stroke, Table 4.1).
velocity
    Peak velocity against the no-load velocity capacity of the valve,
    ``v_max = Q_rated * sqrt((P_s - P_R) / dP_rated) / A_p`` (orifice law,
    Eq 4-4: flow grows with the square root of the pressure drop; with no
    load the whole supply pressure drops across the valve).  Report values:
    57.75 in^3/s at 1000 psi, P_s = 3000 psi, A_p = 2.1 in^2: 47.6 in/s.
force
    Peak inertia force (table + test-article mass) x (peak acceleration)
    against the force capacity, by default ``A_p * (P_s - P_R)`` (6300 lbf;
    Eq 4-7b with |P_1 - P_2| <= P_s).  The actuator's nominal rating
    (5.5 kip, Section 3.4) is lower; pass it as ``force_limit`` to check
    against it (see docs/errata.md).
flow
    The flow the motion needs at the pressure drop left over by the load at
    each instant: the valve passes
    ``Q = Q_rated * sqrt(dP_valve / dP_rated)`` with
    ``dP_valve = P_s - P_R - sign(v) * F / A_p`` (the load pressure
    F/A_p is subtracted when the actuator pushes along its motion, added when
    it brakes), so the motion needs a valve rated at least
    ``Q_eq(t) = A_p |v(t)| sqrt(dP_rated / dP_valve(t))``.  The peak of Q_eq
    is checked against Q_rated; a load pressure above the supply (dP_valve
    <= 0) makes Q_eq infinite.

Time scaling (report Section 8.2).  Compressing time by a factor s
(t' = t/s) at the same accelerations divides displacements by s**2 and
velocities (and Q_eq) by s, and leaves forces unchanged.  So a record that
overruns the stroke or the valve is made to fit by compressing it by

    s = max(sqrt(D / x_m), V / v_max, Q_eq / Q_rated),

which is what the report does: "time-scaling is performed to prevent the
shake-table displacement from exceeding its maximum stroke".  A force
overrun cannot be fixed by time scaling, only by a lower PGA.  Compression
also multiplies every frequency by s, moving energy toward the oil-column
resonance (27 Hz): check the tracking too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError, NotEvaluatedError
from ..units import G0, weight_to_mass
from .motion import GroundMotion, integrate_piecewise_linear

#: Report values (Sections 3.4, 4.3.2, Table 4.1) used by :meth:`TableLimits.report_default`.
REPORT_TABLE = {
    "piston_area": 2.1,  # in^2
    "mid_stroke": 3.2,  # in
    "table_mass": 1600.0 / G0,  # lbf*s^2/in (1600 lb; printed as 4.14)
    "supply_pressure": 3000.0,  # psi
    "rated_flow": 57.75,  # in^3/s (15 gpm)
    "rated_pressure_drop": 1000.0,  # psi
}


def _positive(key: str, value: float, *, allow_zero: bool = False) -> float:
    number = float(value)
    ok = math.isfinite(number) and (number >= 0 if allow_zero else number > 0)
    if not ok:
        raise ConfigError(
            key, "a non-negative finite number" if allow_zero else "a positive finite number", value
        )
    return number


@dataclass(frozen=True)
class TableLimits:
    """Capacity of a shake table for a given test article.

    Parameters
    ----------
    stroke_in : float
        Allowed displacement from mid-stroke [in].
    velocity_in_s : float
        No-load velocity capacity [in/s].
    force_lbf : float
        Force capacity [lbf].
    moving_mass : float
        Table plus test-article mass [lbf*s^2/in].
    piston_area : float or None
        A_p [in^2]; with the next three, enables the ``flow`` check.
    pressure_drop : float or None
        Pressure available across the valve at no load, P_s - P_R [psi].
    rated_flow : float or None
        Q_rated [in^3/s] at ``rated_pressure_drop``.
    rated_pressure_drop : float or None
        [psi].
    """

    stroke_in: float
    velocity_in_s: float
    force_lbf: float
    moving_mass: float
    piston_area: float | None = None
    pressure_drop: float | None = None
    rated_flow: float | None = None
    rated_pressure_drop: float | None = None

    def __post_init__(self) -> None:
        for key in ("stroke_in", "velocity_in_s", "force_lbf", "moving_mass"):
            object.__setattr__(self, key, _positive(key, getattr(self, key)))
        hydraulic = ("piston_area", "pressure_drop", "rated_flow", "rated_pressure_drop")
        given = [getattr(self, key) is not None for key in hydraulic]
        if any(given) and not all(given):
            raise ConfigError("piston_area", "all or none of " + ", ".join(hydraulic))
        if all(given):
            for key in hydraulic:
                object.__setattr__(self, key, _positive(key, getattr(self, key)))

    @property
    def has_hydraulics(self) -> bool:
        """Whether the valve data for the ``flow`` check are present."""
        return self.piston_area is not None

    @classmethod
    def from_numbers(
        cls,
        *,
        piston_area: float,
        mid_stroke: float,
        table_mass: float,
        supply_pressure: float,
        rated_flow: float,
        rated_pressure_drop: float,
        return_pressure: float = 0.0,
        specimen_weight: float = 0.0,
        force_limit: float | None = None,
    ) -> TableLimits:
        """Limits from the table's specification numbers (internal units).

        Parameters
        ----------
        piston_area : float
            A_p [in^2].
        mid_stroke : float
            x_m [in] (half the dynamic stroke).
        table_mass : float
            Moving table mass m_st [lbf*s^2/in].
        supply_pressure, return_pressure : float
            P_s, P_R [psi].
        rated_flow : float
            Q_rated [in^3/s] at ``rated_pressure_drop`` [psi].
        rated_pressure_drop : float
            [psi].
        specimen_weight : float
            Weight of the rigidly mounted test article [lbf] (0 for the bare table).
        force_limit : float or None
            Force capacity [lbf]; default A_p (P_s - P_R).
        """
        area = _positive("piston_area", piston_area)
        drop = _positive("supply_pressure", supply_pressure) - _positive(
            "return_pressure", return_pressure, allow_zero=True
        )
        if drop <= 0:
            raise ConfigError("return_pressure", "less than the supply pressure", return_pressure)
        q_rated = _positive("rated_flow", rated_flow)
        dp_rated = _positive("rated_pressure_drop", rated_pressure_drop)
        mass = _positive("table_mass", table_mass) + weight_to_mass(
            _positive("specimen_weight", specimen_weight, allow_zero=True)
        )
        force = area * drop if force_limit is None else _positive("force_limit", force_limit)
        return cls(
            stroke_in=_positive("mid_stroke", mid_stroke),
            velocity_in_s=q_rated * math.sqrt(drop / dp_rated) / area,
            force_lbf=force,
            moving_mass=mass,
            piston_area=area,
            pressure_drop=drop,
            rated_flow=q_rated,
            rated_pressure_drop=dp_rated,
        )

    @classmethod
    def from_table(cls, table, specimen_weight: float = 0.0, force_limit: float | None = None) -> TableLimits:
        """Limits from a table-parameter object (e.g. :class:`impedance_mil.plant.TableParameters`).

        Uses its ``piston_area``, ``mid_stroke``, ``mass``, ``supply_pressure``,
        ``return_pressure`` (0 if absent), ``rated_flow`` and ``rated_pressure_drop``.
        """
        return cls.from_numbers(
            piston_area=table.piston_area,
            mid_stroke=table.mid_stroke,
            table_mass=table.mass,
            supply_pressure=table.supply_pressure,
            return_pressure=getattr(table, "return_pressure", 0.0),
            rated_flow=table.rated_flow,
            rated_pressure_drop=table.rated_pressure_drop,
            specimen_weight=specimen_weight,
            force_limit=force_limit,
        )

    @classmethod
    def report_default(cls, specimen_weight: float = 0.0, force_limit: float | None = None) -> TableLimits:
        """The report's table (Sections 3.4, 4.3.2, Table 4.1) with a test article of the given weight [lbf]."""
        return cls.from_numbers(**REPORT_TABLE, specimen_weight=specimen_weight, force_limit=force_limit)


@dataclass(frozen=True)
class LimitCheck:
    """One limit: the motion's peak demand against the table's capacity.

    Parameters
    ----------
    name : str
        ``"stroke"``, ``"velocity"``, ``"force"`` or ``"flow"``.
    peak : float
        Peak demand, in ``unit``.
    limit : float
        Capacity, in ``unit``.
    unit : str
        ``"in"``, ``"in/s"``, ``"lbf"`` or ``"in^3/s"``.
    ok : bool
        ``peak <= limit``.
    time_s : float
        Time of the peak [s].
    """

    name: str
    peak: float
    limit: float
    unit: str
    ok: bool
    time_s: float = float("nan")

    @property
    def ratio(self) -> float:
        """Demand over capacity (> 1 means exceeded)."""
        return self.peak / self.limit


@dataclass(frozen=True)
class MotionCheck:
    """Result of :func:`check_motion`.

    Parameters
    ----------
    ok : bool
        Every limit holds.
    checks : list of LimitCheck
        One entry per limit, in the order stroke, velocity, force, flow.
    suggested_time_scale : float or None
        Additional time-compression factor s (t' = t/s, same accelerations)
        that makes stroke, velocity and flow fit, rounded up to 0.01; ``None``
        when they already fit or when time scaling cannot help (force overrun).
    max_pga_g : float
        Largest PGA [g] the force capacity allows for this moving mass.
    """

    ok: bool
    checks: list[LimitCheck]
    suggested_time_scale: float | None
    max_pga_g: float

    @property
    def exceeded(self) -> list[str]:
        """Names of the limits exceeded."""
        return [c.name for c in self.checks if not c.ok]

    def check(self, name: str) -> LimitCheck:
        """The check of the given name (NotEvaluatedError, a KeyError, for another name)."""
        for item in self.checks:
            if item.name == name:
                return item
        raise NotEvaluatedError(f"no check named {name!r}")


def _peak(name: str, values: np.ndarray, limit: float, unit: str, time_step: float) -> LimitCheck:
    k = int(np.argmax(values))
    peak = float(values[k])
    return LimitCheck(name, peak, float(limit), unit, bool(peak <= limit), k * time_step)


def required_rated_flow(velocity: np.ndarray, force: np.ndarray, limits: TableLimits) -> np.ndarray:
    """Rated flow Q_eq(t) [in^3/s] a valve needs to deliver the motion (module docstring).

    Parameters
    ----------
    velocity : ndarray
        Table velocity [in/s].
    force : ndarray
        Actuator force [lbf] (moving mass times acceleration).
    limits : TableLimits
        Must carry the hydraulic data.
    """
    if not limits.has_hydraulics:
        raise ConfigError("limits", "piston_area, pressure_drop, rated_flow and rated_pressure_drop")
    load_pressure = force / limits.piston_area
    drop = limits.pressure_drop - np.sign(velocity) * load_pressure
    flow = limits.piston_area * np.abs(velocity)
    with np.errstate(divide="ignore", invalid="ignore"):
        q_eq = np.where(
            drop > 0,
            flow * np.sqrt(limits.rated_pressure_drop / np.where(drop > 0, drop, 1.0)),
            np.where(flow > 0, np.inf, 0.0),
        )
    return q_eq


def check_motion(
    motion: GroundMotion,
    limits: TableLimits,
    baseline_order: int = 3,
    baseline_correct: bool = True,
    flow: bool = True,
) -> MotionCheck:
    """Check a ground motion against the table's stroke, velocity, force and flow limits.

    By default the motion is baseline-corrected first
    (:meth:`GroundMotion.baseline_corrected`), as it must be before it is sent
    to the table; displacement and velocity come from that corrected record.

    Parameters
    ----------
    motion : GroundMotion
        The motion as it will be run (already time- and amplitude-scaled).
    limits : TableLimits
        Capacity of the table with its test article.
    baseline_order : int
        Order of the baseline correction polynomial.
    baseline_correct : bool
        False: check the motion as given, integrated from rest without
        correction (how the virtual lab's loop integrates a target it
        follows, e.g. a VS basemat acceleration).
    flow : bool
        False: no flow check, even with the hydraulic data (a caller that
        reads only the kinematic checks of a long record: the flow is the
        costliest, ten passes over it).

    Returns
    -------
    MotionCheck
        Every limit with its peak, and the time-compression factor that fixes
        the kinematic overruns.

    Examples
    --------
    >>> from impedance_mil.signals import builtin_motion, check_motion, TableLimits
    >>> gm1 = builtin_motion("elcentro").time_scaled(2.0).scaled_to_pga(0.8)
    >>> check_motion(gm1, TableLimits.report_default(specimen_weight=1200.0)).exceeded
    []
    """
    corrected = motion.baseline_corrected(baseline_order) if baseline_correct else motion
    dt = corrected.time_step
    vel, disp = integrate_piecewise_linear(corrected.accel, dt)  # velocity() and displacement() in one pass
    force = limits.moving_mass * corrected.accel
    checks = [
        _peak("stroke", np.abs(disp), limits.stroke_in, "in", dt),
        _peak("velocity", np.abs(vel), limits.velocity_in_s, "in/s", dt),
        _peak("force", np.abs(force), limits.force_lbf, "lbf", dt),
    ]
    if flow and limits.has_hydraulics:
        checks.append(_peak("flow", required_rated_flow(vel, force, limits), limits.rated_flow, "in^3/s", dt))
    ok = all(c.ok for c in checks)
    needed = [math.sqrt(checks[0].ratio), checks[1].ratio] + ([checks[3].ratio] if len(checks) > 3 else [])
    scale = max(needed)
    suggested = None
    if scale > 1.0 and math.isfinite(scale):
        suggested = math.ceil(scale * 100.0 - 1e-9) / 100.0
    return MotionCheck(ok, checks, suggested, limits.force_lbf / (limits.moving_mass * G0))
