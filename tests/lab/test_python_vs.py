"""User-defined virtual systems in the virtual lab.

A user's type written as a definition (``examples/vs_types/two_storey.py``)
runs in the compiled loop like the built-in ones.  A VS written as Python
methods (:class:`~impedance_mil.virtual.PythonVS`) runs through the plant
interface (:class:`VirtualTable`, the compiled plant kernels) and
``MILRuntime``'s Python VS step.  Reference: the built-in spring-damper SD2
stepped by the compiled loop; a Python transcription of the same equations
(Eq 5-1 corrected) must give the same run.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from impedance_mil.design import design_controller, table_model, virtual_model
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.lab.experiments import run_mil
from impedance_mil.lab.loop import simulate
from impedance_mil.plant.nonlinear import NonlinearTable
from impedance_mil.signals import builtin_motion
from impedance_mil.specimens import FluidVessel
from impedance_mil.virtual import PythonVS, VSOutput, presets

from .conftest import report_parameters


@dataclass(frozen=True)
class PythonSpringDamper(PythonVS):
    """SD VS written as Python methods (no definition, no kernel)."""

    k_s: float = 1.0
    c: float = 0.0

    kind = "PySD"
    user_n_states = 2

    def derivative(self, x, a_g: float, w: float) -> np.ndarray:
        return np.array([x[1], (w - self.k_s * x[0] - self.c * x[1]) / self.m_vs - a_g])

    def outputs(self, x, a_g: float, w: float) -> VSOutput:
        force = self.k_s * x[0] + self.c * x[1]
        return VSOutput(
            z_vs=(w - force) / self.m_vs, displacement=float(x[0]), velocity=float(x[1]), force=float(force)
        )


@pytest.fixture(scope="module")
def setup():
    p = report_parameters()
    sd2 = presets.get("SD2")
    design = design_controller(
        table_model(p), virtual_model(sd2), form="standardized", fc_hz=80.0, emit_warnings=False
    )
    controller = discretize(design.H_uz, design.H_uw, p.loop_time, fc_hz=80.0)
    motion = builtin_motion("elcentro").time_scaled(2).scaled_to_pga(0.4).trimmed(0, 3.0)
    return p, sd2, controller, motion.resampled(p.loop_time).accel


def test_python_vs_runs_the_same_test_as_the_compiled_loop(setup):
    # Same controller (float64), same table, vessel, sensors and noise seed:
    # the Python VS through the plant interface reproduces the compiled run
    # of the built-in SD2 within 1e-9 of peak (measured: bit for bit; the
    # arithmetic is the same, numpy and numba could differ in the last bit).
    p, sd2, controller, a_g = setup
    twin = PythonSpringDamper(m_vs=sd2.m_vs, k_s=sd2.k_s, c=sd2.c)
    table, vessel = NonlinearTable.from_linear(p), FluidVessel.report_default()
    fast = simulate(
        table, a_g=a_g, specimen=vessel, runtime=MILRuntime(controller, vs=sd2, precision="double")
    )
    slow = simulate(
        table, a_g=a_g, specimen=vessel, runtime=MILRuntime(controller, vs=twin, precision="double")
    )
    assert slow.completed and slow.mode == "mil" and slow.config["path"] == "python-vs"
    assert slow.config["substeps"] == fast.config["substeps"]
    for name in ("z", "u", "u_w", "z_vs", "x", "w_lc"):
        ref = fast.channels[name]
        np.testing.assert_allclose(
            slow.channels[name], ref, rtol=0, atol=1e-9 * np.max(np.abs(ref)), err_msg=name
        )
    np.testing.assert_allclose(
        slow.vs_states, fast.vs_states, rtol=0, atol=1e-9 * np.max(np.abs(fast.vs_states))
    )


def test_runtime_python_vs_step_matches_kernel(setup):
    # MILRuntime.mil_step / run_mil with the Python twin equal the compiled
    # kernel's (double precision) on the same inputs, within 1e-12 of peak.
    p, sd2, controller, a_g = setup
    w = -200.0 * np.sin(np.arange(a_g.size) * 0.01)
    ref = MILRuntime(controller, vs=sd2, precision="double").run_mil(a_g, w)
    got = MILRuntime(
        controller, vs=PythonSpringDamper(m_vs=sd2.m_vs, k_s=sd2.k_s, c=sd2.c), precision="double"
    ).run_mil(a_g, w)
    np.testing.assert_allclose(got.u, ref.u, rtol=0, atol=1e-12 * np.max(np.abs(ref.u)))
    np.testing.assert_allclose(got.z_vs, ref.z_vs, rtol=0, atol=1e-12 * np.max(np.abs(ref.z_vs)))


def test_two_storey_example_runs_a_mil_test_in_the_compiled_loop(setup, two_storey):
    # The documented user-defined type (an isolated two-storey frame, written as a
    # definition in the user's own file) runs a MIL test with the vessel in the
    # compiled loop (not the Python path): it completes, records its six states, and
    # the table follows the frame's roof acceleration below 15 Hz (spectral
    # error below 10 %, the bound of the built-in systems' test).
    p, *_ = setup
    vs = two_storey.example_two_storey()
    motion = builtin_motion("elcentro").time_scaled(2).scaled_to_pga(0.3).trimmed(0, 4.0)
    r = run_mil(p, vs, motion, specimen=FluidVessel.report_default())
    assert r.run.completed and r.run.mode == "mil"
    assert r.run.vs_states.shape == (r.run.n_samples, 6)
    assert r.run.config.get("path") != "python-vs"
    assert r.metrics.spectral_error_low < 0.10
