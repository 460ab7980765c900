"""Figures of the shake-table model (report Figures 4.5-4.11): Bode plots and root loci.

Uses matplotlib's Agg backend; the ``save_*`` functions write through
:func:`~impedance_mil.report.motion_plots.save_figure` (temporary name, then
rename), so a failed plot never leaves a half-written file.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..display import UnitSystem, display_unit, format_value  # noqa: E402
from ..errors import ConfigError  # noqa: E402
from ..plant import LinearTable, TableParameters  # noqa: E402
from ..plant.lti_table import LTITable  # noqa: E402
from ..plant.tuning import sweep  # noqa: E402
from .motion_plots import save_figure  # noqa: E402

#: The six transfer functions of Eq 4-15: output, input, label.
SIX_TFS = (
    ("z", "u", "z/u"),
    ("x", "u", "x/u"),
    ("dp", "u", "dP/u"),
    ("z", "w", "z/w"),
    ("x", "w", "x/w"),
    ("dp", "w", "dP/w"),
)

#: Internal unit of each signal of the table model.
SIGNAL_UNITS = {
    "z": "inch / second**2",
    "x": "inch",
    "v": "inch / second",
    "dp": "psi",
    "u": "inch",
    "w": "force_pound",
}
#: Default sweep ranges for root loci (internal units).
LOCUS_RANGE = {"Ke": 45.0, "Kp": 0.004, "loop_time": 2e-3}
#: Resolution of the saved figures [dots per inch].
DPI = 110


def bode_figure(
    p: TableParameters,
    delay: str = "first-order",
    fmin: float = 0.1,
    fmax: float = 200.0,
    units: UnitSystem = UnitSystem.US,
):
    """Figure with magnitude (in ``units``) and phase of the six TFs (frequencies [Hz])."""
    if not (0 < fmin < fmax):
        raise ConfigError("fmin/fmax", "0 < fmin < fmax [Hz]", (fmin, fmax))
    tbl = LinearTable(p, delay=delay)
    model = tbl.sampled() if delay == "sampled" else tbl.state_space()
    title = (
        f"Shake-table transfer functions (Eq 4-15), Ke={format_value(p.Ke, 'volt / inch', units)}, "
        f"Kp={format_value(p.Kp, 'volt / psi', units)}, "
        f"loop time {p.loop_time * 1e6:g} us, delay: {delay}"
    )
    return _bode_grid(model.frequency_response, SIX_TFS, fmin, fmax, units, title)


def lti_bode_figure(
    table: LTITable, fmin: float = 0.1, fmax: float = 200.0, units: UnitSystem = UnitSystem.US
):
    """Magnitude (in ``units``) and phase of every path of an LTI table's design model (frequencies [Hz])."""
    if not (0 < fmin < fmax):
        raise ConfigError("fmin/fmax", "0 < fmin < fmax [Hz]", (fmin, fmax))
    paths = tuple((o, i, f"{o}/{i}") for i in ("u", "w") for o in table.outputs)
    title = f"LTI table ({table.kind}), loop time {table.loop_time * 1e6:g} us, delay: {table.delay}"
    return _bode_grid(table.frequency_response, paths, fmin, fmax, units, title)


def _bode_grid(response, paths, fmin: float, fmax: float, units: UnitSystem, title: str):
    """Magnitude and phase rows of ``paths`` ((output, input, label), three per row) from ``response(out, inp, f)``."""
    f = np.geomspace(fmin, fmax, 400)
    cols = 3
    rows = -(-len(paths) // cols)
    fig, axes = plt.subplots(2 * rows, cols, figsize=(13, 5 * rows), sharex=True, squeeze=False)
    for k, (out, inp, label) in enumerate(paths):
        h = response(out, inp, f)
        row, col = 2 * (k // cols), k % cols
        shown_out, shown_in = display_unit(SIGNAL_UNITS[out], units), display_unit(SIGNAL_UNITS[inp], units)
        axes[row, col].loglog(f, np.abs(h) * shown_out.factor / shown_in.factor)
        axes[row, col].set_title(f"{label} [{shown_out.name} / {shown_in.name}]", fontsize=9)
        axes[row + 1, col].semilogx(f, np.degrees(np.unwrap(np.angle(h))))
        axes[row + 1, col].set_ylabel("phase [deg]", fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("frequency [Hz]")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def save_lti_bode(
    table: LTITable, path: Path, fmin: float = 0.1, fmax: float = 200.0, units: UnitSystem = UnitSystem.US
) -> Path:
    """Write :func:`lti_bode_figure` to ``path`` (format from the suffix, PNG without one)."""
    return save_figure(lti_bode_figure(table, fmin, fmax, units), path, dpi=DPI)


def save_bode(
    p: TableParameters,
    path: Path,
    delay: str = "first-order",
    fmin: float = 0.1,
    fmax: float = 200.0,
    units: UnitSystem = UnitSystem.US,
) -> Path:
    """Write :func:`bode_figure` to ``path`` (format from the suffix, PNG without one)."""
    return save_figure(bode_figure(p, delay, fmin, fmax, units), path, dpi=DPI)


def root_locus_figure(p: TableParameters, name: str, upper: float | None = None, points: int = 60):
    """Root locus of the labelled poles p1..p5 for ``name`` in [0, upper] (Figures 4.7, 4.9, 4.11)."""
    if name not in LOCUS_RANGE:
        raise ConfigError("param", "one of " + ", ".join(LOCUS_RANGE), name)
    upper = LOCUS_RANGE[name] if upper is None else upper
    if not upper > 0:
        raise ConfigError("max", "a positive upper value", upper)
    delay = "first-order" if name == "loop_time" else "none"
    base = p if name == "loop_time" else p.replace(loop_time=0.0)
    if name == "Ke":
        base = base.replace(Kp=0.0)
    sw = sweep(base, name, np.linspace(0.0, upper, points), delay, steps=2)
    fig, ax = plt.subplots(figsize=(7, 6))
    for j, label in enumerate(sw.labels):
        ax.plot(sw.poles[:, j].real, sw.poles[:, j].imag / (2 * np.pi), label=label)
        ax.plot(sw.poles[0, j].real, sw.poles[0, j].imag / (2 * np.pi), "kx")
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_xlabel("real part [rad/s]")
    ax.set_ylabel("imaginary part / 2 pi [Hz]")
    ax.set_title(f"Root locus, {name} from 0 to {upper:g} (delay: {delay})", fontsize=10)
    ax.legend()
    fig.tight_layout()
    return fig


def save_root_locus(p: TableParameters, name: str, path: Path, upper: float | None = None) -> Path:
    """Write :func:`root_locus_figure` to ``path`` (format from the suffix, PNG without one)."""
    return save_figure(root_locus_figure(p, name, upper), path, dpi=DPI)
