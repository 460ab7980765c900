"""The controller's output delay of N loops in the virtual lab (issue 12: "the output delay in samples").

Source: the digital hydraulic loop of Section 4.3.4, ``u_v(k) = K_e (u(k) -
x_m(k-1)) - K_p dP_m(k-1)`` limited to the valve command, applied over one
loop (N = 1, the report's controller); with N loops the command computed at
loop k is applied over loop k + N - 1.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from impedance_mil.design import design_controller, table_model
from impedance_mil.errors import ConfigError
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.lab.loop import VirtualTable, simulate, simulate_interface
from impedance_mil.lab.setup import MAX_OUTPUT_DELAY, default_sensors, ideal_sensors
from impedance_mil.plant.nonlinear import NonlinearTable, valve_command
from impedance_mil.specimens import FluidVessel
from impedance_mil.specimens.sensors import SensorSuite

from .conftest import report_parameters


@pytest.fixture(scope="module")
def table():
    return NonlinearTable.from_linear(report_parameters())


def _step(n=60, at=5, size=0.1):
    u = np.zeros(n)
    u[at:] = size
    return u


@pytest.mark.parametrize("delay", [1, 2, 4])
def test_a_step_command_reaches_the_valve_n_minus_1_loops_after_it_is_computed(table, delay):
    # Ideal sensors, the table at rest at x = 0, dP = 0: the valve command stays exactly 0
    # until the step computed at loop 5 arrives at loop 5 + N - 1, where it is K_e u.
    at, size = 5, 0.1
    run = simulate(
        table, command=_step(at=at, size=size), sensors=ideal_sensors(), quantize=False, output_delay=delay
    )
    uv = run.channels["u_v"]
    arrival = at + delay - 1
    np.testing.assert_array_equal(uv[:arrival], 0.0)
    assert uv[arrival] == pytest.approx(table.Ke * size, rel=1e-12)
    assert run.config["output_delay"] == delay


@pytest.mark.parametrize("delay", [1, 3])
def test_the_valve_receives_the_command_of_n_minus_1_loops_before(table, delay):
    # Invariant on the records of a noisy, quantized run: u_v(k) is the hydraulic loop's
    # command of loop k - N + 1, from u(k - N + 1) and the measurements of loop k - N.
    t = np.arange(800) * table.loop_time
    u = 0.05 * np.sin(2 * np.pi * 5 * t)
    run = simulate(table, command=u, seed=3, output_delay=delay)
    c = run.channels
    pa = table.parameter_array()
    for k in range(delay + 1, u.size):
        j = k - delay + 1
        assert c["u_v"][k] == valve_command(pa, c["u"][j], c["x_meas"][j - 1], c["dp_meas"][j - 1])


def test_the_two_loop_renderings_agree_with_an_output_delay(table):
    t = np.arange(1200) * table.loop_time
    u = 0.05 * np.sin(2 * np.pi * 3 * t) + 0.01 * np.sin(2 * np.pi * 31 * t)
    fast = simulate(table, command=u, seed=9, output_delay=3)
    slow = simulate_interface(VirtualTable(table, seed=9, output_delay=3), command=u)
    for name in ("x", "z", "u_v", "current", "x_meas", "dp_meas"):
        np.testing.assert_array_equal(fast.channels[name], slow.channels[name], err_msg=name)
    assert slow.config["output_delay"] == 3


@pytest.mark.parametrize("delay", [0, MAX_OUTPUT_DELAY + 1, 1.5, True])
def test_an_output_delay_that_is_not_a_whole_number_of_loops_is_refused(table, delay):
    with pytest.raises(ConfigError, match="output_delay"):
        simulate(table, command=np.zeros(3), output_delay=delay)


def test_under_control_with_filters_the_two_renderings_agree(table):
    # Invariant of the tick sequence with both new pieces in a closed loop: the tracking
    # controller reads filtered load cells and accelerometer through a 2-loop output delay
    # on the vessel (2 substeps), compiled and through the plant interface alike.
    p = report_parameters()
    design = design_controller(table_model(p), form="tracking", fc_hz=80.0, emit_warnings=False)
    controller = discretize(design.H_uz, design.H_uw, p.loop_time, fc_hz=80.0)
    a_g = 40.0 * np.sin(2 * np.pi * 3.0 * np.arange(1500) * p.loop_time)
    vessel = FluidVessel.report_default()
    suite = SensorSuite(
        tuple(
            replace(s, bandwidth_hz=250.0) if s.quantity in ("interface_force", "table_acceleration") else s
            for s in default_sensors().sensors
        )
    )
    options = dict(specimen=vessel, sensors=suite, seed=3, output_delay=2)
    fast = simulate(table, a_g=a_g, runtime=MILRuntime(controller), **options)
    slow = simulate_interface(VirtualTable(table, **options), a_g=a_g, runtime=MILRuntime(controller))
    for name in ("u", "u_w", "x", "z", "u_v", "w_lc", "z_meas"):
        a, b = fast.channels[name], slow.channels[name]
        assert np.max(np.abs(a - b)) <= 1e-12 * max(1.0, np.max(np.abs(a))), name
    assert np.max(np.abs(fast.u_w)) > 0  # the feedback path is active
