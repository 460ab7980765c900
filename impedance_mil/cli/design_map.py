"""``imil design --map-x ... --map-y ... --method both``: the two-method feasibility map (issue 15, item 5).

The map part of ``imil design``: parses the two axes, builds the VS of every
grid point from ``--vs`` (so that a bad value is refused before any solve),
runs :func:`~impedance_mil.design.feasibility_both.feasibility_map_both`, and
prints the map (``--json``: classes per point, axes, ``units`` block) and
writes its plot (``-o``, the format from the suffix).

An axis is ``NAME=VALUES``, ``VALUES`` a comma-separated list (``0.3,0.7,1.5``)
or ``LO:HI:N`` (``N`` evenly spaced values from ``LO`` to ``HI``).  ``NAME`` is

* ``mass_ratio``: the basemat mass over the table mass, ``m_vs/m_st`` (Section 9.4.4);
* ``period`` [s]: the isolation period of the VS's targets (SD: ``1/f``; LR, FP: ``T_s``);
* any other key of the VS (``--set-vs`` keys), in its unit (bare numbers: the report's unit).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..config import parse_overrides
from ..design import DesignCriteria, virtual_model
from ..design.feasibility_both import BothMethodsMap, MapAxis, MapPoint, feasibility_map_both
from ..design.forms import VirtualModel
from ..design.optimized import OptimizationSettings
from ..errors import ConfigError, ImilError
from ..plant import TableParameters
from ..report.feasibility_plots import plot_feasibility_map
from ..report.motion_plots import save_figure
from ..virtual.files import LABELS, UNITS, VSSpec, resolve
from .common import console, print_json

#: Most values on one axis (each point may take an optimized solve of 3-50 s).
MAX_AXIS_POINTS = 40

#: Plot formats ``-o`` takes in map mode.
PLOT_SUFFIXES = (".png", ".svg", ".pdf")


@dataclass(frozen=True)
class NamedAxis:
    """An axis the map knows by name, with its unit and plausible range.

    Attributes
    ----------
    unit : str
        Unit of the values (pint expression, ``"1"`` for a ratio).
    shown_unit : str
        The unit as messages write it (``""`` for a ratio).
    label : str
        Plot label with the unit.
    low, high : float
        Plausible range (in ``unit``); values outside are refused.
    reason : str
        Why the range is where it is.
    """

    unit: str
    shown_unit: str
    label: str
    low: float
    high: float
    reason: str


#: The named axes (any other name is a key of the VS).
NAMED_AXES: dict[str, NamedAxis] = {
    "mass_ratio": NamedAxis(
        "1",
        "",
        "basemat mass m_vs/m_st [-]",
        0.05,
        20.0,
        "report 1.25 (Table 9.1), Section 9.4.4 studies 0.4-1.25; below 0.05 or above 20 the "
        "basemat is negligible or the table is",
    ),
    "period": NamedAxis(
        "s",
        " s",
        "isolation period T [s]",
        0.1,
        20.0,
        "report 0.57-2.5 s (Tables 9.1-9.3); isolators have 1-5 s, 0.1 s is a stiff structure, 20 s none",
    ),
}


def parse_axis(option: str, text: str | None) -> tuple[str, tuple[float, ...]]:
    """``"mass_ratio=0.3:1.5:5"`` -> ``("mass_ratio", (0.3, 0.6, 0.9, 1.2, 1.5))``.

    Raises
    ------
    ConfigError
        Naming ``option``: no ``=``, an empty name or value list, a part that is not a
        finite number, repeated or more than :data:`MAX_AXIS_POINTS` values, or a named
        axis outside its plausible range (:data:`NAMED_AXES`).
    """
    form = "NAME=v1,v2,... or NAME=LO:HI:N (e.g. mass_ratio=0.3:1.5:5, period=1.5,2.5,4)"
    name, sep, spec = (text or "").partition("=")
    name, spec = name.strip(), spec.strip()
    if not sep or not name or not spec:
        raise ConfigError(option, form, text)
    values = _axis_values(option, spec, form)
    if len(set(values)) != len(values) or len(values) > MAX_AXIS_POINTS:
        raise ConfigError(option, f"distinct values, at most {MAX_AXIS_POINTS}", text)
    axis = NAMED_AXES.get(name)
    if axis is not None and not all(axis.low <= v <= axis.high for v in values):
        raise ConfigError(
            option,
            f"{name} values from {axis.low:g} to {axis.high:g}{axis.shown_unit} ({axis.reason})",
            text,
        )
    return name, tuple(sorted(values))


def _axis_values(option: str, spec: str, form: str) -> list[float]:
    try:
        if ":" in spec:
            lo, hi, n = spec.split(":")
            count = int(n)
            if count < 1:
                raise ValueError
            values = [float(v) for v in np.linspace(float(lo), float(hi), count)]
        else:
            values = [float(part) for part in spec.split(",")]
    except ValueError:
        raise ConfigError(option, form, spec) from None
    if not values or not all(math.isfinite(v) for v in values):
        raise ConfigError(option, form, spec)
    return values


def map_axis(option: str, name: str, values: tuple[float, ...]) -> MapAxis:
    """The :class:`MapAxis` of a parsed axis; a name neither named nor a VS key is refused."""
    if name in NAMED_AXES:
        axis = NAMED_AXES[name]
        return MapAxis(name, values, axis.unit, axis.label)
    if name not in UNITS:
        raise ConfigError(option, "mass_ratio, period or a VS key (" + ", ".join(sorted(UNITS)) + ")", name)
    unit = UNITS[name]
    shown = "-" if unit == "dimensionless" else unit.replace("force_pound", "lbf").replace(" ", "")
    return MapAxis(name, values, unit, f"{LABELS.get(name, name)}, {name} [{shown}]")


def _overrides(spec: VSSpec, option: str, name: str, value: float, table_mass: float) -> dict[str, float]:
    """The VS overrides (internal units) of one axis value."""
    if name == "mass_ratio":
        return {"m_vs": value * table_mass}
    if name == "period":
        fields = {f.name for f in spec.vstype.target_fields} if spec.vstype is not None else set()
        if spec.targets is None or not fields & {"f", "T_s"}:
            raise ConfigError(option, "a VS given by its targets (SD: f; LR, FP: T_s) for the period axis")
        return {"f": 1.0 / value} if "f" in fields else {"T_s": value}
    return {name: value}


@dataclass(frozen=True)
class MapRequest:
    """What ``imil design`` passes to :func:`run_map` (the options, parsed and checked)."""

    params: Any
    vs: str | None
    sets_vs: list[str] | None
    lin: dict[str, Any]
    amplitudes: list[float]
    fc_hz: float
    criteria: DesignCriteria
    settings: OptimizationSettings
    from_report: dict[str, Any]


def run_map(
    req: MapRequest, map_x: str, map_y: str | None, output: Path | None, json_out: bool, shown
) -> None:
    """Parse the axes, build every point's VS (refusing bad values before solving), run and show the map."""
    if map_y is None:
        raise ConfigError("--map-y", "a second axis with --map-x (NAME=VALUES)")
    if output is not None and output.suffix.lower() not in PLOT_SUFFIXES:
        raise ConfigError("-o", "a plot file (" + ", ".join(PLOT_SUFFIXES) + ") with --map-x", str(output))
    if not isinstance(req.params, TableParameters):
        raise ConfigError("--map-x", "a physical table (the optimized design needs its sampled-data model)")
    if req.vs is None:
        raise ConfigError("--vs", "a VS preset or file for the feasibility map")
    x_name, x_values = parse_axis("--map-x", map_x)
    y_name, y_values = parse_axis("--map-y", map_y)
    if x_name == y_name:
        raise ConfigError("--map-y", f"another parameter than --map-x's {x_name}", y_name)
    x = map_axis("--map-x", x_name, x_values)
    y = map_axis("--map-y", y_name, y_values)
    base = parse_overrides(req.sets_vs, option="--set-vs")
    options = {x_name: "--map-x", y_name: "--map-y"}
    models: dict[tuple[float, float], tuple[VirtualModel, Mapping[str, VirtualModel]]] = {}
    for yv in y.values:
        for xv in x.values:
            models[(xv, yv)] = _point_models(req, base, options, {x_name: xv, y_name: yv})
    fmap = feasibility_map_both(
        req.params,
        lambda **v: models[(v[x_name], v[y_name])][0],
        x,
        y,
        fc_hz=req.fc_hz,
        robust_for=lambda **v: models[(v[x_name], v[y_name])][1],
        criteria=req.criteria,
        settings=req.settings,
        progress=None if json_out else _print_point,
    )
    if output is not None:
        save_figure(
            plot_feasibility_map(fmap, title=f"{req.vs}: feasibility with both design methods"), output
        )
    if json_out:
        print_json({**fmap.to_dict(), "from_report": req.from_report}, shown)
        return
    _print_summary(fmap, output)


def _point_models(req: MapRequest, base, options: dict[str, str], values: dict[str, float]):
    """The design VS and its robust extras (LR/FP: the DF at each robust amplitude) at one point."""
    overrides = dict(base)
    probe = resolve(req.vs or "", base)
    m_st = float(req.params.mass)
    for name, value in values.items():
        overrides.update(_overrides(probe, options[name], name, value, m_st))
    try:
        spec = resolve(req.vs or "", overrides)
        vm = virtual_model(spec.vs, spec.name, **req.lin)
        robust = {}
        if vm.equivalent is not None:
            for a in req.amplitudes:
                robust[f"DF {a:g} in"] = virtual_model(spec.vs, spec.name, **{**req.lin, "amplitude_in": a})
    except ImilError as exc:
        where = " and ".join(f"{options[n]} {n}={v:g}" for n, v in values.items())
        raise ConfigError(where, "values that give a valid VS", str(exc)) from None
    return vm, robust


def _print_point(p: MapPoint) -> None:
    fc = "" if p.best_fc_hz is None or p.map_class != "filter" else f" (f_c {p.best_fc_hz:.4g} Hz)"
    opt = ""
    if p.optimized is not None:
        c = p.optimized.constraints
        opt = (
            f"; optimized: e_I {c.performance_error:.3f}, margin {c.passivity_margin_deg:.2f} deg, "
            f"certified {p.optimized.certified}, {p.optimized.wall_time_s:.1f} s"
        )
    console.print(f"  ({p.x:g}, {p.y:g}): {p.map_class}{fc}{opt}", markup=False, highlight=False)


def _print_summary(fmap: BothMethodsMap, output: Path | None) -> None:
    console.print(
        f"classes of {fmap.x.name} (columns) x {fmap.y.name} (rows); "
        f"{fmap.optimized_runs} optimized solves, the rest took the cheap path (filter feasible)",
        markup=False,
    )
    console.print(f"{'':>9s}" + "".join(f"{v:>16g}" for v in fmap.x.values), markup=False, highlight=False)
    for yv, row in zip(fmap.y.values, fmap.points):
        cells = "".join(f"{p.map_class:>16s}" for p in row)
        console.print(f"{yv:>9g}{cells}", markup=False, highlight=False)
    if output is not None:
        console.print(f"wrote {output}")


__all__ = ["NAMED_AXES", "MapRequest", "map_axis", "parse_axis", "run_map"]
