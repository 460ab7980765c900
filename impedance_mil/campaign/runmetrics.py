"""Campaign metrics of a time history: how well the table reproduced its target.

The report judges its experiments by eye on 5 %-damped acceleration spectra
("the spectral accelerations agree well in the frequency range of 0.25 Hz to
15 Hz", Section 9.3; "accurately up to 20 Hz", Section 1.5).  Band-averaged
errors come from :func:`impedance_mil.lab.metrics.evaluate_run`; to test the
"up to f Hz" statements, this module adds:

``spectral_agreement_hz``
    the highest frequency f such that the spectra agree within
    :data:`AGREEMENT_TOLERANCE` at every oscillator frequency from 0.25 Hz to f
    (:data:`SPECTRUM_FREQUENCIES_HZ`);
``hf_ratio``
    rms of the table acceleration above :data:`HIGH_FREQUENCY_HZ` over the rms
    of the target: the high-frequency oscillation of Sections 8.3.4 and 9.4.4.
"""

from __future__ import annotations

import math

import numpy as np

from ..signals import response_spectrum

#: Relative spectral difference still counted as agreement (tool's choice; the report judges by eye).
AGREEMENT_TOLERANCE = 0.20

#: Lowest frequency of the comparison [Hz] (report Section 9.3: 0.25 Hz).
LOW_FREQUENCY_HZ = 0.25

#: Oscillator frequencies of the comparison [Hz]: 0.25 to 50 Hz, 100 log-spaced values.
SPECTRUM_FREQUENCIES_HZ = np.logspace(math.log10(LOW_FREQUENCY_HZ), math.log10(50.0), 100)

#: Frequency above which table motion counts as high-frequency oscillation [Hz] (Section 9.4.4: 15+ Hz).
HIGH_FREQUENCY_HZ = 15.0


def spectral_ratio(
    table_accel: np.ndarray, target_accel: np.ndarray, time_step: float, damping: float = 0.05
) -> np.ndarray:
    """``PSA_table / PSA_target`` at :data:`SPECTRUM_FREQUENCIES_HZ` (5 % damping by default).

    Parameters
    ----------
    table_accel, target_accel : ndarray
        Accelerations [in/s^2], same sampling.
    time_step : float
        Sample interval [s].
    """
    periods = 1.0 / SPECTRUM_FREQUENCIES_HZ
    table = response_spectrum(table_accel, time_step, periods, damping).psa
    target = response_spectrum(target_accel, time_step, periods, damping).psa
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(target > 0, table / target, np.inf)


def agreement_frequency(ratio: np.ndarray, tolerance: float = AGREEMENT_TOLERANCE) -> float:
    """Highest frequency [Hz] up to which ``|ratio - 1| <= tolerance`` holds from 0.25 Hz on.

    Returns 0 when the spectra already disagree at 0.25 Hz.
    """
    bad = np.flatnonzero(~(np.abs(ratio - 1.0) <= tolerance))
    if bad.size == 0:
        return float(SPECTRUM_FREQUENCIES_HZ[-1])
    return 0.0 if bad[0] == 0 else float(SPECTRUM_FREQUENCIES_HZ[bad[0] - 1])


def high_frequency_ratio(table_accel: np.ndarray, target_accel: np.ndarray, time_step: float) -> float:
    """rms of the table acceleration above :data:`HIGH_FREQUENCY_HZ` over the target's rms."""
    spectrum = np.fft.rfft(table_accel)
    freqs = np.fft.rfftfreq(table_accel.size, time_step)
    spectrum[freqs <= HIGH_FREQUENCY_HZ] = 0.0
    high = np.fft.irfft(spectrum, n=table_accel.size)
    target_rms = float(np.sqrt(np.mean(np.square(target_accel))))
    return float(np.sqrt(np.mean(np.square(high)))) / target_rms if target_rms > 0 else math.inf


def tracking_metrics(table_accel, target_accel, time_step: float) -> dict[str, float]:
    """``spectral_agreement_hz`` [Hz] and ``hf_ratio`` [-] of one run (see the module docstring).

    Parameters
    ----------
    table_accel : array_like
        Table acceleration z_st [in/s^2].
    target_accel : array_like
        Target acceleration (z_vs for MIL, a_g for tracking) [in/s^2].
    time_step : float
        Sample interval [s].
    """
    z = np.asarray(table_accel, dtype=float)
    r = np.asarray(target_accel, dtype=float)
    return {
        "spectral_agreement_hz": agreement_frequency(spectral_ratio(z, r, time_step)),
        "hf_ratio": high_frequency_ratio(z, r, time_step),
    }
