"""The HTML page of one run, from the run and its summary (``imil report``, ``simulate --report``).

The page shows the metrics of the run's summary (:data:`PAGE_METRICS`, the
shared names of :mod:`impedance_mil.lab.runfile`), the histories and spectra
of :class:`~impedance_mil.report.html.RunView` and, for a MIL run, the VS
model's own isolator loop next to the table's.  :func:`run_page` reads a run
file and renders it with its stored summary, or with metrics recomputed when
the file has none.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..display import UnitSystem
from ..lab.results import RunResult, load_run
from ..lab.runfile import MODEL_LOOP, MODEL_LOOP_KEYS, basemat_mass, read_summary, recomputed_summary
from .html import RunView, render_run_html, write_html

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


def write_run_page(
    run: RunResult,
    summary: Mapping[str, Any],
    path: str | Path,
    title: str = "",
    loop: Mapping[str, Any] | None = None,
    units: UnitSystem = UnitSystem.US,
) -> Path:
    """Render the page of ``run`` with the metrics of ``summary`` and write it atomically.

    ``loop`` (:func:`impedance_mil.lab.runfile.model_loop`) adds the VS model's
    force-displacement loop, dashed red, to the table's (report Figures 9-2 to
    9-28, panel c).  The page shows ``units``; the run stays in internal units.
    """
    metrics = {key: summary[key] for key in PAGE_METRICS if summary.get(key) is not None}
    model = (loop[MODEL_LOOP_KEYS[0]], loop[MODEL_LOOP_KEYS[1]]) if loop else None
    view = RunView.from_result(
        run, title=title, metrics=metrics, m_vs=basemat_mass(run), model_loop=model, units=units
    )
    return write_html(path, render_run_html(view))


def run_page(
    run_file: str | Path, path: str | Path, title: str = "", units: UnitSystem = UnitSystem.US
) -> Path:
    """The page of a run file: its stored summary and VS loop, or metrics recomputed without one.

    Raises
    ------
    DataFileError
        Not a run file, or an unreadable summary.
    """
    run = load_run(run_file)
    summary, arrays = read_summary(run_file)
    return write_run_page(run, summary or recomputed_summary(run), path, title, arrays.get(MODEL_LOOP), units)
