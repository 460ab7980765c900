"""Round-off-safe state space -> transfer function (impedance_mil.ss2tf, TransferFunction.from_lti)."""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from impedance_mil.errors import ConfigError
from impedance_mil.lti import StateSpace
from impedance_mil.plant import LinearTable, TableParameters, plant_state_space
from impedance_mil.ss2tf import ss_to_tf
from impedance_mil.systems import CANCEL_RTOL, TransferFunction

from .lti_strategies import root_list

TWO_PI = 2 * np.pi


def _separated(roots, rel=0.2):
    """Distinct roots: every pair (but a conjugate pair) at least ``rel`` apart relative to size."""
    r = np.asarray(roots)
    for i in range(r.size):
        for j in range(i + 1, r.size):
            pair = r[i].imag != 0 and r[i] == np.conj(r[j])
            if not pair and abs(r[i] - r[j]) < rel * max(abs(r[i]), abs(r[j])):
                return False
    return True


def _matched(a, b) -> float:
    """Largest relative distance from a root of ``a`` to the nearest root of ``b``."""
    return max((float(np.min(np.abs(b - x)) / abs(x)) for x in a), default=0.0)


@st.composite
def zpk(draw):
    """Zeros, poles in [1, 1e3] rad/s (stable, 20 % apart), and a gain: a proper function."""
    n = draw(st.integers(1, 6))
    zeros = root_list(draw, draw(st.integers(0, n)))
    poles = root_list(draw, n)
    assume(_separated(poles) and _separated(zeros))
    return zeros, poles, 10 ** draw(st.floats(-3.0, 3.0))


@settings(max_examples=80, deadline=None, derandomize=True)
@given(case=zpk())
def test_tf_ss_tf_round_trip_keeps_relative_degree_poles_zeros_and_gain(case):
    # Property: tf -> ss (controllable canonical) -> tf.  Stated tolerances against the worst
    # measured over 16000 draws: relative degree exact; poles 1e-9 (measured 2e-10) and the
    # leading gain 1e-9 (5e-11) relative; each numerator coefficient within 1e-8 of the terms
    # it sums, |d a_k| + |num_k| (measured 5e-10: with d != 0 the realization holds num as
    # c + d den, so a small coefficient keeps only that share); zeros, found from those
    # coefficients, 5e-4 relative (measured 6e-5, zeros 20 % apart).
    zeros, poles, gain = case
    omega_lo = np.min(np.abs(poles))
    assume(np.prod(np.abs(zeros) / omega_lo) > 1e-10)  # 100 x above ORIGIN_ZERO_RTOL: not "at the origin"
    H = TransferFunction.from_zpk(zeros, poles, gain)
    sys = H.to_lti()
    back = TransferFunction.from_lti(sys)
    assert back.relative_degree == H.relative_degree
    assert _matched(H.poles(), back.poles()) <= 1e-9
    assert back.num[0] == pytest.approx(H.num[0], rel=1e-9)
    d = float(sys.D[0, 0])
    terms = np.abs(d * H.den[-H.num.size :]) + np.abs(H.num)
    assert np.all(np.abs(back.num - H.num) <= 1e-8 * terms)
    assert _matched(H.zeros(), back.zeros()) <= 5e-4


@settings(max_examples=60, deadline=None, derandomize=True)
@given(case=zpk(), seed=st.integers(0, 2**32 - 1))
def test_any_basis_gives_the_eigenvalues_as_poles_and_the_same_response(case, seed):
    # Property: a real modal realization (one block per pole, well conditioned) in a randomly
    # rotated basis; the polynomials give the eigenvalues of A as poles and the response of
    # the state space (resolvent).  Measured worst over 9000 draws: poles 1.4e-12 relative,
    # response 5e-13 of the peak gain.
    _, poles, _ = case
    rng = np.random.default_rng(seed)
    blocks = []
    for p in poles[poles.imag >= 0]:
        blocks.append([[p.real, p.imag], [-p.imag, p.real]] if p.imag > 0 else [[p.real]])
    n = poles.size
    A = np.zeros((n, n))
    k = 0
    for blk in blocks:
        q = len(blk)
        A[k : k + q, k : k + q] = blk
        k += q
    Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    sys = StateSpace(Q @ A @ Q.T, Q @ rng.normal(size=n), rng.normal(size=n) @ Q.T, rng.normal())
    H = TransferFunction.from_lti(sys)
    assert _matched(sys.poles(), H.poles()) <= 1e-10
    f = np.logspace(-1, 3, 30) / TWO_PI
    peak = np.max(np.abs(sys.frequency_response(np.logspace(-3, 4, 300))))
    np.testing.assert_allclose(H.frequency_response(f), sys.frequency_response(f), rtol=0, atol=1e-11 * peak)


def test_a_mass_on_a_spring_in_a_skewed_basis_keeps_relative_degree_two():
    # x/w = 1/(m s^2 + c s + k) in the basis q = T x, T = [[1, 100], [0, 1]] (a change of
    # state units mixing position and velocity).  scipy.signal.ss2tf leaves -6.6e-10 on s
    # (measured), a relative degree of 1; an acceleration path s^2 x/w then looks improper.
    m, c, k = 4.14, 30.0, 1.2e5
    A0 = np.array([[0.0, 1.0], [-k / m, -c / m]])
    T = np.array([[1.0, 100.0], [0.0, 1.0]])
    Ti = np.linalg.inv(T)
    H = TransferFunction.from_ss(T @ A0 @ Ti, T @ np.array([0.0, 1.0 / m]), np.array([1.0, 0.0]) @ Ti)
    assert H.relative_degree == 2
    assert (TransferFunction([1.0, 0.0, 0.0], [1.0]) * H).relative_degree == 0
    # Closed form; the skewed matrices themselves hold the model to ~1e-7 (their resolvent
    # differs from the closed form by 5e-7), measured coefficient errors 3e-8 and 2e-8.
    np.testing.assert_allclose(H.num, [1.0 / m], rtol=1e-7)
    np.testing.assert_allclose(H.den, [1.0, c / m, k / m], rtol=1e-7)


def test_zeros_at_the_origin_are_exact_in_other_units_and_state_order():
    # The double zero of z/u and z/w at s = 0 (Eq 4-15a, d) must be exact so that 1/H_zu
    # cancels the integrators of H_uz (Eq 6-8a) exactly.  A user's state space in other units
    # (mm, MPa, A/s) and another state order: the same exact zeros, the other coefficients
    # within 2e-14 of the report-basis conversion (measured 1.6e-14).
    sys = LinearTable(TableParameters.report_default()).state_space().system
    T = np.diag([25.4, 25.4, 6.894757e-3, 1.0, 1e-3])[[2, 0, 4, 1, 3]]
    Ti = np.linalg.inv(T)
    for output, input in (("z", "u"), ("z", "w"), ("dp", "u")):
        ch = sys.channel(output, input)
        num, _ = ss_to_tf(StateSpace(T @ ch.A @ Ti, T @ ch.B, ch.C @ Ti, ch.D))
        ref, _ = ss_to_tf(ch)
        np.testing.assert_array_equal(num == 0, ref == 0)
        assert ref[-1] == ref[-2] == 0.0
        np.testing.assert_allclose(num, ref, rtol=1e-13, atol=0)


def test_slow_zeros_stay_off_the_origin_round_off_does_not():
    # Trailing coefficients are judged on the low-frequency scale omega (the slowest pole,
    # 1000 rad/s here).  Zeros at 1 and 2 rad/s (terms 2/1e6 of the largest): kept, with the
    # trailing coefficient to 5e-11 (measured; the canonical form holds it as 2 - 1 * 2e6).
    H = TransferFunction.from_zpk([-1.0, -2.0], [-1000.0, -2000.0], 1.0)
    back = TransferFunction.from_lti(H.to_lti())
    assert back.num.size == 3
    assert back.num[-1] == pytest.approx(2.0, rel=1e-9)
    # A zero 1e-13 omega from the origin is below the threshold (1e-12 of the largest term,
    # ORIGIN_ZERO_RTOL): it is the origin on this system's frequency scale; one at 1e-11
    # omega is not.
    tiny = TransferFunction.from_lti(TransferFunction.from_zpk([-1e-10], [-1000.0], 1.0).to_lti())
    assert tiny.num.tolist() == [1.0, 0.0]
    small = TransferFunction.from_lti(TransferFunction.from_zpk([-1e-8], [-1000.0], 1.0).to_lti())
    assert small.num[-1] == pytest.approx(1e-8, rel=1e-5)  # measured 8e-7 (held as 1e-8 - 1e3)


def test_cancellation_with_a_relative_tolerance_is_optional():
    # An uncontrollable mode at -50 rad/s: kept as a pole by default (the eigenvalues of A),
    # cancelled with cancel_rtol; with nothing to cancel the polynomials are returned as they are.
    A = np.diag([-3.0, -50.0])
    sys = StateSpace(A, [1.0, 0.0], [2.0, 1.0], 0.0)
    full = TransferFunction.from_lti(sys)
    assert full.order == 2
    reduced = TransferFunction.from_lti(sys, cancel_rtol=CANCEL_RTOL)
    assert reduced.order == 1
    np.testing.assert_allclose(reduced.poles(), [-3.0], rtol=1e-12)
    minimal = StateSpace([[-3.0]], [1.0], [2.0])
    a, b = TransferFunction.from_lti(minimal), TransferFunction.from_lti(minimal, cancel_rtol=CANCEL_RTOL)
    np.testing.assert_array_equal(a.num, b.num)
    np.testing.assert_array_equal(a.den, b.den)


def test_polynomials_in_z_of_the_sampled_table():
    # The same conversion gives num(z)/den(z) of the sampled-data table; they equal the
    # resolvent (zI - A)^-1 at z = exp(j 2 pi f T) to the conditioning of polynomials in z at
    # a 500 us loop (poles clustered near z = 1): measured worst 5.6e-8 (z/w), 2e-11 (x/u).
    st = LinearTable(TableParameters.report_default(), delay="sampled").sampled()
    f = np.array([0.5, 5.0, 27.0, 200.0])
    z = np.exp(1j * TWO_PI * f * 5e-4)
    for output in ("z", "x", "v", "dp"):
        for input in ("u", "w"):
            sys = st.channel(output, input)
            num, den = ss_to_tf(sys)
            np.testing.assert_allclose(
                np.polyval(num, z) / np.polyval(den, z), sys.frequency_response(f), rtol=5e-7
            )


def test_conversion_needs_one_channel_of_a_continuous_system_for_a_transfer_function():
    sys = plant_state_space(TableParameters.report_default()).system
    with pytest.raises(ConfigError, match="SISO"):
        ss_to_tf(sys)
    with pytest.raises(ConfigError, match="continuous"):
        TransferFunction.from_lti(sys.zoh(1e-3).channel("z", "w"))
    # A static gain converts to a constant.
    g = TransferFunction.from_lti(StateSpace(np.zeros((0, 0)), np.zeros((0, 1)), np.zeros((1, 0)), 2.5))
    assert g.num.tolist() == [2.5] and g.den.tolist() == [1.0]
