"""Design aids: feasible cut-off range, automatic cut-off, basemat-mass study, feasibility map.

Section 9.4.3 shows that constraint I fails for a low cut-off, II for a
high one, and III where the filter's phase lag makes the controlled table
active; the cut-offs that satisfy all three form a range (100-250 Hz for
SD2, Table 9.5).  Section 9.4.4 shows the range shrinking, and vanishing,
as the VS basemat mass drops below the table mass.  These functions
compute that range on a grid of cut-offs and map it over VS parameters:
"can this table imitate that isolator, and with which f_c?".
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError, ImilError
from ..systems import TransferFunction
from .constraints import ConstraintResult, DesignCriteria
from .controller import design_at_fc, report_design_choices
from .coupled import CoupledStability, coupled_stability
from .forms import TableModel, VirtualModel, environment, ideal_controller
from .sampling import implementable_fc

#: Default grid of cut-offs [Hz]: 30 log-spaced points from 20 Hz to the Nyquist frequency.
DEFAULT_FC_POINTS = 30
DEFAULT_FC_LOW_HZ = 20.0


@dataclass(frozen=True)
class FcScan:
    """Constraints on a grid of cut-offs.

    Attributes
    ----------
    results : tuple of ConstraintResult
        One per cut-off, ascending.
    feasible_fc_hz : (float, float) or None
        Widest contiguous run of grid cut-offs that satisfy I, II and III [Hz].
    """

    results: tuple[ConstraintResult, ...]
    feasible_fc_hz: tuple[float, float] | None

    @property
    def fc_hz(self) -> np.ndarray:
        return np.array([r.fc_hz for r in self.results])


@dataclass(frozen=True)
class FcChoice:
    """An automatically chosen cut-off with its reasons.

    Attributes
    ----------
    fc_hz : float
        Chosen cut-off [Hz].
    feasible : bool
        True when it satisfies all three constraints.
    reasons : tuple of str
        Why this cut-off, in words.
    scan : FcScan
    """

    fc_hz: float
    feasible: bool
    reasons: tuple[str, ...]
    scan: FcScan


@dataclass(frozen=True)
class MassRatioCase:
    """One basemat mass in the study of Section 9.4.4.

    Attributes
    ----------
    mass_ratio : float
        m_vs/m_st (dimensionless).
    feasible_fc_hz : (float, float) or None
        Feasible cut-offs [Hz]; None when no cut-off on the grid works.
    scan : FcScan
    design_fc_hz : float or None
        The cut-off of the design checked below [Hz] (the report's 80 Hz).
    at_design_fc : ConstraintResult or None
        Constraints at ``design_fc_hz``; its III is the robust verdict (any passive article).
    coupled : tuple of CoupledStability
        Closed-loop stability at ``design_fc_hz`` with each given article (specimen-specific).
    """

    mass_ratio: float
    feasible_fc_hz: tuple[float, float] | None
    scan: FcScan
    design_fc_hz: float | None = None
    at_design_fc: ConstraintResult | None = None
    coupled: tuple[CoupledStability, ...] = ()

    def to_dict(self) -> dict:
        """The ``mass_ratio_study`` entry of ``imil design --json``."""
        out = {
            "mass_ratio": self.mass_ratio,
            "feasible_fc_hz": None
            if self.feasible_fc_hz is None
            else [float(x) for x in self.feasible_fc_hz],
        }
        if self.at_design_fc is not None:
            r = self.at_design_fc
            out.update(
                {
                    "design_fc_hz": self.design_fc_hz,
                    "passive_at_design_fc": bool(r.III),
                    "passivity_margin_deg": r.passivity_margin_deg,
                    "passivity_tolerant_margin_deg": r.passivity_tolerant_margin_deg,
                    "passivity_worst_hz": r.passivity_worst_hz,
                    "coupled": [c.to_dict() for c in self.coupled],
                }
            )
        return out


@dataclass(frozen=True)
class FeasibilityMap:
    """Feasible cut-off range over a grid of two VS parameters.

    Attributes
    ----------
    x_name, y_name : str
        Parameter names.
    x, y : ndarray
        Parameter values (internal units).
    fc_low_hz, fc_high_hz : ndarray, shape (len(y), len(x))
        Feasible range [Hz]; NaN where none (or where the design is refused).
    """

    x_name: str
    x: np.ndarray
    y_name: str
    y: np.ndarray
    fc_low_hz: np.ndarray
    fc_high_hz: np.ndarray

    @property
    def feasible(self) -> np.ndarray:
        """Boolean grid: some cut-off satisfies all constraints."""
        return np.isfinite(self.fc_low_hz)


def default_fc_grid(table: TableModel, points: int = DEFAULT_FC_POINTS) -> np.ndarray:
    """Log-spaced cut-offs [Hz] from 20 Hz to the Nyquist frequency of the loop (1000 Hz if analog)."""
    return np.logspace(np.log10(DEFAULT_FC_LOW_HZ), np.log10(table.nyquist_hz), points)


def scan_fc(
    table: TableModel,
    vs: VirtualModel | None,
    fc_grid_hz: Sequence[float] | None = None,
    *,
    form: str | None = None,
    family: str | None = None,
    order: int | None = None,
    criteria: DesignCriteria | None = None,
) -> FcScan:
    """Evaluate the three constraints on a grid of cut-offs.

    Parameters
    ----------
    table : TableModel
    vs : VirtualModel or None
        None (or form ``tracking``): acceleration tracking.
    fc_grid_hz : sequence of float, optional
        Cut-offs [Hz]; default :func:`default_fc_grid`.
    form, family, order, criteria
        As for :func:`~impedance_mil.design.design_controller`.
    """
    form, family = report_design_choices(form, family)
    env = environment(form, vs)
    ideal = ideal_controller(form, table, env)
    grid = np.sort(np.asarray(default_fc_grid(table) if fc_grid_hz is None else fc_grid_hz, float))
    results = [
        design_at_fc(table, env, ideal, float(fc), criteria, family=family, order=order).constraints
        for fc in grid
    ]
    return FcScan(tuple(results), _widest_run(results))


def _widest_run(results: Sequence[ConstraintResult]) -> tuple[float, float] | None:
    best, start = None, None
    for i, r in enumerate([*results, None]):
        ok = r is not None and r.all_satisfied
        if ok and start is None:
            start = i
        if not ok and start is not None:
            if best is None or i - start > best[1] - best[0]:
                best = (start, i)
            start = None
    if best is None:
        return None
    return (results[best[0]].fc_hz, results[best[1] - 1].fc_hz)


def choose_fc(
    table: TableModel,
    vs: VirtualModel | None,
    fc_grid_hz: Sequence[float] | None = None,
    *,
    form: str | None = None,
    family: str | None = None,
    order: int | None = None,
    criteria: DesignCriteria | None = None,
) -> FcChoice:
    """Choose the cut-off automatically (``imil design --fc auto``).

    Only grid cut-offs that the implementation accepts are candidates
    (:func:`~impedance_mil.design.sampling.implementable_fc`: below the
    Nyquist frequency, the rule ``imil export`` applies).  Among the feasible cut-offs, the one that balances the two opposing
    constraints: it maximises ``min(log(e_I,max/e_I), log(e_II,max/e_II))``,
    the smaller of the relative slacks of performance (which wants a high
    f_c) and control effort (which wants a low one).  When no cut-off is
    feasible, the one with the largest passivity margin among those that
    satisfy I, else the best balance overall, is returned with ``feasible``
    False.

    Returns
    -------
    FcChoice
    """
    c = criteria or DesignCriteria()
    scan = scan_fc(table, vs, fc_grid_hz, form=form, family=family, order=order, criteria=c)
    # Only a cut-off the implementation accepts (below the Nyquist frequency) is proposed.
    rs = [r for r in scan.results if implementable_fc(r.fc_hz, table.loop_time_s)]
    if not rs:
        raise ConfigError(
            "fc_grid_hz",
            f"a cut-off below the Nyquist frequency {table.nyquist_hz:g} Hz of the loop",
            f"{scan.results[0].fc_hz:.4g}-{scan.results[-1].fc_hz:.4g} Hz",
        )

    def balance(r: ConstraintResult) -> float:
        s1 = np.log(c.performance_max / max(r.performance_error, 1e-300))
        s2 = np.log(c.effort_ratio_max / max(r.effort_ratio, 1e-300))
        return float(min(s1, s2))

    feasible = [r for r in rs if r.all_satisfied]
    if feasible:
        best = max(feasible, key=balance)
        lo, hi = scan.feasible_fc_hz
        reasons = (
            f"constraints I, II, III hold for fc in [{lo:.4g}, {hi:.4g}] Hz on a {len(scan.results)}-point grid",
            f"fc = {best.fc_hz:.4g} Hz balances performance (error {best.performance_error:.3f} of "
            f"{c.performance_max:.3f} allowed) against control effort (ratio {best.effort_ratio:.3g} of "
            f"{c.effort_ratio_max:.3g} allowed)",
            f"passivity margin {best.passivity_margin_deg:.2f} deg "
            f"({best.passivity_tolerant_margin_deg:.2f} deg after the delay-model tolerance)",
        )
        return FcChoice(best.fc_hz, True, reasons, scan)
    ok_I = [r for r in rs if r.I]
    best = max(ok_I, key=lambda r: r.passivity_tolerant_margin_deg) if ok_I else max(rs, key=balance)
    reasons = (
        f"no cut-off on the grid {rs[0].fc_hz:.4g}-{rs[-1].fc_hz:.4g} Hz satisfies I, II and III",
        f"fc = {best.fc_hz:.4g} Hz is the least bad: " + "; ".join(best.violations()),
    )
    return FcChoice(best.fc_hz, False, reasons, scan)


def mass_ratio_study(
    table: TableModel,
    vs_for_mass: Callable[[float], VirtualModel],
    ratios: Sequence[float],
    fc_grid_hz: Sequence[float] | None = None,
    *,
    form: str | None = None,
    criteria: DesignCriteria | None = None,
    design_fc_hz: float | None = None,
    specimens: Mapping[str, TransferFunction] | None = None,
) -> tuple[MassRatioCase, ...]:
    """Feasible cut-offs as the basemat mass changes (Section 9.4.4), and coupled stability.

    Parameters
    ----------
    table : TableModel
    vs_for_mass : callable
        ``vs_for_mass(m_vs)`` -> VirtualModel, with ``m_vs`` [lbf*s**2/in]
        (e.g. ``lambda m: virtual_model(presets.get("SD2", m_vs=m))``).
    ratios : sequence of float
        m_vs/m_st values.
    fc_grid_hz : sequence of float, optional
    form, criteria
        As for :func:`scan_fc`.
    design_fc_hz : float, optional
        A cut-off [Hz] at which to report the passivity verdict (robust: any
        passive article) and, for each of ``specimens``, the closed-loop
        stability (:func:`~impedance_mil.design.coupled.coupled_stability`).
    specimens : mapping of str to TransferFunction, optional
        Article impedances ``w/z`` [lbf per in/s**2] by label, e.g.
        ``{"vessel 36 in": FluidVessel(36).impedance()}``.
    """
    form, family = report_design_choices(form, None)
    m_st = _table_mass(table)
    out = []
    for ratio in ratios:
        vs = vs_for_mass(float(ratio) * m_st)
        scan = scan_fc(table, vs, fc_grid_hz, form=form, family=family, criteria=criteria)
        at, coupled = None, ()
        if design_fc_hz is not None:
            env = environment(form, vs)
            design = design_at_fc(
                table, env, ideal_controller(form, table, env), float(design_fc_hz), criteria, family=family
            )
            at = design.constraints
            coupled = tuple(
                coupled_stability(design.controlled.H_c, Z, label) for label, Z in (specimens or {}).items()
            )
        out.append(MassRatioCase(float(ratio), scan.feasible_fc_hz, scan, design_fc_hz, at, coupled))
    return tuple(out)


def feasibility_map(
    table: TableModel,
    vs_for: Callable[..., VirtualModel],
    x_name: str,
    x_values: Sequence[float],
    y_name: str,
    y_values: Sequence[float],
    fc_grid_hz: Sequence[float] | None = None,
    *,
    form: str | None = None,
    criteria: DesignCriteria | None = None,
) -> FeasibilityMap:
    """Feasible cut-off range over a grid of two VS parameters ("can this table imitate that isolator?").

    Parameters
    ----------
    table : TableModel
    vs_for : callable
        ``vs_for(**{x_name: x, y_name: y})`` -> VirtualModel.
    x_name, y_name : str
        Parameter names passed to ``vs_for``.
    x_values, y_values : sequence of float
        Values (internal units).
    fc_grid_hz, form, criteria
        As for :func:`scan_fc`.

    Notes
    -----
    A parameter pair whose design is refused (an unstable VS, say) is marked
    infeasible rather than aborting the map.
    """
    x = np.asarray(x_values, float)
    y = np.asarray(y_values, float)
    lo = np.full((y.size, x.size), np.nan)
    hi = np.full((y.size, x.size), np.nan)
    for i, yv in enumerate(y):
        for j, xv in enumerate(x):
            try:
                scan = scan_fc(
                    table,
                    vs_for(**{x_name: float(xv), y_name: float(yv)}),
                    fc_grid_hz,
                    form=form,
                    criteria=criteria,
                )
            except ImilError:
                continue
            if scan.feasible_fc_hz is not None:
                lo[i, j], hi[i, j] = scan.feasible_fc_hz
    return FeasibilityMap(x_name, x, y_name, y, lo, hi)


def _table_mass(table: TableModel) -> float:
    """Table mass m_st [lbf*s**2/in]: from the parameters, else from ``H_zw(inf) = 1/m_st``."""
    m = table.parameters.get("mass") if table.parameters else None
    if m:
        return float(m)
    H = table.H_zw
    return float(H.den[0] / H.num[0]) if H.relative_degree == 0 else float("nan")
