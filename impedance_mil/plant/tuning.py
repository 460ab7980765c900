"""Tuning analysis of the table's hydraulic loop (report Section 4.4).

Poles are labelled the report's way (Section 4.4.2): ``p1`` rigid body,
``p2``/``p3`` servovalve (alpha_1, alpha_2), ``p4``/``p5`` oil column.  The
labels are found by continuation from the open loop (K_e = K_p = 0, tau = 0,
where they are known exactly) along the report's tuning path: K_e first, then
K_p, then the loop time, matching poles between small steps.

All frequencies are in Hz and damping ratios dimensionless at the interface;
poles are in rad/s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..lazy import LazyModule
from ..systems import pole_table
from .linear import LinearTable
from .parameters import TableParameters
from .statespace import plant_state_space

#: scipy.optimize, imported on first use (issue 16: a command that only reads a configuration does not need it).
scipy_optimize = LazyModule("scipy.optimize")

#: Report labels of the five poles of Eq 4-14 (Tables 4.2, 4.3).
POLE_LABELS = ("p1", "p2", "p3", "p4", "p5")
#: Labels of the four poles with a first-order valve (one valve pole, p2).
FIRST_ORDER_POLE_LABELS = ("p1", "p2", "p4", "p5")


def pole_labels(p: TableParameters) -> tuple[str, ...]:
    """The pole labels of ``p``'s model: :data:`POLE_LABELS`, or :data:`FIRST_ORDER_POLE_LABELS`."""
    return POLE_LABELS if p.valve_dynamics.order == 2 else FIRST_ORDER_POLE_LABELS


#: Parameters that can be swept.
SWEEPABLE = ("Ke", "Kp", "loop_time")
_STEPS = 12


@dataclass(frozen=True)
class Mode:
    """One pole: frequency [Hz], damping ratio [-] and position [rad/s]."""

    label: str
    pole: complex

    @property
    def frequency_hz(self) -> float:
        return float(abs(self.pole) / (2 * np.pi))

    @property
    def damping(self) -> float:
        w = abs(self.pole)
        return float(-self.pole.real / w) if w > 0 else float("nan")

    def to_dict(self) -> dict:
        return {
            "label": self.label,
            "frequency_hz": self.frequency_hz,
            "damping": self.damping,
            "real": float(self.pole.real),
            "imag": float(self.pole.imag),
        }


def _match(previous: np.ndarray, current: np.ndarray) -> np.ndarray:
    """Reorder ``current`` so that each entry continues the same entry of ``previous``."""
    cost = np.abs(previous[:, None] - current[None, :])
    rows, cols = scipy_optimize.linear_sum_assignment(cost)
    return current[cols[np.argsort(rows)]]


def _open_loop_poles(p: TableParameters) -> np.ndarray:
    """Open-loop poles in label order: rigid body, valve, oil column (upper half plane first)."""
    if p.valve == "two-pole":
        a1, a2 = p.valve_poles
        valve = np.array([-a1, -a2], dtype=complex)
    else:
        valve = np.sort_complex(p.valve_dynamics.poles())[::-1]
    if p.grounded_stiffness == 0.0 and not p.platen_damping:
        w, z = p.omega_oil, p.zeta_oil
        wd = w * np.sqrt(1 - z**2)
        actuator = np.array([0.0, -z * w + 1j * wd, -z * w - 1j * wd], dtype=complex)
    else:
        # the actuator block (x, v, dp) of Eq 4-11: the valve feeds it, it does not feed the valve
        eig = np.linalg.eigvals(plant_state_space(p).A[:3, :3]).astype(complex)
        eig = eig[np.argsort(np.abs(eig))]
        rigid, oil = eig[0], eig[1:]
        oil = oil[np.argsort(-oil.imag)]
        actuator = np.array([rigid, *oil])
    return np.concatenate([actuator[:1], valve, actuator[1:]])


def _continue(
    p: TableParameters, start: np.ndarray, name: str, target: float, delay: str, steps: int = _STEPS
) -> np.ndarray:
    poles = start
    begin = getattr(p, name)
    for value in np.linspace(begin, target, steps + 1)[1:]:
        poles = _match(poles, LinearTable(p.replace(**{name: value}), delay=delay).poles())
    return poles


def labelled_poles(p: TableParameters, delay: str = "first-order") -> list[Mode]:
    """The five closed-loop poles with the report's labels p1..p5 (four, without p3,
    with a first-order valve: :func:`pole_labels`).

    Parameters
    ----------
    p : TableParameters
        Model parameters.
    delay : {"none", "first-order"}
        Delay treatment (the five-state models of Eq 4-14).
    """
    if delay not in ("none", "first-order"):
        raise ConfigError("delay", "none or first-order for labelled poles", delay)
    q = p.replace(Ke=0.0, Kp=0.0, loop_time=0.0)
    poles = _open_loop_poles(q)
    poles = _continue(q, poles, "Ke", p.Ke, delay)
    q = q.replace(Ke=p.Ke)
    poles = _continue(q, poles, "Kp", p.Kp, delay)
    if delay == "first-order" and p.loop_time > 0:
        poles = _continue(q.replace(Kp=p.Kp), poles, "loop_time", p.loop_time, delay)
    return [Mode(label, complex(pole)) for label, pole in zip(pole_labels(p), poles, strict=True)]


def oil_column_mode(p: TableParameters, delay: str = "first-order") -> Mode:
    """The oil-column pole p4 (upper half plane) for any delay treatment.

    For ``"pade"`` and ``"sampled"`` it is the pole of that model nearest the
    first-order model's p4.
    """
    if delay in ("none", "first-order"):
        modes = labelled_poles(p, delay)
    else:
        modes = labelled_poles(p, "first-order")
    p4 = next(m for m in modes if m.label == "p4")
    p4 = Mode("p4", complex(p4.pole.real, abs(p4.pole.imag)))
    if delay in ("none", "first-order"):
        return p4
    poles = LinearTable(p, delay=delay).poles()
    return Mode("p4", complex(poles[np.argmin(np.abs(poles - p4.pole))]))


@dataclass(frozen=True)
class PoleSweep:
    """Poles tracked over a parameter sweep (a root locus).

    Attributes
    ----------
    name : str
        Swept parameter (``"Ke"`` [V/in], ``"Kp"`` [V/psi] or ``"loop_time"`` [s]).
    values : ndarray
        Parameter values, internal units.
    poles : ndarray, shape (len(values), 5)
        Poles [rad/s]; column j continues label ``labels[j]``.
    labels : tuple of str
    """

    name: str
    values: np.ndarray
    poles: np.ndarray
    labels: tuple[str, ...] = POLE_LABELS

    def modes(self, index: int) -> list[Mode]:
        """The labelled modes at ``values[index]``."""
        return [Mode(lbl, complex(pl)) for lbl, pl in zip(self.labels, self.poles[index])]


def sweep(p: TableParameters, name: str, values, delay: str = "first-order", steps: int = 4) -> PoleSweep:
    """Track the labelled poles while ``name`` takes ``values`` (others as in ``p``).

    Parameters
    ----------
    p : TableParameters
    name : {"Ke", "Kp", "loop_time"}
    values : array_like
        Increasing values in internal units ([V/in], [V/psi], [s]).
    delay : {"none", "first-order"}
    steps : int
        Continuation steps between consecutive values (more = safer tracking).
    """
    if name not in SWEEPABLE:
        raise ConfigError("sweep", "one of " + ", ".join(SWEEPABLE), name)
    values = np.asarray(values, dtype=float)
    if values.size == 0 or np.any(np.diff(values) < 0):
        raise ConfigError(name, "a non-empty increasing list of values", values.tolist())
    start = p.replace(**{name: float(values[0])})
    poles = np.array([m.pole for m in labelled_poles(start, delay)])
    rows = [poles]
    for a, b in zip(values[:-1], values[1:]):
        poles = _continue(p.replace(**{name: float(a)}), poles, name, float(b), delay, steps=steps)
        rows.append(poles)
    return PoleSweep(name, values, np.array(rows), pole_labels(p))


def _unstable(p: TableParameters, delay: str) -> bool:
    return not LinearTable(p, delay=delay).is_stable()


def stability_limit(
    p: TableParameters, name: str, upper: float, delay: str = "first-order", points: int = 200
) -> float | None:
    """Smallest value of ``name`` in (0, upper] at which the loop becomes unstable.

    Scans ``points`` values, then bisects to 1e-6 relative.  Returns None when
    the loop stays stable up to ``upper``.  (Report: K_e = 6.7 V/in with
    K_p = 0, tau = 0; K_p > 0.0035 V/psi with K_e = 5 V/in, tau = 0.)
    """
    if name not in SWEEPABLE:
        raise ConfigError("limit", "one of " + ", ".join(SWEEPABLE), name)
    grid = np.linspace(0.0, upper, points + 1)[1:]
    prev = 0.0
    for value in grid:
        if _unstable(p.replace(**{name: float(value)}), delay):
            lo, hi = prev, float(value)
            while hi - lo > 1e-6 * hi:
                mid = 0.5 * (lo + hi)
                lo, hi = (lo, mid) if _unstable(p.replace(**{name: mid}), delay) else (mid, hi)
            return hi
        prev = float(value)
    return None


def breakaway(
    p: TableParameters, name: str, upper: float, delay: str = "none", points: int = 200
) -> float | None:
    """Value of ``name`` at which the real poles p1 and p2 meet and become complex.

    (Report: K_e = 39.3 V/in with K_p = 0, tau = 0; K_p = 0.0006 V/psi with
    K_e = 5 V/in, tau = 0.)  Returns None when they stay real up to ``upper``.
    """

    def complex_pair(value: float) -> bool:
        modes = labelled_poles(p.replace(**{name: value}), delay)
        return abs(modes[0].pole.imag) > 1e-6 * abs(modes[0].pole)

    grid = np.linspace(0.0, upper, points + 1)[1:]
    prev = 0.0
    for value in grid:
        if complex_pair(float(value)):
            lo, hi = prev, float(value)
            while hi - lo > 1e-5 * hi:
                mid = 0.5 * (lo + hi)
                lo, hi = (lo, mid) if complex_pair(mid) else (mid, hi)
            return hi
        prev = float(value)
    return None


@dataclass(frozen=True)
class KpRecommendation:
    """K_p maximizing the oil-column damping for the given K_e and loop time.

    Attributes
    ----------
    Kp : float
        Recommended differential-pressure gain [V/psi].
    damping : float
        Oil-column damping ratio at that K_p [-].
    frequency_hz : float
        Oil-column frequency at that K_p [Hz].
    """

    Kp: float
    damping: float
    frequency_hz: float


def recommend_kp(p: TableParameters, delay: str = "first-order", upper: float = 0.005) -> KpRecommendation:
    """K_p [V/psi] that maximizes the oil-column (p4) damping, K_e and loop time as in ``p``.

    Report Section 4.4.3: about 0.001 V/psi for K_e = 5 V/in, tau = 0.
    """

    def negative_damping(kp: float) -> float:
        return -oil_column_mode(p.replace(Kp=float(kp)), delay).damping

    grid = np.linspace(0.0, upper, 26)
    values = [negative_damping(k) for k in grid]
    i = int(np.argmin(values))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    res = scipy_optimize.minimize_scalar(
        negative_damping, bounds=(lo, hi), method="bounded", options={"xatol": 1e-7}
    )
    mode = oil_column_mode(p.replace(Kp=float(res.x)), delay)
    return KpRecommendation(float(res.x), mode.damping, mode.frequency_hz)


@dataclass(frozen=True)
class DelayComparison:
    """Oil-column mode under each delay treatment at one loop time.

    Attributes
    ----------
    loop_time : float
        [s].
    first_order, pade, sampled : Mode
        p4 of the first-order (Eq 4-14a), Pade (exact ``e^{-s tau}``) and exact
        sampled-data (ZOH + one-loop delay) models.
    """

    loop_time: float
    first_order: Mode
    pade: Mode
    sampled: Mode

    def errors(self, reference: str = "pade") -> tuple[float, float]:
        """First-order minus reference: (damping error [-], relative frequency error [-])."""
        ref = self.pade if reference == "pade" else self.sampled
        return (
            self.first_order.damping - ref.damping,
            self.first_order.frequency_hz / ref.frequency_hz - 1.0,
        )


def compare_delay_models(p: TableParameters, loop_times) -> list[DelayComparison]:
    """Oil-column frequency and damping of the three delay treatments for each loop time [s]."""
    rows = []
    for tau in np.asarray(loop_times, dtype=float):
        if not tau > 0:
            raise ConfigError("loop_time", "positive loop times", float(tau))
        q = p.replace(loop_time=float(tau))
        rows.append(
            DelayComparison(
                float(tau),
                oil_column_mode(q, "first-order"),
                oil_column_mode(q, "pade"),
                oil_column_mode(q, "sampled"),
            )
        )
    return rows


def first_order_validity_limit(
    p: TableParameters,
    reference: str = "pade",
    damping_tolerance: float = 0.01,
    frequency_tolerance: float = 0.02,
    upper: float = 4e-3,
) -> float | None:
    """Longest loop time [s] for which the first-order delay model (Eq 4-13) is valid.

    Valid means its oil-column damping is within ``damping_tolerance``
    (absolute, default 0.01 = the report's printed precision) and its
    frequency within ``frequency_tolerance`` (relative, default 2 %) of the
    reference model: ``"pade"`` (the delay ``e^{-s tau}`` the approximation
    stands for) or ``"sampled"`` (the exact sampled-data loop, which adds the
    zero-order hold's half-loop lag).  Returns None when valid up to ``upper``.
    """
    if reference not in ("pade", "sampled"):
        raise ConfigError("reference", "pade or sampled", reference)

    def excess(tau: float) -> float:
        dz, df = compare_delay_models(p, [tau])[0].errors(reference)
        return max(abs(dz) / damping_tolerance, abs(df) / frequency_tolerance) - 1.0

    grid = np.linspace(upper / 40, upper, 40)
    prev = None
    for tau in grid:
        if excess(float(tau)) > 0:
            if prev is None:
                return 0.0
            return float(scipy_optimize.brentq(excess, prev, float(tau), xtol=1e-7))
        prev = float(tau)
    return None


def pole_rows(p: TableParameters, delay: str = "first-order", pade_order: int = 6) -> list[dict]:
    """Closed-loop poles as :func:`~impedance_mil.systems.pole_table` rows, labelled p1..p5 where the
    delay model has them (``none``, ``first-order``: the label of the nearest :func:`labelled_poles` pole)."""
    rows = pole_table(LinearTable(p, delay=delay, pade_order=pade_order).poles())
    if delay in ("none", "first-order"):
        labels = {complex(m.pole): m.label for m in labelled_poles(p, delay)}
        for row in rows:
            q = complex(row["real"], row["imag"])
            row["label"] = min(labels.items(), key=lambda kv: abs(kv[0] - q))[1]
    return rows


def pole_summary(
    p: TableParameters, delay: str = "first-order", pade_order: int = 6
) -> tuple[bool, list[dict]]:
    """``(stable, rows)`` of the closed loop with a delay model (rows as :func:`pole_rows`)."""
    return LinearTable(p, delay=delay, pade_order=pade_order).is_stable(), pole_rows(p, delay, pade_order)


#: Upper ends of the searches of :func:`tuning_summary`: K_e [V/in], K_p [V/psi] (stability),
#: K_p [V/psi] (break-away); beyond the report's table by an order of magnitude.
TUNING_SEARCH = {"Ke": 100.0, "Kp": 0.05, "Kp_breakaway": 0.01}


def tuning_summary(p: TableParameters) -> dict:
    """Stability limits, break-away points, the K_p maximizing oil-column damping (Section 4.4).

    ``*_analog*`` entries are for ``loop_time = 0`` (and ``K_p = 0`` where named), as the
    report's printed figures; every gain in V/in or V/psi, frequencies in Hz, the
    validity limit of the first-order delay model in s (None: valid up to its search limit).
    """
    analog = p.replace(loop_time=0.0)
    rec = recommend_kp(p)
    return {
        "Ke_limit_analog_Kp0": stability_limit(analog.replace(Kp=0.0), "Ke", TUNING_SEARCH["Ke"], "none"),
        "Ke_limit": stability_limit(p, "Ke", TUNING_SEARCH["Ke"]),
        "Kp_limit": stability_limit(p, "Kp", TUNING_SEARCH["Kp"]),
        "Ke_breakaway_analog_Kp0": breakaway(analog.replace(Kp=0.0), "Ke", TUNING_SEARCH["Ke"]),
        "Kp_breakaway_analog": breakaway(analog, "Kp", TUNING_SEARCH["Kp_breakaway"]),
        "recommended_Kp": rec.Kp,
        "recommended_oil_damping": rec.damping,
        "recommended_oil_frequency_hz": rec.frequency_hz,
        "first_order_delay_valid_up_to_s": first_order_validity_limit(p),
        "stable": LinearTable(p).is_stable(),
    }
