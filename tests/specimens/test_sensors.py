"""Sensors (Table 7.1, Section 7.2.2, Appendix A) and the feedback force (Sections 7.3.4, 8.3.2).

Sources: scale factors from Table 7.1 and Section 3.5 (0.2 kip/V); 16-bit,
+-10 V analog inputs from Section 7.2.2; the load-cell sum from the RMC
listing of Figure 7.9; w_FE from Eq 4-7b and Section 8.3.2; table mass
4.14 lbf*s^2/in and piston area 2.1 in^2 from Section 4.4 (Table 4.1).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.specimens import FluidVessel, RigidMass, rk4_step, sensors
from impedance_mil.specimens.sensors import (
    REPORT_CHANNELS,
    Sensor,
    SensorSuite,
    force_from_equilibrium,
    load_cell_force_kernel,
    measure_kernel,
)
from impedance_mil.units import G0

LSB = 20.0 / 2**16
M_ST = 4.14  # lbf*s^2/in, Section 4.4
A_P = 2.1  # in^2, Section 4.4


def _kernel_measure(suite, quantities, draws):
    out = np.empty(suite.n_channels)
    return measure_kernel(
        np.asarray(quantities, float),
        draws,
        suite.quantity_index,
        suite.gain,
        suite.scale,
        suite.offset,
        suite.noise_rms,
        suite.lsb,
        suite.v_low,
        suite.v_high,
        out,
    )


def test_report_scale_factors_table_7_1():
    suite = SensorSuite.report_default()
    assert suite.names == (
        "accelerometer",
        "string_pot",
        "dp_cell",
        "ALC1",
        "ALC2",
        "LC-03",
        "LC-06",
        "LC-08",
        "LC-14",
    )
    expected_scale = [0.6711 * G0, -1.25, -400.0, -1000.0, -1000.0, 200.0, 200.0, 200.0, 200.0]
    expected_offset = [0.067 * G0, 6.0, 0, 0, 0, 0, 0, 0, 0]
    np.testing.assert_allclose(suite.scale, expected_scale, rtol=1e-15)
    np.testing.assert_allclose(suite.offset, expected_offset, rtol=1e-15)
    # Section 3.5: "each load cell reads a maximum shear force of 2 kip" at 10 V.
    assert suite.sensors[suite.index("LC-03")].to_physical(10.0) == pytest.approx(2000.0)


def test_quantization_step_is_20_V_over_2_to_16():
    suite = SensorSuite.report_default()
    np.testing.assert_array_equal(suite.lsb, LSB)
    assert REPORT_CHANNELS[0].lsb_v == pytest.approx(3.0517578125e-4, rel=1e-15)


def test_in_range_signal_round_trips_within_half_lsb():
    suite = SensorSuite.report_default()
    rng = np.random.default_rng(7)
    volts = rng.uniform(-9.99, 9.99, size=(2000, suite.n_channels))
    values = suite.offset + suite.scale * volts
    readings = suite.measure(values)
    # Rounding to the nearest code: error <= LSB/2 in volts, times |scale| in units
    # (plus 1e-9 relative for floating-point rounding).
    bound = 0.5 * LSB * np.abs(suite.scale) * (1 + 1e-9)
    assert np.all(np.abs(readings.values - values) <= bound)
    assert np.max(np.abs(readings.values - values) / bound) > 0.9  # the bound is attained
    # Readings sit on the converter's codes.
    codes = readings.volts / LSB
    np.testing.assert_allclose(codes, np.round(codes), atol=1e-9)


def test_saturation_at_plus_minus_10_V():
    suite = SensorSuite.report_default()
    big = suite.offset + suite.scale * 25.0
    small = suite.offset - suite.scale * 25.0
    # Two's-complement 16-bit converter: -10 V is code -32768, +10 V reads one LSB below.
    np.testing.assert_allclose(suite.measure(big).volts, 10.0 - LSB, rtol=1e-15)
    np.testing.assert_allclose(suite.measure(small).volts, -10.0, rtol=1e-15)
    # A string pot (-1.25 in/V, +6 in) reads between -6.5 and 18.5 in.
    pot = suite.index("string_pot")
    assert suite.measure(suite.channel_values(table_displacement=-100.0)).values[pot] == pytest.approx(
        -1.25 * (10.0 - LSB) + 6.0
    )
    # A conditioner that saturates earlier limits the reading there.
    low = SensorSuite((Sensor("a", "table_acceleration", "in/s**2", 1.0, saturation_v=5.0),))
    assert low.measure([100.0]).volts[0] == pytest.approx(5.0, abs=LSB)


def test_noise_rms_matches_setting():
    noise = 0.01  # V rms, 33 LSB: quantization adds LSB^2/12, negligible (4e-5 relative)
    suite = SensorSuite.report_default(noise_rms_v=noise)
    n = 40000
    values = np.broadcast_to(
        suite.channel_values(table_displacement=1.0, differential_pressure=100.0), (n, suite.n_channels)
    )
    readings = suite.measure(values, np.random.default_rng(11))
    err_v = (readings.values - values) / suite.scale
    rms = np.sqrt(np.mean(err_v**2, axis=0))
    # Sample rms of n Gaussian draws has relative std 1/sqrt(2n) = 0.35 %; 4 sigma = 1.4 %.
    np.testing.assert_allclose(rms, math.sqrt(noise**2 + LSB**2 / 12), rtol=4 / math.sqrt(2 * n))
    assert np.all(np.abs(np.mean(err_v, axis=0)) < 4 * noise / math.sqrt(n))


def test_noise_is_reproducible_and_needs_a_generator():
    suite = SensorSuite.report_default(noise_rms_v={"accelerometer": 0.02})
    assert suite.noise_rms[0] == 0.02 and np.all(suite.noise_rms[1:] == 0)
    values = suite.channel_values(table_acceleration=100.0)
    a = suite.measure(values, np.random.default_rng(3)).values
    b = suite.measure(values, np.random.default_rng(3)).values
    np.testing.assert_array_equal(a, b)
    with pytest.raises(ConfigError, match="rng"):
        suite.measure(values)
    with pytest.raises(ConfigError, match="noise_rms_v"):
        suite.with_noise({"nonexistent": 1.0})


def test_kernel_equals_python_measure():
    # Same seed -> same draws -> identical readings from the compiled kernel
    # and the numpy reference (generated code = runtime).
    suite = SensorSuite.report_default(noise_rms_v=0.003)
    rng = np.random.default_rng(5)
    q = rng.normal(size=(200, 5)) * [300.0, 2.0, 800.0, 3000.0, 4000.0]
    values = suite.channel_values(*q.T)
    python = suite.measure(values, np.random.default_rng(99)).values
    draws = suite.draw_noise(np.random.default_rng(99), len(q))
    compiled = np.array([_kernel_measure(suite, q[k], draws[k]) for k in range(len(q))])
    np.testing.assert_allclose(compiled, python, rtol=0, atol=1e-9)


def test_reaction_load_cells_signs_and_equal_shares():
    suite = SensorSuite.report_default()
    w = 1234.5  # lbf
    values = suite.channel_values(interface_force=w)
    cells = [suite.index(n) for n in sensors.REACTION_CELLS]
    # Equal shares w/4; LC-14 (on _AI[8], subtracted in the RMC sum) reads the other sign.
    np.testing.assert_allclose(values[cells], [-w / 4, -w / 4, -w / 4, w / 4])
    # RMC listing (Figure 7.9): w := -(_AI[5] + _AI[6] + _AI[7] - _AI[8]) * 200.0
    volts = suite.measure(values).volts[cells]
    rmc = -(volts[0] + volts[1] + volts[2] - volts[3]) * 200.0
    readings = suite.measure(values).values
    assert suite.load_cell_force(readings) == pytest.approx(rmc, rel=1e-12)
    assert load_cell_force_kernel(readings, suite.load_cell_weights) == pytest.approx(rmc, rel=1e-12)
    # Each cell is off by at most LSB/2 * 200 lbf/V.
    assert abs(rmc - w) <= 4 * 0.5 * LSB * 200.0


def _table_with_specimen(specimen, actuator_force, dt):
    """Table obeying Eq 4-7b (m_st z = A_p dP + w) carrying ``specimen``; returns z, dP, w.

    With w = C x + D z, Eq 4-7b gives z = (F + C x) / (m_st - D), so the
    coupled system is x' = (A + B C / m) x + (B / m) F with m = m_st - D,
    integrated exactly enough by the RK4 kernel with substeps.
    """
    ss = specimen.state_space()
    m = M_ST - ss.D
    a_c = ss.A + np.outer(ss.B, ss.C) / m
    b_c, c_z = ss.B / m, ss.C / m
    n_sub = max(1, int(np.ceil(np.max(np.abs(np.linalg.eigvals(a_c)), initial=0.0) * dt / 1.4)))
    x = np.zeros(ss.n_states)
    z, w = np.zeros(actuator_force.size), np.zeros(actuator_force.size)
    z[0] = actuator_force[0] / m
    w[0] = ss.output(x, z[0])
    for k in range(actuator_force.size - 1):
        f0, f1 = actuator_force[k], actuator_force[k + 1]
        for j in range(n_sub):
            fa, fb = f0 + (f1 - f0) * j / n_sub, f0 + (f1 - f0) * (j + 1) / n_sub
            z[k + 1] = rk4_step(a_c, b_c, c_z, 1.0 / m, x, fa, fb, dt / n_sub, x)
        w[k + 1] = ss.output(x, z[k + 1])  # the specimen's own force, -sum m a
    return z, actuator_force / A_P, w


@pytest.mark.parametrize(
    "specimen", [RigidMass(3600.0), FluidVessel.report_default()], ids=["rigid", "vessel"]
)
def test_w_fe_equals_true_interface_force(specimen):
    t = np.arange(0, 2.0, 5e-4)
    force = 2500.0 * np.sin(2 * np.pi * 1.3 * t) + 800.0 * np.sin(2 * np.pi * 17.0 * t)
    z, dp, w_true = _table_with_specimen(specimen, force, 5e-4)
    # Exact data: w_FE reproduces w to rounding.
    np.testing.assert_allclose(
        force_from_equilibrium(z, dp, M_ST, A_P), w_true, atol=1e-9 * np.max(np.abs(w_true))
    )
    # Through the noiseless 16-bit sensors: error <= m_st*LSB/2*|scale_acc| + A_p*LSB/2*400.
    suite = SensorSuite.report_default()
    meas = suite.measure(
        suite.channel_values(table_acceleration=z, differential_pressure=dp, interface_force=w_true)
    ).values
    w_fe = force_from_equilibrium(meas[:, 0], meas[:, 2], M_ST, A_P)
    bound = 0.5 * LSB * (M_ST * 0.6711 * G0 + A_P * 400.0)
    assert np.max(np.abs(w_fe - w_true)) <= bound * (1 + 1e-9)
    w_lc = suite.load_cell_force(meas)
    assert np.max(np.abs(w_lc - w_true)) <= 4 * 0.5 * LSB * 200.0 * (1 + 1e-9)
    # Appendix C's A_p dP - m_st z is the negative of w (docs/errata.md).
    np.testing.assert_allclose(A_P * dp - M_ST * z, -w_true, atol=1e-9 * np.max(np.abs(w_true)))
    if isinstance(specimen, RigidMass):
        np.testing.assert_allclose(w_true, -specimen.total_mass * z, rtol=1e-12)


def test_invalid_sensor_definitions():
    with pytest.raises(ConfigError, match="scale"):
        Sensor("x", "table_displacement", "in", 0.0)
    with pytest.raises(ConfigError, match="quantity"):
        Sensor("x", "temperature", "degF", 1.0)
    with pytest.raises(ConfigError, match="sensors"):
        SensorSuite((REPORT_CHANNELS[0], REPORT_CHANNELS[0]))
    with pytest.raises(ConfigError, match="values"):
        SensorSuite.report_default().measure(np.zeros(3))
    assert SensorSuite.report_default().to_dict()["sensors"][5]["name"] == "LC-03"
