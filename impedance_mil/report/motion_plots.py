"""Figures of ground motions: response spectra (report Figure 8.1) and histories (Figures 8.2-8.4 a-c).

Matplotlib with the non-interactive Agg backend; every function returns the
figure and :func:`save_figure` writes it atomically (temporary name, then
rename), so a failed write leaves nothing half-written.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
from matplotlib.backend_bases import FigureCanvasBase  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from ..display import UnitSystem, display_unit  # noqa: E402
from ..errors import ConfigError  # noqa: E402
from ..fileio import atomic_path  # noqa: E402
from ..signals import GroundMotion, Spectrum  # noqa: E402
from ..units import in_s2_to_g  # noqa: E402


def plot_spectra(spectra: Sequence[Spectrum], labels: Sequence[str] | None = None, title: str = "") -> Figure:
    """Pseudo-acceleration spectra [g] against period [s], log period axis (report Figure 8.1).

    Parameters
    ----------
    spectra : sequence of Spectrum
        One curve each.
    labels : sequence of str, optional
        Legend entries.
    title : str
        Figure title.
    """
    fig, ax = plt.subplots(figsize=(6.4, 4.2), layout="constrained")
    names = list(labels) if labels is not None else [""] * len(spectra)
    for spec, label in zip(spectra, names):
        ax.plot(spec.period_s, spec.psa_g, label=label or None)
    ax.set_xscale("log")
    ax.set_xlabel("Period [s]")
    damping = spectra[0].damping if spectra else 0.05
    ax.set_ylabel(f"Pseudo-acceleration, {100 * damping:g}% damping [g]")
    ax.grid(True, which="both", alpha=0.3)
    if any(names):
        ax.legend()
    if title:
        ax.set_title(title)
    return fig


def plot_histories(motion: GroundMotion, title: str = "", units: UnitSystem = UnitSystem.US) -> Figure:
    """Displacement, velocity (in ``units``) and acceleration [g] of a motion (report Figures 8.2 a-c).

    Displacement and velocity are those of the baseline-corrected motion
    (:meth:`GroundMotion.baseline_corrected`), the ones the table runs.
    """
    corrected = motion.baseline_corrected()
    t = corrected.time
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(6.4, 6.0), layout="constrained")
    disp, vel = display_unit("inch", units), display_unit("inch / second", units)
    rows = [
        (disp(corrected.displacement()), f"Displacement [{disp.name}]"),
        (vel(corrected.velocity()), f"Velocity [{vel.name}]"),
        (in_s2_to_g(corrected.accel), "Acceleration [g]"),
    ]
    for ax, (values, label) in zip(axes, rows):
        ax.plot(t, values, linewidth=0.8)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("Time [s]")
    fig.suptitle(title or motion.name)
    return fig


def check_figure_path(path: str | Path, key: str = "-o") -> Path:
    """Check, before any work, that a figure can be written to ``path``.

    Raises
    ------
    ConfigError
        Unknown image format (suffix) or a folder that does not exist.
    """
    target = Path(path)
    formats = FigureCanvasBase.get_supported_filetypes()
    fmt = target.suffix.lstrip(".").lower()
    if fmt not in formats:
        raise ConfigError(key, "a file name ending in one of ." + ", .".join(sorted(formats)), str(path))
    if not target.parent.is_dir():
        raise ConfigError(key, "a path in an existing folder", str(path))
    return target


def save_figure(fig: Figure, path: str | Path, dpi: int = 150) -> Path:
    """Write ``fig`` to ``path`` (format from the suffix) via a temporary file, then close it.

    Raises
    ------
    OSError
        The folder does not exist or is not writable (nothing is left behind).
    ValueError
        Matplotlib does not know the suffix.
    """
    target = Path(path)
    fmt = target.suffix.lstrip(".").lower() or "png"
    try:
        with atomic_path(target) as tmp:
            fig.savefig(tmp, format=fmt, dpi=dpi)
    finally:
        plt.close(fig)
    return target
