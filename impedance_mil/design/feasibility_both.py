"""Feasibility map with both design methods: the report's "virtual systems that cannot be imitated".

Section 9.4.4 maps where the filter design of Section 6.4 works; Section 10.4
names optimization as the way past its limits.  :func:`feasibility_map_both`
puts the two side by side on a grid of two VS parameters and classifies
each point as

* ``"filter"``: some cut-off on the scan of :func:`~.feasibility.choose_fc`
  satisfies I, II and III (the optimization is then skipped: the cheap path);
* ``"optimized only"``: the filter design fails, and
  :func:`~.optimized.design_optimized` meets I, II and III with its grid-free
  passivity certificate;
* ``"neither"``: no design of either method imitates that VS on this table.

>>> MAP_CLASSES
('filter', 'optimized only', 'neither')
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from ..errors import ImilError, MissingDependencyError
from ..plant import TableParameters
from .adapters import table_model
from .constraints import ConstraintResult, DesignCriteria
from .controller import ControllerDesign
from .feasibility import choose_fc
from .forms import TableModel, VirtualModel
from .optimized import OptimizationSettings, design_optimized

#: The classes of a point, in the order of the plot's legend.
MAP_CLASSES = ("filter", "optimized only", "neither")
FILTER, OPTIMIZED_ONLY, NEITHER = MAP_CLASSES

#: Unit of ``passivity_index``, ``min Re(1/H_vw)`` (equivalent damping).
PASSIVITY_INDEX_UNIT = "force_pound * second / inch"

#: Why a point has no optimized design although it was not refused.
CHEAP_PATH = "not run: the filter design already meets I, II and III (the cheap path)"


@dataclass(frozen=True)
class MapAxis:
    """One parameter axis of the map.

    Attributes
    ----------
    name : str
        Parameter name passed to the VS factory (e.g. ``mass_ratio``, ``period``).
    values : tuple of float
        Grid values, in ``unit``.
    unit : str
        Unit of the values (pint expression; ``"1"`` for a ratio).
    label : str
        Axis label for the plot, with the unit (e.g. ``"m_vs/m_st [-]"``).
    """

    name: str
    values: tuple[float, ...]
    unit: str
    label: str

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "label": self.label, "unit": self.unit, "values": list(self.values)}


@dataclass(frozen=True)
class OptimizedOutcome:
    """What :func:`~.optimized.design_optimized` achieved at one point.

    Attributes
    ----------
    meets_all : bool
        Feasible, certified and I, II, III satisfied: the point is imitable by optimization.
    feasible, certified : bool
        The solver's verdict and the grid-free passivity certificate (``design.optimization``).
    constraints : ConstraintResult
        I, II, III of the optimized controller (``passivity_margin_deg`` [deg] on the
        first-order model, ``passivity_margin_sampled_deg`` [deg] on the sampled-data one).
    binding : str or None
        The constraint that binds when infeasible (III or I).
    passivity_deficit : float or None
        Best trade-off when infeasible: the smallest normalized passivity deficit at the
        allowed e_I (dimensionless, 0 = passive).
    wall_time_s : float
        Time of the solve [s].
    """

    meets_all: bool
    feasible: bool
    certified: bool
    constraints: ConstraintResult
    binding: str | None
    passivity_deficit: float | None
    wall_time_s: float

    @classmethod
    def of(cls, design: ControllerDesign) -> OptimizedOutcome:
        report = design.optimization or {}
        c = design.constraints[0]
        feasible, certified = bool(report.get("feasible")), bool(report.get("certified"))
        trade = report.get("best_tradeoff") or {}
        return cls(
            meets_all=feasible and certified and c.all_satisfied,
            feasible=feasible,
            certified=certified,
            constraints=c,
            binding=report.get("binding"),
            passivity_deficit=trade.get("passivity_deficit"),
            wall_time_s=float(report.get("wall_time_s", float("nan"))),
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "meets_all": self.meets_all,
            "feasible": self.feasible,
            "certified": self.certified,
            "binding": self.binding,
            "passivity_deficit": self.passivity_deficit,
            "wall_time_s": self.wall_time_s,
            "constraints": self.constraints.to_dict(),
        }


@dataclass(frozen=True)
class MapPoint:
    """The verdict at one grid point.

    Attributes
    ----------
    x, y : float
        Parameter values (units of the map's axes).
    map_class : str
        One of :data:`MAP_CLASSES`.
    filter_feasible_fc_hz : (float, float) or None
        Widest run of feasible cut-offs of the filter scan [Hz].
    best_fc_hz : float or None
        The cut-off :func:`~.feasibility.choose_fc` picks [Hz] (feasible for class
        ``"filter"``, else the least bad one); None when the filter design was refused.
    filter_constraints : ConstraintResult or None
        I, II, III of the filter design at ``best_fc_hz``.
    optimized : OptimizedOutcome or None
        None when not run (see ``note``).
    note : str
        Why the optimization was skipped, or why a design was refused ("" otherwise).
    """

    x: float
    y: float
    map_class: str
    filter_feasible_fc_hz: tuple[float, float] | None
    best_fc_hz: float | None
    filter_constraints: ConstraintResult | None
    optimized: OptimizedOutcome | None
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        lo_hi = self.filter_feasible_fc_hz
        return {
            "x": self.x,
            "y": self.y,
            "class": self.map_class,
            "filter": {
                "feasible_fc_hz": None if lo_hi is None else [float(v) for v in lo_hi],
                "best_fc_hz": self.best_fc_hz,
                "constraints": None if self.filter_constraints is None else self.filter_constraints.to_dict(),
            },
            "optimized": None if self.optimized is None else self.optimized.to_dict(),
            "note": self.note,
        }


@dataclass(frozen=True)
class BothMethodsMap:
    """Class of every point of a two-parameter VS grid (see the module docstring).

    Attributes
    ----------
    x, y : MapAxis
    points : tuple of tuple of MapPoint
        ``points[i][j]`` at ``y.values[i]``, ``x.values[j]``.
    reference_fc_hz : float
        Reference cut-off of the optimized design's basis [Hz].
    """

    x: MapAxis
    y: MapAxis
    points: tuple[tuple[MapPoint, ...], ...]
    reference_fc_hz: float

    @property
    def classes(self) -> np.ndarray:
        """Class names, shape ``(len(y.values), len(x.values))``."""
        return np.array([[p.map_class for p in row] for row in self.points], dtype=object)

    @property
    def optimized_runs(self) -> int:
        """Number of optimized designs solved (points where the filter design failed)."""
        return sum(p.optimized is not None for row in self.points for p in row)

    def to_dict(self) -> dict[str, Any]:
        """The ``imil design --map-x ... --json`` document, with its ``units`` block (internal units)."""
        flat = [p for row in self.points for p in row]
        units = {f"points[{k}].x": self.x.unit for k in range(len(flat))}
        units.update({f"points[{k}].y": self.y.unit for k in range(len(flat))})
        for k in range(len(flat)):  # names the unit registry does not know under this path
            units[f"points[{k}].optimized.passivity_deficit"] = "1"
            for method in ("filter", "optimized"):
                units[f"points[{k}].{method}.constraints.passivity_index"] = PASSIVITY_INDEX_UNIT
        units["optimized_runs"] = "1"
        return {
            "method": "both",
            "x": self.x.to_dict(),
            "y": self.y.to_dict(),
            "classes": list(MAP_CLASSES),
            "class_grid": [[p.map_class for p in row] for row in self.points],
            "class_grid_layout": "class_grid[i][j] at y.values[i], x.values[j]",
            "reference_fc_hz": self.reference_fc_hz,
            "optimized_runs": self.optimized_runs,
            "points": [p.to_dict() for p in flat],
            "units": units,
        }


def feasibility_map_both(
    params: TableParameters,
    vs_for: Callable[..., VirtualModel],
    x: MapAxis,
    y: MapAxis,
    *,
    fc_hz: float,
    robust_for: Callable[..., Mapping[str, VirtualModel]] | None = None,
    fc_grid_hz: Sequence[float] | None = None,
    criteria: DesignCriteria | None = None,
    settings: OptimizationSettings | None = None,
    progress: Callable[[MapPoint], None] | None = None,
) -> BothMethodsMap:
    """Classify a grid of VS parameters as filter-feasible, optimized-only or neither.

    Parameters
    ----------
    params : TableParameters
        The table (Table 4.1); the optimized design needs the physical table.
    vs_for : callable
        ``vs_for(**{x.name: xv, y.name: yv})`` -> VirtualModel, the values in the axes' units.
    x, y : MapAxis
        The two parameter axes.
    fc_hz : float
        Reference cut-off of the optimized design [Hz] (the report's is
        ``report_config().design.fc_hz``).
    robust_for : callable, optional
        ``robust_for(**{x.name: xv, y.name: yv})`` -> mapping of further VS models for
        the optimized design's robust set (``robust_vs`` of ``design_optimized``).
    fc_grid_hz : sequence of float, optional
        Cut-offs [Hz] of the filter scan; default :func:`~.feasibility.default_fc_grid`.
    criteria : DesignCriteria, optional
        Thresholds of I and II, shared by both methods.
    settings : OptimizationSettings, optional
        Settings of the optimized design.
    progress : callable, optional
        Called with each :class:`MapPoint` when it is done (the library prints nothing).

    Returns
    -------
    BothMethodsMap

    Notes
    -----
    The filter design is the standardized form (the form the optimized design
    has), scanned with :func:`~.feasibility.choose_fc`; the optimization runs
    only where it fails.  A point whose VS or designs are refused (an
    :class:`~impedance_mil.errors.ImilError`) is ``"neither"`` with the reason
    in its note.  The certificate covers the first-order model with the VS's
    rational impedance (see docs/design.md, "Optimized design").

    Examples
    --------
    See docs/design.md, "Feasibility map with both methods".
    """
    tm = table_model(params)
    solve = _Solver(params, tm, fc_hz, fc_grid_hz, criteria, settings)
    rows = []
    for yv in y.values:
        row = []
        for xv in x.values:
            values = {x.name: float(xv), y.name: float(yv)}
            blank = MapPoint(float(xv), float(yv), NEITHER, None, None, None, None)
            point = solve.classify(blank, partial(vs_for, **values), partial(_robust, robust_for, values))
            if progress is not None:
                progress(point)
            row.append(point)
        rows.append(tuple(row))
    return BothMethodsMap(x, y, tuple(rows), float(fc_hz))


def _robust(robust_for, values: dict[str, float]) -> Mapping[str, VirtualModel]:
    return robust_for(**values) if robust_for is not None else {}


@dataclass(frozen=True)
class _Solver:
    """The two designs of one point, with the map's table and settings."""

    params: TableParameters
    tm: TableModel
    fc_hz: float
    fc_grid_hz: Sequence[float] | None
    criteria: DesignCriteria | None
    settings: OptimizationSettings | None

    def classify(self, blank: MapPoint, vs: Callable[[], VirtualModel], robust) -> MapPoint:
        """``blank`` (a ``"neither"`` point at its x, y) filled in: filter scan first, optimization if needed."""
        try:
            vm, extra = vs(), robust()
        except MissingDependencyError:
            raise
        except ImilError as exc:
            return dataclasses.replace(blank, note=f"VS refused: {exc}")
        point, notes = blank, []
        try:
            choice = choose_fc(self.tm, vm, self.fc_grid_hz, form="standardized", criteria=self.criteria)
        except MissingDependencyError:
            raise
        except ImilError as exc:
            notes.append(f"filter design refused: {exc}")
        else:
            point = dataclasses.replace(
                blank,
                filter_feasible_fc_hz=choice.scan.feasible_fc_hz,
                best_fc_hz=float(choice.fc_hz),
                filter_constraints=next(r for r in choice.scan.results if r.fc_hz == choice.fc_hz),
            )
            if choice.feasible:
                return dataclasses.replace(point, map_class=FILTER, note=CHEAP_PATH)
        try:
            design = design_optimized(
                self.params,
                vm,
                fc_hz=self.fc_hz,
                robust_vs=extra,
                criteria=self.criteria,
                settings=self.settings,
            )
        except MissingDependencyError:
            raise
        except ImilError as exc:
            return dataclasses.replace(point, note="; ".join([*notes, f"optimized design refused: {exc}"]))
        outcome = OptimizedOutcome.of(design)
        if outcome.feasible and not outcome.certified:
            notes.append("optimized design feasible on its grids but not certified (a finer --grid may help)")
        return dataclasses.replace(
            point,
            map_class=OPTIMIZED_ONLY if outcome.meets_all else NEITHER,
            optimized=outcome,
            note="; ".join(notes),
        )


__all__ = [
    "CHEAP_PATH",
    "MAP_CLASSES",
    "BothMethodsMap",
    "MapAxis",
    "MapPoint",
    "OptimizedOutcome",
    "feasibility_map_both",
]
