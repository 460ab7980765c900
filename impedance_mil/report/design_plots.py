"""Figures of the MIL controller design in the layout of report Figure 9.31.

One row per cut-off frequency, three columns: (left) Bode plot of the VS
impedance and of the controlled table's impedance ``H_zw^st + H_zu^st H_wu``;
(middle) the ``w -> u`` controller before and after filtering
(``H_uw^controller``); (right) Nyquist plot of the controlled table's
force-velocity transfer function (Eq 9-2).  A second figure summarises
constraints I, II, III against f_c.  Matplotlib with the Agg backend;
functions return figures, :func:`~impedance_mil.report.motion_plots.save_figure`
writes them.
"""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from ..design import (  # noqa: E402
    ConstraintResult,
    DesignCriteria,
    TableModel,
    VirtualModel,
    controlled_table,
    ideal_controller,
)
from ..design.controller import filter_controller, report_design_choices  # noqa: E402
from ..design.forms import environment  # noqa: E402
from ..display import UnitSystem, display_unit  # noqa: E402

#: Frequency axis of the Bode plots [Hz].
BODE_HZ = np.logspace(-1, np.log10(2000.0), 600)


def _wu_ideal(ideal, vs: VirtualModel, form: str, f: np.ndarray) -> np.ndarray:
    out = ideal.H_uw.frequency_response(f)
    if form in ("standardized", "tracking") and not vs.H_zw.is_zero:
        out = out + ideal.H_uz.frequency_response(f) * vs.H_zw.frequency_response(f)
    return out


def plot_design_rows(
    table: TableModel,
    vs: VirtualModel | None,
    fcs_hz: Sequence[float],
    *,
    form: str | None = None,
    family: str | None = None,
    order: int | None = None,
    title: str = "",
    units: UnitSystem = UnitSystem.US,
) -> Figure:
    """Figure 9.31: impedances, controller response, Nyquist plot (in ``units``); one row per cut-off.

    Parameters
    ----------
    table : TableModel
    vs : VirtualModel or None
        None: acceleration tracking (zero VS impedance).
    fcs_hz : sequence of float
        Cut-off frequencies [Hz], one row each.
    form, family, order
        Controller form and filter (form and family: the report's where None).
    title : str
        Figure title.
    """
    form, family = report_design_choices(form, family)
    env = environment(form, vs)
    ideal = ideal_controller(form, table, env)
    f = BODE_HZ
    rows = len(fcs_hz)
    fig, axes = plt.subplots(rows, 3, figsize=(13, 3.2 * rows), squeeze=False)
    H_vs = env.H_zw.frequency_response(f)
    wu_ideal = _wu_ideal(ideal, env, form, f)
    accel, disp = display_unit("inch / second**2", units), display_unit("inch", units)
    vel, force = display_unit("inch / second", units), display_unit("force_pound", units)
    zw, uw, vw = accel.factor / force.factor, disp.factor / force.factor, vel.factor / force.factor
    for k, fc in enumerate(fcs_hz):
        paths = filter_controller(ideal, float(fc), family, order)
        ct = controlled_table(table, env, paths.H_uz, paths.H_uw, form)
        Hc = ct.impedance(f)
        ax = axes[k, 0]
        if not env.H_zw.is_zero:
            ax.loglog(f, zw * np.abs(H_vs), "r--", label="VS $H_{zw}^{vs}$")
        ax.loglog(f, zw * np.abs(table.H_zw.frequency_response(f)), color="0.6", lw=0.8, label="bare table")
        ax.loglog(f, zw * np.abs(Hc), "b-", label="controlled table")
        ax.set_ylabel(f"|z/w| [{accel.name} / {force.name}]")
        ax.set_title(f"impedance, $f_c$ = {fc:g} Hz", fontsize=9)
        ax.legend(fontsize=7, loc="lower right")
        ax = axes[k, 1]
        ax.loglog(f, uw * np.abs(wu_ideal), "k--", label="unfiltered")
        ax.loglog(f, uw * np.abs(ct.wu_response(f)), "b-", label="filtered")
        ax.axvline(fc, color="0.7", lw=0.8)
        ax.set_ylabel(f"|u/w| [{disp.name} / {force.name}]")
        ax.set_title(f"controller $H_{{uw}}^{{controller}}$, $f_c$ = {fc:g} Hz", fontsize=9)
        ax.legend(fontsize=7, loc="upper left")
        ax = axes[k, 2]
        fn = np.logspace(-2, np.log10(table.nyquist_hz), 3000)
        v = vw * ct.velocity_response(fn)
        ax.plot(v.real, v.imag, "b-", lw=1)
        ax.plot(v.real, -v.imag, "b:", lw=0.6)
        ax.axvline(0.0, color="k", lw=0.8)
        ax.axhline(0.0, color="k", lw=0.5)
        ax.set_xlabel(f"Re [{vel.name} / {force.name}]")
        ax.set_ylabel(f"Im [{vel.name} / {force.name}]")
        ax.set_title(f"Nyquist of $H_{{vw}}^{{st}}$ (Eq 9-2), $f_c$ = {fc:g} Hz", fontsize=9)
    for ax in axes[-1, :2]:
        ax.set_xlabel("frequency [Hz]")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig


def plot_constraint_summary(
    results: Sequence[ConstraintResult],
    criteria: DesignCriteria | None = None,
    feasible_fc_hz: tuple[float, float] | None = None,
    title: str = "",
) -> Figure:
    """Constraints I, II, III against the cut-off f_c, thresholds dashed, feasible range shaded.

    Parameters
    ----------
    results : sequence of ConstraintResult
        One per cut-off.
    criteria : DesignCriteria, optional
        Thresholds drawn (defaults when omitted).
    feasible_fc_hz : (float, float), optional
        Feasible range [Hz] to shade.
    title : str
    """
    c = criteria or DesignCriteria()
    rs = sorted(results, key=lambda r: r.fc_hz)
    fc = np.array([r.fc_hz for r in rs])
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    series = [
        ([r.performance_error for r in rs], c.performance_max, "I: impedance error [-]", True),
        ([r.effort_ratio for r in rs], c.effort_ratio_max, "II: HF/in-band controller gain [-]", True),
        ([r.passivity_tolerant_margin_deg for r in rs], 0.0, "III: passivity margin [deg]", False),
    ]
    for ax, (values, limit, label, log) in zip(axes, series):
        ok = (
            [r.I for r in rs]
            if "I:" in label
            else [r.II for r in rs]
            if "II:" in label
            else [r.III for r in rs]
        )
        ax.plot(fc, values, "k-", lw=1)
        ax.scatter(fc, values, c=["tab:green" if o else "tab:red" for o in ok], zorder=3, s=18)
        ax.axhline(limit, color="tab:red", ls="--", lw=1)
        if "III" in label:
            ax.plot(fc, [r.passivity_margin_deg for r in rs], color="0.5", lw=0.8, label="raw margin")
            ax.legend(fontsize=7)
        if log:
            ax.set_yscale("log")
        ax.set_ylabel(label, fontsize=9)
        if feasible_fc_hz is not None:
            ax.axvspan(*feasible_fc_hz, color="tab:green", alpha=0.12)
    axes[-1].set_xscale("log")
    axes[-1].set_xlabel("filter cut-off $f_c$ [Hz]")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig
