"""`imil report RUN.h5 -o run.html`: the self-contained HTML page of one run.

The page (``report.html.render_run_html``) shows the run's status (and the
safety limit that stopped it, if one did), its metrics, the acceleration
histories of table, target and input, their 5 %-damped response spectra,
the isolator's force-displacement loop (MIL runs) and the full
configuration.  Figures are embedded, there is no script, and the page
fetches nothing.

The metrics are those ``imil simulate`` / ``imil track`` stored in the file;
for other run files (e.g. a campaign's ``run.h5``) they are recomputed with
``lab.metrics.evaluate_run`` (without the energy error, which needs the VS
model).

Exit status: 0 on success; 2 for bad input (not a run file, an existing
output without ``--overwrite``), with one line on stderr and nothing written.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import typer

from ..errors import ConfigError, DataFileError
from ..lab.metrics import evaluate_run, vs_force_history
from ..lab.results import RunResult, load_run
from ..report.html import RunView, render_run_html, write_html
from .common import console
from .runopts import output_path, read_summary, run_summary

#: Summary entries shown in the page's metrics table, in this order.
PAGE_METRICS = (
    "simulated_s",
    "aborted",
    "abort_reason",
    "spectral_error_0p25_15hz",
    "spectral_error_15_50hz",
    "nrms_error",
    "peak_error",
    "energy_error",
    "peak_table_accel_g",
    "peak_target_accel_g",
    "peak_table_disp_in",
    "f_oil_hz",
    "omega_oil_rad_s",
    "zeta_oil",
    "d",
    "model_error_0p25_100hz",
)

#: Names of the stored VS model loop (group ``MODEL_LOOP`` of the run file's ``imil`` group).
MODEL_LOOP = "vs_model_loop"
MODEL_LOOP_KEYS = ("displacement_in", "force_lbf")

#: Shortest run with metrics [s] (lab.experiments computes none below 1 s).
MIN_METRICS_S = 1.0


def basemat_mass(run: RunResult) -> float | None:
    """m_vs [lbf*s^2/in] of a MIL run's VS (for the isolator loop), else None."""
    vs = run.config.get("vs") if run.mode == "mil" else None
    value = vs.get("m_vs") if isinstance(vs, Mapping) else None
    return float(value) if value is not None else None


def model_loop(run: RunResult, vs) -> dict:
    """The VS model's own isolator loop along the run (displacement [in], force [lbf]), for the page."""
    return {MODEL_LOOP_KEYS[0]: run.vs_states[:, 0], MODEL_LOOP_KEYS[1]: vs_force_history(vs, run.vs_states)}


def write_report(
    run: RunResult,
    summary: Mapping[str, Any],
    path: Path,
    title: str = "",
    loop: Mapping[str, Any] | None = None,
) -> Path:
    """Render the run page of ``run`` with the metrics of ``summary`` and write it atomically.

    ``loop`` (see :func:`model_loop`) adds the VS model's force-displacement
    loop, dashed red, to the table's (report Figures 9-2 to 9-28, panel c).
    """
    metrics = {key: summary[key] for key in PAGE_METRICS if summary.get(key) is not None}
    model = (loop[MODEL_LOOP_KEYS[0]], loop[MODEL_LOOP_KEYS[1]]) if loop else None
    view = RunView.from_result(run, title=title, metrics=metrics, m_vs=basemat_mass(run), model_loop=model)
    return write_html(path, render_run_html(view))


def recomputed_summary(run: RunResult) -> dict:
    """Summary of a run file without a stored one: lab metrics against ``z_vs`` (no energy error)."""
    metrics = None
    if run.mode in ("track", "mil") and run.n_samples * run.loop_time >= MIN_METRICS_S:
        metrics = evaluate_run(run)
    return run_summary(run, metrics)


def report(
    run_file: Path = typer.Argument(
        ..., metavar="RUN.h5", help="Run file written by imil simulate/track/frf or a campaign."
    ),
    output: Path = typer.Option(..., "-o", "--output", help="HTML file to write."),
    title: str = typer.Option("", "--title", help="Page title (default: mode and motion)."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace an existing output file."),
) -> None:
    """Write the self-contained HTML report of one run."""
    if not run_file.is_file():
        raise DataFileError(run_file, "no such run file")
    out = output_path("-o", output, overwrite)
    if out.resolve() == run_file.resolve():
        raise ConfigError("-o", "a path other than the run file", str(output))
    run = load_run(run_file)
    summary, arrays = read_summary(run_file)
    write_report(run, summary or recomputed_summary(run), out, title, arrays.get(MODEL_LOOP))
    console.print(f"wrote {out}", markup=False)
