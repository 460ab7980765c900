"""`imil report RUN.h5 -o run.html`: the self-contained HTML page of one run.

The page (``report.html.render_run_html``) shows the run's status (and the
safety limit that stopped it, if one did), its metrics, the acceleration
histories of table, target and input, their 5 %-damped response spectra,
the isolator's force-displacement loop (MIL runs) and the full
configuration.  Figures are embedded, there is no script, and the page
fetches nothing.

The metrics are those the run's producer (``imil simulate``/``track``/``frf``,
a campaign) stored in the file (:mod:`impedance_mil.lab.runfile`); for a run
file without them they are recomputed with ``lab.metrics.evaluate_run``
(without the energy error, which needs the VS model).  The page is the
library's (:mod:`impedance_mil.report.runpage`).

Exit status: 0 on success; 2 for bad input (not a run file, an existing
output without ``--overwrite``), with one line on stderr and nothing written.
"""

from __future__ import annotations

from pathlib import Path

import typer

from ..errors import ConfigError, DataFileError
from ..report.runpage import run_page
from .common import UnitsOpt, console, output_units
from .runopts import output_path


def report(
    run_file: Path = typer.Argument(
        ..., metavar="RUN.h5", help="Run file written by imil simulate/track/frf or a campaign."
    ),
    output: Path = typer.Option(..., "-o", "--output", help="HTML file to write."),
    title: str = typer.Option("", "--title", help="Page title (default: mode and motion)."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace an existing output file."),
    units: str | None = UnitsOpt,
) -> None:
    """Write the self-contained HTML report of one run (in --units us|si)."""
    shown = output_units(units)
    if not run_file.is_file():
        raise DataFileError(run_file, "no such run file")
    output_path("-o", output, overwrite)
    if output.resolve() == run_file.resolve():
        raise ConfigError("-o", "a path other than the run file", str(output))
    run_page(run_file, output, title, shown)
    console.print(f"wrote {output}", markup=False)
