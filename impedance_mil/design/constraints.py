"""The three design constraints of the filtered MIL controller, as numbers (Sections 6.4, 9.4).

Each constraint is a metric with a threshold in :class:`DesignCriteria`;
the defaults are set once, from engineering reasoning (docs/design.md), and
used for every table, VS and cut-off:

I   performance: ``e_I = max |H_c(f)/H_zw^vs(f) - 1|`` over the band of
    interest ``band_hz`` (default 0.25-15 Hz, the band in which Section 9.1
    reports accurate imitation), where ``H_c = H_zw^st + H_zu^st H_wu`` is
    the controlled table's impedance and ``H_wu`` the whole path from ``w`` to
    ``u``.  A complex relative error covers magnitude and phase together;
    the limit ``1 - 10**(-3/20) = 0.292`` is the half-power (-3 dB) deviation.
    For tracking (``H_zw^vs = 0``) the reference is the bare table's
    impedance: ``e_I = max |H_c/H_zw^st|``, the share of the table-article
    interaction left uncompensated.
II  control effort: ``e_II = max |H_wu| over [f_s/10, f_s/2]`` divided by
    ``max |H_wu|`` over the band of interest: the controller must respond to
    high-frequency ``w`` (noise, unmodelled table dynamics above a tenth of
    the loop rate) no more than to the ``w`` it is meant to compensate.
    Limit 1 (0 dB).
III stability: passivity of ``H_vw = H_c/s`` (Eq 9-2) from 0.01 Hz to the
    Nyquist frequency, with the delay-model tolerance of
    :mod:`impedance_mil.design.passivity`.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ..errors import ConfigError
from ..systems import TransferFunction
from ..units import TWO_PI
from .forms import TableModel, VirtualModel
from .passivity import PassivityResult, log_grid_hz, passivity

#: Half-power complex relative error, 1 - 10**(-3/20).
HALF_POWER_ERROR = 1.0 - 10.0 ** (-3.0 / 20.0)

#: Fields of :class:`ConstraintResult` that may be absent (None): the passivity indices.
OPTIONAL_FIELDS = ("passivity_margin_sampled_deg", "passivity_index", "III_design_model", "III_sampled")

#: Which model's passivity verdict constraint III reports (docs/design.md, "The design model and the hold"):
#: the first-order delay model with its tolerance (reproduces Table 9.5; the default), the exact
#: sampled-data table (with the command hold), or the stricter of the two.
PASSIVITY_MODELS = ("first-order", "sampled", "strictest")

#: Points per decade for the performance and effort metrics.
GRID_PER_DECADE = 200


@dataclass(frozen=True)
class DesignCriteria:
    """Thresholds of constraints I, II, III (one set of defaults for every design).

    Parameters
    ----------
    band_hz : (float, float)
        Band of interest [Hz] for constraint I and the reference gain of II.
    performance_max : float
        Limit of the complex relative impedance error (dimensionless).
    effort_ratio_max : float
        Limit of the high- to low-frequency controller gain ratio (dimensionless).
    effort_start_fraction : float
        Start of the high-frequency band of II as a fraction of the loop rate 1/tau.
    passivity_low_hz : float
        Lowest frequency of the passivity check [Hz].
    passivity_extra_tolerance_deg : float
        Extra passivity tolerance [deg] on top of the delay-model tolerance.
    """

    band_hz: tuple[float, float] = (0.25, 15.0)
    performance_max: float = HALF_POWER_ERROR
    effort_ratio_max: float = 1.0
    effort_start_fraction: float = 0.1
    passivity_low_hz: float = 0.01
    passivity_extra_tolerance_deg: float = 0.0

    def __post_init__(self):
        lo, hi = (float(x) for x in self.band_hz)
        if not (0 < lo < hi):
            raise ConfigError("band_hz", "two frequencies 0 < low < high in Hz", self.band_hz)
        object.__setattr__(self, "band_hz", (lo, hi))
        for key in ("performance_max", "effort_ratio_max", "effort_start_fraction", "passivity_low_hz"):
            if not float(getattr(self, key)) > 0:
                raise ConfigError(key, "a positive number", getattr(self, key))
        if not 0 < self.effort_start_fraction < 0.5:
            raise ConfigError(
                "effort_start_fraction", "a fraction of the loop rate in (0, 0.5)", self.effort_start_fraction
            )
        if not 0 <= self.passivity_extra_tolerance_deg < np.inf:  # NaN fails too
            raise ConfigError(
                "passivity_extra_tolerance_deg",
                "a finite non-negative angle in deg",
                self.passivity_extra_tolerance_deg,
            )

    def effort_band_hz(self, nyquist_hz: float) -> tuple[float, float]:
        """High-frequency band of constraint II [Hz] below the Nyquist frequency ``nyquist_hz`` [Hz]."""
        return (2.0 * self.effort_start_fraction * nyquist_hz, nyquist_hz)

    def to_dict(self) -> dict:
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(self).items()}


@dataclass(frozen=True)
class ControlledTable:
    """The table under MIL control, seen from the test article.

    Attributes
    ----------
    H_c : TransferFunction
        Controlled impedance ``z/w`` [in/s**2 per lbf] (Eq 6-5).
    H_vw : TransferFunction
        Force-velocity transfer function ``H_c/s`` [in/s per lbf] (Eq 9-2).
    H_wu : TransferFunction
        Whole path from ``w`` [lbf] to ``u`` [in], through the VS model for the
        standardized form.
    H_zw_st, H_zu_st : TransferFunction
        The table's ``H_zw^st``, ``H_zu^st``.
    H_uw, H_uz : TransferFunction
        The filtered controller paths.
    target : object or None
        The VS impedance closing ``w -> z_vs`` (see :func:`target_impedance`);
        None when the form closes no VS path.

    The responses (:meth:`impedance`, :meth:`wu_response`) are evaluated from
    these factors, which keeps full precision where the polynomial products
    ``H_c``, ``H_wu`` lose a few digits to clustered roots; the polynomials
    give the poles.
    """

    H_c: TransferFunction
    H_vw: TransferFunction
    H_wu: TransferFunction
    H_zw_st: TransferFunction
    H_zu_st: TransferFunction
    H_uw: TransferFunction
    H_uz: TransferFunction
    target: Any = None

    def wu_response(self, f_hz) -> np.ndarray:
        """``H_wu`` at ``f_hz`` [Hz], factor by factor."""
        out = self.H_uw.frequency_response(f_hz)
        if self.target is not None:
            out = out + self.H_uz.frequency_response(f_hz) * self.target.frequency_response(f_hz)
        return out

    def impedance(self, f_hz) -> np.ndarray:
        """Controlled impedance ``H_c`` at ``f_hz`` [Hz] [in/s**2 per lbf]."""
        return self.H_zw_st.frequency_response(f_hz) + self.H_zu_st.frequency_response(
            f_hz
        ) * self.wu_response(f_hz)

    def velocity_response(self, f_hz) -> np.ndarray:
        """Force-velocity response ``H_c/(j 2 pi f)`` at ``f_hz`` [Hz] [in/s per lbf] (Eq 9-2)."""
        f = np.asarray(f_hz, dtype=float)
        return self.impedance(f) / (1j * TWO_PI * f)


@dataclass(frozen=True)
class ConstraintResult:
    """Constraints I, II, III for one cut-off frequency.

    Attributes
    ----------
    fc_hz : float
        Cut-off [Hz].
    I, II, III : bool
        Verdicts.
    performance_error : float
        ``e_I`` (dimensionless) and where it peaks, ``performance_worst_hz`` [Hz].
    magnitude_error_db, phase_error_deg : float
        Largest magnitude [dB] and phase [deg] deviation over the band.
    effort_ratio : float
        ``e_II`` (dimensionless), peaking at ``effort_worst_hz`` [Hz].
    passivity_margin_deg : float
        Raw passivity margin [deg] (negative: Nyquist plot in the LHP) at ``passivity_worst_hz``.
    passivity_tolerant_margin_deg : float
        Margin after the delay-model tolerance [deg]; III holds when >= 0 and stable.
    stable : bool
        The controlled table ``H_vw`` is stable.
    passivity_margin_sampled_deg : float or None
        Raw passivity margin [deg] on the exact sampled-data table (None when not evaluated;
        :mod:`impedance_mil.design.optimized.indices`).
    passivity_index : float or None
        ``min Re(1/H_vw)`` [lbf*s/in], the smallest equivalent damping (None when not evaluated).
    III_design_model : bool or None
        III on the first-order delay model with its tolerance (the verdict that reproduces Table 9.5).
    III_sampled : bool or None
        III on the exact sampled-data table: stable and ``passivity_margin_sampled_deg`` plus the
        user's extra tolerance ``>= 0`` (no model tolerance; None when not evaluated).
        ``III`` is one of the two, or both, as the passivity model chosen says (:data:`PASSIVITY_MODELS`).
    """

    fc_hz: float
    I: bool  # noqa: E741 (the report names constraint I)
    II: bool
    III: bool
    performance_error: float
    performance_worst_hz: float
    magnitude_error_db: float
    phase_error_deg: float
    effort_ratio: float
    effort_worst_hz: float
    passivity_margin_deg: float
    passivity_worst_hz: float
    passivity_tolerant_margin_deg: float
    passivity_tolerant_worst_hz: float
    stable: bool
    passivity_margin_sampled_deg: float | None = None
    passivity_index: float | None = None
    III_design_model: bool | None = None
    III_sampled: bool | None = None

    @property
    def all_satisfied(self) -> bool:
        return self.I and self.II and self.III

    def to_dict(self) -> dict:
        return {
            k: (bool(v) if isinstance(v, (bool, np.bool_)) else None if v is None else float(v))
            for k, v in asdict(self).items()
        }

    def violations(self) -> list[str]:
        """One sentence per violated constraint."""
        out = []
        if not self.I:
            out.append(
                f"constraint I (performance) violated at fc = {self.fc_hz:g} Hz: impedance error "
                f"{self.performance_error:.3f} at {self.performance_worst_hz:.3g} Hz"
            )
        if not self.II:
            out.append(
                f"constraint II (control effort) violated at fc = {self.fc_hz:g} Hz: high-frequency "
                f"controller gain {self.effort_ratio:.3g} x its in-band gain "
                f"(at {self.effort_worst_hz:.4g} Hz)"
            )
        if not self.III:
            if not self.stable:
                why = "unstable"
            elif self.III_design_model and self.passivity_margin_sampled_deg is not None:
                why = (
                    f"passivity margin {self.passivity_margin_sampled_deg:.2f} deg on the sampled-data table"
                )
            else:
                why = f"passivity margin {self.passivity_margin_deg:.2f} deg at {self.passivity_worst_hz:.3g} Hz"
            out.append(f"constraint III (passivity) violated at fc = {self.fc_hz:g} Hz: {why}")
        return out


def controlled_table(
    table: TableModel, vs: VirtualModel, H_uz: TransferFunction, H_uw: TransferFunction, form: str
) -> ControlledTable:
    """The controlled table's impedance and force-velocity transfer function.

    Parameters
    ----------
    table, vs : TableModel, VirtualModel
        Models (``VirtualModel.rigid()`` for tracking).
    H_uz, H_uw : TransferFunction
        Filtered controller paths (sign convention of :mod:`.forms`).
    form : str
        For ``standardized`` and ``tracking`` the VS model closes a second
        path ``w -> z_vs -> u``: ``H_wu = H_uw + H_uz H_zw^vs``.
    """
    closes_vs = form in ("standardized", "tracking") and not vs.H_zw.is_zero
    target = target_impedance(vs, form)
    if closes_vs:
        H_wu = (H_uw + H_uz.mul_cancel(target.H_zw)).minreal()
    else:
        H_wu = H_uw
    H_c = (table.H_zw + table.H_zu.mul_cancel(H_wu)).minreal()
    H_vw = H_c.div_cancel(TransferFunction.s())
    return ControlledTable(H_c, H_vw, H_wu, table.H_zw, table.H_zu, H_uw, H_uz, target if closes_vs else None)


def target_impedance(vs: VirtualModel, form: str):
    """The VS impedance the constraints use: the equivalent linearization or the linear part.

    For the standardized form the real-time VS model (nonlinear for LR, FP)
    closes the path ``w -> z_vs``, so its equivalent linearization
    (``vs.equivalent``, :mod:`.linearize`) stands for it when present.
    Returns an object with ``H_zw`` (rational, for poles) and
    ``frequency_response(f_hz)`` [in/s**2 per lbf].
    """
    if form == "standardized" and vs.equivalent is not None:
        return vs.equivalent
    return _LinearTarget(vs.H_zw)


@dataclass(frozen=True)
class _LinearTarget:
    """The linear part's ``H_zw`` seen through the interface of :func:`target_impedance`."""

    H_zw: TransferFunction

    def frequency_response(self, f_hz) -> np.ndarray:
        return self.H_zw.frequency_response(f_hz)


def evaluate_constraints(
    table: TableModel,
    vs: VirtualModel,
    ct: ControlledTable,
    fc_hz: float,
    criteria: DesignCriteria | None = None,
) -> ConstraintResult:
    """Evaluate constraints I, II, III for one filtered design.

    Parameters
    ----------
    table, vs : TableModel, VirtualModel
    ct : ControlledTable
        From :func:`controlled_table`.
    fc_hz : float
        Cut-off of the design [Hz] (recorded in the result).
    criteria : DesignCriteria, optional
        Thresholds; the defaults when omitted.
    """
    c = criteria or DesignCriteria()
    f = log_grid_hz(c.band_hz, GRID_PER_DECADE)
    Hc = ct.impedance(f)
    tracking = vs.H_zw.is_zero
    # The target is the VS impedance that closes w -> z_vs (the equivalent linearization, when used).
    target = ct.target if ct.target is not None else vs.H_zw
    ref = table.H_zw.frequency_response(f) if tracking else target.frequency_response(f)
    ratio = Hc / ref
    err = np.abs(ratio) if tracking else np.abs(ratio - 1.0)
    i = int(np.argmax(err))
    if tracking:
        mag_db, ph_deg = float(np.max(20 * np.log10(np.abs(ratio)))), float("nan")
    else:
        mags = 20 * np.log10(np.abs(ratio))
        phs = np.degrees(np.angle(ratio))
        mag_db = float(mags[np.argmax(np.abs(mags))])
        ph_deg = float(phs[np.argmax(np.abs(phs))])

    in_band = np.max(np.abs(ct.wu_response(f)))
    fh = log_grid_hz(c.effort_band_hz(table.nyquist_hz), GRID_PER_DECADE)
    high = np.abs(ct.wu_response(fh))
    j = int(np.argmax(high))
    effort = float(high[j] / in_band) if in_band > 0 else float("inf")

    pas: PassivityResult = passivity(
        ct.H_vw,
        (c.passivity_low_hz, table.nyquist_hz),
        table.loop_time_s,
        c.passivity_extra_tolerance_deg,
        response=ct.velocity_response,
    )
    return ConstraintResult(
        fc_hz=float(fc_hz),
        I=bool(err[i] <= c.performance_max),
        II=bool(effort <= c.effort_ratio_max),
        III=pas.passive,
        performance_error=float(err[i]),
        performance_worst_hz=float(f[i]),
        magnitude_error_db=mag_db,
        phase_error_deg=ph_deg,
        effort_ratio=effort,
        effort_worst_hz=float(fh[j]),
        passivity_margin_deg=pas.margin_deg,
        passivity_worst_hz=pas.worst_hz,
        passivity_tolerant_margin_deg=pas.tolerant_margin_deg,
        passivity_tolerant_worst_hz=pas.tolerant_worst_hz,
        stable=pas.stable,
        III_design_model=pas.passive,
    )
