"""Figures of virtual systems: force-displacement loops (report Figures 1.7b, 9.1).

Agg backend (set in :mod:`impedance_mil.report.motion_plots`); write with
:func:`~impedance_mil.report.motion_plots.save_figure` (atomic).
"""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
from matplotlib.figure import Figure

from ..display import UnitSystem, display_unit  # noqa: E402
from ..errors import ConfigError
from ..units import in_s2_to_g
from ..virtual import VSResponse
from .motion_plots import save_figure

__all__ = ["plot_loops", "save_figure"]


def plot_loops(
    responses: Sequence[VSResponse],
    labels: Sequence[str],
    axial_loads: Sequence[float] | None = None,
    title: str = "",
    units: UnitSystem = UnitSystem.US,
) -> Figure:
    """Isolator force against displacement, and the basemat acceleration history.

    Parameters
    ----------
    responses : sequence of VSResponse
        One loop each (e.g. from :func:`impedance_mil.virtual.excitation.rigid_article_response`).
    labels : sequence of str
        Legend entries, one per response.
    axial_loads : sequence of float, optional
        Axial load per response [lbf]; when given the force is normalised by
        it, as in Figure 9.1 (shear force / axial load).
    title : str
        Figure title.
    units : UnitSystem
        Units of the axes (the responses are in internal units).

    Raises
    ------
    ConfigError
        No responses, or a label/axial-load count that does not match.
    """
    if not responses or len(labels) != len(responses):
        raise ConfigError("labels", f"one label per response ({len(responses)})", len(labels))
    if axial_loads is not None and len(axial_loads) != len(responses):
        raise ConfigError("axial_loads", f"one axial load per response ({len(responses)})", len(axial_loads))
    fig, (ax_loop, ax_z) = plt.subplots(1, 2, figsize=(10.0, 4.2), constrained_layout=True)
    disp, shear = display_unit("inch", units), display_unit("force_pound", units)
    for k, (r, label) in enumerate(zip(responses, labels)):
        force = shear(r.force) if axial_loads is None else r.force / axial_loads[k]
        ax_loop.plot(disp(r.displacement), force, lw=1.0, label=label)
        ax_z.plot(r.time, in_s2_to_g(r.z_vs), lw=0.8, label=f"{label} z_vs")
    ax_z.plot(responses[0].time, in_s2_to_g(responses[0].a_g), "k", lw=0.6, label="a_g")
    ax_loop.set_xlabel(f"Displacement relative to ground [{disp.name}]")
    ax_loop.set_ylabel(
        "Shear force / axial load [-]" if axial_loads is not None else f"Shear force [{shear.name}]"
    )
    ax_loop.grid(True, alpha=0.3)
    ax_loop.legend(fontsize=8)
    ax_z.set_xlabel("Time [s]")
    ax_z.set_ylabel("Acceleration [g]")
    ax_z.grid(True, alpha=0.3)
    ax_z.legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return fig
