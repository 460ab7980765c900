"""Plots of an identification: measured FRF against the physical and rational fits (``imil identify --plot``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..lab.identify import RecordedIdentification
from .html import new_figure
from .motion_plots import save_figure


def identification_figure(ident: RecordedIdentification):
    """Magnitude, phase [deg] and coherence of the measured FRF, with both fits, against frequency [Hz]."""
    frf = ident.frf
    f = frf.frequency_hz
    fits = (
        ("physical model", ident.physical_response(), {"color": "tab:red", "linestyle": "--"}),
        ("rational model", ident.rational.response(f), {"color": "tab:green", "linestyle": ":"}),
    )
    fig, (mag, phase, coh) = new_figure(width=7.0, height=2.6, rows=3)
    mag.loglog(f, np.abs(frf.response), ".", color="tab:blue", markersize=3, label="measured")
    phase.semilogx(f, np.degrees(np.unwrap(np.angle(frf.response))), ".", color="tab:blue", markersize=3)
    for label, h, style in fits:
        mag.loglog(f, np.abs(h), label=label, linewidth=1.2, **style)
        phase.semilogx(f, np.degrees(np.unwrap(np.angle(h))), linewidth=1.2, **style)
    coh.semilogx(f, frf.coherence, ".", color="tab:blue", markersize=3)
    unit = {"z": "(in/s^2)/in", "x": "in/in", "dp": "psi/in"}[ident.output]
    mag.set_ylabel(f"|{ident.output}/u| [{unit}]")
    phase.set_ylabel("phase [deg]")
    coh.set_ylabel("coherence")
    coh.set_ylim(min(0.9, float(frf.coherence.min())) - 0.02, 1.01)
    coh.set_xlabel("frequency [Hz]")
    mag.legend(fontsize="small")
    for ax in (mag, phase, coh):
        ax.grid(True, which="both", alpha=0.3)
    return fig


def save_identification_plot(ident: RecordedIdentification, path: str | Path) -> Path:
    """Write :func:`identification_figure` to ``path`` (format from the suffix), atomically."""
    return save_figure(identification_figure(ident), path)
