"""Goodness measures of tracking and MIL runs (report Sections 8.3, 9.3, Appendix C).

The report judges runs by eye (response spectra, force-displacement loops);
Appendix C asks for "a more quantitative-based indicator".  These are:

* **spectral error**: mean absolute relative error of the 5 %-damped PSA of
  the table acceleration against the target, over 0.25-15 Hz and 15-50 Hz
  (the report's accuracy claims: good up to ~20 Hz, reduced above);
* **history errors**: normalized RMS error ``rms(z - z_t)/rms(z_t)`` and peak
  error ``(max|z| - max|z_t|)/max|z_t|`` of the acceleration history;
* **energy error**: relative error of the energy dissipated by the isolator,
  ``E = integral F dx``, between the loop the table achieved (displacement
  ``x_st - x_g``, force ``w - m_vs z_st`` from the basemat's equilibrium
  ``m_vs z = w - F``) and the VS model's own loop.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from ..errors import ConfigError
from ..signals.spectrum import response_spectrum

#: Frequency bands of the spectral error [Hz].
BANDS_HZ = ((0.25, 15.0), (15.0, 50.0))
#: Oscillators per band.
POINTS_PER_BAND = 40


@dataclass(frozen=True)
class RunMetrics:
    """Errors of a run against its target (dimensionless fractions).

    Attributes
    ----------
    spectral_error_low : float
        Mean |PSA_table/PSA_target - 1| over 0.25-15 Hz.
    spectral_error_high : float
        Same over 15-50 Hz.
    nrms_error : float
        ``rms(z - z_target) / rms(z_target)``.
    peak_error : float
        ``(max|z| - max|z_target|) / max|z_target|`` (signed).
    energy_error : float or None
        ``(E_table - E_vs) / E_vs`` of the isolator's dissipated energy (MIL runs).
    """

    spectral_error_low: float
    spectral_error_high: float
    nrms_error: float
    peak_error: float
    energy_error: float | None = None

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class SpectralErrorCurve:
    """Relative 5 % PSA error of the table against the target, frequency by frequency.

    Attributes
    ----------
    frequency_hz : ndarray
        Oscillator frequencies [Hz] (geometric grid over the band).
    relative_error : ndarray
        ``PSA(z) / PSA(z_target) - 1`` at each frequency.
    """

    frequency_hz: np.ndarray
    relative_error: np.ndarray

    @property
    def mean_abs(self) -> float:
        """Mean absolute relative error (the run metrics' spectral error)."""
        return float(np.mean(np.abs(self.relative_error)))

    @property
    def max_abs(self) -> float:
        """Largest absolute relative error over the band."""
        return float(np.max(np.abs(self.relative_error)))

    @property
    def worst_frequency_hz(self) -> float:
        """Frequency [Hz] of the largest absolute relative error."""
        return float(self.frequency_hz[np.argmax(np.abs(self.relative_error))])


def spectral_error_curve(
    z,
    z_target,
    time_step: float,
    band_hz: tuple[float, float],
    damping: float = 0.05,
    n_points: int = POINTS_PER_BAND,
) -> SpectralErrorCurve:
    """Relative PSA error of ``z`` against ``z_target`` at each oscillator of a band [Hz].

    Parameters
    ----------
    z, z_target : array_like
        Achieved and target accelerations [in/s^2], same sampling.
    time_step : float
        Sampling interval [s].
    band_hz : (float, float)
        Band of oscillator frequencies [Hz].
    damping : float
        Oscillator damping ratio (default 5 %).
    n_points : int
        Oscillators, geometrically spaced over the band.
    """
    f = np.geomspace(band_hz[0], band_hz[1], n_points)
    periods = 1.0 / f
    got = response_spectrum(z, time_step, periods, damping).psa
    ref = response_spectrum(z_target, time_step, periods, damping).psa
    if np.any(ref <= 0):
        raise ConfigError("z_target", "a target with spectral content in every band")
    return SpectralErrorCurve(f, got / ref - 1.0)


def spectral_error(
    z,
    z_target,
    time_step: float,
    band_hz: tuple[float, float],
    damping: float = 0.05,
    n_points: int = POINTS_PER_BAND,
) -> float:
    """Mean absolute relative PSA error over a band [Hz] (5 % damping by default).

    Parameters as :func:`spectral_error_curve`, whose ``mean_abs`` this is.
    """
    return spectral_error_curve(z, z_target, time_step, band_hz, damping, n_points).mean_abs


def history_errors(z, z_target) -> tuple[float, float]:
    """``(normalized RMS error, signed relative peak error)`` of an acceleration history."""
    z = np.asarray(z, dtype=float)
    zt = np.asarray(z_target, dtype=float)
    rms_t = np.sqrt(np.mean(zt**2))
    if rms_t == 0:
        raise ConfigError("z_target", "a nonzero target history")
    peak_t = np.max(np.abs(zt))
    return (float(np.sqrt(np.mean((z - zt) ** 2)) / rms_t), float((np.max(np.abs(z)) - peak_t) / peak_t))


def dissipated_energy(force, displacement) -> float:
    """Energy ``integral F dx`` [lbf*in] of a force-displacement history (trapezoids)."""
    f = np.asarray(force, dtype=float)
    x = np.asarray(displacement, dtype=float)
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x)))


def vs_force_history(vs, states) -> np.ndarray:
    """Isolator force F [lbf] of a VS along recorded states (the force output of its definition)."""
    return vs.force_along(np.asarray(states, dtype=float))


def energy_error(result, vs, ground_displacement, vs_force=None) -> float:
    """Relative error of the isolator's dissipated energy, table loop vs VS loop.

    Parameters
    ----------
    result : RunResult
        A MIL run (VS states recorded).
    vs : VirtualSystem
        The built-in VS of the run.
    ground_displacement : array_like
        Ground displacement x_g [in] at the loop samples.
    vs_force : array_like, optional
        ``vs_force_history(vs, result.vs_states)`` [lbf] when the caller has it already
        (a MIL run stores it with the run file); computed otherwise.
    """
    n = result.n_samples
    xg = np.asarray(ground_displacement, dtype=float)[:n]
    f_vs = vs_force_history(vs, result.vs_states) if vs_force is None else np.asarray(vs_force, dtype=float)
    e_vs = dissipated_energy(f_vs, result.vs_states[:, 0])
    f_table = result.w_used - vs.m_vs * result.z_meas
    e_table = dissipated_energy(f_table, result.x_meas - xg)
    if e_vs == 0:
        raise ConfigError("vs", "a run in which the isolator dissipates energy")
    return (e_table - e_vs) / e_vs


def evaluate_run(result, *, vs=None, ground_displacement=None, vs_force=None) -> RunMetrics:
    """Metrics of a tracking run (target ``a_g``) or a MIL run (target ``z_vs``).

    The measured table acceleration (accelerometer) is compared with the
    target, as in the report's figures.  ``vs_force`` [lbf]: the VS model's
    isolator force along the run, when the caller has it (see :func:`energy_error`).
    """
    if result.n_samples < 4:
        raise ConfigError("result", "a run with recorded samples", result.n_samples)
    target = result.z_vs
    z = result.z_meas
    dt = result.loop_time
    low, high = (spectral_error(z, target, dt, band) for band in BANDS_HZ)
    nrms, peak = history_errors(z, target)
    energy = None
    if vs is not None and ground_displacement is not None and result.vs_states.size:
        energy = energy_error(result, vs, ground_displacement, vs_force)
    return RunMetrics(low, high, nrms, peak, energy)
