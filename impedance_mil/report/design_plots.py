"""Figures of the MIL controller design in the layout of report Figure 9.31.

One row per cut-off frequency, four columns: (1) Bode plot of the VS
impedance and of the controlled table's impedance ``H_zw^st + H_zu^st H_wu``;
(2) the ``w -> u`` controller before and after filtering
(``H_uw^controller``); (3) Nyquist plot of the controlled table's
force-velocity transfer function (Eq 9-2), annotated with the passivity
margins (first-order delay model and sampled-data table) and the passivity
index; (4) ``Re(1/H_vw)``, the equivalent damping the controlled table
presents, whose minimum is the passivity index (issue 15, item 3).  A second figure summarises
constraints I, II, III against f_c.  Matplotlib with the Agg backend;
functions return figures, :func:`~impedance_mil.report.motion_plots.save_figure`
writes them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

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

#: Internal unit of the passivity index (an equivalent damping).
INDEX_UNIT = "lbf*s/in"


def _number(value: float | None, fmt: str) -> str:
    return "n/a" if value is None or not np.isfinite(value) else format(value, fmt)


def passivity_annotation(c: ConstraintResult, units: UnitSystem = UnitSystem.US) -> str:
    """The passivity lines of a Figure 9.31 row: margins [deg] on both models and the index (in ``units``).

    Numbers are those of the constraint result (the design's JSON), rounded
    to two decimals.
    """
    unit = display_unit(INDEX_UNIT, units)
    index = None if c.passivity_index is None else c.passivity_index * unit.factor
    return (
        f"margin first-order: {_number(c.passivity_margin_deg, '+.2f')} deg "
        f"(tolerant {_number(c.passivity_tolerant_margin_deg, '+.2f')} deg)\n"
        f"margin sampled-data: {_number(c.passivity_margin_sampled_deg, '+.2f')} deg\n"
        f"index min Re(1/H_vw): {_number(index, '+.2f')} {unit.name}"
    )


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
    indices: Mapping[float, ConstraintResult] | None = None,
) -> Figure:
    """Figure 9.31: impedances, controller response, Nyquist plot, Re(1/H_vw) (in ``units``); one row per cut-off.

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
    units : UnitSystem
        Units of the axes and of the annotated index.
    indices : mapping of float to ConstraintResult, optional
        Constraint results by cut-off [Hz] whose passivity margins and index
        (:func:`passivity_annotation`) annotate that row's Nyquist plot.
    """
    form, family = report_design_choices(form, family)
    env = environment(form, vs)
    ideal = ideal_controller(form, table, env)
    f = BODE_HZ
    rows = len(fcs_hz)
    fig, axes = plt.subplots(rows, 4, figsize=(17, 3.2 * rows), squeeze=False)
    H_vs = env.H_zw.frequency_response(f)
    wu_ideal = _wu_ideal(ideal, env, form, f)
    accel, disp = display_unit("inch / second**2", units), display_unit("inch", units)
    vel, force = display_unit("inch / second", units), display_unit("force_pound", units)
    zw, uw, vw = accel.factor / force.factor, disp.factor / force.factor, vel.factor / force.factor
    damping = display_unit(INDEX_UNIT, units)
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
        row = None if indices is None else indices.get(float(fc))
        if row is not None:
            ax.text(
                0.02,
                0.02,
                passivity_annotation(row, units),
                transform=ax.transAxes,
                fontsize=6.5,
                va="bottom",
                bbox={"boxstyle": "round", "fc": "white", "alpha": 0.8},
            )
        _damping_panel(axes[k, 3], fn, ct.velocity_response(fn), damping, float(fc))
    for ax in (*axes[-1, :2], axes[-1, 3]):
        ax.set_xlabel("frequency [Hz]")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig


def _damping_panel(ax, f: np.ndarray, h_vw: np.ndarray, unit, fc: float) -> None:
    """``Re(1/H_vw)`` [``unit``] against frequency [Hz], its minimum (the passivity index) marked."""
    d = unit.factor * np.real(1.0 / h_vw)
    i = int(np.argmin(d))
    ax.semilogx(f, d, "b-", lw=1)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.plot(f[i], d[i], "o", color="tab:red" if d[i] < 0 else "tab:green", ms=4)
    # Symmetric log: the damping spans decades, and its sign is what matters.
    ax.set_yscale("symlog", linthresh=max(abs(float(d[i])), 1e-9))
    ax.set_ylabel(f"Re(1/$H_{{vw}}$) [{unit.name}]")
    ax.set_title(f"equivalent damping, $f_c$ = {fc:g} Hz (min at {f[i]:.3g} Hz)", fontsize=9)


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
