"""The tick sequence exists once: compiled for the virtual plant, in Python for any plant interface."""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.design import design_controller, table_model, virtual_model
from impedance_mil.errors import LimitTripped
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.lab import Measurements, simulate, simulate_interface
from impedance_mil.lab.structures import LoopControl
from impedance_mil.lab.tick import run_loop
from impedance_mil.lab.trips import TripCause
from impedance_mil.plant.nonlinear import NonlinearTable
from impedance_mil.specimens import FluidVessel, LinearMDOF
from impedance_mil.virtual import presets

from .conftest import report_parameters


class SpyPlant:
    """A plant interface that logs its calls and trips on the stroke at loop ``trip_at``."""

    loop_time = 500e-6

    def __init__(self, trip_at: int):
        self.trip_at = trip_at
        self.calls: list[tuple[str, int]] = []
        self.k = 0

    def reset(self) -> None:
        self.calls.clear()
        self.k = 0

    def read_sensors(self) -> Measurements:
        self.calls.append(("read_sensors", self.k))
        if self.k == self.trip_at:
            raise LimitTripped(TripCause.STROKE, self.k * self.loop_time, "value 3.5", value=3.5)
        return Measurements(self.k * self.loop_time, 0.01 * self.k, 0.0, 0.0, 0.0, 0.0)

    def write_command(self, u: float) -> None:
        self.calls.append(("write_command", self.k))

    def advance(self) -> None:
        self.calls.append(("advance", self.k))
        self.k += 1


def test_python_path_calls_the_plant_in_tick_order_and_stops_at_a_trip():
    # The interface contract: per loop read -> write -> advance; a trip raised by
    # read_sensors ends the run there with the plant's cause and value, and the
    # loop's records stop before it (channels the plant does not know are NaN).
    plant = SpyPlant(trip_at=3)
    run = simulate_interface(plant, command=np.linspace(0.0, 1.0, 10))
    expected = [(call, k) for k in range(3) for call in ("read_sensors", "write_command", "advance")]
    assert plant.calls == expected + [("read_sensors", 3)]
    assert run.n_samples == 3 and run.trip.cause is TripCause.STROKE and run.trip.value == 3.5
    assert run.trip.time_s == pytest.approx(3 * plant.loop_time)
    np.testing.assert_array_equal(run.x_meas, [0.0, 0.01, 0.02])
    assert np.all(np.isnan(run.x)) and np.all(np.isnan(run.u_v))


def test_compiled_loop_has_one_variant_per_controller_precision():
    # One compiled loop for every VS kind, specimen form (oscillator bank or general
    # state space), feedback source and mode: numba compiles it once per controller
    # dtype (float32, float64); the VS enters as a first-class function of one signature.
    p = report_parameters()
    table = NonlinearTable.from_linear(p)
    a_g = 40.0 * np.sin(2 * np.pi * 2.0 * np.arange(200) * p.loop_time)
    mdof = LinearMDOF.shear_building([2000.0, 1000.0], [500.0, 400.0], 0.02)
    for name in ("SD2", "LR2", "FP2"):
        vs = presets.get(name)
        d = design_controller(
            table_model(p), virtual_model(vs), form="standardized", fc_hz=80.0, emit_warnings=False
        )
        c = discretize(d.H_uz, d.H_uw, p.loop_time, fc_hz=80.0)
        for precision in ("single", "double"):
            for specimen, feedback in ((FluidVessel.report_default(), "lc"), (mdof, "fe")):
                rt = MILRuntime(c, vs=vs, precision=precision)
                assert simulate(table, a_g=a_g, runtime=rt, specimen=specimen, feedback=feedback).completed
            rt = MILRuntime(c, precision=precision)  # tracking: the VS slot holds a placeholder
            assert simulate(table, a_g=a_g, runtime=rt).completed
    assert simulate(table, command=np.zeros(10)).completed  # open loop: a float64 placeholder controller
    # numba's type of a named tuple is indexed by field position
    controller = LoopControl._fields.index("controller")
    dtypes = sorted(str(sig[1][controller][0].dtype) for sig in run_loop.signatures)  # its m_z
    assert dtypes == ["float32", "float64"], run_loop.signatures
