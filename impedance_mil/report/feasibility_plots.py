"""The two-method feasibility map (issue 15, item 5): where a VS can be imitated, and how.

One cell per grid point of :class:`~impedance_mil.design.feasibility_both.BothMethodsMap`,
coloured by its class (filter design / optimized only / neither), the legend
naming all three classes whether or not they occur, each cell
annotated with the filter design's cut-off, the optimized design's e_I, or
(neither) the passivity margin of its best trade-off.  Matplotlib with the Agg backend;
:func:`~impedance_mil.report.motion_plots.save_figure` writes the figure.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from ..design.feasibility_both import FILTER, MAP_CLASSES, BothMethodsMap  # noqa: E402

#: Colour of each class, in the order of MAP_CLASSES.
CLASS_COLOURS = ("tab:green", "tab:orange", "tab:red")

#: Legend text of each class.
CLASS_LABELS = {
    "filter": "filter: the filter design meets I/II/III at some f_c",
    "optimized only": "optimized only: only the optimized design meets I/II/III",
    "neither": "neither: cannot be imitated by either method",
}


def _edges(values: np.ndarray) -> tuple[np.ndarray, bool]:
    """Cell edges around grid values, and whether the axis is logarithmic.

    Positive values spaced more evenly in log than in linear terms (and one or
    two positive values, whose linear cells could reach below zero):
    geometric midpoints on a log axis, a single value getting a cell of a
    factor 1.1 each side; otherwise arithmetic midpoints on a linear axis.
    """
    v = np.asarray(values, float)
    log = bool(np.all(v > 0)) and (v.size < 3 or _spread(np.log(v)) < _spread(v))
    u = np.log(v) if log else v
    if u.size == 1:
        half = np.log(1.1) if log else max(0.1 * abs(u[0]), 0.5)
        e = np.array([u[0] - half, u[0] + half])
    else:
        mid = 0.5 * (u[1:] + u[:-1])
        e = np.concatenate([[u[0] - (mid[0] - u[0])], mid, [u[-1] + (u[-1] - mid[-1])]])
    return (np.exp(e) if log else e), log


def _spread(u: np.ndarray) -> float:
    """Relative spread of the steps of ``u`` (0: evenly spaced)."""
    d = np.diff(u)
    return float(np.ptp(d) / np.mean(d))


def _annotation(p) -> str:
    """Text of one cell: the filter design's f_c, the optimized design's e_I, or its best margin."""
    if p.map_class == FILTER and p.best_fc_hz is not None:
        return f"f_c {p.best_fc_hz:.0f} Hz"
    if p.optimized is not None and p.optimized.meets_all:
        return f"opt. e_I {p.optimized.constraints.performance_error:.2f}"
    if p.optimized is not None:  # the best trade-off: the margin it reaches at the allowed e_I
        return f"opt. margin {p.optimized.constraints.passivity_margin_deg:.1f} deg"
    return ""


def plot_feasibility_map(fmap: BothMethodsMap, title: str = "") -> Figure:
    """The map's classes as coloured cells over its two axes (labels with units).

    Parameters
    ----------
    fmap : BothMethodsMap
    title : str
    """
    x = np.asarray(fmap.x.values, float)
    y = np.asarray(fmap.y.values, float)
    codes = np.vectorize(MAP_CLASSES.index)(fmap.classes).astype(float)
    fig, ax = plt.subplots(figsize=(7, 5))
    (xe, x_log), (ye, y_log) = _edges(x), _edges(y)
    ax.pcolormesh(
        xe,
        ye,
        codes,
        cmap=ListedColormap(CLASS_COLOURS),
        vmin=-0.5,
        vmax=2.5,
        edgecolors="white",
        linewidth=1.0,
    )
    for i, row in enumerate(fmap.points):
        for j, p in enumerate(row):
            ax.text(x[j], y[i], _annotation(p), ha="center", va="center", fontsize=7)
    for log, set_scale, set_ticks, values in (
        (x_log, ax.set_xscale, ax.set_xticks, x),
        (y_log, ax.set_yscale, ax.set_yticks, y),
    ):
        if log:
            set_scale("log")
        set_ticks(values, [f"{v:.3g}" for v in values])
        ax.minorticks_off()
    ax.set_xlabel(fmap.x.label)
    ax.set_ylabel(fmap.y.label)
    handles = [Patch(color=c, label=CLASS_LABELS[k]) for k, c in zip(MAP_CLASSES, CLASS_COLOURS)]
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=1, fontsize=8)
    ax.set_title(
        title or "Feasibility with both design methods (cells: filter f_c, optimized e_I or best margin)",
        fontsize=9,
    )
    fig.tight_layout()
    return fig


__all__ = ["CLASS_COLOURS", "CLASS_LABELS", "plot_feasibility_map"]
