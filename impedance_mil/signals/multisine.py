"""Periodic multisine excitation for frequency-response tests (report Section 4.5.2).

The report's signal: 512 lines of equal amplitude from 0.25 to 125 Hz,
8192 points per period at 2000 Hz (a 4.096 s period, 0.244 Hz resolution),
three periods, phases chosen for a low crest factor (Schoukens et al., 2012).

The crest factor here is the usual ``peak / RMS`` (Schoukens et al. 2012,
Section 2.4); a single sine has sqrt(2).  The report's wording "ratio of
maximum peak to minimum peak" is not that quantity (see docs/errata.md).

Phases are Schroeder's (``phi_k = -pi k (k-1) / K``) or, with
``phases="min-crest"``, improved from Schroeder's by the iterative clipping
algorithm of Van der Ouderaa, Schoukens and Renneboog (1988): clip the time
signal, restore the amplitude spectrum, keep the phases, repeat.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bounds import MAX_MULTISINE_ITERATIONS, MAX_RECORD_SAMPLES, check_count
from ..errors import ConfigError

_PHASE_METHODS = ("schroeder", "min-crest", "random")

#: Period of the report's multisine [s]: 8192 points at 2000 Hz (Section 4.5.2).
REPORT_PERIOD_S = 8192 / 2000.0


def crest_factor(x) -> float:
    """Crest factor ``max|x| / rms(x)`` (dimensionless) of a signal."""
    x = np.asarray(x, dtype=float)
    rms = np.sqrt(np.mean(x**2))
    if rms == 0:
        raise ConfigError("signal", "a signal that is not identically zero")
    return float(np.max(np.abs(x)) / rms)


@dataclass(frozen=True, eq=False)
class Multisine:
    """One period of a multisine and how it was built.

    Attributes
    ----------
    period : ndarray
        One period of the signal [signal unit, e.g. in].
    sample_rate_hz : float
        Sampling rate [Hz].
    lines : ndarray of int
        Excited FFT bins of one period.
    phases : ndarray
        Phase of each line [rad].
    crest_factor : float
        ``peak / RMS`` of the period (dimensionless).
    n_periods : int
        Number of periods of the test signal (the first is the transient).
    """

    period: np.ndarray
    sample_rate_hz: float
    lines: np.ndarray
    phases: np.ndarray
    crest_factor: float
    n_periods: int = 3

    @property
    def n_points(self) -> int:
        """Samples per period."""
        return int(self.period.size)

    @property
    def frequencies_hz(self) -> np.ndarray:
        """Frequencies of the excited lines [Hz]."""
        return self.lines * self.sample_rate_hz / self.n_points

    @property
    def time_step(self) -> float:
        """Sampling interval [s]."""
        return 1.0 / self.sample_rate_hz

    @property
    def signal(self) -> np.ndarray:
        """The test signal: ``n_periods`` repetitions of the period."""
        return np.tile(self.period, self.n_periods)

    @property
    def duration(self) -> float:
        """Length of the test signal [s]."""
        return self.n_periods * self.n_points / self.sample_rate_hz

    def time(self) -> np.ndarray:
        """Sample times of :attr:`signal` [s]."""
        return np.arange(self.n_periods * self.n_points) / self.sample_rate_hz


def _lines(f_min_hz, f_max_hz, n_lines, n_points, sample_rate_hz) -> np.ndarray:
    df = sample_rate_hz / n_points
    k_min = max(1, int(round(f_min_hz / df)))
    k_max = min(n_points // 2 - 1, int(round(f_max_hz / df)))
    if k_max < k_min:
        raise ConfigError(
            "multisine.f_max_hz", f"a band of at least one line above {df:.4g} Hz", (f_min_hz, f_max_hz)
        )
    if n_lines > k_max - k_min + 1:
        raise ConfigError(
            "multisine.n_lines",
            f"at most {k_max - k_min + 1} lines between {f_min_hz} and {f_max_hz} Hz "
            f"at {n_points} points per period",
            n_lines,
        )
    return np.unique(np.round(np.linspace(k_min, k_max, n_lines)).astype(int))


def _synthesize(lines, phases, n_points) -> np.ndarray:
    spec = np.zeros(n_points // 2 + 1, dtype=complex)
    spec[lines] = np.exp(1j * phases)
    return np.fft.irfft(spec, n_points)


def _min_crest_phases(lines, phases, n_points, iterations) -> np.ndarray:
    """Iterative clipping (Van der Ouderaa et al. 1988), keeping the best phases found."""
    best = phases.copy()
    x = _synthesize(lines, phases, n_points)
    best_cf = crest_factor(x)
    for it in range(iterations):
        peak = np.max(np.abs(x))
        clip_level = peak * (0.85 + 0.1 * it / max(iterations, 1))
        spec = np.fft.rfft(np.clip(x, -clip_level, clip_level))
        phases = np.angle(spec[lines])
        x = _synthesize(lines, phases, n_points)
        cf = crest_factor(x)
        if cf < best_cf:
            best, best_cf = phases.copy(), cf
    return best


def design_multisine(
    *,
    peak: float = 0.1,
    f_min_hz: float = 0.25,
    f_max_hz: float = 125.0,
    n_lines: int = 512,
    n_points: int = 8192,
    sample_rate_hz: float = 2000.0,
    n_periods: int = 3,
    phases: str = "min-crest",
    iterations: int = 100,
    seed: int = 0,
) -> Multisine:
    """Equal-amplitude multisine of report Section 4.5.2.

    Parameters
    ----------
    peak : float
        Peak value of the signal [signal unit; in for a position command].
    f_min_hz, f_max_hz : float
        Band of the excited lines [Hz] (rounded to FFT bins of one period).
    n_lines : int
        Number of excited lines (report: 512).
    n_points : int
        Samples per period (report: 8192).
    sample_rate_hz : float
        Sampling rate [Hz] (report: 2000 Hz, the controller loop rate).
    n_periods : int
        Periods of the test signal (report: 3; the first is discarded as transient).
    phases : {"min-crest", "schroeder", "random"}
        Phase choice: Schroeder phases, Schroeder improved by iterative
        clipping, or uniform random phases (``seed``).
    iterations : int
        Clipping iterations for ``"min-crest"``.
    seed : int
        Seed of the random phases.

    Returns
    -------
    Multisine

    Examples
    --------
    >>> ms = design_multisine()
    >>> int(ms.lines.size), round(float(ms.frequencies_hz[0]), 3), float(ms.frequencies_hz[-1])
    (512, 0.244, 125.0)
    """
    if phases not in _PHASE_METHODS:
        raise ConfigError("multisine.phases", f"one of {_PHASE_METHODS}", phases)
    if not (peak > 0 and np.isfinite(peak)):
        raise ConfigError("multisine.peak", "a positive amplitude", peak)
    if n_periods < 2:
        raise ConfigError("multisine.n_periods", "at least 2 (the first is transient)", n_periods)
    if n_points < 4 or sample_rate_hz <= 0:
        raise ConfigError(
            "multisine.n_points", "at least 4 points and a positive rate", (n_points, sample_rate_hz)
        )
    for key, value in (("n_points", n_points), ("n_periods", n_periods), ("n_lines", n_lines)):
        if isinstance(value, bool) or int(value) != value:
            raise ConfigError(f"multisine.{key}", "a whole number", value)
    if n_lines < 1:  # no line: an all-zero signal, refused later without naming the key
        raise ConfigError("multisine.n_lines", "at least 1 line", n_lines)
    check_count(
        "multisine.n_periods", n_points * n_periods, MAX_RECORD_SAMPLES, "samples (n_points x n_periods)"
    )
    check_count("multisine.iterations", iterations, MAX_MULTISINE_ITERATIONS, "clipping iterations")
    lines = _lines(f_min_hz, f_max_hz, n_lines, n_points, sample_rate_hz)
    k = np.arange(1, lines.size + 1)
    if phases == "random":
        phi = np.random.default_rng(seed).uniform(-np.pi, np.pi, lines.size)
    else:
        phi = -np.pi * k * (k - 1) / lines.size
        if phases == "min-crest":
            phi = _min_crest_phases(lines, phi, n_points, iterations)
    x = _synthesize(lines, phi, n_points)
    x *= peak / np.max(np.abs(x))
    return Multisine(
        period=x,
        sample_rate_hz=float(sample_rate_hz),
        lines=lines,
        phases=phi,
        crest_factor=crest_factor(x),
        n_periods=int(n_periods),
    )


def report_multisine(loop_time: float, peak: float = 0.1) -> Multisine:
    """The report's multisine (Section 4.5.2) at the loop rate, its 4.096 s period kept.

    :func:`design_multisine` with ``sample_rate_hz = 1 / loop_time`` and as
    many points per period as make :data:`REPORT_PERIOD_S` (8192 at the
    report's 0.0005 s loop time), so the line spacing stays 0.244 Hz at any
    loop time.

    Parameters
    ----------
    loop_time : float
        Controller loop time [s].
    peak : float
        Peak of the position command [in] (report: 0.1).

    Examples
    --------
    >>> ms = report_multisine(0.001)
    >>> ms.n_points, ms.sample_rate_hz, ms.n_points / ms.sample_rate_hz
    (4096, 1000.0, 4.096)
    """
    return design_multisine(
        peak=peak, sample_rate_hz=1.0 / loop_time, n_points=int(round(REPORT_PERIOD_S / loop_time))
    )
