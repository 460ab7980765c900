"""The sampled-data loop: compiled path vs Python plant interface, safety trips, run files."""

from __future__ import annotations

import os
import pickle

import h5py
import numpy as np
import pytest

from impedance_mil.design import design_controller, table_model
from impedance_mil.errors import ConfigError, DataFileError, LimitTripped
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.lab.loop import VirtualTable, simulate, simulate_interface
from impedance_mil.lab.plant_interface import PlantInterface
from impedance_mil.lab.reference import ScipyTable
from impedance_mil.lab.results import load_run, save_run
from impedance_mil.lab.setup import SafetyLimits, ideal_sensors
from impedance_mil.plant.nonlinear import NonlinearTable
from impedance_mil.specimens import FluidVessel, RigidMass, SpecimenStateSpace

from .conftest import report_parameters

T = 500e-6


@pytest.fixture(scope="module")
def table():
    return NonlinearTable.from_linear(report_parameters())


def _command(n, seed=0):
    t = np.arange(n) * T
    return 0.05 * np.sin(2 * np.pi * 3 * t) + 0.01 * np.sin(2 * np.pi * 31 * t)


@pytest.mark.parametrize("specimen", [None, RigidMass(1200.0), FluidVessel.report_default()])
def test_interface_path_equals_compiled_path(table, specimen):
    # Invariant: the Python PlantInterface loop and the compiled loop call the same
    # kernels in the same order with the same noise draws -> identical to 1e-12.
    u = _command(3000)
    fast = simulate(table, command=u, specimen=specimen, seed=7)
    plant = VirtualTable(table, specimen=specimen, seed=7)
    assert isinstance(plant, PlantInterface)
    slow = simulate_interface(plant, command=u)
    for name in ("x", "v", "dp", "z", "w", "u_v", "x_meas", "dp_meas", "z_meas", "w_lc", "w_fe"):
        a, b = fast.channels[name], slow.channels[name]
        assert np.max(np.abs(a - b)) <= 1e-12 * max(1.0, np.max(np.abs(a))), name


@pytest.mark.parametrize("precision", ["single", "double"])
def test_interface_path_equals_compiled_path_under_control(table, precision):
    # Invariant: with the tracking controller in the loop the two paths also agree, and
    # the recorded u_w is the controller's own H_uw output in its arithmetic, so that
    # u_z + u_w = u holds exactly (the record once recomputed u_w in float64 beside a
    # float32 controller).
    p = report_parameters()
    design = design_controller(table_model(p), form="tracking", fc_hz=80.0, emit_warnings=False)
    controller = discretize(design.H_uz, design.H_uw, p.loop_time, fc_hz=80.0)
    a_g = 40.0 * np.sin(2 * np.pi * 3.0 * np.arange(2000) * p.loop_time)
    vessel = FluidVessel.report_default()
    fast = simulate(
        table, a_g=a_g, runtime=MILRuntime(controller, precision=precision), specimen=vessel, seed=3
    )
    slow = simulate_interface(
        VirtualTable(table, specimen=vessel, seed=3),
        a_g=a_g,
        runtime=MILRuntime(controller, precision=precision),
    )
    for name in ("u", "u_w", "u_z", "x", "z", "w_lc"):
        a, b = fast.channels[name], slow.channels[name]
        assert np.max(np.abs(a - b)) <= 1e-12 * max(1.0, np.max(np.abs(a))), name
    assert np.max(np.abs(fast.u_w)) > 0  # the feedback path is active
    np.testing.assert_array_equal(fast.channels["u_z"] + fast.channels["u_w"], fast.channels["u"])


def test_rest_stays_at_rest(table):
    # Equilibrium P1 = P2 = Ps/2 with zero command: the table only settles onto the
    # string potentiometer's quantization of x = 0 (Table 7.1: 1.25 in/V, 16 bits
    # over +-10 V -> 1 LSB = 3.8e-4 in), and dP stays within friction/LSB levels.
    r = simulate(table, command=np.zeros(4000), sensors=ideal_sensors())
    lsb = 1.25 * 20.0 / 2**16
    assert r.completed and np.max(np.abs(r.x)) < lsb and np.max(np.abs(r.dp)) < 5.0


@pytest.mark.parametrize("substeps, tol", [(1, 5e-3), (2, 1e-3)])
def test_substeps_converge(table, substeps, tol):
    # RK4 with 1 or 2 substeps per 500 us loop vs 8 substeps on a 3 Hz + 31 Hz
    # command: peak acceleration error below tol of the peak (measured 2.5e-3
    # and ~4e-4; the accelerometer's LSB is 1.6e-3 of this peak).
    u = _command(4000)
    a = simulate(table, command=u, substeps=substeps, sensors=ideal_sensors(), quantize=False)
    b = simulate(table, command=u, substeps=8, sensors=ideal_sensors(), quantize=False)
    assert np.max(np.abs(a.z - b.z)) < tol * np.max(np.abs(b.z))


def test_stroke_trip_keeps_data_and_says_when(table):
    # A ramp to 4 in must trip the 3 in stroke interlock (report Section 8.2: +-3 in);
    # the data up to the trip are kept, and the trip time follows the last record.
    n = 8000
    u = np.linspace(0.0, 4.0, n)
    r = simulate(table, command=u)
    assert r.trip is not None and r.trip.limit == "stroke"
    assert abs(r.trip.value) > 3.0
    assert 0 < r.n_samples < n
    assert r.trip.time_s == pytest.approx(r.t[-1] + T)
    assert np.max(np.abs(r.x_meas)) <= 3.0
    with pytest.raises(LimitTripped, match="stroke"):
        r.raise_if_tripped()
    # the Python interface path trips at the same loop
    slow = simulate_interface(VirtualTable(table), command=u)
    assert slow.trip == r.trip and slow.n_samples == r.n_samples


def test_velocity_and_valve_saturation_trips(table):
    r = simulate(table, command=np.full(4000, 0.5), limits=SafetyLimits(velocity=5.0))
    assert r.trip.limit == "velocity" and r.trip.value > 5.0
    r = simulate(
        table, command=np.full(4000, 2.9), limits=SafetyLimits(valve_saturation_time=0.02, actuator_force=1e5)
    )
    assert r.trip.limit == "valve_saturation" and r.trip.time_s == pytest.approx(0.0205, abs=2e-3)


def test_force_trip_with_heavy_specimen(table):
    # A 40 000 lb rigid mass shaken at 8 Hz needs ~5000 lbf of actuator force;
    # a 4000 lbf interlock must trip on it (the default is 95 % of A_p*Ps = 5985 lbf).
    u = 0.5 * np.sin(2 * np.pi * 8 * np.arange(4000) * T)
    r = simulate(table, command=u, specimen=RigidMass(40000.0), limits=SafetyLimits(actuator_force=4000.0))
    assert r.trip.limit == "actuator_force" and abs(r.trip.value) > 4000.0


class _UnstableSpecimen:
    # x' = 50 x + z, w = 100 x: an exponentially growing specimen model.
    def state_space(self):
        return SpecimenStateSpace(np.array([[50.0]]), np.array([1.0]), np.array([100.0]), 0.0)


def test_divergence_is_detected(table):
    # With the interlocks off, a diverging model must stop on divergence or NaN.
    r = simulate(table, command=np.zeros(40000), specimen=_UnstableSpecimen(), limits=SafetyLimits.disabled())
    assert r.trip is not None and r.trip.limit in ("divergence", "nan")
    assert np.all(np.isfinite(r.x))


def test_unstable_gain_trips_an_interlock(table):
    # K_e = 40 V/in with K_p = 0 is far beyond the stability limit (Table 4.2:
    # 6.7 V/in); valve saturation bounds it into a violent limit cycle, which an
    # interlock (force, valve saturation or velocity) must stop within 1 s.
    r = simulate(table.with_gains(Ke=40.0, Kp=0.0), command=np.full(20000, 0.01))
    assert r.trip is not None and r.trip.time_s < 1.0
    assert r.trip.limit in ("actuator_force", "valve_saturation", "velocity")


def test_run_file_round_trip(table, tmp_path):
    r = simulate(table, command=_command(1000), specimen=RigidMass(1200.0))
    path = save_run(r, tmp_path / "run.h5")
    assert [p.name for p in tmp_path.iterdir()] == ["run.h5"]  # no temporary left
    mask = os.umask(0)
    os.umask(mask)
    assert path.stat().st_mode & 0o777 == 0o666 & ~mask  # the mode of any new file
    back = load_run(path)
    for name, arr in r.channels.items():
        np.testing.assert_array_equal(back.channels[name], arr)
    assert back.config["table"]["Ke"] == table.Ke
    assert back.software_version == r.software_version and back.mode == "open"
    tripped = simulate(table, command=np.linspace(0, 4, 8000))
    assert load_run(save_run(tripped, tmp_path / "trip.h5")).trip == tripped.trip


def test_run_file_extras(table, tmp_path):
    r = simulate(table, command=_command(200))
    path = save_run(
        r,
        tmp_path / "run.h5",
        extra_attrs={"note": "hello"},
        extra_groups={"extra": {"a": np.arange(3.0), "sub": {"b": [1, 2]}}},
    )
    with h5py.File(path) as fh:
        assert fh.attrs["note"] == "hello"
        np.testing.assert_array_equal(fh["extra/a"][()], [0.0, 1.0, 2.0])
        np.testing.assert_array_equal(fh["extra/sub/b"][()], [1, 2])
    np.testing.assert_array_equal(load_run(path).x, r.x)  # still a run file
    with pytest.raises(ValueError, match="'mode'"):
        save_run(r, tmp_path / "bad.h5", extra_attrs={"mode": "mil"})
    with pytest.raises(ValueError, match="'channels'"):
        save_run(r, tmp_path / "bad.h5", extra_groups={"channels": {}})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.h5"]


def test_bad_run_file(tmp_path):
    bad = tmp_path / "bad.h5"
    bad.write_text("not hdf5")
    with pytest.raises(DataFileError, match="bad.h5"):
        load_run(bad)


def test_rk4_agrees_with_solve_ivp_reference(table):
    # Independent integrator: scipy RK45 (rtol 1e-8) between ticks vs the compiled
    # RK4 (default "auto": 2 substeps with 36 in of water); exact sensors; 0.3 s of a
    # 3 Hz + 31 Hz command with the vessel.  Agreement 1e-3 of the peak acceleration (measured ~1e-4).
    u = _command(600)
    vessel = FluidVessel.report_default()
    ref = simulate_interface(
        ScipyTable(table, specimen=vessel, sensors=ideal_sensors(), quantize=False), command=u
    )
    fast = simulate(table, command=u, specimen=vessel, sensors=ideal_sensors(), quantize=False)
    for name in ("z", "x", "dp", "w"):
        scale = np.max(np.abs(ref.channels[name]))
        assert np.max(np.abs(fast.channels[name] - ref.channels[name])) < 1e-3 * scale, name


def test_bad_inputs_are_named(table):
    with pytest.raises(ConfigError, match="command"):
        simulate(table, command=[0.0, np.nan])
    with pytest.raises(ConfigError, match="command"):
        simulate(table)
    with pytest.raises(ConfigError, match="feedback"):
        simulate(table, command=[0.0], feedback="strain")
    with pytest.raises(ConfigError, match="substeps"):
        simulate(table, command=[0.0], substeps=0)


def test_controller_loop_time_must_match_the_table(table):
    design = design_controller(
        table_model(report_parameters()), form="tracking", fc_hz=80.0, emit_warnings=False
    )
    runtime = MILRuntime(discretize(design.H_uz, design.H_uw, 1e-3, fc_hz=80.0))
    with pytest.raises(ConfigError, match="loop_time"):
        simulate(table, a_g=np.zeros(10), runtime=runtime)


def test_run_result_pickles(table):
    # Campaign executors ship results between processes.
    r = simulate(table, command=_command(200))
    back = pickle.loads(pickle.dumps(r))
    np.testing.assert_array_equal(back.x, r.x)
    assert back.completed and back.config == r.config
