"""Multisine design and H1 FRF estimation (signals/multisine.py, signals/frf.py).

References: report Section 4.5.2 (512 lines, 0.25-125 Hz, 8192 points at
2000 Hz, 3 periods); closed-form responses of known linear systems.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.signal

from impedance_mil.errors import ConfigError
from impedance_mil.signals.frf import FRF, estimate_frf, fit_frf
from impedance_mil.signals.multisine import crest_factor, design_multisine


@pytest.fixture(scope="module")
def report_multisine():
    return design_multisine(peak=1.0, iterations=60)


def test_report_multisine_layout(report_multisine):
    # Section 4.5.2: 512 equal lines 0.25..125 Hz, 8192 points, 3 periods at 2000 Hz.
    ms = report_multisine
    assert ms.lines.size == 512 and ms.n_points == 8192 and ms.n_periods == 3
    assert ms.frequencies_hz[0] == pytest.approx(0.244, abs=1e-3)
    assert ms.frequencies_hz[-1] == pytest.approx(125.0)
    assert ms.duration == pytest.approx(3 * 4.096)
    spec = np.abs(np.fft.rfft(ms.period))
    on = spec[ms.lines]
    assert np.ptp(on) / np.mean(on) < 1e-9  # equal amplitudes
    off = np.delete(spec, ms.lines)
    assert np.max(off) < 1e-9 * np.mean(on)  # nothing between the lines
    assert np.max(np.abs(ms.period)) == pytest.approx(1.0)


def test_crest_factor_minimization_beats_schroeder(report_multisine):
    # Schroeder phases give ~1.7 for a flat multisine (Schoukens et al. 2012);
    # iterative clipping must improve on them, and stay above sqrt(2)... not
    # necessarily: a multisine can go below a sine's sqrt(2), so only compare.
    schroeder = design_multisine(phases="schroeder")
    assert 1.4 < schroeder.crest_factor < 2.0
    assert report_multisine.crest_factor < schroeder.crest_factor - 0.05
    rand = design_multisine(phases="random", seed=3)
    assert rand.crest_factor > schroeder.crest_factor


def test_crest_factor_of_a_sine_is_sqrt2():
    # Definition peak/RMS (Schoukens et al. 2012): sqrt(2) for one sine, exact.
    t = np.arange(1000) / 1000
    assert crest_factor(np.sin(2 * np.pi * 5 * t)) == pytest.approx(np.sqrt(2), rel=1e-12)


def _plant():
    # 2nd-order system, f_n = 12 Hz, zeta = 0.3, static gain 2 (closed form).
    wn, z = 2 * np.pi * 12, 0.3
    return ([2 * wn**2], [1, 2 * z * wn, wn**2])


def _simulate(ms, noise=0.0, seed=0):
    num, den = _plant()
    dnum, dden, _ = scipy.signal.cont2discrete((num, den), ms.time_step, method="zoh")
    u = ms.signal
    y = scipy.signal.lfilter(dnum.ravel(), dden, u)
    if noise:
        y = y + noise * np.std(y) * np.random.default_rng(seed).standard_normal(y.size)
    return u, y, (dnum.ravel(), dden)


def test_h1_recovers_known_system(report_multisine):
    # Reference: the exact frequency response of the ZOH-discretized system
    # (scipy.signal.freqz); noiseless periodic data -> errors ~1e-10 (after the
    # first period, the 12 Hz / 30 % transient has decayed by ~1e-40).
    ms = report_multisine
    u, y, (b, a) = _simulate(ms)
    frf = estimate_frf(u, y, ms.n_points, ms.sample_rate_hz, lines=ms.lines)
    _, ref = scipy.signal.freqz(b, a, worN=frf.frequency_hz, fs=ms.sample_rate_hz)
    assert frf.n_averages == 2
    assert np.max(np.abs(frf.response / ref - 1)) < 1e-8
    assert np.min(frf.coherence) > 1 - 1e-10


def test_h1_with_noise_has_lower_coherence():
    # 5 % output noise, 10 averaged periods: coherence drops below 1 where the
    # response is small; where coherence > 0.98 the H1 relative standard
    # deviation is sqrt((1-g)/(2 n g)) < 0.032, so every such line is within
    # 0.15 (~4.5 sigma) of the truth.
    ms = design_multisine(n_points=2048, n_lines=100, f_max_hz=100.0, n_periods=11, phases="schroeder")
    u, y, (b, a) = _simulate(ms, noise=0.05)
    frf = estimate_frf(u, y, ms.n_points, ms.sample_rate_hz, lines=ms.lines)
    _, ref = scipy.signal.freqz(b, a, worN=frf.frequency_hz, fs=ms.sample_rate_hz)
    good = frf.coherence > 0.98
    assert frf.n_averages == 10
    assert good.sum() > 20 and np.min(frf.coherence) < 0.9
    assert np.max(np.abs(frf.response[good] / ref[good] - 1)) < 0.15


def _model(params, f_hz):
    s = 2j * np.pi * f_hz
    wn = 2 * np.pi * params["fn"]
    return params["k"] * wn**2 / (s**2 + 2 * params["zeta"] * wn * s + wn**2)


@pytest.mark.parametrize("noise, tol", [(0.0, 1e-6), (0.05, 0.03)])
def test_fit_recovers_parameters(noise, tol):
    # Continuous model fitted to the continuous response of the same system
    # (sampled with 8 periods of a 2048-point multisine, H1 averaged over 7).
    # Noiseless: exact recovery (1e-6); 5 % noise: within 3 %.
    f = np.arange(1, 400) * 2000 / 2048
    true = {"k": 2.0, "fn": 12.0, "zeta": 0.3}
    h = _model(true, f)
    rng = np.random.default_rng(4)
    meas = h * (1 + noise * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    frf = FRF(f, meas, np.full(f.size, 1.0 / (1.0 + noise**2 + 1e-12)), 7)
    fit = fit_frf(frf, _model, {"k": 1.0, "fn": 9.0, "zeta": 0.5}, f_range_hz=(0.5, 100))
    assert fit.success
    for name, value in true.items():
        assert fit.parameters[name] == pytest.approx(value, rel=tol)


def test_bad_requests_raise():
    with pytest.raises(ConfigError, match="n_lines"):
        design_multisine(n_lines=5000)
    with pytest.raises(ConfigError, match="n_points"):
        estimate_frf(np.zeros(100), np.zeros(100), 30, 1.0)
    with pytest.raises(ConfigError, match="phases"):
        design_multisine(phases="bogus")
