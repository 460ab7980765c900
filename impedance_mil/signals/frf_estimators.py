"""FRF estimates with their uncertainty: synchronous averaging over periods, and Welch's H1 for random drives.

* :func:`synchronous_frf`: for a periodic drive (the multisine of Section 4.5.2),
  the periods after the transient are averaged in the time domain and
  ``H = Y_mean / U_mean`` at the excited lines (Pintelon and Schoukens 2012,
  *System Identification: A Frequency Domain Approach*, 2nd ed., Section 2.4).
  The noise variance at each line comes from the spread of the per-period
  residuals ``Y_p - H U_p`` (``P - 1`` degrees of freedom), smoothed over
  :data:`SMOOTHING_LINES` neighbouring lines (the noise spectrum is smooth, the
  two or three periods of a test give too few degrees of freedom at one line),
  so that ``std(H)^2 = sigma_noise^2 / (P |U_mean|^2)``.  The coherence is the H1
  coherence over the periods (:func:`impedance_mil.signals.frf.estimate_frf`).
* :func:`welch_frf`: for a random drive, ``H1 = S_yu / S_uu`` from Hann-windowed
  segments overlapped by half, the coherence, and ``std(H) = |H| sqrt((1 - g^2)
  / (2 n_d g^2))`` (Bendat and Piersol 2010, *Random Data*, 4th ed., Eq 9.90).
"""

from __future__ import annotations

import numpy as np
import scipy.signal

from ..errors import ConfigError
from .frf import FRF, estimate_frf

#: Lines on each side averaged into the noise variance of one line.
SMOOTHING_LINES = 8
#: Smallest relative standard deviation reported (noise-free data still get finite weights).
STD_FLOOR = 1e-12


def smoothed(values: np.ndarray, half_width: int) -> np.ndarray:
    """Moving mean over ``2 half_width + 1`` neighbours (fewer at the ends)."""
    kernel = np.ones(2 * half_width + 1)
    total = np.convolve(values, kernel, mode="same")
    count = np.convolve(np.ones_like(values), kernel, mode="same")
    return total / count


def period_spectra(signal, n_points: int, lines: np.ndarray, discard_periods: int) -> np.ndarray:
    """The spectra at ``lines`` of each period after the transient, shape (periods, lines)."""
    x = np.asarray(signal, dtype=float)[discard_periods * n_points :]
    if x.size == 0 or x.size % n_points:
        raise ConfigError("frf.n_points", f"records of a whole number of {n_points}-sample periods")
    return np.fft.rfft(x.reshape(-1, n_points), axis=1)[:, lines]


def synchronous_frf(u, y, n_points: int, sample_rate_hz: float, lines, discard_periods: int = 1) -> FRF:
    """Synchronous-average FRF of a periodic test at ``lines``, with its standard deviation.

    Parameters
    ----------
    u, y : array_like
        Input and output records [their units], a whole number of periods.
    n_points : int
        Samples per period.
    sample_rate_hz : float
        Sampling rate [Hz].
    lines : array_like of int
        Excited FFT bins of one period.
    discard_periods : int
        Leading periods dropped as transient.

    Returns
    -------
    FRF
        ``response`` the averaged estimate, ``coherence`` the H1 coherence over
        the periods, ``std`` the standard deviation of ``response``.

    Raises
    ------
    ConfigError
        Fewer than two periods after the transient (no noise estimate), or records
        that are not a whole number of periods.
    """
    h1 = estimate_frf(u, y, n_points, sample_rate_hz, lines=lines, discard_periods=discard_periods)
    if h1.n_averages < 2:
        raise ConfigError("frf.n_periods", "at least two periods after the transient (a noise estimate)")
    lines = np.asarray(lines, dtype=int)
    U = period_spectra(u, n_points, lines, discard_periods)
    Y = period_spectra(y, n_points, lines, discard_periods)
    u_mean, y_mean = U.mean(axis=0), Y.mean(axis=0)
    h = y_mean / u_mean
    p = U.shape[0]
    residual = Y - h * U
    noise_var = np.sum(np.abs(residual) ** 2, axis=0) / (p - 1)
    noise_var = smoothed(noise_var, SMOOTHING_LINES)
    std = np.maximum(np.sqrt(noise_var / (p * np.abs(u_mean) ** 2)), STD_FLOOR * np.abs(h))
    return FRF(h1.frequency_hz, h, h1.coherence, p, std)


def welch_frf(
    u, y, sample_rate_hz: float, segment_points: int, f_range_hz: tuple[float, float] | None = None
) -> FRF:
    """H1 FRF of a random test from Hann-windowed, half-overlapped segments, with coherence and std.

    Parameters
    ----------
    u, y : array_like
        Input and output records [their units], same length.
    sample_rate_hz : float
        Sampling rate [Hz].
    segment_points : int
        Samples per segment (frequency resolution ``rate / segment_points``).
    f_range_hz : (float, float), optional
        Keep the frequencies in this band [Hz] (default all but DC and Nyquist).
    """
    u = np.asarray(u, dtype=float)
    y = np.asarray(y, dtype=float)
    if u.shape != y.shape or u.ndim != 1 or segment_points < 8 or segment_points > u.size:
        raise ConfigError("frf.segment_points", f"8 to {u.size} samples per segment", segment_points)
    kw = dict(fs=sample_rate_hz, window="hann", nperseg=segment_points, noverlap=segment_points // 2)
    f, s_uu = scipy.signal.csd(u, u, **kw)
    _, s_yu = scipy.signal.csd(u, y, **kw)  # conj(U) Y
    _, s_yy = scipy.signal.csd(y, y, **kw)
    n_segments = 1 + (u.size - segment_points) // (segment_points // 2)
    keep = (f > 0) & (f < sample_rate_hz / 2)
    if f_range_hz is not None:
        keep &= (f >= f_range_hz[0]) & (f <= f_range_hz[1])
    s_uu, s_yu, s_yy, f = s_uu.real[keep], s_yu[keep], s_yy.real[keep], f[keep]
    if np.any(s_uu <= 0):
        raise ConfigError("frf.f_range_hz", "frequencies excited by the input")
    h = s_yu / s_uu
    coherence = np.clip(np.abs(s_yu) ** 2 / (s_uu * s_yy), 1e-12, 1.0)
    std = np.abs(h) * np.maximum(np.sqrt((1.0 - coherence) / (2.0 * n_segments * coherence)), STD_FLOOR)
    return FRF(f, h, coherence, int(n_segments), std)
