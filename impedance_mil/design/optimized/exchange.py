"""Exchange loop: solve on small grids, check on a dense grid, add the worst points, repeat.

A frequency-domain constraint imposed on a grid can fail between grid points
(a design 0.2 deg non-passive between points was seen); the loop therefore
checks every row on a dense grid (``check_per_decade`` points per decade,
2000 by default), adds the local maxima of the violation to the active grid
and solves again, until no dense row is violated by more than the tolerance.
The final answer is certified without a grid by :mod:`.certify`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .problem import GridSolution, Problem, Rows, rows_for, solve

#: Points added per row family and round (the largest local violations).
ADD_PER_ROUND = 20

#: Relative slack on the impedance-error bound t before a dense point counts as a violation of I.
OBJECTIVE_RTOL = 1e-3


def log_points(band_hz: tuple[float, float], per_decade: int) -> np.ndarray:
    """Log-spaced frequencies [Hz] over ``band_hz`` [Hz], ``per_decade`` per decade, ends included."""
    lo, hi = band_hz
    n = max(int(np.ceil(per_decade * np.log10(hi / lo))) + 1, 2)
    return np.logspace(np.log10(lo), np.log10(hi), n)


@dataclass(frozen=True)
class ExchangeResult:
    """Outcome of the exchange loop.

    Attributes
    ----------
    solution : GridSolution
        Last solution (``solution.ok`` False when a grid problem was infeasible).
    rounds : int
        Solves done.
    grid_points : int
        Active grid points at the end (all families).
    worst_violation : float
        Largest dense-grid violation of the last solution (dimensionless; <= tolerance when converged).
    converged : bool
        No dense-grid violation above the tolerance.
    wall_time_s : float
        Wall time of the loop [s].
    solver_time_s : float
        Sum of the solver's own times [s].
    """

    solution: GridSolution
    rounds: int
    grid_points: int
    worst_violation: float
    converged: bool
    wall_time_s: float
    solver_time_s: float


def dense_rows(problem: Problem, check_per_decade: int) -> list[Rows]:
    """Every constraint family of every model on the dense grid."""
    out = rows_for(problem, "I", problem.design_model, log_points(problem.band_hz, check_per_decade))
    f_ii = log_points(problem.effort_band_hz, check_per_decade)
    f_t = log_points(problem.transition_band_hz, check_per_decade)
    f_iii = log_points(problem.margin_band_hz, check_per_decade)
    seen_targets = set()
    for m in problem.models:
        out += rows_for(problem, "III", m, f_iii)
        if m.target_label not in seen_targets:
            seen_targets.add(m.target_label)
            out += rows_for(problem, "II", m, f_ii)
            out += rows_for(problem, "T", m, f_t)
    return out


def _subset(R: Rows, idx: np.ndarray) -> Rows:
    return Rows(R.kind, R.model, R.f_hz[idx], R.c[idx], R.M[idx], R.bound)


def _initial_index(R: Rows, per_decade: int) -> np.ndarray:
    span = np.log10(R.f_hz[-1] / R.f_hz[0])
    n = max(int(np.ceil(per_decade * span)) + 1, 2)
    return np.unique(np.round(np.linspace(0, R.f_hz.size - 1, n)).astype(int))


def _worst_points(v: np.ndarray, tol: float, k: int) -> np.ndarray:
    """Indices of up to ``k`` local maxima of ``v`` that exceed ``tol``."""
    bad = v > tol
    if not np.any(bad):
        return np.zeros(0, int)
    left = np.r_[-np.inf, v[:-1]]
    right = np.r_[v[1:], -np.inf]
    peaks = np.nonzero(bad & (v >= left) & (v >= right))[0]
    if peaks.size == 0:
        peaks = np.nonzero(bad)[0]
    return peaks[np.argsort(v[peaks])[::-1][:k]]


def _violations(R: Rows, sol: GridSolution, tol: float) -> tuple[np.ndarray, float]:
    if sol.x is None:
        return np.full(R.f_hz.size, np.inf), float("inf")
    v = R.violation(sol.x, sol.t)
    if R.kind == "I":
        v = v - OBJECTIVE_RTOL * max(sol.t, tol)
    return v, float(np.max(v))


def exchange(
    problem: Problem,
    dense: list[Rows],
    *,
    initial_per_decade: int,
    max_rounds: int,
    tolerance: float,
    t_max: float | None = None,
    last_resort: bool = False,
) -> ExchangeResult:
    """Run the exchange loop on ``problem`` against the dense rows ``dense``.

    Parameters
    ----------
    problem : Problem
    dense : list of Rows
        From :func:`dense_rows`.
    initial_per_decade : int
        Points per decade of the first active grids.
    max_rounds : int
        Solves before stopping unconverged.
    tolerance : float
        Accepted dense violation (dimensionless).
    t_max : float, optional
        Cap on the impedance error (trade-off search) passed to :func:`~.problem.solve`.
    last_resort : bool
        Let :func:`~.problem.solve` fall back to SCS.
    """
    start = time.perf_counter()
    active = [_initial_index(R, initial_per_decade) for R in dense]
    solver_time = 0.0
    sol = GridSolution("not_solved", None, float("nan"), 0.0)
    worst = float("inf")
    for rnd in range(1, max_rounds + 1):
        rows = [_subset(R, idx) for R, idx in zip(dense, active, strict=True)]
        trial = solve(problem, rows, t_max, last_resort)
        solver_time += 0.0 if np.isnan(trial.solve_time_s) else trial.solve_time_s
        if not trial.ok:  # keep the last good solution (unconverged) when a later round stalls
            return ExchangeResult(
                sol if sol.ok else trial,
                rnd,
                int(sum(a.size for a in active)),
                worst,
                False,
                time.perf_counter() - start,
                solver_time,
            )
        sol = trial
        worst, added = -np.inf, 0
        for i, R in enumerate(dense):
            v, vmax = _violations(R, sol, tolerance)
            worst = max(worst, vmax)
            new = _worst_points(v, tolerance, ADD_PER_ROUND)
            new = np.setdiff1d(new, active[i])
            if new.size:
                active[i] = np.union1d(active[i], new)
                added += new.size
        if added == 0:
            return ExchangeResult(
                sol,
                rnd,
                int(sum(a.size for a in active)),
                float(worst),
                True,
                time.perf_counter() - start,
                solver_time,
            )
    return ExchangeResult(
        sol,
        max_rounds,
        int(sum(a.size for a in active)),
        float(worst),
        False,
        time.perf_counter() - start,
        solver_time,
    )
