"""`imil vs` commands: list, describe and plot the virtual isolation systems (report Sections 5, 9.2).

VS is a preset (SD1..SD3, LR1..LR3, FP1..FP3, Tables 9.1-9.3) or a VS file
(TOML with ``kind`` and values with units, see docs/virtual.md).  ``--set
KEY=VALUE`` changes a value (bare numbers in the report's unit, or strings
with units such as ``m_vs="2150 lb"``).

Exit status: 0 on success; 2 for bad input (one line on stderr, nothing written).
"""

from __future__ import annotations

from types import MappingProxyType

import typer

from ..config import parse_overrides
from ..display import UnitSystem, display_unit, format_value
from ..lazy import lazy_attributes
from ..units import G0
from ..virtual import presets
from ..virtual.files import VSSpec, resolve
from ..virtual.files import describe as describe_spec
from .common import UnitsOpt, console, output_units, print_json
from .main import LazyCommand, LazyGroup

#: The commands of ``imil vs``, in the order its help lists them: ``loops`` lives in
#: ``cli/vs_figures.py`` and imports the loop simulation and matplotlib only when it runs
#: (docs/architecture.md, "The lazy command registry").
VS_COMMANDS: MappingProxyType[str, LazyCommand] = MappingProxyType(
    {
        "list": LazyCommand(
            "impedance_mil.cli.vs:list_presets",
            "List the presets (Tables 9.1-9.3 and those of the other types) with their targets or "
            "parameters.",
        ),
        "describe": LazyCommand(
            "impedance_mil.cli.vs:describe",
            "All properties of a VS (targets, parameters, derived values) with units.",
        ),
        "loops": LazyCommand(
            "impedance_mil.cli.vs_figures:loops",
            "Force-displacement loops of one or more VS for a harmonic or recorded ground motion.",
        ),
    }
)


#: ``impedance_mil.cli.vs.loops`` read from ``cli/vs_figures.py`` (PEP 562).
__getattr__ = lazy_attributes(__name__, "impedance_mil.cli.vs_figures", ("loops",))


class VSGroup(LazyGroup):
    """``imil vs``: the commands of :data:`VS_COMMANDS`, each imported when first used."""

    registry = VS_COMMANDS


app = typer.Typer(
    cls=VSGroup,
    help="Virtual isolation systems: presets, properties, force-displacement loops.",
    no_args_is_help=True,
)

VS_HELP = "Preset (" + ", ".join(presets.names()) + ") or a VS file (TOML)."
SET_HELP = "Change a value: KEY=VALUE (bare number in the report's unit, or with a unit: 'u_y=10 mm')."

#: Short display form of the internal units.
_SHORT_UNITS = {
    "force_pound * second**2 / inch": "lbf*s^2/in",
    "force_pound": "lbf",
    "force_pound / inch": "lbf/in",
    "force_pound * second / inch": "lbf*s/in",
    "inch": "in",
    "hertz": "Hz",
    "second": "s",
    "second / inch": "s/in",
    "dimensionless": "-",
}


def _spec(vs: str, sets: list[str] | None) -> VSSpec:
    return resolve(vs, parse_overrides(sets))


@app.command("list")
def list_presets(
    json_out: bool = typer.Option(False, "--json", help="Print JSON."), units: str | None = UnitsOpt
) -> None:
    """List the presets (Tables 9.1-9.3 and those of the other types) with their targets or parameters."""
    rows = [presets.listing(name) for name in presets.names()]
    shown = output_units(units)
    if json_out:
        print_json(rows, shown)
        return
    for row in rows:
        keys = ("f", "zeta", "q_ratio", "mu_max", "mu_min", "T_s", "mu1", "mu2", "mu4", "R1", "R2")
        text = ", ".join(f"{k}={row[k]:.4g}" for k in keys if k in row)
        stiffness = f"  k_s={row['k_s']:.1f} lbf/in" if row.get("k_s") is not None else ""
        console.print(f"{row['name']:4s} {row['kind']:3s}  {text}{stiffness}")


@app.command("describe")
def describe(
    vs: str = typer.Argument(..., help=VS_HELP),
    sets: list[str] | None = typer.Option(None, "--set", help=SET_HELP),
    json_out: bool = typer.Option(False, "--json", help="Print JSON (values in internal units)."),
    units: str | None = UnitsOpt,
) -> None:
    """All properties of a VS (targets, parameters, derived values) with units."""
    shown = output_units(units)
    spec = _spec(vs, sets)
    props = describe_spec(spec)
    if json_out:
        data = {"name": spec.name, "kind": spec.vs.kind}
        data.update({p.key: p.value for p in props})
        data["units"] = {p.key: p.unit for p in props}  # internal units, for print_json
        print_json(data, shown)
        return
    console.print(f"{spec.name}: {spec.vs.kind} virtual system")
    for p in props:
        weight = format_value(p.value * G0, "force_pound", shown) if p.key in ("m_vs", "m_ps") else ""
        extra = f"  (weight {weight})" if weight else ""
        unit = display_unit(p.unit, shown) if shown is UnitSystem.SI else None
        value, name = (
            (unit(p.value), unit.name) if unit is not None else (p.value, _SHORT_UNITS.get(p.unit, p.unit))
        )
        console.print(f"  {p.label:45s} {p.key:9s} {value:12.6g} {name}{extra}")
