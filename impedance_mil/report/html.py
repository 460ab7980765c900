"""Self-contained HTML pages: one run's page, and the building blocks other pages share.

Every page is a single file: figures are embedded as base64 PNG (or inline
SVG), the style sheet is inline, and there is no JavaScript, so the page
opens offline, can be mailed, and never fetches anything.

:func:`render_run_html` renders one run from plain arrays (a :class:`RunView`),
so it does not depend on the virtual lab's internals: build the view with
:meth:`RunView.from_channels` from any mapping of channel arrays (e.g. a lab
``RunResult.channels``) and the run's metrics and configuration.

Colours follow the report's figures: table response solid blue, target
(VS or input motion) dashed red, input ground motion solid black.
"""

from __future__ import annotations

import base64
import html
import io
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from ..display import UnitSystem, display_unit, human_name  # noqa: E402
from ..fileio import atomic_write_text  # noqa: E402
from ..signals import response_spectrum  # noqa: E402
from ..signals.motion import integrate_piecewise_linear  # noqa: E402
from ..units import in_s2_to_g  # noqa: E402
from .documents import express  # noqa: E402

#: Line styles of the report's figures, by role.
STYLES: dict[str, dict[str, Any]] = {
    "table": {"color": "tab:blue", "linestyle": "-", "linewidth": 1.2},
    "target": {"color": "tab:red", "linestyle": "--", "linewidth": 1.2},
    "input": {"color": "black", "linestyle": "-", "linewidth": 1.0},
    "model": {"color": "tab:red", "linestyle": "--", "linewidth": 1.2},
    "other": {"color": "tab:green", "linestyle": ":", "linewidth": 1.2},
}

#: Oscillator frequencies of the run page's spectra [Hz] (0.1 to 50 Hz, log-spaced).
SPECTRUM_FREQUENCIES_HZ = np.logspace(-1.0, math.log10(50.0), 120)

_CSS = """
body{font-family:DejaVu Sans,Helvetica,Arial,sans-serif;margin:2em auto;max-width:1100px;color:#222;
line-height:1.4;padding:0 1em}
h1{font-size:1.6em;border-bottom:2px solid #345;padding-bottom:.2em}h2{font-size:1.25em;margin-top:1.6em}
table{border-collapse:collapse;margin:.6em 0}td,th{border:1px solid #bbb;padding:.25em .6em;text-align:left;
vertical-align:top}th{background:#eef}td.num{text-align:right;font-variant-numeric:tabular-nums}
figure{margin:.8em 0;display:inline-block}figcaption{font-size:.9em;color:#444}
img,svg{max-width:100%;height:auto}.meta{color:#555;font-size:.9em}
.verdict{font-weight:bold;padding:.1em .5em;border-radius:.3em}.agree{background:#d4f4d4;color:#063}
.disagree{background:#f9d0d0;color:#800}.not-run{background:#e4e4e4;color:#444}
.claim{border:1px solid #ccc;border-radius:.4em;padding:.4em 1em;margin:1em 0}
blockquote{border-left:4px solid #99a;margin:.5em 0;padding:.2em .8em;color:#333;background:#f7f7fb}
"""


# ------------------------------------------------------------------ building blocks
def escape(value: Any) -> str:
    """HTML-escape any value's text."""
    return html.escape(str(value), quote=True)


def fmt_number(value: Any, digits: int = 4) -> str:
    """A number in ``digits`` significant figures; other values as text; None as an en dash."""
    if value is None:
        return "\u2013"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float, np.floating, np.integer)):
        return f"{float(value):.{digits}g}" if math.isfinite(float(value)) else str(float(value))
    return str(value)


def figure_png(fig: Figure, alt: str, caption: str = "", dpi: int = 110) -> str:
    """Embed a figure as a base64 PNG ``<figure>`` (and close it)."""
    buffer = io.BytesIO()
    try:
        fig.savefig(buffer, format="png", dpi=dpi)
        width, height = (int(round(v * dpi)) for v in fig.get_size_inches())
    finally:
        plt.close(fig)
    data = base64.b64encode(buffer.getvalue()).decode("ascii")
    cap = f"<figcaption>{escape(caption)}</figcaption>" if caption else ""
    return (
        f'<figure><img src="data:image/png;base64,{data}" alt="{escape(alt)}" '
        f'width="{width}" height="{height}">{cap}</figure>'
    )


def figure_svg(fig: Figure, caption: str = "") -> str:
    """Embed a figure as inline SVG ``<figure>`` (and close it)."""
    buffer = io.StringIO()
    try:
        fig.savefig(buffer, format="svg")
    finally:
        plt.close(fig)
    text = buffer.getvalue()
    svg = text[text.index("<svg") :]
    cap = f"<figcaption>{escape(caption)}</figcaption>" if caption else ""
    return f"<figure>{svg}{cap}</figure>"


def key_value_table(rows: Mapping[str, Any], header: tuple[str, str] = ("quantity", "value")) -> str:
    """A two-column table of names and values (numbers right-aligned, 4 significant figures)."""
    body = "".join(
        f'<tr><td>{escape(k)}</td><td class="num">{escape(fmt_number(v))}</td></tr>' for k, v in rows.items()
    )
    return f"<table><tr><th>{escape(header[0])}</th><th>{escape(header[1])}</th></tr>{body}</table>"


def flatten(mapping: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """Nested tables as dotted keys (``{"table": {"Kp": 1}}`` -> ``{"table.Kp": 1}``)."""
    out: dict[str, Any] = {}
    for key, value in mapping.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            out.update(flatten(value, name + "."))
        elif isinstance(value, (list, tuple)) and value and all(isinstance(v, Mapping) for v in value):
            # A list of records (e.g. the sensor channels): one dotted row per record field,
            # keyed by the record's name when it has one.
            for i, item in enumerate(value):
                out.update(flatten(item, f"{name}[{item.get('name', i)}]."))
        elif isinstance(value, (list, tuple)) and len(value) > 8:
            out[name] = f"[{len(value)} values]"
        else:
            out[name] = value
    return out


def html_page(title: str, sections: Sequence[str], subtitle: str = "") -> str:
    """A complete, self-contained HTML document (inline CSS, no scripts)."""
    sub = f'<p class="meta">{escape(subtitle)}</p>' if subtitle else ""
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f'<meta name="viewport" content="width=device-width, initial-scale=1">'
        # an empty data: icon keeps browsers from fetching /favicon.ico
        '<link rel="icon" href="data:,">'
        f"<title>{escape(title)}</title><style>{_CSS}</style></head>"
        f"<body><h1>{escape(title)}</h1>{sub}{''.join(sections)}</body></html>\n"
    )


def write_html(path: str | Path, text: str) -> Path:
    """Write an HTML page atomically (temporary name, then rename)."""
    return atomic_write_text(path, text)


def new_figure(width: float = 7.0, height: float = 3.2, rows: int = 1) -> tuple[Figure, Any]:
    """A figure with ``rows`` stacked axes sharing x (constrained layout)."""
    fig, axes = plt.subplots(
        rows, 1, figsize=(width, height * rows), sharex=True, layout="constrained", squeeze=False
    )
    return fig, axes[:, 0]


# ------------------------------------------------------------------ one run
@dataclass(frozen=True)
class ForceDisplacement:
    """A force-displacement loop of the isolation system.

    Attributes
    ----------
    label : str
        Legend entry.
    displacement : ndarray
        Isolator displacement [in].
    force : ndarray
        Isolator force [lbf].
    role : str
        Key of :data:`STYLES`.
    """

    label: str
    displacement: np.ndarray = field(repr=False)
    force: np.ndarray = field(repr=False)
    role: str = "table"


@dataclass(frozen=True, eq=False)
class RunView:
    """What the run page shows, as plain arrays (internal units).

    Attributes
    ----------
    title : str
        Page title.
    time_s : ndarray
        Sample times [s], uniform.
    table_accel : ndarray
        Table acceleration z_st [in/s^2].
    target_accel : ndarray or None
        Target acceleration (z_vs in MIL, the input motion in tracking) [in/s^2].
    ground_accel : ndarray or None
        Input ground acceleration a_g [in/s^2].
    table_disp : ndarray or None
        Table displacement [in].
    histories : mapping of str to (ndarray, str)
        Further histories to plot, ``name -> (values, unit)`` (e.g. ``w``, ``u_w``).
    loops : tuple of ForceDisplacement
        Isolator force-displacement loops (report Figures 9.x c).
    metrics : mapping
        Scalar metrics of the run.
    config : mapping
        The run configuration (shown flattened).
    status : str
        ``"completed"`` or why the run stopped (e.g. a tripped limit).
    units : UnitSystem
        The units the page shows (its arrays stay in internal units).
    """

    title: str
    time_s: np.ndarray = field(repr=False)
    table_accel: np.ndarray = field(repr=False)
    target_accel: np.ndarray | None = field(default=None, repr=False)
    ground_accel: np.ndarray | None = field(default=None, repr=False)
    table_disp: np.ndarray | None = field(default=None, repr=False)
    histories: Mapping[str, tuple[np.ndarray, str]] = field(default_factory=dict, repr=False)
    loops: tuple[ForceDisplacement, ...] = ()
    metrics: Mapping[str, Any] = field(default_factory=dict)
    config: Mapping[str, Any] = field(default_factory=dict)
    status: str = "completed"
    units: UnitSystem = UnitSystem.US

    @property
    def time_step(self) -> float:
        """Sample interval [s]."""
        return float(self.time_s[1] - self.time_s[0]) if self.time_s.size > 1 else 0.0

    @classmethod
    def from_channels(
        cls,
        channels: Mapping[str, Any],
        *,
        title: str = "Run",
        metrics: Mapping[str, Any] | None = None,
        config: Mapping[str, Any] | None = None,
        status: str = "completed",
        m_vs: float | None = None,
        model_loop: tuple[Any, Any] | None = None,
        units: UnitSystem = UnitSystem.US,
    ) -> RunView:
        """Build a view from named channel arrays (the lab's channel names).

        Parameters
        ----------
        channels : mapping
            ``t`` [s] and ``z`` [in/s^2] are required; ``z_vs``, ``a_g`` [in/s^2],
            ``x`` [in], ``w`` [lbf], ``u_w``, ``u`` [in] are used when present.
        title, metrics, config, status
            See the attributes.
        m_vs : float, optional
            Basemat mass [lbf*s^2/in].  With ``w``, ``x`` and ``a_g`` it gives the
            experimental isolator loop of report Section 9.3: ``F = w - m_vs z``,
            ``D = x - x_g``.
        """
        t = np.asarray(channels["t"], dtype=float)
        z = np.asarray(channels["z"], dtype=float)
        get = lambda name: None if channels.get(name) is None else np.asarray(channels[name], float)
        a_g, z_vs, x, w = get("a_g"), get("z_vs"), get("x"), get("w")
        target = z_vs if z_vs is not None and np.any(z_vs != 0.0) else a_g
        histories = {
            name: (get(name), unit) for name, unit in (("w", "lbf"), ("u_w", "in")) if get(name) is not None
        }
        loops: tuple[ForceDisplacement, ...] = ()
        if m_vs is not None and w is not None and x is not None and a_g is not None and t.size > 1:
            _, x_g = integrate_piecewise_linear(a_g, float(t[1] - t[0]))
            loops = (ForceDisplacement("shake table: w - m_vs z, x - x_g", x - x_g, w - m_vs * z),)
        if model_loop is not None:
            disp, force = (np.asarray(v, dtype=float) for v in model_loop)
            loops += (ForceDisplacement("VS model", disp, force, "model"),)
        return cls(
            title=title,
            time_s=t,
            table_accel=z,
            target_accel=target,
            ground_accel=a_g,
            table_disp=x,
            histories=histories,
            loops=loops,
            metrics=dict(metrics or {}),
            config=dict(config or {}),
            status=status,
            units=units,
        )

    @classmethod
    def from_result(
        cls,
        result: Any,
        *,
        title: str = "",
        metrics: Mapping[str, Any] | None = None,
        m_vs: float | None = None,
        model_loop: tuple[Any, Any] | None = None,
        units: UnitSystem = UnitSystem.US,
    ) -> RunView:
        """Build a view from a run result (anything with ``channels``, ``config`` and ``trip``).

        Works with :class:`impedance_mil.lab.results.RunResult` (e.g. from
        ``load_run``) without importing the lab.  The status names the tripped
        limit, if any; ``m_vs`` [lbf*s^2/in] and ``model_loop`` add the isolator
        loops (see :meth:`from_channels`).
        """
        trip = getattr(result, "trip", None)
        status = (
            "completed"
            if trip is None
            else (f"stopped: limit '{trip.limit}' tripped at t = {trip.time_s:.4f} s")
        )
        config = dict(getattr(result, "config", {}) or {})
        motion = config.get("motion", "")
        if isinstance(motion, Mapping):  # the lab stores the motion's description as a mapping
            motion = motion.get("name", "")
        name = title or f"{getattr(result, 'mode', 'run')} run: {motion}".strip(": ")
        return cls.from_channels(
            result.channels,
            title=name,
            metrics=metrics,
            config=config,
            status=status,
            m_vs=m_vs,
            model_loop=model_loop,
            units=units,
        )


def history_figure(view: RunView) -> Figure:
    """Acceleration histories [g] (table, target, input) and the other histories of the run."""
    extra = [(name, values, unit) for name, (values, unit) in view.histories.items()]
    if view.table_disp is not None:
        extra.insert(0, ("table displacement", view.table_disp, "inch"))
    fig, axes = new_figure(rows=1 + len(extra), height=2.4)
    ax = axes[0]
    if view.ground_accel is not None and view.ground_accel is not view.target_accel:
        ax.plot(view.time_s, in_s2_to_g(view.ground_accel), label="input a_g", **STYLES["input"])
    ax.plot(view.time_s, in_s2_to_g(view.table_accel), label="table", **STYLES["table"])
    if view.target_accel is not None:
        ax.plot(view.time_s, in_s2_to_g(view.target_accel), label="target", **STYLES["target"])
    ax.set_ylabel("acceleration [g]")
    ax.legend(loc="upper right", fontsize="small")
    for axis, (name, values, unit) in zip(axes[1:], extra):
        shown = display_unit(unit, view.units)
        axis.plot(view.time_s, shown(values), **STYLES["table"])
        axis.set_ylabel(f"{name} [{shown.name}]")
    for axis in axes:
        axis.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    return fig


def spectra_figure(view: RunView, damping: float = 0.05) -> Figure:
    """5 %-damped pseudo-acceleration spectra [g] of table, target and input against frequency."""
    fig, (ax,) = new_figure(height=3.6)
    periods = 1.0 / SPECTRUM_FREQUENCIES_HZ
    curves = [
        ("input a_g", view.ground_accel, "input"),
        ("table", view.table_accel, "table"),
        ("target", view.target_accel, "target"),
    ]
    for label, accel, role in curves:
        if accel is None or (role == "input" and accel is view.target_accel):
            continue
        spec = response_spectrum(accel, view.time_step, periods, damping)
        ax.plot(SPECTRUM_FREQUENCIES_HZ, spec.psa_g, label=label, **STYLES[role])
    ax.set_xscale("log")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel(f"pseudo-acceleration, {100 * damping:g}% damping [g]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    return fig


def loops_figure(loops: Sequence[ForceDisplacement], units: UnitSystem = UnitSystem.US) -> Figure:
    """Isolator force against displacement (internal in, lbf), drawn in ``units``."""
    fig, (ax,) = new_figure(width=5.0, height=4.0)
    disp, force = display_unit("in", units), display_unit("lbf", units)
    for loop in loops:
        style = STYLES.get(loop.role, STYLES["other"])
        ax.plot(disp(loop.displacement), force(loop.force), label=loop.label, **style)
    ax.set_xlabel(f"isolator displacement [{disp.name}]")
    ax.set_ylabel(f"isolator force [{force.name}]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small")
    return fig


def _with_unit(key: str, unit: str | None) -> str:
    """``peak_table_disp_mm [mm]``: a metric's name and its unit (none for pure numbers)."""
    return key if unit in (None, "1", "unknown") else f"{key} [{human_name(unit)}]"


def render_run_html(view: RunView, extra_sections: Sequence[str] = ()) -> str:
    """The HTML page of one run: status, metrics (then ``extra_sections``), histories, spectra, loops, configuration."""
    sections = [
        f"<h2>Status</h2><p>{escape(view.status)}; {view.time_s.size} samples, "
        f"time step {fmt_number(view.time_step)} s.</p>"
    ]
    if view.metrics:
        shown = express(view.metrics, view.units)
        rows = {
            _with_unit(k, shown["units"].get(k)): v
            for k, v in shown.items()
            if k not in ("units", "unit_system")
        }
        sections.append("<h2>Metrics</h2>" + key_value_table(rows, ("metric", "value")))
    sections.extend(extra_sections)
    if view.time_s.size > 1:
        sections.append(
            "<h2>Histories</h2>"
            + figure_png(
                history_figure(view),
                "acceleration and other histories",
                "Table (solid blue), target (dashed red) and input ground motion (black).",
            )
        )
        sections.append(
            "<h2>Response spectra</h2>"
            + figure_png(
                spectra_figure(view),
                "5% damped response spectra",
                "5%-damped pseudo-acceleration spectra of the table, target and input accelerations.",
            )
        )
    if view.loops:
        sections.append(
            "<h2>Force-displacement</h2>"
            + figure_png(
                loops_figure(view.loops, view.units),
                "isolator force-displacement loops",
                "Isolator force against displacement (report Section 9.3, panel c).",
            )
        )
    if view.config:
        sections.append("<h2>Configuration</h2>" + key_value_table(flatten(view.config), ("key", "value")))
    return html_page(view.title, sections, subtitle="impedance-mil run report")
