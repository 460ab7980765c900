"""`imil vs` commands: list, describe and plot the virtual isolation systems (report Sections 5, 9.2).

VS is a preset (SD1..SD3, LR1..LR3, FP1..FP3, Tables 9.1-9.3) or a VS file
(TOML with ``kind`` and values with units, see docs/virtual.md).  ``--set
KEY=VALUE`` changes a value (bare numbers in the report's unit, or strings
with units such as ``m_vs="2150 lb"``).

Exit status: 0 on success; 2 for bad input (one line on stderr, nothing written).
"""

from __future__ import annotations

import typer

from ..config import parse_overrides, quantity
from ..display import UnitSystem, display_unit, format_value
from ..lab.vs_loops import harmonic_input, recorded_input, vs_loops
from ..plant import TableParameters
from ..report.motion_plots import check_figure_path
from ..report.vs_plots import plot_loops, save_figure
from ..report_config import report_config
from ..units import G0, in_s2_to_g
from ..virtual import presets
from ..virtual.files import VSSpec, resolve
from ..virtual.files import describe as describe_spec
from .common import UnitsOpt, console, output_units, print_json
from .motion import UNITS_HELP, load_motion
from .runopts import err_console

app = typer.Typer(
    help="Virtual isolation systems: presets, properties, force-displacement loops.", no_args_is_help=True
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


def report_loop_time() -> float:
    """Loop time [s] of the report's table (Table 4.1, via the report's setup)."""
    return TableParameters.report_default().loop_time


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


@app.command("loops")
def loops(
    vs: list[str] = typer.Argument(..., help=VS_HELP + " Several give overlaid loops."),
    output: str = typer.Option(..., "-o", "--output", help="Figure file (.png, .pdf, .svg ...)."),
    amplitude: str = typer.Option(
        "0.3 g0", help="Peak of the harmonic ground acceleration (bare number: in/s^2; or '0.3 g0')."
    ),
    frequency: str = typer.Option("1.0", help="Frequency of the harmonic input [Hz]."),
    cycles: float = typer.Option(3.0, help="Cycles at full amplitude (after a half-cycle ramp)."),
    motion: str | None = typer.Option(
        None,
        help="Recorded ground motion instead of the harmonic input: built-in name or file (see imil motion).",
    ),
    pga: float | None = typer.Option(None, help="Scale the recorded motion to this PGA [g]."),
    motion_units: str | None = typer.Option(None, "--motion-units", help=UNITS_HELP),
    article_weight: str | None = typer.Option(
        None,
        help="Weight of the rigid test article on the basemat (default: the VS's w_ps, else the report's "
        f"article, {report_config().specimen.article_weight_lbf:g} lbf); '0' for the basemat alone.",
    ),
    dt: float | None = typer.Option(
        None, help="Integration step [s] (default the loop time of the report's table, Table 4.1)."
    ),
    normalize: bool = typer.Option(False, help="Plot shear force / axial load (Figure 9.1)."),
    sets: list[str] | None = typer.Option(None, "--set", help=SET_HELP),
    json_out: bool = typer.Option(False, "--json", help="Print the summary as JSON."),
    units: str | None = UnitsOpt,
) -> None:
    """Force-displacement loops of one or more VS for a harmonic or recorded ground motion."""
    shown = output_units(units)
    target = check_figure_path(output)
    step = quantity("--dt", dt if dt is not None else report_loop_time(), "second", "positive")
    weight = (
        None
        if article_weight is None
        else quantity("--article-weight", article_weight, "force_pound", "nonnegative")
    )
    # A preset carries the article given (its axial load: FP's w_ps), as in a run.
    specs = [resolve(name, parse_overrides(sets), weight) for name in vs]
    if motion is not None:
        loop_input = recorded_input(load_motion(motion, motion_units, pga=pga), step, motion)
    else:
        amp = quantity("--amplitude", amplitude, "inch / second**2", "positive")
        freq = quantity("--frequency", frequency, "hertz", "positive")
        loop_input = harmonic_input(amp, freq, cycles, step)
    for spec in specs:
        for note in spec.notes:
            err_console.print(f"imil: note: {note}", markup=False)
    loops = vs_loops(specs, loop_input, weight)
    responses = [loop.response for loop in loops]
    labels = [loop.spec.name for loop in loops]
    loads = [loop.axial_load for loop in loops]
    summary = [loop.summary() for loop in loops]
    input_text, step = loop_input.text, loop_input.dt
    fig = plot_loops(
        responses, labels, loads if normalize else None, title=f"Ground motion: {input_text}", units=shown
    )
    save_figure(fig, target)
    if json_out:
        print_json({"figure": str(target), "input": input_text, "dt": step, "systems": summary}, shown)
        return
    for row in summary:
        console.print(
            f"{row['name']}: peak displacement {format_value(row['peak_displacement'], 'inch', shown)}, "
            f"peak force {format_value(row['peak_force'], 'force_pound', shown)}, "
            f"peak z_vs {in_s2_to_g(row['peak_z_vs']):.3f} g, "
            f"dissipated {format_value(row['dissipated_energy'], 'force_pound * inch', shown)}"
        )
    console.print(f"wrote {target}")
