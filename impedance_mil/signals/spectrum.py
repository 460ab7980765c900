"""Exact response spectra of piecewise-linear ground accelerations (Nigam & Jennings, 1969).

For a linear oscillator of period T and damping ratio zeta under the ground
acceleration a(t),

    u'' + 2 zeta omega u' + omega**2 u = -a(t),      omega = 2 pi / T,

with a(t) linear between samples, the state (u, v) at the next sample is an
exact linear function of the state and of the two end samples of the input:

    [u, v]_{k+1} = A [u, v]_k + B [a_k, a_{k+1}]          (Nigam & Jennings, 1969)

We compute A and B for each period from the matrix exponential (compiled
Taylor series with scaling and squaring) of the oscillator augmented with a
ramp input, written in time normalised by the
sample interval and displacement normalised by dt**2.  Every entry of that
normalised exponential is of order one, so the coefficients keep full
relative precision for any omega*dt: the closed-form Nigam-Jennings
expressions lose digits to cancellation when omega*dt is small (a 10 s
oscillator at 2000 Hz loses about six), the normalised exponential does not.
Any damping ratio >= 0 is allowed (zeta >= 1 included).  The recurrence then
runs in a compiled loop over samples, all periods at once (vectorized).

Peaks are taken at the sample instants (as in most spectrum programs); for
periods shorter than a few samples, resample the record finer first.
PSA = omega**2 SD and PSV = omega SD are the pseudo-spectral values; report
Figure 8.1 plots the 5 %-damped PSA in g.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np

from ..bounds import MAX_SPECTRUM_PERIODS, MAX_SPECTRUM_STEPS, check_count
from ..errors import ConfigError
from ..units import G0, TWO_PI

#: Default periods of a spectrum [s]: 100 log-spaced values from 0.01 s to 10 s.
DEFAULT_PERIODS = np.logspace(-2.0, 1.0, 100)


@dataclass(frozen=True, eq=False)
class Spectrum:
    """A response spectrum.

    Parameters
    ----------
    period_s : ndarray
        Oscillator periods [s].
    psa : ndarray
        Pseudo-spectral acceleration omega**2 SD [in/s**2].
    sd : ndarray
        Spectral displacement, peak relative displacement [in].
    sv : ndarray
        Pseudo-spectral velocity omega SD [in/s].
    damping : float
        Damping ratio (dimensionless).
    """

    period_s: np.ndarray = field(repr=False)
    psa: np.ndarray = field(repr=False)
    sd: np.ndarray = field(repr=False)
    sv: np.ndarray = field(repr=False)
    damping: float = 0.05

    @property
    def psa_g(self) -> np.ndarray:
        """Pseudo-spectral acceleration [g]."""
        return self.psa / G0

    @property
    def frequency_hz(self) -> np.ndarray:
        """Oscillator frequencies 1/T [Hz]."""
        return 1.0 / self.period_s


@numba.njit(cache=True)
def _expm_taylor(m):  # pragma: no cover - compiled kernel
    """exp(m) of a small square matrix by scaling and squaring of a Taylor series.

    The series is summed until a term is below 1e-20 of the running norm
    (at most 40 terms after scaling to norm <= 0.5), so truncation is below
    rounding.
    """
    n = m.shape[0]
    norm = 0.0
    for i in range(n):
        row = 0.0
        for j in range(n):
            row += abs(m[i, j])
        norm = max(norm, row)
    squarings = 0
    while norm > 0.5:
        norm *= 0.5
        squarings += 1
    scaled = m / (2.0**squarings)
    result = np.eye(n)
    term = np.eye(n)
    for k in range(1, 41):
        term = term @ scaled / k
        result += term
        if np.max(np.abs(term)) < 1e-20:
            break
    for _ in range(squarings):
        result = result @ result
    return result


@numba.njit(cache=True)
def _coefficients(omegas, damping, time_step):  # pragma: no cover - compiled kernel
    n_per = omegas.shape[0]
    a_coef = np.zeros((n_per, 2, 2))
    b_coef = np.zeros((n_per, 2, 2))
    scale = np.array([time_step * time_step, time_step])
    for j in range(n_per):
        big_omega = omegas[j] * time_step
        # Normalised time s = t/dt, displacement q = u/dt**2: q'' + 2 zeta W q' + W**2 q = -a,
        # input a(s) = a_k + r s with the slope r as a fourth state (r' = 0).
        m = np.zeros((4, 4))
        m[0, 1] = 1.0
        m[1, 0] = -big_omega * big_omega
        m[1, 1] = -2.0 * damping * big_omega
        m[1, 2] = -1.0
        m[2, 3] = 1.0
        e = _expm_taylor(m)
        for r in range(2):
            for c in range(2):
                a_coef[j, r, c] = e[r, c] * scale[r] / scale[c]
            # Response to a_k (with slope -a_k) and to a_{k+1} (slope +a_{k+1}).
            b_coef[j, r, 0] = (e[r, 2] - e[r, 3]) * scale[r]
            b_coef[j, r, 1] = e[r, 3] * scale[r]
    return a_coef, b_coef


def recurrence_coefficients(omega: float, damping: float, time_step: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact one-step matrices A, B of the oscillator under piecewise-linear input.

    Parameters
    ----------
    omega : float
        Natural circular frequency [rad/s], positive.
    damping : float
        Damping ratio, >= 0.
    time_step : float
        Sample interval [s].

    Returns
    -------
    A, B : ndarray
        2x2 arrays with ``[u, v]_{k+1} = A [u, v]_k + B [a_k, a_{k+1}]``;
        u [in], v [in/s], a [in/s**2].
    """
    a_coef, b_coef = _coefficients(np.array([float(omega)]), float(damping), float(time_step))
    return a_coef[0], b_coef[0]


@numba.njit(cache=True)
def _peak_responses(accel, a_coef, b_coef):  # pragma: no cover - compiled kernel
    """Peak |u| of every oscillator: samples in the outer loop, oscillators in the inner one.

    The oscillators are independent, so the inner loop runs over contiguous
    rows (``coef[entry, oscillator]``, ``state[u|v|peak, oscillator]``) and
    the compiler vectorizes it; each oscillator's arithmetic is the same
    expression in the same order as one oscillator at a time (the loop of
    ``tests/signals/test_spectrum_kernel.py``), so the peaks are bit-identical.
    """
    n_per = a_coef.shape[0]
    n = accel.shape[0]
    coef = np.empty((8, n_per))
    for j in range(n_per):
        coef[0, j] = a_coef[j, 0, 0]
        coef[1, j] = a_coef[j, 0, 1]
        coef[2, j] = b_coef[j, 0, 0]
        coef[3, j] = b_coef[j, 0, 1]
        coef[4, j] = a_coef[j, 1, 0]
        coef[5, j] = a_coef[j, 1, 1]
        coef[6, j] = b_coef[j, 1, 0]
        coef[7, j] = b_coef[j, 1, 1]
    state = np.zeros((3, n_per))
    for k in range(n - 1):
        a0 = accel[k]
        a1 = accel[k + 1]
        for j in range(n_per):
            u = state[0, j]
            v = state[1, j]
            u_next = coef[0, j] * u + coef[1, j] * v + coef[2, j] * a0 + coef[3, j] * a1
            state[1, j] = coef[4, j] * u + coef[5, j] * v + coef[6, j] * a0 + coef[7, j] * a1
            state[0, j] = u_next
            size = abs(u_next)
            peak = state[2, j]
            state[2, j] = size if size > peak else peak  # a select, not a branch: it vectorizes
    return state[2].copy()


@numba.njit(cache=True)
def _response_history(accel, a_coef, b_coef):  # pragma: no cover - compiled kernel
    n = accel.shape[0]
    out = np.zeros((n, 2))
    for k in range(n - 1):
        out[k + 1, 0] = (
            a_coef[0, 0] * out[k, 0]
            + a_coef[0, 1] * out[k, 1]
            + b_coef[0, 0] * accel[k]
            + b_coef[0, 1] * accel[k + 1]
        )
        out[k + 1, 1] = (
            a_coef[1, 0] * out[k, 0]
            + a_coef[1, 1] * out[k, 1]
            + b_coef[1, 0] * accel[k]
            + b_coef[1, 1] * accel[k + 1]
        )
    return out


def _checked_inputs(accel, time_step, damping) -> tuple[np.ndarray, float, float]:
    a = np.ascontiguousarray(accel, dtype=float)
    if a.ndim != 1 or a.size < 2 or not np.all(np.isfinite(a)):
        raise ConfigError("accel", "a 1-D array of at least 2 finite samples", f"shape {a.shape}")
    dt = float(time_step)
    if not (math.isfinite(dt) and dt > 0):
        raise ConfigError("time_step", "a positive finite interval in s", time_step)
    zeta = float(damping)
    if not (math.isfinite(zeta) and zeta >= 0):
        raise ConfigError("damping", "a damping ratio >= 0", damping)
    return a, dt, zeta


def oscillator_response(
    accel, time_step: float, period: float, damping: float = 0.05
) -> tuple[np.ndarray, np.ndarray]:
    """Exact relative displacement and velocity history of one oscillator.

    Parameters
    ----------
    accel : array_like
        Ground acceleration samples [in/s**2], piecewise linear in between.
    time_step : float
        Sample interval [s].
    period : float
        Oscillator period [s].
    damping : float
        Damping ratio.

    Returns
    -------
    u, v : ndarray
        Relative displacement [in] and velocity [in/s] at the samples, from rest.
    """
    a, dt, zeta = _checked_inputs(accel, time_step, damping)
    if not (math.isfinite(float(period)) and float(period) > 0):
        raise ConfigError("period", "a positive period in s", period)
    a_mat, b_mat = recurrence_coefficients(TWO_PI / float(period), zeta, dt)
    hist = _response_history(a, a_mat, b_mat)
    return hist[:, 0], hist[:, 1]


def response_spectrum(accel, time_step: float, periods=None, damping: float = 0.05) -> Spectrum:
    """Pseudo-acceleration response spectrum, exact for piecewise-linear input.

    Parameters
    ----------
    accel : array_like
        Ground acceleration samples [in/s**2].
    time_step : float
        Sample interval [s].
    periods : array_like, optional
        Oscillator periods [s], positive; default :data:`DEFAULT_PERIODS`.
    damping : float
        Damping ratio (default 0.05, report Figure 8.1).

    Returns
    -------
    Spectrum
        ``psa`` [in/s**2] (``psa_g`` [g]), ``sd`` [in], ``sv`` [in/s].

    Raises
    ------
    ConfigError
        Bad samples, interval, damping or periods; more than
        :data:`~impedance_mil.bounds.MAX_SPECTRUM_PERIODS` periods or
        :data:`~impedance_mil.bounds.MAX_SPECTRUM_STEPS` periods x samples.

    Examples
    --------
    >>> from impedance_mil.signals import builtin_motion, response_spectrum
    >>> gm = builtin_motion("elcentro")
    >>> spec = response_spectrum(gm.accel, gm.time_step, [0.02, 0.5, 2.0])
    >>> bool(abs(spec.psa_g[0] - gm.pga_g) < 0.01)
    True
    """
    a, dt, zeta = _checked_inputs(accel, time_step, damping)
    if periods is not None and hasattr(periods, "__len__"):
        check_count("periods", len(periods), MAX_SPECTRUM_PERIODS, "periods")
    per = np.array(DEFAULT_PERIODS if periods is None else periods, dtype=float).ravel()
    if per.size == 0 or not np.all(np.isfinite(per)) or np.any(per <= 0):
        raise ConfigError("periods", "one or more positive periods in s", periods)
    check_count("periods", per.size, MAX_SPECTRUM_PERIODS, "periods")
    check_count("periods", per.size * a.size, MAX_SPECTRUM_STEPS, "oscillator steps (periods x samples)")
    omegas = TWO_PI / per
    a_coef, b_coef = _coefficients(omegas, zeta, dt)
    sd = _peak_responses(a, a_coef, b_coef)
    per.setflags(write=False)
    return Spectrum(per, omegas**2 * sd, sd, omegas * sd, zeta)


def log_periods(low: float, high: float, count: int) -> np.ndarray:
    """``count`` log-spaced periods from ``low`` to ``high`` [s], refused before allocating too many.

    Raises
    ------
    ConfigError
        ``0 < low < high`` does not hold, fewer than 2 periods, or more than
        :data:`~impedance_mil.bounds.MAX_SPECTRUM_PERIODS`.

    Examples
    --------
    >>> log_periods(0.01, 10.0, 4).round(3).tolist()
    [0.01, 0.1, 1.0, 10.0]
    """
    check_count("--periods", count, MAX_SPECTRUM_PERIODS, "periods")
    if not (0 < low < high < math.inf and count >= 2):
        raise ConfigError("--periods", "log:MIN:MAX:N with 0 < MIN < MAX and N >= 2", (low, high, count))
    return np.logspace(np.log10(low), np.log10(high), int(count))
