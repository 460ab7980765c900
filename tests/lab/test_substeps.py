"""The accuracy rule for RK4 substeps per loop (impedance_mil.lab.substeps; docs/lab.md, Section 2)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from impedance_mil.design import design_controller, table_model, virtual_model
from impedance_mil.errors import ConfigError
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.lab import ideal_sensors, load_run, save_run, simulate
from impedance_mil.lab.kernels import coupled_derivative
from impedance_mil.lab.plant_interface import VirtualTable, specimen_arrays
from impedance_mil.lab.substeps import (
    RK4_STEP_BOUND,
    RK4_STEP_TOLERANCE,
    choose_substeps,
    coupled_state_matrix,
    rk4_factor,
    rk4_oscillation_error,
)
from impedance_mil.plant.nonlinear import N_TABLE_STATES, NonlinearTable
from impedance_mil.signals import builtin_motion
from impedance_mil.specimens import FluidVessel
from impedance_mil.specimens.structural import LinearMDOF
from impedance_mil.virtual import presets

from .conftest import report_parameters

DEPTHS = (None, 0.0, 18.0, 30.0, 36.0, 42.0)  # bare table, then the report's water depths [in]


@pytest.fixture(scope="module")
def table():
    return NonlinearTable.from_linear(report_parameters())


def _specimen(depth):
    return None if depth is None else FluidVessel.report_default(water_depth_in=depth)


def test_step_bound_meets_the_tolerance():
    # Closed form (independent of rk4_factor): |R(i t)|^2 = 1 - t^6/72 + t^8/576 and
    # Im/Re of R(i t) = (t - t^3/6) / (1 - t^2/2 + t^4/24).  At the bound the one-step
    # error |R e^(-i t) - 1| equals the tolerance (brentq, xtol 1e-12) and both of its
    # parts, amplitude and phase error, stay below it.
    t = RK4_STEP_BOUND
    amp = math.sqrt(1 - t**6 / 72 + t**8 / 576)
    phase = math.atan2(t - t**3 / 6, 1 - t**2 / 2 + t**4 / 24)
    assert abs(rk4_factor(1j * t)) == pytest.approx(amp, rel=1e-14)
    assert abs(abs(amp * complex(math.cos(phase - t), math.sin(phase - t)) - 1) - RK4_STEP_TOLERANCE) < 1e-12
    assert 0 < 1 - amp < RK4_STEP_TOLERANCE and 0 < t - phase < RK4_STEP_TOLERANCE
    assert rk4_oscillation_error(0.99 * t) < RK4_STEP_TOLERANCE < rk4_oscillation_error(1.01 * t)


@pytest.mark.parametrize("depth", [None, 18.0, 36.0])
def test_coupled_linearization_is_the_jacobian_of_the_loop_derivative(table, depth):
    # Invariant: the coupled state matrix built from NonlinearTable.linearize and the
    # specimen's state space equals central differences of the compiled loop's own
    # derivative (coupled_derivative) at equilibrium; 1e-6 of the largest entry per
    # column (differencing error of the table's steps is ~1e-9 relative).
    spec = _specimen(depth)
    a = coupled_state_matrix(table, spec)
    arrs = specimen_arrays(spec)
    pa = table.parameter_array()
    n = a.shape[0]
    y0 = np.zeros(n)
    y0[:N_TABLE_STATES] = table.equilibrium_state()
    steps = np.r_[1e-6, 1e-5, 1e-3, 1e-3, 1e-6, 1e-3, np.full(n - N_TABLE_STATES, 1e-6)]
    for j in range(n):
        e = np.zeros(n)
        e[j] = steps[j]
        hi, lo = np.empty(n), np.empty(n)
        coupled_derivative(pa, y0 + e, *arrs, 0.0, hi)
        coupled_derivative(pa, y0 - e, *arrs, 0.0, lo)
        col = (hi - lo) / (2 * steps[j])
        assert np.max(np.abs(a[:, j] - col)) <= 1e-6 * max(np.max(np.abs(col)), 1e-12), j


@pytest.mark.parametrize("depth", DEPTHS)
def test_choice_is_the_smallest_count_within_the_bound(table, depth):
    # Definition of the rule: |lambda|_max T / n <= bound < |lambda|_max T / (n - 1).
    # The fastest eigenvalue is the valve's 110 Hz pole for the bare table and the
    # empty vessel (report Table 4.1), above the vessel's wall mode (192-400 Hz,
    # specimens/vessel.py) once the table is coupled to it.
    c = choose_substeps(table, _specimen(depth))
    wt = c.fastest_rad_s * table.loop_time
    assert c.theta <= RK4_STEP_BOUND and c.step_error <= RK4_STEP_TOLERANCE
    assert c.substeps == 1 or wt / (c.substeps - 1) > RK4_STEP_BOUND
    spec = _specimen(depth)
    wall = spec.flexible_impulsive_mode() if spec is not None else None
    if wall is None:
        assert c.fastest_rad_s == pytest.approx(2 * math.pi * 110.0, rel=1e-6)
    else:
        assert c.fastest_rad_s > 2 * math.pi * wall.frequency_hz


@pytest.fixture(scope="module")
def mil_case():
    # Benchmark case (benchmarks/bench_lab.py), first 4 s: El Centro x2 at 0.6 g, SD2.
    p = report_parameters()
    gm = builtin_motion("elcentro").time_scaled(2).scaled_to_pga(0.6).resampled(p.loop_time)
    vs = presets.get("SD2")
    design = design_controller(
        table_model(p),
        virtual_model(vs, linearization="open-fh"),
        form="standardized",
        fc_hz=80.0,
        emit_warnings=False,
    )
    ctrl = discretize(design.H_uz, design.H_uw, p.loop_time, fc_hz=80.0)
    return gm.accel[:8000], MILRuntime(ctrl, vs=vs, precision="double")


@pytest.mark.parametrize("depth", DEPTHS)
def test_auto_choice_matches_eight_substeps_on_a_mil_run(table, mil_case, depth):
    # MIL run, exact sensors without quantization and a double-precision controller (so
    # that only the integration differs; with 16-bit sensors one flipped LSB dominates).
    # Reference: 8 substeps (measured within 5e-7 of the peak of 32 substeps).
    # Tolerance 2e-4 of the peak z: a quarter of the accelerometer's LSB (0.079 in/s^2,
    # 8e-4 of the ~100 in/s^2 peak), invisible in the measured channel.  Measured
    # 1.6e-5..6.8e-5; one substep gives 4.2e-4..8.2e-4 with the vessel (18-42 in).
    a_g, runtime = mil_case
    spec = _specimen(depth)
    kw = dict(a_g=a_g, runtime=runtime, specimen=spec, sensors=ideal_sensors(), quantize=False)
    auto = simulate(table, **kw)
    ref = simulate(table, substeps=8, **kw)
    assert auto.completed and ref.completed
    assert auto.config["substeps"] == choose_substeps(table, spec).substeps
    peak = np.max(np.abs(ref.z))
    assert np.max(np.abs(auto.z - ref.z)) < 2e-4 * peak


def test_stiff_specimen_gets_enough_substeps(table):
    # A 0.5 lbf*s^2/in mass on a 3000 Hz spring (coupled to the table ~3200 Hz,
    # |lambda| T ~ 10): the old fixed default of 2 substeps lies outside RK4's
    # stability interval (|lambda| h <= 2.83) and trips an interlock; the automatic
    # choice stays within the bound, completes, and agrees with 4x its substeps to
    # 1e-4 of the peak z (measured ~5e-6 for a 1500 Hz spring).
    m = 0.5
    spec = LinearMDOF.with_modal_damping([m], [[m * (2 * math.pi * 3000.0) ** 2]], 0.02)
    t = np.arange(4000) * table.loop_time
    u = 0.05 * np.sin(2 * np.pi * 3 * t) + 0.01 * np.sin(2 * np.pi * 31 * t)
    kw = dict(command=u, specimen=spec, sensors=ideal_sensors(), quantize=False)
    fixed = simulate(table, substeps=2, **kw)
    assert fixed.trip is not None
    auto = simulate(table, **kw)
    n = auto.config["substeps"]
    assert (
        auto.completed
        and n * RK4_STEP_BOUND >= auto.config["fastest_eigenvalue_rad_s"] * table.loop_time > 2 * 2.83
    )
    ref = simulate(table, substeps=4 * n, **kw)
    assert np.max(np.abs(auto.z - ref.z)) < 1e-4 * np.max(np.abs(ref.z))


def test_explicit_count_overrides_and_is_recorded(table, tmp_path):
    vessel = FluidVessel.report_default()
    u = np.zeros(200)
    auto = simulate(table, command=u, specimen=vessel)
    assert auto.config["substeps"] == 2 and auto.config["substeps_rule"] == "auto"
    one = simulate(table, command=u, specimen=vessel, substeps=1)
    assert one.config["substeps"] == 1 and one.config["substeps_rule"] == "explicit"
    assert VirtualTable(table, specimen=vessel, substeps=5).substeps == 5
    assert VirtualTable(table, specimen=vessel).substeps == 2
    path = tmp_path / "run.h5"
    save_run(auto, path)
    cfg = load_run(path).config
    assert cfg["substeps"] == 2 and cfg["substeps_rule"] == "auto"
    assert cfg["rk4_step_bound"] == RK4_STEP_BOUND
    for bad in ("fast", 0, 1.5, True):
        with pytest.raises(ConfigError, match="substeps"):
            simulate(table, command=u, substeps=bad)
