"""`imil vs loops`: force-displacement loops of virtual isolation systems (report Section 9.2, Figure 9.1).

Apart from ``imil vs list`` and ``describe`` (``cli/vs.py``, whose :data:`VS_COMMANDS
<impedance_mil.cli.vs.VS_COMMANDS>` lists it) because it runs the systems and draws the
loops (numba kernels, matplotlib): ``imil vs list`` does not wait for them.
"""

from __future__ import annotations

import typer

from ..config import parse_overrides, quantity
from ..display import format_value
from ..lab.vs_loops import harmonic_input, recorded_input, vs_loops
from ..plant import TableParameters
from ..report.motion_plots import check_figure_path
from ..report.vs_plots import plot_loops, save_figure
from ..report_config import report_config
from ..units import in_s2_to_g
from ..virtual.files import resolve
from .common import UnitsOpt, console, output_units, print_json
from .motion import UNITS_HELP, load_motion
from .runopts import err_console
from .vs import SET_HELP, VS_HELP


def report_loop_time() -> float:
    """Loop time [s] of the report's table (Table 4.1, via the report's setup)."""
    return TableParameters.report_default().loop_time


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
