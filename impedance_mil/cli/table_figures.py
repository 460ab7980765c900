"""`imil table bode` and `imil table rlocus`: figures of the shake-table model (report Section 4).

Apart from the other ``imil table`` commands (``cli/table.py``, whose :data:`TABLE_COMMANDS
<impedance_mil.cli.table.TABLE_COMMANDS>` lists these two) because they import matplotlib:
``imil table info`` does not wait for it.
"""

from __future__ import annotations

from pathlib import Path

import typer

from ..display import UnitSystem
from ..plant.lti_table import LTITable
from ..report import table_plots
from ..report.motion_plots import check_figure_path
from .common import LabOpt, UnitsOpt, console, output_units, print_json, table_definition, table_parameters
from .table import DelayOpt, JsonOpt, SetOpt, TableOpt, delay_model


def _wrote(path: Path, as_json: bool, units: UnitSystem = UnitSystem.US) -> None:
    """Report a written file: ``{"file": ...}`` with ``--json``, else ``wrote PATH``."""
    if as_json:
        print_json({"file": str(path)}, units)
    else:
        console.print(f"wrote {path}", markup=False)


def bode(
    table: Path | None = TableOpt,
    lab: str | None = LabOpt,
    set: list[str] | None = SetOpt,
    json: bool = JsonOpt,
    delay: str = DelayOpt,
    out: Path = typer.Option(Path("table-bode.png"), "-o", "--out", help="PNG file."),
    fmin: float = typer.Option(0.1, "--fmin", help="Lowest frequency [Hz]."),
    fmax: float = typer.Option(200.0, "--fmax", help="Highest frequency [Hz]."),
    units: str | None = UnitsOpt,
) -> None:
    """Bode plots of the six transfer functions (PNG, magnitudes in --units us|si); an LTI table's paths."""
    p = table_definition(table, set, lab)
    delay = delay_model(delay, p)
    check_figure_path(out, "-o")
    shown = output_units(units, lab, table)
    if isinstance(p, LTITable):
        written = table_plots.save_lti_bode(p, out, fmin=fmin, fmax=fmax, units=shown)
    else:
        written = table_plots.save_bode(p, out, delay=delay, fmin=fmin, fmax=fmax, units=shown)
    _wrote(written, json, shown)


def rlocus(
    table: Path | None = TableOpt,
    lab: str | None = LabOpt,
    set: list[str] | None = SetOpt,
    json: bool = JsonOpt,
    param: str = typer.Option("Ke", "--param", help="Ke, Kp or loop_time."),
    upper: float | None = typer.Option(None, "--max", help="Largest value (internal units)."),
    out: Path = typer.Option(Path("table-rlocus.png"), "-o", "--out", help="PNG file."),
    units: str | None = UnitsOpt,
) -> None:
    """Root locus of the five poles for a K_e, K_p or loop-time sweep (PNG; poles in rad/s)."""
    p = table_parameters(table, set, lab)
    _wrote(table_plots.save_root_locus(p, param, out, upper=upper), json, output_units(units, lab, table))
