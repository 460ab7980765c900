"""Servovalve model fitted to a manufacturer curve (report Section 4.3.2, Eq 4-2, Figure 4.3).

``Q/u_i = K / ((s + alpha_1)(s + alpha_2))`` with two real poles; the curve
is normalized (amplitude ratio 1 at low frequency), so ``K = alpha_1 alpha_2``
and the static flow gain K_r is kept separately (Eq 4-3).

A curve file is CSV with a header line and the columns ``frequency_hz``
and at least one of ``amplitude_ratio`` [-] and ``phase_lag_deg`` [deg,
positive = lag]; ``#`` starts a comment line.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.optimize

from ..errors import DataFileError
from ..fileio import read_text

#: Packaged example curve (synthetic, see impedance_mil/data/valve/PROVENANCE.md).
EXAMPLE_CURVE = Path(__file__).resolve().parent.parent / "data" / "valve" / "mts_252_25_synthetic.csv"
#: Weight of 1 degree of phase error relative to 1 dB of amplitude error in the fit.
PHASE_WEIGHT_DB_PER_DEG = 0.1


@dataclass(frozen=True, eq=False)
class ValveCurve:
    """A valve frequency-response curve.

    Attributes
    ----------
    frequency_hz : ndarray
        [Hz], increasing.
    amplitude_ratio : ndarray or None
        Flow amplitude ratio Q/Q_static [-].
    phase_lag_deg : ndarray or None
        Phase lag [deg] (positive = output lags).
    source : str
        File name (for messages).
    """

    frequency_hz: np.ndarray
    amplitude_ratio: np.ndarray | None
    phase_lag_deg: np.ndarray | None
    source: str = ""


def read_valve_curve(path: str | Path) -> ValveCurve:
    """Read a valve curve CSV file.

    Raises
    ------
    DataFileError
        Missing/unreadable file, missing columns, non-numeric, non-positive or
        non-increasing frequencies, non-positive amplitude ratios, fewer than 3 points.
    """
    p = Path(path)
    text = read_text(p, "a valve-curve file (CSV)")
    rows = list(csv.reader(line for line in text.splitlines() if line.strip() and not line.startswith("#")))
    if not rows:
        raise DataFileError(p, "empty valve curve")
    header = [h.strip() for h in rows[0]]
    if "frequency_hz" not in header or not ({"amplitude_ratio", "phase_lag_deg"} & set(header)):
        raise DataFileError(p, "expected a header with frequency_hz and amplitude_ratio and/or phase_lag_deg")
    columns: dict[str, list[float]] = {h: [] for h in header}
    for n, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise DataFileError(p, f"data line {n}: expected {len(header)} values, got {len(row)}")
        for h, cell in zip(header, row):
            try:
                value = float(cell)
            except ValueError:
                raise DataFileError(p, f"data line {n}: {h} is not a number: {cell.strip()!r}") from None
            if not np.isfinite(value):
                raise DataFileError(p, f"data line {n}: {h} is not finite")
            columns[h].append(value)
    f = np.array(columns["frequency_hz"])
    if f.size < 3:
        raise DataFileError(p, "need at least 3 points")
    if np.any(f <= 0) or np.any(np.diff(f) <= 0):
        raise DataFileError(p, "frequency_hz must be positive and increasing")
    amp = np.array(columns["amplitude_ratio"]) if "amplitude_ratio" in columns else None
    if amp is not None and np.any(amp <= 0):
        raise DataFileError(p, "amplitude_ratio must be positive")
    phase = np.array(columns["phase_lag_deg"]) if "phase_lag_deg" in columns else None
    return ValveCurve(f, amp, phase, str(p))


@dataclass(frozen=True)
class ValveFit:
    """Two real poles fitted to a valve curve (Eq 4-2).

    Attributes
    ----------
    poles_hz : tuple of float
        alpha_1/2pi <= alpha_2/2pi [Hz].
    amplitude_error_db : float
        Largest amplitude error of the fit over the fitted points [dB].
    phase_error_deg : float
        Largest phase error over the fitted points [deg].
    """

    poles_hz: tuple[float, float]
    amplitude_error_db: float
    phase_error_deg: float

    def frequency_response(self, f_hz) -> np.ndarray:
        """Normalized response ``a1 a2 / ((s + a1)(s + a2))`` at ``f_hz`` [Hz]."""
        return _model(np.asarray(f_hz, dtype=float), *self.poles_hz)


def _model(f, f1, f2):
    s = 1j * f
    return f1 * f2 / ((s + f1) * (s + f2))  # in Hz units: same shape as in rad/s


def _residuals(curve: ValveCurve, f1: float, f2: float, mask) -> np.ndarray:
    h = _model(curve.frequency_hz[mask], f1, f2)
    parts = []
    if curve.amplitude_ratio is not None:
        parts.append(20 * np.log10(np.abs(h)) - 20 * np.log10(curve.amplitude_ratio[mask]))
    if curve.phase_lag_deg is not None:
        parts.append(PHASE_WEIGHT_DB_PER_DEG * (-np.degrees(np.angle(h)) - curve.phase_lag_deg[mask]))
    return np.concatenate(parts)


def fit_valve_poles(curve: ValveCurve, fmax_hz: float = 100.0) -> ValveFit:
    """Fit the two real poles of Eq 4-2 to ``curve`` up to ``fmax_hz`` [Hz].

    Least squares in dB (amplitude) and degrees (phase, weighted
    :data:`PHASE_WEIGHT_DB_PER_DEG` dB per degree) on log-pole parameters.

    Raises
    ------
    DataFileError
        Fewer than 3 points below ``fmax_hz``.
    """
    mask = curve.frequency_hz <= fmax_hz
    if np.count_nonzero(mask) < 3:
        raise DataFileError(curve.source, f"fewer than 3 points below {fmax_hz:g} Hz to fit")

    def res(theta):
        return _residuals(curve, *np.exp(theta), mask)

    best = None
    for start in ((30.0, 300.0), (60.0, 120.0), (10.0, 1000.0)):
        sol = scipy.optimize.least_squares(res, np.log(start), bounds=(np.log(0.1), np.log(1e5)))
        if best is None or sol.cost < best.cost:
            best = sol
    f1, f2 = sorted(np.exp(best.x))
    h = _model(curve.frequency_hz[mask], f1, f2)
    amp_err = (
        float(np.max(np.abs(20 * np.log10(np.abs(h) / curve.amplitude_ratio[mask]))))
        if curve.amplitude_ratio is not None
        else float("nan")
    )
    ph_err = (
        float(np.max(np.abs(-np.degrees(np.angle(h)) - curve.phase_lag_deg[mask])))
        if curve.phase_lag_deg is not None
        else float("nan")
    )
    return ValveFit((float(f1), float(f2)), amp_err, ph_err)
