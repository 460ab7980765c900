"""`imil export`: discretize a design and write C, IEC 61131-3 ST, JSON or CSV (report Sections 6.5, 7).

    imil export DESIGN.json --format c --precision single --prefix imil -o out/
    imil export --table table.toml --vs SD2 --fc 80 --format st -o out/
    imil export DESIGN.json --stroke "3 in" --max-rate "40 in/s" -o out/
    imil export DESIGN.json --io-units si -o out/          (reads m/s**2 and N, writes mm)

The generated C and ST carry a safety layer (``implement.safety``): a clamp to
the stroke and a rate limit on the command, from the design's table (its
mid-stroke and the valve's velocity capacity) unless ``--stroke`` and
``--max-rate`` say otherwise (at most the table's), input and overflow guards
and a fault word.

``--io-units`` (default the lab file's ``[controller] io_units`` with
``--lab``, else ``us``) sets the units the generated code reads and writes:
``us`` (in/s^2, lbf, in; the code without scaling), ``si`` (m/s**2, N, mm) or
``accel=UNIT,force=UNIT,disp=UNIT`` (:mod:`impedance_mil.implement.io_units`).

Designing here uses the report's controller form and filter (``[design]`` of
the report's setup file); ``--precision`` defaults to the report's.

Exit status 0 on success; 2 for bad input (one line on stderr), and then no
output directory is left behind.
"""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import typer

from ..design import design_controller, load_design, table_model, virtual_model
from ..errors import ConfigError, DataFileError, ImilError
from ..implement.export import FORMATS, controller_from_design, designed_vs, render, write_directory
from ..implement.io_units import IOUnits
from ..implement.safety import command_limits
from ..lab.labfile import load_lab
from ..report_config import report_config
from ..virtual.files import resolve
from .common import LabOpt, console, table_definition


def _design(design_file, table, vs, fc, lab=None):
    if design_file is not None:
        if table is not None or fc is not None:
            raise ConfigError("--table/--fc", "either a design file or --table/--fc, not both")
        return load_design(design_file)
    if fc is None:
        raise ConfigError("DESIGN", "a design file, or --fc [Hz] (with --table, --vs) to design one")
    spec = resolve(vs) if vs else None
    vm = virtual_model(spec.vs, spec.name) if spec is not None else None
    return design_controller(
        table_model(table_definition(table, None, lab)),
        vm,
        fc_hz=fc,
        emit_warnings=False,
    )


#: Keys of the errors that are about an option, not about the design's content.
_OPTION_KEYS = ("prefix", "precision")


@contextmanager
def _naming(design_file: Path | None):
    """An error in what the design file holds names the file (errors about options do not)."""
    try:
        yield
    except DataFileError:
        raise
    except ImilError as exc:
        key = getattr(exc, "key", "")
        if design_file is None or key.startswith("-") or key in _OPTION_KEYS:
            raise
        raise DataFileError(design_file, str(exc)) from None


def export(
    design_file: Path | None = typer.Argument(None, metavar="DESIGN", help="Design file (JSON)."),
    fmt: str = typer.Option("c", "--format", help="c | st | json | csv."),
    precision: str | None = typer.Option(
        None,
        "--precision",
        help=f"single | double (default the report's {report_config().controller.precision}).",
    ),
    prefix: str = typer.Option("imil", "--prefix", help="Identifier prefix of the generated code."),
    output: Path = typer.Option(..., "-o", "--output", help="Output directory (created)."),
    table: Path | None = typer.Option(None, "--table", help="Table file (TOML) to design from."),
    lab: str | None = LabOpt,
    vs: str | None = typer.Option(None, "--vs", help="VS preset or file (MIL step)."),
    fc: float | None = typer.Option(None, "--fc", help="Cut-off [Hz] when designing here."),
    loop_time: float | None = typer.Option(None, "--loop-time", help="Check: loop time [s]."),
    method: str = typer.Option("tustin", "--method", help="tustin | zoh | matched."),
    prewarp: float | None = typer.Option(None, "--prewarp", help="Tustin pre-warp [Hz]."),
    leak: float | None = typer.Option(None, "--leak-hz", help="Leak replacing the double integrator [Hz]."),
    stroke: str | None = typer.Option(
        None, "--stroke", help="Command clamp, e.g. '3 in' (default: the design table's mid-stroke)."
    ),
    max_rate: str | None = typer.Option(
        None,
        "--max-rate",
        help="Command rate limit, e.g. '40 in/s' (default: the valve's velocity capacity).",
    ),
    io_units: str | None = typer.Option(
        None,
        "--io-units",
        help="Units the code reads and writes: us (in/s^2, lbf, in), si (m/s**2, N, mm) or "
        "accel=UNIT,force=UNIT,disp=UNIT (default: the --lab file's, else us).",
    ),
    force: bool = typer.Option(False, "--force", help="Replace an existing output directory."),
) -> None:
    """Export a discretized MIL controller as C, IEC 61131-3 ST, JSON or CSV."""
    if fmt not in FORMATS:
        raise ConfigError("--format", "one of " + ", ".join(FORMATS), fmt)
    if io_units is not None:
        io = IOUnits.parse(io_units, "--io-units")
    else:
        io = load_lab(lab).controller.io_units if lab is not None else IOUnits.internal()
    design = _design(design_file, table, vs, fc, lab)
    spec = resolve(vs) if vs is not None else None
    precision = report_config().controller.precision if precision is None else precision
    with _naming(design_file):
        controller = controller_from_design(
            design, loop_time_s=loop_time, method=method, prewarp_hz=prewarp, leak_hz=leak
        )
        chosen = designed_vs(design, spec.vs if spec else None, spec.name if spec else "")
        vs_obj = chosen.vs if fmt in ("c", "st") else None
        summary = f"{design.form} form, fc {design.fc_hz:g} Hz" + (
            f", VS {chosen.name} ({chosen.vs.kind})" if vs_obj is not None else ""
        )
        limits = (
            command_limits(design.table, stroke=stroke, max_rate=max_rate, capacity=design.capacity)
            if fmt in ("c", "st")
            else None
        )
        files = render(
            controller, fmt, precision, prefix, vs=vs_obj, design_summary=summary, limits=limits, io_units=io
        )
    out = write_directory(files, output, force=force)
    console.print(f"wrote {', '.join(sorted(files))} to {out}")
    if not io.is_internal:
        console.print(f"I/O units {io.spec}: {io.describe()}")
    if chosen.note:
        console.print(f"note: {chosen.note}")
    elif fmt in ("c", "st") and vs_obj is None:
        console.print("note: the design has no virtual system: the code has no MIL step (--vs adds one)")
