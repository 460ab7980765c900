"""Reference runtime of the MIL controller (report Section 6.5 Step 6, Figures 7.8-7.11)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.signal

from impedance_mil.errors import ConfigError
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.virtual import PythonVS, VSOutput, presets

from .conftest import FC_HZ, LOOP_TIME_S, broadband_record


@pytest.fixture(scope="module")
def controller(controller_tfs):
    return discretize(*controller_tfs, LOOP_TIME_S, fc_hz=FC_HZ)


@pytest.fixture(scope="module")
def record():
    _, a = broadband_record(duration_s=2.0)
    return a, -9.3 * a - 40.0 * np.sin(np.arange(a.size) * 0.01)


def _numpy_reference(m_z, m_w, z, w, dtype):
    """Independent scalar re-implementation of the documented operation order in ``dtype``."""

    def out(m, x, v):
        n = x.size
        y = m[n, n] * v
        for j in range(n):
            y = dtype(y + m[n, j] * x[j])
        return y

    def upd(m, x, c, v):
        n = x.size
        t = np.empty(n, dtype)
        for i in range(n):
            acc = m[i, n] * v
            for j in range(n):
                acc = dtype(acc + m[i, j] * x[j])
            t[i] = acc
        for i in range(n):
            r = dtype(t[i] - c[i])
            s = dtype(x[i] + r)
            c[i] = dtype(dtype(s - x[i]) - r)
            x[i] = s

    xz = np.zeros(m_z.shape[0] - 1, dtype)
    cz = np.zeros_like(xz)
    xw = np.zeros(m_w.shape[0] - 1, dtype)
    cw = np.zeros_like(xw)
    u = np.empty(z.size, dtype)
    for k in range(z.size):
        zv, wv = dtype(z[k]), dtype(w[k])
        u[k] = dtype(out(m_z, xz, zv) + out(m_w, xw, wv))
        upd(m_z, xz, cz, zv)
        upd(m_w, xw, cw, wv)
    return u


@pytest.mark.parametrize("precision,dtype", [("single", np.float32), ("double", np.float64)])
def test_kernel_is_the_documented_arithmetic_in_its_precision(controller, record, precision, dtype):
    # Bit-exact against an independent numpy-scalar implementation in the same dtype:
    # proves float32 mode really computes in float32 (no silent promotion).
    rt = MILRuntime(controller, precision=precision)
    z, w = record[0][:300], record[1][:300]
    u = rt.run(z, w)
    assert u.dtype == dtype and rt.m_z.dtype == dtype and rt.s_z.dtype == dtype
    np.testing.assert_array_equal(u, _numpy_reference(rt.m_z, rt.m_w, z, w, dtype))


def test_step_equals_run_and_is_deterministic(controller, record):
    z, w = record
    rt = MILRuntime(controller, precision="single")
    buffers = (rt.s_z, rt.s_w, rt.tmp)
    stepped = np.array([rt.step(zz, ww) for zz, ww in zip(z, w)], np.float32)
    assert all(a is b for a, b in zip(buffers, (rt.s_z, rt.s_w, rt.tmp)))  # preallocated, reused
    rt.reset()
    np.testing.assert_array_equal(rt.run(z, w), stepped)
    rt.reset()
    np.testing.assert_array_equal(rt.run(z, w), stepped)


def test_double_runtime_equals_dlsim_of_the_discrete_transfer_functions(controller, record):
    # Independent method: scipy.signal.dlsim of each channel's discrete zpk (float64).
    z, w = record
    u = MILRuntime(controller, precision="double").run(z, w)
    ref = np.zeros(z.size)
    for ch, v in zip(controller.channels, (z, w)):
        num = ch.zpk.gain * np.real(np.poly(ch.zpk.zeros))
        den = np.real(np.poly(ch.zpk.poles))
        ref += scipy.signal.dlsim((num, den, LOOP_TIME_S), v)[1][:, 0]
    # Tolerance 1e-6 of the peak: dlsim realises the polynomial (canonical) form, whose
    # double root at z = 1 is perturbed by ~sqrt(eps64) ~ 1.5e-8 (measured error 3e-8).
    np.testing.assert_allclose(u, ref, rtol=0, atol=1e-6 * np.max(np.abs(ref)))


def test_step6_listing_as_printed_ignores_w(controller, record):
    # Report Step 6 prints u_w = G*x + H*z_vs (the H_uz states and input). Then the force
    # feedback w never reaches u. The corrected runtime responds to w through H_uw.
    z, w = record
    zero = np.zeros_like(z)
    rt = MILRuntime(controller, precision="double")
    u_w_only = rt.run(zero, w)
    assert np.max(np.abs(u_w_only)) > 1e-4
    ch = controller.w
    x = np.zeros(controller.z.n_states)
    printed = []
    for zz, _ww in zip(zero, w):  # the printed listing, with z_vs = 0
        g_row = np.zeros(controller.z.n_states)
        g_row[: ch.n_states] = ch.C
        printed.append(g_row @ x + ch.D * zz)
        x = controller.z.A @ x + controller.z.B * zz
    assert np.max(np.abs(printed)) == 0.0


def test_mil_step_runs_the_vs_and_the_controller_in_one_loop(controller, record):
    # Figure 7.9 (corrected): z_vs from the VS state at the loop start, RK3 step, then
    # u from z_vs and w; the H_uz states are driven by z_vs (not a_g as printed).
    a_g, w = record
    vs = presets.get("SD2")
    rt = MILRuntime(controller, vs=vs, precision="double")
    trace = rt.run_mil(a_g, w)
    ref = vs.simulate(a_g, w, dt=LOOP_TIME_S)
    np.testing.assert_allclose(trace.z_vs, ref.z_vs, rtol=0, atol=1e-12 * np.max(np.abs(ref.z_vs)))
    u_ref = MILRuntime(controller, precision="double").run(trace.z_vs, w)
    np.testing.assert_array_equal(trace.u, u_ref)
    rt.reset()
    first = rt.mil_step(a_g[0], w[0])
    assert first.u == trace.u[0] and first.z_vs == trace.z_vs[0]


class _PythonSpring(PythonVS):
    """A VS written as Python methods (the Python path of the runtime)."""

    kind = "PySpring"
    user_n_states = 2

    def derivative(self, x, a_g: float, w: float) -> np.ndarray:
        return np.array([x[1], (w - 900.0 * x[0] - 50.0 * x[1]) / self.m_vs - a_g])

    def outputs(self, x, a_g: float, w: float) -> VSOutput:
        force = 900.0 * x[0] + 50.0 * x[1]
        return VSOutput((w - force) / self.m_vs, float(x[0]), float(x[1]), float(force))


@pytest.mark.parametrize("user_type", ["python", "definition"])
def test_user_vs_mil_step_equals_run_mil_in_single_precision(controller, record, two_storey, user_type):
    # A user-defined VS, written as Python methods (Python path) or as a definition
    # in the user's own file (compiled): loop-by-loop mil_step and run_mil give the
    # same u and z_vs bit for bit, z_vs being the float32 value the controller used.
    a_g, w = record[0][:400], record[1][:400]
    vs = _PythonSpring(m_vs=5.18) if user_type == "python" else two_storey.example_two_storey()
    rt = MILRuntime(controller, vs=vs, precision="single")
    assert rt.python_vs == (user_type == "python")
    trace = rt.run_mil(a_g, w)
    rt.reset()
    steps = [rt.mil_step(a, f) for a, f in zip(a_g, w)]
    np.testing.assert_array_equal(np.array([s.u for s in steps]), trace.u)
    np.testing.assert_array_equal(np.array([s.z_vs for s in steps]), trace.z_vs)
    assert all(s.z_vs == np.float32(s.z_vs) for s in steps)


def test_rmc_programs_update_with_a_g_differ_from_z_vs(controller, record):
    # The printed programs update X with B*ag: the u_z channel then realises
    # D*z_vs + C*(states of a_g), not H_uz*z_vs. For an SD VS z_vs != a_g, so they differ.
    a_g, w = record
    vs = presets.get("SD2")
    z_vs = MILRuntime(controller, vs=vs, precision="double").run_mil(a_g, w).z_vs
    ch = controller.z
    x = np.zeros(ch.n_states)
    printed = np.empty(a_g.size)
    for k in range(a_g.size):
        printed[k] = ch.C @ x + ch.D * z_vs[k]
        x = ch.A @ x + ch.B * a_g[k]
    correct = MILRuntime(controller, precision="double").run(z_vs, np.zeros_like(w))
    assert np.max(np.abs(printed - correct)) > 0.05 * np.max(np.abs(correct))


def test_runtime_errors(controller):
    rt = MILRuntime(controller)
    with pytest.raises(ConfigError, match="vs"):
        rt.mil_step(1.0, 0.0)
    with pytest.raises(ConfigError, match="precision"):
        MILRuntime(controller, precision="half")
