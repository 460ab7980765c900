"""Recordings of known linear systems driven by a multisine: the exact periodic steady state.

For a periodic, band-limited input ``u`` (a multisine: energy only at its lines)
the steady-state output of a linear system ``H`` is ``irfft(H(f_k) U_k)`` period by
period, exactly (no discretization of H).  Noise is white, ``level * rms(y)``.
"""

from __future__ import annotations

import numpy as np

from impedance_mil.signals.drive import multisine_metadata, write_drive
from impedance_mil.signals.multisine import design_multisine


def multisine(n_points=4096, rate=2000.0, n_lines=160, f_min=1.0, f_max=100.0, periods=6, peak=0.05):
    return design_multisine(
        peak=peak,
        n_points=n_points,
        sample_rate_hz=rate,
        n_lines=n_lines,
        f_min_hz=f_min,
        f_max_hz=f_max,
        n_periods=periods,
        iterations=20,
    )


def write_multisine_drive(folder, ms, overwrite=False, file_format="csv"):
    """The drive files of ``ms`` in ``folder`` (command in mm), as ``imil drive multisine`` writes them."""
    return write_drive(
        folder,
        "multisine",
        ms.signal,
        sample_rate_hz=ms.sample_rate_hz,
        unit="mm",
        file_format=file_format,
        multisine=multisine_metadata(ms, "min-crest"),
        overwrite=overwrite,
    )


def steady_response(ms, response):
    """``y`` [output unit] of the system with frequency response ``response(f_hz)`` to ``ms.signal``."""
    spectrum = np.fft.rfft(ms.period)
    f = np.arange(spectrum.size) * ms.sample_rate_hz / ms.n_points
    h = np.zeros(spectrum.size, dtype=complex)
    h[ms.lines] = response(f[ms.lines])
    return np.tile(np.fft.irfft(h * spectrum, ms.n_points), ms.n_periods)


def random_periodic_response(
    response, n_points=4096, periods=32, rate=2000.0, band_hz=(0.5, 150.0), peak=0.005, seed=1
):
    """A random drive (random phases at every bin of ``band_hz``, ``periods`` repeats) and its exact steady state.

    Returns ``u`` [in] and ``y`` [output unit] of the system with frequency response ``response(f_hz)``.
    """
    f = np.arange(n_points // 2 + 1) * rate / n_points
    band = (f >= band_hz[0]) & (f <= band_hz[1])
    spectrum = np.zeros(f.size, dtype=complex)
    spectrum[band] = np.exp(2j * np.pi * np.random.default_rng(seed).random(np.count_nonzero(band)))
    u = np.fft.irfft(spectrum, n_points)
    u *= peak / np.max(np.abs(u))
    h = np.zeros(f.size, dtype=complex)
    h[band] = response(f[band])
    y = np.fft.irfft(h * np.fft.rfft(u), n_points)
    return np.tile(u, periods), np.tile(y, periods)


def noisy(y, level, seed):
    if level == 0:
        return y
    return y + level * np.sqrt(np.mean(y**2)) * np.random.default_rng(seed).standard_normal(y.size)


def zpk_response(zeros_hz, poles_hz, gain, zeros_at_origin=0):
    """``H(s) = gain s^q prod(1 - s/z) / prod(1 - s/p)`` with z, p given as complex Hz (conjugates included)."""

    def h(f):
        s = 2j * np.pi * np.asarray(f, float)
        out = gain * s**zeros_at_origin * np.ones_like(s)
        for z in zeros_hz:
            out = out * (1 - s / (2 * np.pi * z))
        for p in poles_hz:
            out = out / (1 - s / (2 * np.pi * p))
        return out

    return h


def pair(f_hz, zeta):
    """The complex pair of natural frequency f [Hz] and damping zeta, in Hz."""
    re, im = -zeta * f_hz, f_hz * np.sqrt(1 - zeta**2)
    return [complex(re, im), complex(re, -im)]
