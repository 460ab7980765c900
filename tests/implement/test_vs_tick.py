"""The VS slot of the MIL step: one compiled tick per VS, one compiled caller for every VS."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from numba import types
from numba.core.errors import NumbaExperimentalFeatureWarning

from impedance_mil.errors import ConfigError
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.implement.runtime import mil_run_kernel, mil_step_kernel
from impedance_mil.implement.vs_tick import no_vs_tick, tick_signature, vs_tick_function
from impedance_mil.virtual import PythonVS, VSOutput, presets
from impedance_mil.virtual.codegen import compiled

from .conftest import FC_HZ, LOOP_TIME_S


class _PythonSpring(PythonVS):
    kind = "PySpring"
    user_n_states = 2

    def derivative(self, x, a_g: float, w: float) -> np.ndarray:
        return np.array([x[1], (w - 900.0 * x[0]) / self.m_vs - a_g])

    def outputs(self, x, a_g: float, w: float) -> VSOutput:
        return VSOutput((w - 900.0 * x[0]) / self.m_vs, float(x[0]), float(x[1]), 900.0 * float(x[0]))


def _drive(n: int = 300):
    # Random a_g [in/s^2] and w [lbf] large enough to drive LR, FP and TFP through their hysteresis.
    rng = np.random.default_rng(4)
    return zip(300.0 * rng.standard_normal(n), 2000.0 * rng.standard_normal(n))


@pytest.mark.parametrize("name", ["SD2", "LR2", "FP2", "TFP3"])
def test_tick_is_output_then_rk3_step_bit_for_bit(name):
    # Definition of the slot (float64): z_vs from the state at the start of the loop, then
    # one RK3 step in place -- compared bit for bit over 300 steps with the VS's own
    # outputs() and step_rk3() (the definition's outputs kernel and RK3 step).
    vs = presets.get(name)
    tick = vs_tick_function(vs, np.float64)
    params = vs.parameter_array()
    x_tick = np.asarray(vs.initial_state(), float).copy()
    x_ref = x_tick.copy()
    work = np.zeros(4 * vs.n_states)
    dt = LOOP_TIME_S
    for a, f in _drive():
        z = tick(params, x_tick, a, f, dt, work)
        z_ref = vs.outputs(x_ref, a, f).z_vs
        x_ref = vs.step_rk3(x_ref, a, f, dt)
        assert z == z_ref
        assert x_tick.tobytes() == x_ref.tobytes()
    assert np.max(np.abs(x_tick)) > 0


@pytest.mark.parametrize("name", ["SD2", "LR2", "FP2", "TFP3"])
def test_single_precision_tick_is_the_generated_float32_kernel(name):
    # The VSTick of float32 calls the definition's float32 kernel: same state bytes, a float32 z.
    vs = presets.get(name)
    tick = vs_tick_function(vs, np.float32)
    kernel = compiled(vs.definition).tick32
    params = vs.parameter_array().astype(np.float32)
    x_tick = np.asarray(vs.initial_state(), np.float32).copy()
    x_ref = x_tick.copy()
    w_tick, w_ref = np.zeros(4 * vs.n_states, np.float32), np.zeros(4 * vs.n_states, np.float32)
    dt = np.float32(LOOP_TIME_S)
    for a_g, w in _drive():
        a, f = np.float32(a_g), np.float32(w)
        z = tick(params, x_tick, a, f, dt, w_tick)
        assert z == np.float32(z) and z == kernel(params, x_ref, a, f, dt, w_ref)
        assert x_tick.tobytes() == x_ref.tobytes()


def test_tick_signature_and_refusals():
    # The contract: T(T[::1], T[::1], T, T, T, T[::1]) for T = float32 (and float64).
    sig = tick_signature(np.float32)
    arr = types.Array(types.float32, 1, "C")
    assert sig.return_type == types.float32
    assert sig.args == (arr, arr, types.float32, types.float32, types.float32, arr)
    assert vs_tick_function(presets.get("SD2"), np.float32).signature() == sig
    assert no_vs_tick(np.float32).signature() == sig
    with pytest.raises(ConfigError, match="dtype"):
        tick_signature(np.int64)
    with pytest.raises(ConfigError, match="defined type"):
        vs_tick_function(_PythonSpring(m_vs=5.18), np.float64)  # a VS written as Python methods


def test_mil_step_compiles_once_per_dtype_for_every_vs(controller_tfs):
    # The kernel takes the VS as a first-class function of one signature: stepping SD, LR,
    # FP and TFP in both precisions adds at most one compiled variant per dtype, and numba's
    # experimental-feature warning does not reach the caller.
    controller = discretize(*controller_tfs, LOOP_TIME_S, fc_hz=FC_HZ)
    with warnings.catch_warnings():
        warnings.simplefilter("error", NumbaExperimentalFeatureWarning)
        for name in ("SD2", "LR2", "FP2", "TFP3"):
            for precision in ("single", "double"):
                rt = MILRuntime(controller, vs=presets.get(name), precision=precision)
                rt.mil_step(10.0, -50.0)
                rt.run_mil(np.full(10, 10.0), -50.0)
    for kernel in (mil_step_kernel, mil_run_kernel):
        # (dtype of ControllerArrays.m_z, type of the VS slot) of every compiled variant
        variants = sorted({(str(sig[0][0].dtype), str(sig[1])) for sig in kernel.signatures})
        assert [dtype for dtype, _ in variants] == ["float32", "float64"], kernel.signatures
        assert all(slot.startswith(f"FunctionType[{dtype}(") for dtype, slot in variants)
    assert len(mil_step_kernel.signatures) == 2
