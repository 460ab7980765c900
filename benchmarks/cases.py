"""What the lab's benchmarks share: bench_lab.py's MIL case, and pinning to one core.

``bench_lab.py`` and ``bench_tick_floor.py`` (with its C binding ``c/tick_floor.py``) run the same
case, so that the floor is the floor of the loop ``bench_lab.py`` times; it is built here once.
"""

from __future__ import annotations

import os
from typing import NamedTuple

import numpy as np

from impedance_mil.design import design_controller, table_model, virtual_model
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.plant import TableParameters
from impedance_mil.plant.nonlinear import NonlinearTable
from impedance_mil.signals import GroundMotion, builtin_motion
from impedance_mil.specimens import FluidVessel
from impedance_mil.virtual import presets


class BenchCase(NamedTuple):
    """The MIL case: the table's parameters and model, the vessel, the runtime and the motion."""

    params: TableParameters
    table: NonlinearTable
    vessel: FluidVessel
    runtime: MILRuntime
    motion: GroundMotion

    @property
    def a_g(self) -> np.ndarray:
        """The motion at the loop time [in/s^2] (a writable copy)."""
        return np.array(self.motion.accel)

    @property
    def loop_time(self) -> float:
        """The loop time [s]."""
        return self.params.loop_time


def bench_case() -> BenchCase:
    """El Centro x2 at 0.6 g, SD2, vessel with 36 in of water, nonlinear table, float32 controller at 80 Hz."""
    p = TableParameters.report_default()
    gm = builtin_motion("elcentro").time_scaled(2).scaled_to_pga(0.6).resampled(p.loop_time)
    vs = presets.get("SD2")
    design = design_controller(
        table_model(p), virtual_model(vs), form="standardized", fc_hz=80.0, emit_warnings=False
    )
    controller = discretize(design.H_uz, design.H_uw, p.loop_time, fc_hz=80.0)
    runtime = MILRuntime(controller, vs=vs, precision="single")
    return BenchCase(p, NonlinearTable.from_linear(p), FluidVessel.report_default(), runtime, gm)


def pin_one_core() -> str:
    """Pin this process to its first allowed CPU; say where (or that it could not)."""
    if hasattr(os, "sched_setaffinity"):
        cpu = sorted(os.sched_getaffinity(0))[0]
        os.sched_setaffinity(0, {cpu})
        return f"pinned to CPU {cpu}"
    return "not pinned"
