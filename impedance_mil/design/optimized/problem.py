"""The convex problem of the optimized design on finite frequency grids (cvxpy + Clarabel).

Unknowns: the coefficients of ``C_z`` and ``C_w`` on a :class:`~.basis.PoleBasis`
and the error bound ``t``.  On grids chosen by the exchange loop
(:mod:`.exchange`)::

    minimize    t  (+ effort_weight * e)
    subject to  |H_c/Z - 1| <= t                 band of interest, design model     (I)
                |C_w|, |C_z Z| <= beta G          f_s/10 .. f_s/2, every target      (II, per path)
                |C_w + C_z Z| <= min(beta, e) G    same band (II, sum)
                |C_w|, |C_z Z| <= gamma G         band top .. f_s/10 (transition)
                Re(exp(+-j delta) H_vw) >= 0      passivity band, every model        (III)
                a_2 = lim s**2/H_zu,  C_w(0) = -lim H_zw/H_zu                        (DC tracking exact)

``G`` is the in-band gain of the ideal ``w -> u`` path, ``beta`` the limit of
constraint II, ``delta`` the passivity margin [deg]: the phase of ``H_vw``
within ``+-(90 - delta)`` is the intersection of the two half-planes.  Every
row is scaled to be dimensionless (passivity rows by ``|Z/(j w)|``, the VS's
own ``H_vw``), and the coefficients by their column sizes.
"""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...bounds import MAX_GRID_PER_DECADE, check_count
from ...errors import ConfigError, MissingDependencyError
from ...lazy import LazyModule
from ...units import TWO_PI
from .basis import PoleBasis
from .models import LoopModel

#: cvxpy (the optional extra: pip install 'impedance-mil[optimize]'), None when not installed;
#: imported on first use (0.17 s, which every ``imil simulate`` paid through the lab's choices,
#: issue 16).  test_missing_solver sets it to None.
cp: Any = LazyModule("cvxpy") if importlib.util.find_spec("cvxpy") else None

#: Bound on the scaled coefficients: keeps the problem bounded where the grid alone would let
#: coefficients of cancelling terms grow without limit (the scaled filter design's are below 10).
COEFFICIENT_BOUND = 1e4

#: Clarabel settings tried in turn: its defaults (gap 1e-8), then a gap of 1e-6 when it stalls
#: ("insufficient progress" near the optimum of these badly scaled frequency-domain problems;
#: a relative gap of 1e-6 on e_I is far below what the constraints resolve).
#: SCS (first-order, installed with cvxpy) is the last resort of the trade-off search only.
SOLVER_ATTEMPTS: tuple[tuple[str, dict[str, Any]], ...] = (
    ("CLARABEL", {}),
    ("CLARABEL", {"tol_gap_abs": 1e-6, "tol_gap_rel": 1e-6, "tol_feas": 1e-7, "max_iter": 400}),
    ("CLARABEL", {"tol_gap_abs": 1e-5, "tol_gap_rel": 1e-5, "tol_feas": 1e-6, "max_iter": 400}),
    ("SCS", {"eps_abs": 1e-8, "eps_rel": 1e-8, "max_iters": 20000}),
)

#: Largest factor by which a passivity row is scaled up.
ROW_SCALE_MAX = 1e3

#: Message when the solver is missing.
MISSING_SOLVER = "the optimized design needs cvxpy and Clarabel: pip install 'impedance-mil[optimize]'"


def require_solver():
    """The cvxpy module, or :class:`MissingDependencyError` naming the extra to install."""
    if cp is None or "CLARABEL" not in cp.installed_solvers():
        raise MissingDependencyError(MISSING_SOLVER)
    return cp


def reduce_request(value: str | int) -> str | int:
    """``"none"``, ``"auto"`` or a positive order (an integer, or its text), checked."""
    text = str(value).strip().lower()
    if text in ("none", "auto"):
        return text
    try:
        order = int(text)
    except ValueError:
        order = 0
    if order < 1:
        raise ConfigError("reduce", "none, auto or a positive order (states of each path)", value)
    return order


@dataclass(frozen=True)
class OptimizationSettings:
    """Targets, bounds and grids of the optimized design.

    Parameters
    ----------
    margin_deg : float
        Passivity margin delta [deg]: the phase of ``H_vw`` must stay within
        ``+-(90 - delta)`` on every model of the robust set (III).
    passivity_band_hz : (float, float) or None
        Band of III [Hz]; default 0.01 Hz to the Nyquist frequency.  Its top
        may not exceed the Nyquist frequency.
    transition_gain_max : float
        Per-path gain bound between the band of interest and ``f_s/10``, as a
        multiple of the ideal in-band gain ``G`` (dimensionless).
    effort_weight : float
        Weight of the high-frequency summed gain in the objective (0: pure I).
    initial_per_decade : int
        Points per decade of the first grids of the exchange loop.
    check_per_decade : int
        Points per decade of the dense grid the exchange loop checks (both
        grids at most :data:`impedance_mil.bounds.MAX_GRID_PER_DECADE`).
    max_rounds : int
        Exchange rounds before giving up.
    tolerance : float
        Violation (dimensionless, of a scaled row) accepted on the dense grid.
    reduce : str or int
        Order reduction of the realization (:mod:`.realize`): ``"none"``,
        ``"auto"`` (the smallest orders that keep the verdicts of I, II, III
        and the certificate) or the order of each path (an integer, the
        double integrator of ``C_z`` counted).
    reduce_tolerance : float
        First relative path error tried by ``"auto"`` (dimensionless; then
        tenfold smaller until the verdicts are kept).
    """

    margin_deg: float = 0.0
    passivity_band_hz: tuple[float, float] | None = None
    transition_gain_max: float = 3.0
    effort_weight: float = 0.0
    initial_per_decade: int = 30
    check_per_decade: int = 2000
    max_rounds: int = 25
    tolerance: float = 1e-6
    reduce: str | int = "none"
    reduce_tolerance: float = 1e-3

    def __post_init__(self):
        # A cone wider than a half-plane (negative margin) is not convex: 0 <= delta.
        if not (np.isfinite(self.margin_deg) and 0.0 <= self.margin_deg < 45.0):
            raise ConfigError("margin", "a passivity margin in deg from 0 to 45", self.margin_deg)
        if self.passivity_band_hz is not None:
            lo, hi = (float(x) for x in self.passivity_band_hz)
            if not (0 < lo < hi and np.isfinite(hi)):
                raise ConfigError(
                    "margin_band", "two frequencies 0 < low < high in Hz", self.passivity_band_hz
                )
            object.__setattr__(self, "passivity_band_hz", (lo, hi))
        object.__setattr__(self, "reduce", reduce_request(self.reduce))
        for key in ("transition_gain_max", "tolerance", "reduce_tolerance"):
            if not float(getattr(self, key)) > 0:
                raise ConfigError(key, "a positive number", getattr(self, key))
        if not self.effort_weight >= 0:
            raise ConfigError("effort_weight", "a non-negative weight", self.effort_weight)
        for key in ("initial_per_decade", "check_per_decade", "max_rounds"):
            if int(getattr(self, key)) < 1:
                raise ConfigError(key, "a positive integer", getattr(self, key))
        for key in ("initial_per_decade", "check_per_decade"):
            check_count(key, getattr(self, key), MAX_GRID_PER_DECADE, "points per decade")

    def margin_band(self, nyquist_hz: float) -> tuple[float, float]:
        """The band of III [Hz]; refused above the Nyquist frequency ``nyquist_hz`` [Hz].

        Raises
        ------
        ConfigError
            The band's top lies above the Nyquist frequency.
        """
        band = self.passivity_band_hz or (0.01, nyquist_hz)
        if band[1] > nyquist_hz * (1 + 1e-12):
            raise ConfigError(
                "margin_band",
                f"a band below the Nyquist frequency {nyquist_hz:g} Hz of the loop",
                f"{band[0]:g}-{band[1]:g} Hz",
            )
        return band

    def to_dict(self) -> dict:
        return {
            "margin_deg": float(self.margin_deg),
            "passivity_band_hz": None if self.passivity_band_hz is None else list(self.passivity_band_hz),
            "transition_gain_max": float(self.transition_gain_max),
            "effort_weight": float(self.effort_weight),
            "initial_per_decade": int(self.initial_per_decade),
            "check_per_decade": int(self.check_per_decade),
            "max_rounds": int(self.max_rounds),
            "tolerance": float(self.tolerance),
            "reduce": self.reduce,
            "reduce_tolerance": float(self.reduce_tolerance),
        }


@dataclass(frozen=True)
class Problem:
    """Everything the grids need: basis, models, bands, targets and the DC equalities.

    Attributes
    ----------
    basis : PoleBasis
    design_model : LoopModel
        The model of the objective (first-order table, design target).
    models : tuple of LoopModel
        The robust set (III on each; II on each distinct target).
    band_hz, effort_band_hz, transition_band_hz, margin_band_hz : (float, float)
        Bands [Hz] of I, II, the transition bound and III.
    effort_gain : float
        ``G``, the ideal in-band gain of the ``w -> u`` path [in/lbf].
    effort_max : float
        ``beta`` (dimensionless).
    transition_max : float
        ``gamma`` (dimensionless).
    margin_deg : float
        ``delta`` [deg] (may be lowered by the trade-off search).
    a2 : float
        Required coefficient of ``1/s**2`` in ``C_z``.
    cw0 : float
        Required ``C_w(0)`` [in/lbf].
    effort_weight : float
    """

    basis: PoleBasis
    design_model: LoopModel
    models: tuple[LoopModel, ...]
    band_hz: tuple[float, float]
    effort_band_hz: tuple[float, float]
    transition_band_hz: tuple[float, float]
    margin_band_hz: tuple[float, float]
    effort_gain: float
    effort_max: float
    transition_max: float
    margin_deg: float
    a2: float
    cw0: float
    effort_weight: float = 0.0
    scale: np.ndarray = field(default_factory=lambda: np.ones(0))

    @property
    def n(self) -> int:
        return self.basis.n_z + self.basis.n_w

    def split(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Coefficients of ``C_z`` and ``C_w``."""
        return x[: self.basis.n_z], x[self.basis.n_z :]


@dataclass(frozen=True)
class Rows:
    """Affine rows ``c + M x`` of one kind on one grid, dimensionless.

    Attributes
    ----------
    kind : str
        ``"I"``, ``"III+"``, ``"III-"``, ``"II"`` (sum), ``"IIz"``, ``"IIw"``, ``"Tz"``, ``"Tw"``.
    model : str
        Model name.
    f_hz : ndarray
        Grid [Hz].
    c : ndarray
        Constant part (complex for norm rows, real for half-planes).
    M : ndarray
        Matrix on the (unscaled) coefficients.
    bound : float
        Norm bound of a norm row (``|c + M x| <= bound``), or 0 for a half-plane ``>= 0``.
    """

    kind: str
    model: str
    f_hz: np.ndarray
    c: np.ndarray
    M: np.ndarray
    bound: float

    def values(self, x: np.ndarray) -> np.ndarray:
        return self.c + self.M @ x

    def violation(self, x: np.ndarray, t: float) -> np.ndarray:
        """Positive where the row is violated (dimensionless)."""
        v = self.values(x)
        if self.kind.startswith("III"):
            return -np.real(v)
        limit = t if self.kind == "I" else self.bound
        return np.abs(v) - limit


#: Share of the VS's own passivity margin required where it is below delta (near DC, a damper's margin -> 0).
VS_MARGIN_SHARE = 0.5


def required_margin_deg(margin_deg: float, vs_vw: np.ndarray) -> np.ndarray:
    """Margin [deg] required at each frequency: ``delta``, or half the VS's own margin where that is smaller.

    A spring-damper's ``H_vw = s/(m s**2 + c s + k)`` has a margin
    ``atan(w c/k)`` that vanishes at DC (0.23 deg at 0.01 Hz for SD2), and
    exact DC tracking makes the controlled table follow it there; no
    controller can be more passive than the system it imitates.
    """
    own = 90.0 - np.abs(np.degrees(np.angle(vs_vw)))
    return np.minimum(margin_deg, VS_MARGIN_SHARE * np.maximum(own, 0.0))


def _blocks(problem: Problem, model: LoopModel, f: np.ndarray):
    r = model.responses(f)
    Pz = problem.basis.columns_z(r.s_controller)
    Pw = problem.basis.columns_w(r.s_controller)
    return r, Pz, Pw


def rows_for(problem: Problem, kind: str, model: LoopModel, f_hz: np.ndarray) -> list[Rows]:
    """The rows of one constraint family (``"I"``, ``"III"``, ``"II"``, ``"T"``) of one model on ``f_hz``."""
    f = np.atleast_1d(np.asarray(f_hz, dtype=float))
    r, Pz, Pw = _blocks(problem, model, f)
    col = lambda a: a[:, None]  # noqa: E731
    if kind == "I":
        c = r.P_zw / r.Z - 1.0
        M = np.hstack([col(r.P_zu) * Pz, col(r.P_zu / r.Z) * Pw])
        return [Rows("I", model.name, f, c, M, 0.0)]
    if kind == "III":
        vs_vw = r.Z / (1j * TWO_PI * f)
        ref = np.abs(vs_vw)
        delta = required_margin_deg(problem.margin_deg, vs_vw)
        out = []
        for sign, name in ((1.0, "III+"), (-1.0, "III-")):
            rot = np.exp(1j * sign * np.radians(delta)) / ref
            c = np.real(rot * r.P_vw)
            M = np.real(np.hstack([col(rot * r.P_vu * r.Z) * Pz, col(rot * r.P_vu) * Pw]))
            out.append(Rows(name, model.name, f, c, M, 0.0))
        return out
    G = problem.effort_gain
    zero_z, zero_w = np.zeros_like(Pz), np.zeros_like(Pw)
    path_z = np.hstack([col(r.Z) * Pz, zero_w]) / G
    path_w = np.hstack([zero_z, Pw]) / G
    c0 = np.zeros(f.size, complex)
    if kind == "II":
        beta = problem.effort_max
        return [
            Rows("II", model.name, f, c0, path_z + path_w, beta),
            Rows("IIz", model.name, f, c0, path_z, beta),
            Rows("IIw", model.name, f, c0, path_w, beta),
        ]
    gamma = problem.transition_max
    return [Rows("Tz", model.name, f, c0, path_z, gamma), Rows("Tw", model.name, f, c0, path_w, gamma)]


@dataclass(frozen=True)
class GridSolution:
    """The solver's answer on the current grids.

    Attributes
    ----------
    status : str
        cvxpy status (``optimal``, ``infeasible`` ...).
    x : ndarray or None
        Coefficients (``C_z`` then ``C_w``), unscaled.
    t : float
        Bound on the impedance error on the grid (dimensionless).
    solve_time_s : float
        Solver time [s].
    """

    status: str
    x: np.ndarray | None
    t: float
    solve_time_s: float

    @property
    def ok(self) -> bool:
        return self.status.split(" ")[0] in ("optimal", "optimal_inaccurate") and self.x is not None


def solve(
    problem: Problem, rows: list[Rows], t_max: float | None = None, last_resort: bool = False
) -> GridSolution:
    """Solve the problem on the rows.

    With ``t_max`` (the trade-off search) the impedance error is capped at
    ``t_max`` and the passivity rows are relaxed to ``>= -rho``; ``rho``, the
    largest normalized passivity deficit, is minimized and returned as ``t``.
    ``last_resort`` lets SCS try when every Clarabel setting fails.
    """
    cvx = require_solver()
    scale = problem.scale
    y = cvx.Variable(problem.n)
    t = cvx.Variable()
    e = cvx.Variable()
    rho = cvx.Variable(nonneg=True)
    cons = []
    x_of = lambda M: M * scale[None, :]  # noqa: E731  (x = scale * y)
    for R in rows:
        A = x_of(R.M)
        if R.kind.startswith("III"):
            # Rows the coefficients barely move (near DC the DC equalities fix H_vw) are
            # scaled up to unit size, so that the solver's equilibration does not stall on them.
            w = 1.0 / np.clip(np.max(np.abs(A), axis=1), 1.0 / ROW_SCALE_MAX, None)
            cons.append(A * w[:, None] @ y + R.c * w >= (-rho if t_max is not None else 0))
            continue
        re = np.real(A) @ y + np.real(R.c)
        im = np.imag(A) @ y + np.imag(R.c)
        X = cvx.vstack([re, im])
        if R.kind == "I":
            cons.append(cvx.SOC(t * np.ones(R.f_hz.size), X, axis=0))
        elif R.kind == "II":
            cons.append(cvx.SOC(e * np.ones(R.f_hz.size), X, axis=0))
            cons.append(e <= R.bound)
        else:
            cons.append(cvx.SOC(R.bound * np.ones(R.f_hz.size), X, axis=0))
    nz = problem.basis.n_z
    cons.append(cvx.norm(y, "inf") <= COEFFICIENT_BOUND)
    cons.append(y[0] * scale[0] == problem.a2)
    cons.append((problem.basis.dc_row_w() * scale[nz:]) @ y[nz:] == problem.cw0)
    objective = t + problem.effort_weight * e
    if t_max is not None:
        cons.append(t <= t_max)
        objective = rho
    prob = cvx.Problem(cvx.Minimize(objective), cons)
    used = "CLARABEL"
    for used, options in SOLVER_ATTEMPTS:
        if used == "SCS" and not last_resort:
            continue  # slow and inaccurate: only for the trade-off report of an infeasible design
        try:
            prob.solve(solver=used, **options)
            if y.value is not None:
                break
        except cvx.error.SolverError:
            continue
    else:
        return GridSolution("solver_error", None, float("nan"), float("nan"))
    st = prob.solver_stats.solve_time if prob.solver_stats is not None else float("nan")
    status = str(prob.status) + ("" if used == "CLARABEL" else f" ({used})")
    if y.value is None:
        return GridSolution(status, None, float("nan"), float(st or np.nan))
    value = float(rho.value) if t_max is not None else float(t.value)
    return GridSolution(status, np.asarray(y.value) * scale, value, float(st or np.nan))
