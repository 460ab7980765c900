"""The LTI value object (impedance_mil.lti.StateSpace): invariants against independent methods."""

import control
import numpy as np
import pytest
import scipy.signal
from hypothesis import given, settings
from hypothesis import strategies as st

from impedance_mil.errors import ConfigError, ImproperSystemError
from impedance_mil.implement.realization import discrete_zpk
from impedance_mil.lti import StateSpace
from impedance_mil.plant import TableParameters, plant_state_space
from impedance_mil.systems import TransferFunction

from .lti_strategies import root_list

TWO_PI = 2 * np.pi


@st.composite
def proper_tfs(draw, max_order: int = 6):
    """Proper transfer functions with stable poles and zeros in [1, 1e3] rad/s."""
    n = draw(st.integers(1, max_order))
    zeros = root_list(draw, draw(st.integers(0, n)))
    return TransferFunction.from_zpk(zeros, root_list(draw, n), 10 ** draw(st.floats(-3.0, 3.0)))


def _peak(H: TransferFunction) -> float:
    """Largest |H(j w)| over 0.01 ... 1e5 rad/s (the scale of round-off in a realization's response)."""
    return float(np.max(np.abs(H(1j * np.logspace(-2, 5, 400)))))


def _table():
    return plant_state_space(TableParameters.report_default()).system


# ------------------------------------------------------------- frequency response
@settings(max_examples=60, deadline=None, derandomize=True)
@given(H=proper_tfs(), f=st.lists(st.floats(0.01, 500.0), min_size=1, max_size=8))
def test_frequency_response_equals_the_transfer_functions(H, f):
    # Invariant: the resolvent C (sI - A)^-1 B + D of a realization equals num/den at any s.
    # Round-off is relative to the peak gain (where |H| is far below it, D and the strictly
    # proper part cancel and both evaluations lose those digits): measured worst 1.1e-15 of
    # the peak over 3000 draws (1.4e-4 relative to |H| at |H| ~ 1e-11 of the peak).
    ref = H.frequency_response(f)
    np.testing.assert_allclose(H.to_lti().frequency_response(f), ref, rtol=0, atol=1e-13 * _peak(H))


def test_mimo_response_shape_and_channels_by_name():
    sys = _table()
    f = np.array([1.0, 27.0, 120.0])
    h = sys.frequency_response(f)
    assert sys.inputs == ("u_i", "w") and sys.outputs == ("z", "x", "v", "dp")
    assert h.shape == (4, 2, 3)
    for i, out in enumerate(sys.outputs):
        for j, inp in enumerate(sys.inputs):
            np.testing.assert_array_equal(sys.channel(out, inp).frequency_response(f), h[i, j])
    # A scalar frequency keeps its shape for a SISO system.
    assert sys.channel("z", "w").frequency_response(5.0).shape == ()
    with pytest.raises(ConfigError, match="output: expected one of z, x, v, dp"):
        sys.channel("a", "w")
    with pytest.raises(ConfigError, match="input: expected one of u_i, w"):
        sys.channel("z", "u")


def test_batched_evaluation_equals_one_solve_per_point():
    # The batches of BATCH_POINTS give the same numbers as a plain loop of numpy.linalg.solve
    # (same LU per point); 5000 points span three batches.  Measured: bit-identical.
    sys = _table().channel("z", "u_i")
    f = np.logspace(-1, 3, 5000)
    s = 1j * TWO_PI * f
    A, b, c, d = sys.A, sys.B[:, 0], sys.C[0], sys.D[0, 0]
    ref = np.array([c @ np.linalg.solve(p * np.eye(5) - A, b) + d for p in s])
    np.testing.assert_allclose(sys.frequency_response(f), ref, rtol=1e-14, atol=0)


def test_poles_dcgain_stability_and_a_point_on_a_pole():
    # x' = -2 x + 2 u, y = x: pole -2, dc gain 1 (closed form).
    sys = StateSpace([[-2.0]], [[2.0]], [[1.0]])
    np.testing.assert_allclose(sys.poles(), [-2.0])
    assert sys.dcgain() == pytest.approx(1.0, rel=1e-15)
    assert sys.is_stable()
    # The open loop of Eq 4-11 integrates (pole at s = 0): its dc gain is infinite.
    ol = _table()
    assert not ol.is_stable()
    assert np.isinf(ol.channel("x", "u_i").dcgain())
    # A static gain (no states) evaluates to D everywhere.
    g = StateSpace(np.zeros((0, 0)), np.zeros((0, 2)), np.zeros((1, 0)), [[3.0, -1.0]])
    np.testing.assert_array_equal(g.frequency_response([1.0, 10.0])[0, 1], [-1.0, -1.0])


def test_bad_matrices_are_refused_naming_the_shapes():
    with pytest.raises(ConfigError, match="state_space: expected A .n x n., B"):
        StateSpace(np.eye(2), np.ones(3), np.ones(2))
    with pytest.raises(ConfigError, match="finite"):
        StateSpace([[np.nan]], [1.0], [1.0])
    with pytest.raises(ConfigError, match="dt"):
        StateSpace([[-1.0]], [1.0], [1.0], 0.0, dt=-1e-3)
    with pytest.raises(ConfigError, match="inputs: expected 1 distinct names"):
        StateSpace([[-1.0]], [1.0], [1.0], inputs=("u", "w"))
    # An improper function has no realization: the same error as TransferFunction's algebra.
    with pytest.raises(ImproperSystemError, match="relative degree -1"):
        StateSpace.from_polynomials([1.0, 0.0, 0.0], [1.0, 1.0])
    with pytest.raises(ImproperSystemError):
        TransferFunction([1.0, 0.0], [1.0]).to_lti()


def test_the_callers_arrays_are_copied_not_frozen():
    A = np.array([[-1.0]])
    sys = StateSpace(A, [1.0], [1.0])
    A[0, 0] = -5.0  # still writable, and the value object is unchanged
    assert sys.A[0, 0] == -1.0 and not sys.A.flags.writeable


# ------------------------------------------------------------------ ZOH
def test_zoh_of_a_first_order_lag_is_the_closed_form():
    # x' = a (u - x): held input over T gives x[k+1] = e^{-aT} x[k] + (1 - e^{-aT}) u[k] (exact).
    a, T = 40.0, 5e-4
    d = StateSpace([[-a]], [[a]], [[1.0]]).zoh(T)
    assert d.dt == T
    assert d.A[0, 0] == pytest.approx(np.exp(-a * T), rel=1e-15)
    assert d.B[0, 0] == pytest.approx(-np.expm1(-a * T), rel=1e-14)


def test_zoh_preserves_the_step_response_at_the_samples():
    # Invariant (as scipy's TestC2dInvariants): the discrete step response at t_k equals the
    # continuous one, computed independently by scipy.signal.step on a fine grid and read at
    # the samples.  Table of Eq 4-11 closed with a static gain so that it is stable; measured
    # 1.6e-15 of the peak.
    p = TableParameters.report_default()
    ol = _table()
    k = np.array([p.Ke, 0.0, p.Kp, 0.0, 0.0]) * p.Kv
    cl = StateSpace(ol.A - np.outer(ol.B[:, 0], k), ol.B[:, :1], ol.C[1:2], 0.0)
    T, n = 5e-4, 400
    d = cl.zoh(T)
    x, y = np.zeros(5), []
    for _ in range(n):
        y.append(d.C[0] @ x)
        x = d.A @ x + d.B[:, 0]
    t = np.arange(n) * T
    _, ref = scipy.signal.step((cl.A, cl.B, cl.C, cl.D), T=t)
    np.testing.assert_allclose(y, ref, rtol=0, atol=1e-13 * np.max(np.abs(ref)))


def test_zoh_matrices_equal_scipy_cont2discrete():
    # Independent implementation of the same definition (block matrix exponential): measured
    # bit-identical.
    ol = _table()
    d = ol.zoh(5e-4)
    Ad, Bd, _, _, _ = scipy.signal.cont2discrete((ol.A, ol.B, ol.C, ol.D), 5e-4, method="zoh")
    np.testing.assert_allclose(d.A, Ad, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(d.B, Bd, rtol=1e-14, atol=1e-15 * np.max(np.abs(Bd)))


# ----------------------------------------------------------------- Tustin
@settings(max_examples=40, deadline=None, derandomize=True)
@given(H=proper_tfs(max_order=4), fp=st.floats(1.0, 900.0))
def test_tustin_maps_the_prewarp_frequency_exactly(H, fp):
    # H_d(exp(j w_p T)) = H(j w_p) at the pre-warp frequency (Section 6.5, Step 4); measured
    # worst 1.8e-13 of the peak gain over 2000 draws (round-off relative to the peak, as above).
    T = 5e-4
    sys = H.to_lti()
    d = sys.tustin(T, prewarp_hz=fp)
    np.testing.assert_allclose(
        d.frequency_response(fp), sys.frequency_response(fp), rtol=0, atol=1e-11 * _peak(H)
    )


def test_tustin_without_prewarp_is_the_bilinear_map_of_scipy_and_of_the_zpk_route():
    # Three routes to s = (2/T)(z-1)/(z+1): this state-space map, scipy's bilinear
    # cont2discrete, and the pole-by-pole map of implement.realization.discrete_zpk.  Measured
    # 7e-15 (scipy), 1.3e-12 (zpk, polynomial roots) and 1.3e-12 (warped closed form).
    H = TransferFunction.from_zpk([-30.0], [-5.0, -80.0 + 300j, -80.0 - 300j], 4e4)
    T = 5e-4
    f = np.logspace(-1, np.log10(900.0), 40)
    mine = H.to_lti().tustin(T).frequency_response(f)
    A, B, C, D = H.to_ss()
    Ad, Bd, Cd, Dd, _ = scipy.signal.cont2discrete((A, B, C, D), T, method="bilinear")
    ref = StateSpace(Ad, Bd, Cd, Dd, T).frequency_response(f)
    np.testing.assert_allclose(mine, ref, rtol=1e-13)
    np.testing.assert_allclose(mine, discrete_zpk(H, T, "tustin").frequency_response(f), rtol=1e-11)
    # ... and it equals H at the warped frequency (2/T) tan(w T/2).
    warped = 2 / T * np.tan(TWO_PI * f * T / 2)
    np.testing.assert_allclose(mine, H(1j * warped), rtol=1e-11)


def test_discretization_needs_a_continuous_system_and_a_positive_step():
    d = StateSpace([[0.5]], [1.0], [1.0], dt=1e-3)
    with pytest.raises(ConfigError, match="zoh"):
        d.zoh(1e-3)
    c = StateSpace([[-1.0]], [1.0], [1.0])
    with pytest.raises(ConfigError, match="dt"):
        c.tustin(0.0)
    with pytest.raises(ConfigError, match="prewarp_hz"):
        c.tustin(1e-3, prewarp_hz=600.0)  # above the 500 Hz Nyquist frequency


def test_discrete_stability_is_the_unit_circle():
    assert StateSpace([[0.99]], [1.0], [1.0], dt=1e-3).is_stable()
    assert not StateSpace([[-1.01]], [1.0], [1.0], dt=1e-3).is_stable()


# ---------------------------------------------------------- python-control
def test_control_state_space_round_trip_keeps_matrices_names_and_dt():
    sys = _table()
    back = StateSpace.from_control(sys.to_control())
    for name in ("A", "B", "C", "D"):
        np.testing.assert_array_equal(getattr(back, name), getattr(sys, name))
    assert (back.inputs, back.outputs, back.states) == (sys.inputs, sys.outputs, sys.states)
    d = sys.zoh(1e-3)
    assert StateSpace.from_control(d.to_control()).dt == 1e-3


def test_control_transfer_functions_siso_and_mimo_without_slycot():
    # A MIMO control.TransferFunction has no slycot-free ss(); it is realized channel by channel.
    G = control.tf(
        [[[1.0], [2.0, 1.0]], [[1.0, 0.0], [3.0]]],
        [[[1.0, 1.0], [1.0, 3.0]], [[1.0, 2.0], [1.0, 5.0, 6.0]]],
        inputs=["u", "w"],
        outputs=["z", "x"],
    )
    sys = StateSpace.from_control(G)
    assert (sys.inputs, sys.outputs, sys.n_states) == (("u", "w"), ("z", "x"), 5)
    f = np.array([0.1, 1.0, 10.0])
    ref = np.asarray(G.frequency_response(TWO_PI * f).complex)  # python-control's own evaluation
    np.testing.assert_allclose(sys.frequency_response(f), ref, rtol=1e-14)  # measured 4e-16
    H = TransferFunction([2.0, 1.0], [1.0, 3.0, 5.0])
    assert TransferFunction.from_control(H.to_control()).isclose(H, rtol=0)
    assert TransferFunction.from_control(H.to_lti().to_control()).isclose(H, rtol=1e-14)  # measured 2e-16
    with pytest.raises(ConfigError, match="dt"):
        StateSpace.from_control(control.tf([1.0], [1.0, 0.5], True))
    with pytest.raises(ConfigError, match="system"):
        StateSpace.from_control(H)
