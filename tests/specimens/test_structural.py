"""Rigid mass and linear MDOF specimens: closed forms and the w = -sum m a contract."""

from __future__ import annotations

import math

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.specimens import LinearMDOF, RigidMass, rk4_step
from impedance_mil.units import G0 as G


def test_rigid_mass_has_no_states_and_w_is_minus_m_z():
    spec = RigidMass(1600.0)
    ss = spec.state_space()
    assert ss.n_states == 0
    assert ss.D == pytest.approx(-1600.0 / G, rel=1e-5)
    assert spec.total_weight == pytest.approx(1600.0, rel=1e-12)
    assert spec.impedance().num.tolist() == pytest.approx([-1600.0 / G], rel=1e-5)
    assert ss.output(np.zeros(0), 2.0) == pytest.approx(-2.0 * 1600.0 / G, rel=1e-5)
    with pytest.raises(ConfigError, match="weight_lbf"):
        RigidMass(0.0)


def test_sdof_matches_closed_form():
    # Base-excited SDOF: w/z = -m (2 zeta w s + w^2) / (s^2 + 2 zeta w s + w^2).
    m, f_n, zeta = 2.0, 5.0, 0.04
    w_n = 2 * math.pi * f_n
    spec = LinearMDOF.with_modal_damping([m], [[m * w_n**2]], zeta)
    f = np.array([0.1, 1.0, 4.9, 5.0, 5.1, 30.0, 300.0])
    s = 2j * math.pi * f
    expected = -m * (2 * zeta * w_n * s + w_n**2) / (s**2 + 2 * zeta * w_n * s + w_n**2)
    np.testing.assert_allclose(spec.state_space().frequency_response(f), expected, rtol=1e-12)
    np.testing.assert_allclose(spec.impedance().frequency_response(f), expected, rtol=1e-9)


def test_shear_building_frequencies_and_modal_damping():
    # Two equal floors and stories: w^2 = (k/m) (3 -+ sqrt 5) / 2 (Chopra Ex. 10.1 form).
    weight, k = 1000.0, 500.0
    spec = LinearMDOF.shear_building([weight, weight], [k, k], [0.02, 0.05], base_weight_lbf=200.0)
    modes = spec.modes()
    m = weight / G
    expected = np.sqrt(k / m * np.array([(3 - 5**0.5) / 2, (3 + 5**0.5) / 2])) / (2 * math.pi)
    np.testing.assert_allclose(modes.frequencies_hz, expected, rtol=1e-5)
    np.testing.assert_allclose(modes.damping_ratios, [0.02, 0.05], rtol=1e-10)
    assert modes.effective_masses.sum() == pytest.approx(2 * m, rel=1e-10)
    assert spec.total_weight == pytest.approx(2200.0, rel=1e-12)
    assert spec.impedance().dcgain() == pytest.approx(-spec.total_mass, rel=1e-9)


def test_output_equals_minus_sum_of_mass_times_absolute_acceleration():
    # The contract: w = -r^T M (u'' + r z) - m_b z at any state and input.
    rng = np.random.default_rng(1)
    M = np.array([[2.0, 0.3], [0.3, 1.0]])
    K = np.array([[400.0, -150.0], [-150.0, 150.0]])
    spec = LinearMDOF.with_modal_damping(M, K, 0.05, influence=[1.0, 0.8], base_mass=0.7)
    ss = spec.state_space()
    for _ in range(5):
        x, z = rng.normal(size=4), rng.normal()
        accel_rel = ss.derivative(x, z)[2:]
        absolute = accel_rel + spec.influence * z
        expected = -spec.influence @ M @ absolute - 0.7 * z
        assert ss.output(x, z) == pytest.approx(expected, rel=1e-12)


def test_rk4_kernel_reaches_frequency_response_in_steady_state():
    # Invariant: time integration of the state space (compiled RK4, 2 kHz)
    # gives the amplitude and phase of the frequency response at steady state.
    m, f_n, zeta, f = 1.5, 8.0, 0.1, 6.0
    spec = LinearMDOF.with_modal_damping([m], [[m * (2 * math.pi * f_n) ** 2]], zeta)
    ss = spec.state_space()
    dt, n = 5e-4, 8000  # 4 s, > 30 time constants of 1/(zeta w_n)
    t = np.arange(n + 1) * dt
    z = np.sin(2 * math.pi * f * t)
    x = np.zeros(ss.n_states)
    w = np.zeros(n + 1)
    for k in range(n):
        w[k + 1] = rk4_step(ss.A, ss.B, ss.C, ss.D, x, z[k], z[k + 1], dt, x)
    h = ss.frequency_response(f)[0]
    tail = t > 3.0
    expected = np.abs(h) * np.sin(2 * math.pi * f * t[tail] + np.angle(h))
    # RK4 error at w dt = 0.025 is ~1e-8; 1e-4 of the amplitude is generous.
    assert np.max(np.abs(w[tail] - expected)) < 1e-4 * np.abs(h)


def test_rk4_substeps_for_stiff_modes():
    ss = LinearMDOF.with_modal_damping([1.0], [[(2 * math.pi * 1000.0) ** 2]], 0.02).state_space()
    n = ss.rk4_substeps(5e-4)
    # |lambda| dt / n must stay inside RK4's stability interval on the imaginary axis (2.83).
    assert 2 * math.pi * 1000.0 * 5e-4 / n < 2.83
    assert LinearMDOF.with_modal_damping([1.0], [[1.0]], 0.02).state_space().rk4_substeps(5e-4) == 1


def test_invalid_matrices_raise_config_error():
    with pytest.raises(ConfigError, match="stiffness"):
        LinearMDOF([1.0, 1.0], [[1.0, 2.0], [0.0, 1.0]], np.zeros((2, 2)))
    with pytest.raises(ConfigError, match="mass"):
        LinearMDOF([1.0, -1.0], np.eye(2), np.zeros((2, 2)))
    with pytest.raises(ConfigError, match="damping"):
        LinearMDOF([1.0], [[1.0]], [[-0.1]])
    with pytest.raises(ConfigError, match="influence"):
        LinearMDOF([1.0], [[1.0]], [[0.1]], influence=[1.0, 1.0])
    with pytest.raises(ConfigError, match="story_stiffness"):
        LinearMDOF.shear_building([1.0, 1.0], [1.0], 0.05)
