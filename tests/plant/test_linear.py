"""Linear table model: state space (Eq 4-11, 4-14) against the closed forms of Eq 4-15."""

import numpy as np
import pytest

from impedance_mil.errors import ConfigError, UnstableSystemError
from impedance_mil.plant import LinearTable, TableParameters, plant_state_space

TWO_PI = 2 * np.pi
# Coefficient comparisons: both sides are evaluated in double precision from the same
# parameters, so they agree to round-off; 1e-9 relative leaves room for the recursion.
RTOL = 1e-9


def eq_4_15(p):
    """The six transfer functions as printed in Eq 4-15 (num, den), first-order delay form."""
    a1, a2 = TWO_PI * np.array(p.valve_poles_hz)
    g, dl = a1 * a2, a1 + a2
    w2 = (TWO_PI * p.f_oil_hz) ** 2
    e = 2 * p.zeta_oil * TWO_PI * p.f_oil_hz
    d, ap, m, kv, ke, kp, tau = p.d, p.piston_area, p.mass, p.Kv, p.Ke, p.Kp, p.loop_time
    den = [
        1.0,
        dl + e,
        w2 + dl * e + g - g * d * kv * kp * tau,
        dl * w2 + g * e + g * d * kv * kp,
        g * w2 - g * d * ap * kv * ke * tau / m,
        g * d * ap * kv * ke / m,
    ]
    k0 = g * d * ap * kv * ke / m
    wnum = [1.0, dl + e, dl * e + g - g * d * kv * kp * tau, g * e + g * d * kv * kp]
    return {
        ("z", "u"): ([k0, 0.0, 0.0], den),
        ("x", "u"): ([k0], den),
        ("dp", "u"): ([g * d * kv * ke, 0.0, 0.0], den),
        ("z", "w"): ([c / m for c in wnum] + [0.0, 0.0], den),
        ("x", "w"): ([c / m for c in wnum], den),
        ("dp", "w"): (
            [-w2 / ap, -dl * w2 / ap, -(g * w2 / ap - g * d * kv * ke * tau / m), -g * d * kv * ke / m],
            den,
        ),
    }


PARAMS = [
    TableParameters.report_default(),  # Table 4.1 (tau = 500 us)
    TableParameters.report_default().replace(loop_time=0.0),  # analog, Eq 4-14b
    TableParameters.report_default().replace(
        Ke=3.0, Kp=0.0006, loop_time=1e-3, d=2e5, zeta_oil=0.05, f_oil_hz=31.0
    ),
]


@pytest.mark.parametrize("p", PARAMS)
@pytest.mark.parametrize("pair", list(eq_4_15(PARAMS[0])))
def test_six_tfs_match_eq_4_15_coefficient_by_coefficient(p, pair):
    # Source: Eq 4-15a-f (closed forms), first-order delay; tau = 0 gives the analog model.
    num, den = eq_4_15(p)[pair]
    delay = "first-order" if p.loop_time > 0 else "none"
    H = LinearTable(p, delay=delay).tf(*pair)
    assert H.den.size == len(den)
    np.testing.assert_allclose(H.den, den, rtol=RTOL, atol=0)
    np.testing.assert_allclose(H.num, num, rtol=RTOL, atol=0)  # zeros at s=0 are exact


def test_state_space_matches_eq_4_14b_and_printed_eq_4_14a_lacks_kv():
    p = TableParameters.report_default()
    a1, a2 = TWO_PI * 70, TWO_PI * 110
    g, dl = a1 * a2, a1 + a2
    w2, e = (TWO_PI * 27) ** 2, 2 * 0.09 * TWO_PI * 27
    m, ap, d, kv, ke, kp, tau = 4.14, 2.1, 1e5, 3.0, 5.0, 0.001, 500e-6
    top = [[0, 1, 0, 0, 0], [0, 0, ap / m, 0, 0], [0, -w2 * m / ap, -e, d, 0], [0, 0, 0, 0, 1]]
    # Eq 4-14b, as printed.
    A_b = np.array(top + [[-kv * ke * g, 0, -kv * kp * g, -g, -dl]])
    np.testing.assert_allclose(LinearTable(p, delay="none").state_space().A, A_b, rtol=1e-12)
    # Eq 4-14a with K_v in entry (5,4): gamma (K_v d K_p tau - 1).
    row = [
        -kv * ke * g,
        kv * g * tau * (ke - kp * w2 * m / ap),
        -kv * kp * g * (1 + tau * e),
        g * (kv * d * kp * tau - 1),
        -dl,
    ]
    A_a = np.array(top + [row])
    np.testing.assert_allclose(LinearTable(p).state_space().A, A_a, rtol=1e-12)
    # As printed, entry (5,4) reads gamma (d K_p tau - 1): its characteristic polynomial
    # differs from the Eq 4-15 denominator (which has K_v) in the s^3 coefficient.
    A_printed = A_a.copy()
    A_printed[4, 3] = g * (d * kp * tau - 1)
    den_printed = np.poly(A_printed)
    den_415 = eq_4_15(p)[("x", "u")][1]
    assert abs(den_printed[2] - den_415[2]) / den_415[2] > 0.05
    np.testing.assert_allclose(np.poly(A_a), den_415, rtol=1e-9)


def test_open_loop_eq_4_11_poles():
    # Section 4.4.2: K_e = K_p = 0 -> p1 = 0, valve poles -2 pi 70, -2 pi 110, oil -15.3 +- 169i.
    ol = plant_state_space(TableParameters.report_default())
    poles = sorted(ol.poles(), key=lambda q: (abs(q), q.imag))
    assert abs(poles[0]) < 1e-9
    oil = poles[2]
    assert oil.real == pytest.approx(-15.3, abs=0.05)  # printed to 0.1
    assert oil.imag == pytest.approx(169.0, abs=0.5)  # printed to 3 digits
    assert poles[3].real == pytest.approx(-TWO_PI * 70, rel=1e-12)
    assert poles[4].real == pytest.approx(-TWO_PI * 110, rel=1e-12)


@pytest.mark.parametrize("delay", ["none", "first-order", "pade"])
def test_tf_equals_state_space_frequency_response(delay):
    # Invariant: polynomial TFs equal the resolvent C (sI-A)^-1 b + D of the same model.
    tbl = LinearTable(TableParameters.report_default(), delay=delay)
    f = np.array([0.5, 5.0, 27.0, 60.0, 150.0])
    ss = tbl.state_space()
    for out in ("z", "x", "v", "dp"):
        for inp in ("u", "w"):
            ref = ss.frequency_response(out, inp, f)
            np.testing.assert_allclose(tbl.tf(out, inp).frequency_response(f), ref, rtol=1e-7)


def test_static_gains_and_sign_convention():
    tbl = LinearTable(TableParameters.report_default())
    assert tbl.tf("x", "u").dcgain() == pytest.approx(1.0, rel=1e-12)  # position loop: x -> u
    # A steady force w must be resisted by dP: A_p dP = -w (Eq 4-7b with z = 0).
    assert tbl.tf("dp", "w").dcgain() == pytest.approx(-1 / 2.1, rel=1e-12)
    # z/w at high frequency -> 1/m_st (the force accelerates the table mass alone).
    assert abs(tbl.tf("z", "w").frequency_response([1e5])[0]) == pytest.approx(1 / 4.14, rel=1e-3)
    v = tbl.tf("v", "u")
    s = 2j * np.pi * 3.0
    assert v(s) == pytest.approx(s * tbl.tf("x", "u")(s), rel=1e-12)


def test_pade_converges_to_first_order_for_short_delays():
    # e^{-s tau} ~ 1 - s tau for |s tau| << 1: at tau = 20 us the models agree to 1e-3 below 100 Hz.
    p = TableParameters.report_default().replace(loop_time=20e-6)
    f = np.linspace(1, 100, 12)
    a = LinearTable(p, delay="pade").tf("z", "u").frequency_response(f)
    b = LinearTable(p, delay="first-order").tf("z", "u").frequency_response(f)
    np.testing.assert_allclose(a, b, rtol=1e-3)


def test_sampled_model_and_errors():
    p = TableParameters.report_default()
    tbl = LinearTable(p, delay="sampled")
    assert tbl.is_stable()
    with pytest.raises(ConfigError, match="delay"):
        tbl.tf("z", "u")
    H = tbl.sampled().tf("x", "u")
    assert H.frequency_response([0.0])[0].real == pytest.approx(1.0, rel=1e-9)  # DC gain 1
    with pytest.raises(ConfigError, match="loop_time"):
        LinearTable(p.replace(loop_time=0.0), delay="sampled")
    with pytest.raises(ConfigError, match="delay"):
        LinearTable(p, delay="exact")
    with pytest.raises(ConfigError, match="output"):
        LinearTable(p).tf("a", "u")
    with pytest.raises(ConfigError, match="input"):
        LinearTable(p).tf("z", "q")


def test_require_stable():
    p = TableParameters.report_default()
    assert LinearTable(p).require_stable().is_stable()
    bad = LinearTable(p.replace(Kp=0.0, Ke=8.0, loop_time=0.0))  # beyond K_e = 6.7 V/in
    assert not bad.is_stable()
    with pytest.raises(UnstableSystemError, match="unstable"):
        bad.require_stable()
