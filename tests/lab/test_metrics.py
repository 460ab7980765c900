"""Run metrics (lab/metrics.py) against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.lab.metrics import dissipated_energy, history_errors, spectral_error


def test_history_errors_closed_form():
    # z = 1.1 z_t: normalized RMS error 0.1 and peak error +0.1 (exact).
    t = np.linspace(0, 10, 5001)
    zt = np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.1 * t)
    nrms, peak = history_errors(1.1 * zt, zt)
    assert nrms == pytest.approx(0.1, rel=1e-12) and peak == pytest.approx(0.1, rel=1e-12)


def test_dissipated_energy_of_viscous_loop():
    # F = c v, x = A sin(w t) over one cycle: E = pi c w A^2 (closed form);
    # trapezoids on 20 000 samples: 1e-6 relative.
    c, A, w = 50.0, 0.8, 2 * np.pi * 1.25
    t = np.linspace(0, 2 * np.pi / w, 20001)
    x = A * np.sin(w * t)
    e = dissipated_energy(c * A * w * np.cos(w * t), x)
    assert e == pytest.approx(np.pi * c * w * A**2, rel=1e-6)


def test_spectral_error_is_relative_psa_error():
    # PSA is linear in the input: a 1.2x record has error 0.2 in every band (exact
    # up to rounding); an identical record has error 0.
    rng = np.random.default_rng(0)
    a = np.convolve(rng.standard_normal(8000), np.ones(5) / 5, mode="same") * 100
    assert spectral_error(a, a, 0.0005, (0.25, 15.0)) == 0.0
    assert spectral_error(1.2 * a, a, 0.0005, (15.0, 50.0)) == pytest.approx(0.2, rel=1e-9)


def test_zero_target_is_rejected():
    with pytest.raises(ConfigError, match="z_target"):
        history_errors(np.ones(10), np.zeros(10))
