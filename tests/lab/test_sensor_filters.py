"""Anti-alias filters of the sensor channels in the virtual lab (issue 12: "a bandwidth (anti-alias filter)").

Sources: the Butterworth low-passes' closed forms ``H(s) = wc / (s + wc)`` and
``wc^2 / (s^2 + sqrt 2 wc s + wc^2)``; the first-order hold's response to a
sine, ``sinc^2(f h)`` (a triangle kernel of width 2h), which is what the
filter sees of a signal known at the RK4 substep boundaries joined linearly.
The report's channels have no filter (Table 7.1 lists none).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.lab.loop import VirtualTable, simulate, simulate_interface
from impedance_mil.lab.setup import default_sensors, first_order_hold, ideal_sensors, sensor_arrays
from impedance_mil.plant.nonlinear import NonlinearTable
from impedance_mil.specimens import FluidVessel
from impedance_mil.specimens.sensors import Sensor, SensorSuite

from .conftest import report_parameters

#: Channels given a filter in these tests (the others read as today).
FILTERED = ("table_displacement", "table_acceleration")


@pytest.fixture(scope="module")
def table():
    return NonlinearTable.from_linear(report_parameters())


def _filtered(suite: SensorSuite, bandwidth_hz: float, order: int = 2, quantities=FILTERED) -> SensorSuite:
    return SensorSuite(
        tuple(
            replace(s, bandwidth_hz=bandwidth_hz, filter_order=order) if s.quantity in quantities else s
            for s in suite.sensors
        )
    )


def _phasor(t, y, f_hz):
    """Complex amplitude of the ``f_hz`` component of ``y(t)`` (least squares with an offset)."""
    X = np.column_stack([np.sin(2 * np.pi * f_hz * t), np.cos(2 * np.pi * f_hz * t), np.ones(t.size)])
    a = np.linalg.lstsq(X, y, rcond=None)[0]
    return a[0] + 1j * a[1]


@pytest.mark.parametrize(
    "f_hz, bandwidth_hz, order, tol",
    [
        # measured |ratio / expected - 1| (x, z): 2.3e-6, 5.8e-6; 1.1e-6, 5.3e-6; 4.7e-6, 2.2e-6
        # (the plant's harmonics and RK4); without the sinc^2 factor 3.3e-4, 3.3e-4, 3.0e-3
        (20.0, 200.0, 2, 2e-5),
        (20.0, 100.0, 1, 2e-5),
        (60.0, 100.0, 2, 2e-5),
    ],
)
def test_a_filtered_channel_reads_the_filters_gain_and_phase(table, f_hz, bandwidth_hz, order, tol):
    # A sine command through the lab (bare table, one substep of h = T): the reading of a
    # filtered channel over the true signal, at the sine's frequency, is the filter's
    # closed form times the first-order hold's sinc^2(f h) (3.3e-4 at 20 Hz, no phase).
    T = table.loop_time
    suite = _filtered(ideal_sensors(), bandwidth_hz, order)
    t = np.arange(int(round(2.0 / T))) * T
    run = simulate(table, command=0.02 * np.sin(2 * np.pi * f_hz * t), sensors=suite, quantize=False)
    h = T / run.config["substeps"]
    wc = 2 * np.pi * bandwidth_hz
    s = 2j * np.pi * f_hz
    closed = wc / (s + wc) if order == 1 else wc**2 / (s**2 + np.sqrt(2) * wc * s + wc**2)
    expected = closed * np.sinc(f_hz * h) ** 2
    keep = t > 1.0  # the transient of the table's start has died out
    for true, read in (("x", "x_meas"), ("z", "z_meas")):
        ratio = _phasor(t[keep], run.channels[read][keep], f_hz) / _phasor(
            t[keep], run.channels[true][keep], f_hz
        )
        assert abs(ratio / expected - 1.0) < tol, (true, ratio, expected)
    # the unfiltered dP channel reads the true dP (to the 1e-14 V step of quantize=False)
    np.testing.assert_allclose(run.channels["dp_meas"], run.channels["dp"], rtol=0, atol=1e-9)


def test_no_bandwidth_is_the_channel_as_before_and_the_plant_never_sees_a_filter(table):
    # Invariant: a filter on the accelerometer (which nothing feeds back in open loop; the
    # hydraulic loop reads x_meas and dP_meas) changes that channel's readings only: the
    # plant's trajectory and every other channel are the same to the last bit.
    T = table.loop_time
    t = np.arange(2000) * T
    u = 0.03 * np.sin(2 * np.pi * 7 * t)
    plain = simulate(table, command=u, seed=4)
    accel = simulate(
        table, command=u, seed=4, sensors=_filtered(default_sensors(), 150.0, 2, ("table_acceleration",))
    )
    for name in ("x", "v", "z", "dp", "u_v", "x_meas", "dp_meas", "w_lc"):
        np.testing.assert_array_equal(accel.channels[name], plain.channels[name], err_msg=name)
    assert np.max(np.abs(accel.channels["z_meas"] - plain.channels["z_meas"])) > 1.0  # in/s^2: it acts


def test_a_very_wide_filter_reads_as_no_filter(table):
    # Limit: with the bandwidth 1000 times the loop rate the filter's lag is ~1e-7 s; the
    # readings equal the unfiltered ones to the quantization (one 16-bit step at most).
    T = table.loop_time
    t = np.arange(1500) * T
    u = 0.03 * np.sin(2 * np.pi * 7 * t)
    plain = simulate(table, command=u, seed=2)
    wide = simulate(table, command=u, seed=2, sensors=_filtered(default_sensors(), 1000.0 / T))
    step = 1.25 * 20.0 / 2**16  # string pot: 1.25 in/V over the 0.305 mV step
    assert np.max(np.abs(wide.channels["x_meas"] - plain.channels["x_meas"])) <= step * (1 + 1e-9)


@pytest.mark.parametrize("specimen", [None, FluidVessel.report_default()])
def test_the_two_loop_renderings_agree_with_filters(table, specimen):
    # Invariant of the tick sequence: the compiled loop and the plant interface step the
    # same filters with the same kernels (the vessel takes 2 substeps: a filter step inside
    # the loop and one at the sensing).
    T = table.loop_time
    t = np.arange(1500) * T
    u = 0.05 * np.sin(2 * np.pi * 3 * t) + 0.01 * np.sin(2 * np.pi * 31 * t)
    suite = _filtered(default_sensors(), 120.0, 2, FILTERED + ("interface_force",))
    fast = simulate(table, command=u, specimen=specimen, sensors=suite, seed=5)
    slow = simulate_interface(VirtualTable(table, specimen=specimen, sensors=suite, seed=5), command=u)
    for name in ("x", "z", "w", "u_v", "x_meas", "z_meas", "dp_meas", "w_lc", "w_fe"):
        a, b = fast.channels[name], slow.channels[name]
        assert np.max(np.abs(a - b)) <= 1e-12 * max(1.0, np.max(np.abs(a))), name


def test_first_order_hold_is_exact_for_a_ramp():
    # x' = -a x + a u with u = t (a ramp): x(t) = t - 1/a + (x0 + 1/a) e^{-a t} (closed form).
    a, h, x0 = 700.0, 3e-4, 0.2
    phi, g0, g1 = first_order_hold(np.array([[-a]]), np.array([a]), h)
    x = x0
    for k in range(10):
        x = phi[0, 0] * x + g0[0] * (k * h) + g1[0] * ((k + 1) * h)
    t = 10 * h
    assert x == pytest.approx(t - 1 / a + (x0 + 1 / a) * np.exp(-a * t), rel=1e-12)


def test_a_first_order_filter_leaves_its_padding_state_at_zero():
    suite = _filtered(ideal_sensors(), 50.0, 1, ("table_displacement",))
    f = sensor_arrays(suite, substep_s=1e-3).filters
    assert f.channel.tolist() == [suite.names.index("string_pot")]
    np.testing.assert_array_equal(f.phi[0, 1], [0.0, 1.0])
    np.testing.assert_array_equal([f.g0[0, 1], f.g1[0, 1]], [0.0, 0.0])


@pytest.mark.parametrize(
    "fields, key",
    [
        ({"bandwidth_hz": 0.0}, "x.bandwidth_hz"),
        ({"bandwidth_hz": float("inf")}, "x.bandwidth_hz"),
        ({"bandwidth_hz": 100.0, "filter_order": 3}, "x.filter_order"),
    ],
)
def test_a_sensor_refuses_a_filter_that_is_not_one(fields, key):
    with pytest.raises(ConfigError, match=key):
        Sensor("x", "table_displacement", "in", 1.0, **fields)


def test_filters_need_the_substep():
    with pytest.raises(ConfigError, match="substep_s"):
        sensor_arrays(_filtered(ideal_sensors(), 100.0))
