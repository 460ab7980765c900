"""Tests of the transfer-function value object (impedance_mil.systems)."""

import control
import numpy as np
import pytest

from impedance_mil.plant import LinearTable, TableParameters
from impedance_mil.systems import TransferFunction, pole_table

TWO_PI = 2 * np.pi


def test_denominator_is_monic_and_leading_zeros_trimmed():
    H = TransferFunction([0.0, 2.0, 4.0], [2.0, 6.0, 8.0])
    np.testing.assert_allclose(H.den, [1.0, 3.0, 4.0])
    np.testing.assert_allclose(H.num, [1.0, 2.0])


def test_inverse_of_relative_degree_three_is_improper_and_cancels_exactly():
    # H_zu-like: s^2 / ((s+a)(s+b)(s^2+2 z w s + w^2) s)  (relative degree 3)
    a, b, w, z = TWO_PI * 70, TWO_PI * 110, TWO_PI * 27, 0.09
    den = np.polymul(np.polymul([1, a], [1, b]), np.polymul([1, 2 * z * w, w**2], [1, 5.0]))
    H = TransferFunction([3e9, 0, 0], den)
    Hinv = H.inv()
    assert Hinv.relative_degree == -3 and not Hinv.is_proper
    one = (H * Hinv).minreal()
    np.testing.assert_allclose(one.num, [1.0], rtol=1e-9)
    np.testing.assert_allclose(one.den, [1.0])


def test_relative_tolerance_cancels_far_and_near_roots_alike():
    # Poles at -1e-3 and -1e4 rad/s, each with a zero perturbed by a relative 1e-9:
    # an absolute tolerance cannot treat both; a relative one does.
    p1, p2 = -1e-3, -1e4
    H = TransferFunction.from_zpk([p1 * (1 + 1e-9), p2 * (1 + 1e-9)], [p1, p2, -3.0], 2.0)
    R = H.minreal(rtol=1e-6)
    assert R.order == 1
    np.testing.assert_allclose(R.poles(), [-3.0])
    # ...but does not cancel a zero 1% away from a pole.
    H2 = TransferFunction.from_zpk([p2 * 1.01], [p2, -3.0], 2.0)
    assert H2.minreal(rtol=1e-6).order == 2


def test_common_powers_of_s_cancel_exactly():
    H = TransferFunction([1.0, 0.0, 0.0], [1.0, 3.0, 2.0, 0.0])
    R = H.minreal()
    np.testing.assert_allclose(R.num, [1.0, 0.0])
    np.testing.assert_allclose(R.den, [1.0, 3.0, 2.0])


def test_algebra_matches_frequency_response_pointwise():
    H1 = TransferFunction([1.0, 2.0], [1.0, 0.5, 4.0])
    H2 = TransferFunction([3.0], [1.0, 7.0])
    f = np.logspace(-1, 2, 50)
    for expr, ref in [
        (H1 + H2, H1.frequency_response(f) + H2.frequency_response(f)),
        (H1 - H2, H1.frequency_response(f) - H2.frequency_response(f)),
        (H1 * H2, H1.frequency_response(f) * H2.frequency_response(f)),
        (H1 / H2, H1.frequency_response(f) / H2.frequency_response(f)),
        (
            H1.feedback(H2),
            H1.frequency_response(f) / (1 + H1.frequency_response(f) * H2.frequency_response(f)),
        ),
        (2.0 * H1 + 1.0, 2.0 * H1.frequency_response(f) + 1.0),
    ]:
        np.testing.assert_allclose(expr.frequency_response(f), ref, rtol=1e-10)


def test_state_space_round_trip():
    H = TransferFunction([2.0, 1.0], [1.0, 3.0, 5.0, 7.0])
    A, B, C, D = H.to_ss()
    assert TransferFunction.from_ss(A, B, C, D).isclose(H, rtol=1e-10)
    with pytest.raises(ValueError):
        H.inv().to_ss()


def test_pole_table_frequency_and_damping():
    w, z = TWO_PI * 27, 0.09
    p = -z * w + 1j * w * np.sqrt(1 - z**2)
    rows = pole_table([p, np.conj(p), -TWO_PI * 70])
    assert rows[0]["frequency_hz"] == pytest.approx(27.0)
    assert rows[0]["damping"] == pytest.approx(0.09)
    assert rows[2]["frequency_hz"] == pytest.approx(70.0)
    assert rows[2]["damping"] == pytest.approx(1.0)


def test_wide_coefficient_range_is_not_trimmed():
    # Coefficients spanning 20+ decades (H_uz of Eq 6-8a times a filter) must survive:
    # only exact zeros are leading zeros.
    H = TransferFunction([4.3e-12, 5.0e-9, 1.4e-6, 5.8e-4, 3.7e-2, 1.0], [1.0, 0.0, 0.0])
    P = H * TransferFunction([1.27e8], [1.0, 1.01e3, 5.05e5, 1.27e8])
    assert P.num.size == 6 and P.relative_degree == 0


def test_sum_cancels_to_exact_zero_relative_to_operands():
    a = TransferFunction([1.0 / 3.0, 2.0], [1.0, 1.0])
    b = TransferFunction([1.0 / 3.0 * (1 + 1e-15), 1.0], [1.0, 1.0])
    d = a - b
    # (s+1)/(s+1)^2 before cancellation: the s^2 term of the numerator (1e-16) is removed exactly.
    assert d.num.size == 2 and d.relative_degree == 1


def test_mul_cancel_removes_shared_denominator_exactly():
    # H_zw/H_zu of the report's table share the fifth-order denominator and s^2: the quotient
    # is the cubic polynomial of Eq 6-8b.  A product-then-minreal loses those roots in clusters.
    a1, a2, w, z = TWO_PI * 70, TWO_PI * 110, TWO_PI * 27, 0.09
    den = np.polymul(np.polymul([1, a1], [1, a2]), np.polymul([1, 2 * z * w, w**2], [1, 5.0]))
    Hzu = TransferFunction([3e9, 0, 0], den)
    Hzw = TransferFunction(np.polymul([1.0, 300.0, 4e4, 2e6], [1.0, 0.0, 0.0]), den)
    Q = Hzw.div_cancel(Hzu)
    assert Q.den.tolist() == [1.0]
    np.testing.assert_allclose(Q.num, np.array([1.0, 300.0, 4e4, 2e6]) / 3e9, rtol=1e-9)


def test_dict_round_trip_and_bad_dicts():
    H = TransferFunction([1e-12, 3.0], [1.0, 2.0, 5.0])
    assert TransferFunction.from_dict(H.to_dict()).isclose(H, rtol=0)
    for bad in (
        {"num": [1]},
        {"num": "x", "den": [1]},
        {"num": [[1, 2]], "den": [1]},
        {"num": [float("nan")], "den": [1]},
    ):
        with pytest.raises(ValueError):
            TransferFunction.from_dict(bad)


def test_from_ss_drops_rounding_residue_in_numerator():
    # x'' = u: ss2tf may leave ~1e-16 leading numerator terms; the result must be 1/s^2.
    A = [[0.0, 1.0], [-4.0, -0.4]]
    H = TransferFunction.from_ss(A, [0.0, 1.0], [1.0, 0.0])
    assert H.relative_degree == 2


def test_report_table_state_space_to_tf_keeps_relative_degree_and_dc_gain_exact():
    # Issue 13: from_ss once left round-off in the polynomials ("H_zw is improper (relative
    # degree -1)").  The report's table (Eq 4-14a) as a state space, in its own basis, through
    # python-control and in an exactly rescaled and permuted basis (powers of 2: no rounding
    # in the similarity): every path keeps the relative degree of Eq 4-15 and its DC gain
    # exactly (0.0 where z has s**2; x/u = 1 to rounding, 2e-15 measured).
    ss = LinearTable(TableParameters.report_default()).state_space().system
    perm = np.array([3, 0, 4, 2, 1])
    scale = 2.0 ** np.array([-3, 5, -7, 2, 9])
    T = np.diag(scale)[:, perm]
    Ti = np.linalg.inv(T)  # exact: a scaled permutation
    expected = {("z", "u"): (3, 0.0), ("z", "w"): (0, 0.0), ("v", "u"): (4, 0.0), ("v", "w"): (1, 0.0)}
    for (o, i), (degree, gain) in expected.items():
        c = ss.channel(o, i)
        for H in (
            TransferFunction.from_ss(c.A, c.B, c.C, c.D),
            TransferFunction.from_control(control.ss(c.A, c.B, c.C, c.D)),
            TransferFunction.from_ss(Ti @ c.A @ T, Ti @ c.B, c.C @ T, c.D),
        ):
            assert H.relative_degree == degree and H.dcgain() == gain
    for realization in ((ss.A, ss.B, ss.C), (Ti @ ss.A @ T, Ti @ ss.B, ss.C @ T)):
        A, B, C = realization
        H = TransferFunction.from_ss(A, B[:, :1], C[ss.outputs.index("x")], 0.0)
        assert H.relative_degree == 5 and H.dcgain() == pytest.approx(1.0, rel=1e-14)
        Hw = TransferFunction.from_ss(A, B[:, 1:], C[ss.outputs.index("x")], 0.0)
        assert Hw.relative_degree == 2 and Hw.is_proper


def test_to_zpk_gives_the_roots_and_monic_gain():
    H = TransferFunction.from_zpk([-1.0], [-2.0 + 3j, -2.0 - 3j], 5.0)
    doc = H.to_zpk()
    assert doc["gain"] == 5.0 and doc["zeros"] == [[-1.0, 0.0]]
    np.testing.assert_allclose(sorted(p[1] for p in doc["poles"]), [-3.0, 3.0], rtol=1e-14)
    assert TransferFunction.constant(0.0).to_zpk() == {"zeros": [], "poles": [], "gain": 0.0}
