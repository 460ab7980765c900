"""The HTML page of an evaluated recording, with a virtual-lab prediction overlaid (``imil evaluate --report``).

The same page as a virtual run's (:func:`impedance_mil.report.runpage.write_run_page`),
plus, with a prediction: its table acceleration as a history, its isolator loop
(``w - m_vs z`` against ``x - x_g``, dotted green) beside the measured and the VS
model's loops, and a table of prediction against measurement for every metric.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from ..display import UnitSystem
from ..lab.results import RunResult
from ..lab.runfile import MODEL_LOOP_KEYS, basemat_mass
from ..signals.motion import integrate_piecewise_linear
from .documents import express
from .html import ForceDisplacement, RunView, escape, fmt_number, render_run_html, write_html
from .runpage import PAGE_METRICS


def comparison_table(comparison: Mapping[str, Mapping[str, Any]], units: UnitSystem = UnitSystem.US) -> str:
    """``<table>`` of measured, predicted and difference for each metric (in ``units``)."""
    comparison = {k: v for k, v in express(comparison, units).items() if k not in ("units", "unit_system")}
    rows = "".join(
        f"<tr><td>{escape(key)}</td><td>{fmt_number(v['measured'])}</td><td>{fmt_number(v['predicted'])}</td>"
        f"<td>{fmt_number(v['difference'])}</td></tr>"
        for key, v in comparison.items()
    )
    head = "<tr><th>metric</th><th>measured</th><th>predicted</th><th>measured - predicted</th></tr>"
    return f"<h2>Prediction against measurement</h2><table>{head}{rows}</table>"


def _prediction_loop(prediction: RunResult, m_vs: float) -> ForceDisplacement | None:
    ch = prediction.channels
    if not all(k in ch for k in ("w_used", "x_meas", "a_g", "z_meas")) or prediction.n_samples < 2:
        return None
    _, x_g = integrate_piecewise_linear(ch["a_g"], prediction.loop_time)
    return ForceDisplacement(
        "prediction: w - m_vs z, x - x_g", ch["x_meas"] - x_g, ch["w_used"] - m_vs * ch["z_meas"], "other"
    )


def write_evaluation_page(
    run: RunResult,
    summary: Mapping[str, Any],
    path: str | Path,
    *,
    loop: Mapping[str, Any] | None = None,
    prediction: RunResult | None = None,
    comparison: Mapping[str, Mapping[str, Any]] | None = None,
    title: str = "",
    units: UnitSystem = UnitSystem.US,
) -> Path:
    """Render the evaluation of a recording (and a prediction) in ``units`` and write it atomically."""
    metrics = {key: summary[key] for key in PAGE_METRICS if summary.get(key) is not None}
    model = (loop[MODEL_LOOP_KEYS[0]], loop[MODEL_LOOP_KEYS[1]]) if loop else None
    m_vs = basemat_mass(run)
    view = RunView.from_result(
        run,
        title=title or f"evaluation of {summary.get('recording', {}).get('file', 'a recording')}",
        metrics=metrics,
        m_vs=m_vs,
        model_loop=model,
        units=units,
    )
    sections = []
    if prediction is not None:
        n = run.n_samples
        z = np.full(n, np.nan)
        k = min(n, prediction.n_samples)
        z[:k] = prediction.channels["z_meas"][:k]
        histories = {**view.histories, "table acceleration, prediction": (z, "in/s^2")}
        loops = view.loops
        extra = _prediction_loop(prediction, m_vs) if m_vs is not None else None
        if extra is not None:
            loops = (*loops, extra)
        view = replace(view, histories=histories, loops=loops)
    if comparison:
        sections.append(comparison_table(comparison, units))
    return write_html(path, render_run_html(view, sections))
