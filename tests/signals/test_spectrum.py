"""Response spectra: exact Nigam-Jennings recurrence against closed forms and independent methods."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lsim

from impedance_mil.errors import ConfigError
from impedance_mil.signals import builtin_motion, oscillator_response, response_spectrum
from impedance_mil.signals.spectrum import recurrence_coefficients

TWO_PI = 2 * np.pi


def _nigam_jennings_closed_form(w, z, dt):
    """Nigam & Jennings (1969) coefficients as printed in the literature (0 <= z < 1)."""
    wd = w * np.sqrt(1 - z * z)
    e, s, c, r = np.exp(-z * w * dt), np.sin(wd * dt), np.cos(wd * dt), z / np.sqrt(1 - z * z)
    k1, k2 = (2 * z * z - 1) / (w * w * dt), 2 * z / (w**3 * dt)
    a = np.array([[e * (r * s + c), e * s / wd], [-w / np.sqrt(1 - z * z) * e * s, e * (c - r * s)]])
    b = np.array(
        [
            [
                e * ((k1 + z / w) * s / wd + (k2 + 1 / w**2) * c) - k2,
                -e * (k1 * s / wd + k2 * c) - 1 / w**2 + k2,
            ],
            [
                e * ((k1 + z / w) * (c - r * s) - (k2 + 1 / w**2) * (wd * s + z * w * c)) + 1 / (w * w * dt),
                -e * (k1 * (c - r * s) - k2 * (wd * s + z * w * c)) - 1 / (w * w * dt),
            ],
        ]
    )
    return a, b


@pytest.mark.parametrize(
    ("w", "z", "dt"), [(TWO_PI, 0.05, 0.01), (50.0, 0.2, 0.003), (1.0, 0.0, 0.1), (300.0, 0.05, 0.02)]
)
def test_coefficients_match_published_closed_form(w, z, dt):
    # Independent formula; at these omega*dt (0.06 to 6) the closed form has no cancellation,
    # so agreement to 1e-12 relative (of the largest entry) is expected.
    a_ref, b_ref = _nigam_jennings_closed_form(w, z, dt)
    a, b = recurrence_coefficients(w, z, dt)
    np.testing.assert_allclose(a, a_ref, rtol=0, atol=1e-12 * np.max(np.abs(a_ref)))
    np.testing.assert_allclose(b, b_ref, rtol=0, atol=1e-12 * np.max(np.abs(b_ref)))


def _step_response(t, w, z, a0):
    wd = w * np.sqrt(1 - z * z)
    return -(a0 / w**2) * (
        1 - np.exp(-z * w * t) * (np.cos(wd * t) + z / np.sqrt(1 - z * z) * np.sin(wd * t))
    )


def _ramp_response(t, w, z, c):
    # u'' + 2 z w u' + w^2 u = -c t from rest: particular -c (t/w^2 - 2z/w^3) plus the free response.
    wd = w * np.sqrt(1 - z * z)
    c1 = -2 * z * c / w**3
    c2 = c * (1 - 2 * z * z) / (w**2 * wd)
    return -c * (t / w**2 - 2 * z / w**3) + np.exp(-z * w * t) * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))


@pytest.mark.parametrize("dt", [0.0005, 0.01, 0.05, 0.2])
@pytest.mark.parametrize(("period", "zeta"), [(0.1, 0.05), (1.0, 0.02), (3.0, 0.3), (10.0, 0.05)])
def test_step_and_ramp_exact_for_any_dt(dt, period, zeta):
    # Step and ramp are piecewise linear, so the recurrence is exact: 1e-9 of the peak response
    # regardless of dt (rounding only, over up to 40 000 steps).
    w = TWO_PI / period
    n = int(round(20.0 / dt)) + 1
    t = np.arange(n) * dt
    u, _ = oscillator_response(np.full(n, 100.0), dt, period, zeta)
    exact = _step_response(t, w, zeta, 100.0)
    assert np.max(np.abs(u - exact)) <= 1e-9 * np.max(np.abs(exact))
    u, _ = oscillator_response(7.0 * t, dt, period, zeta)
    exact = _ramp_response(t, w, zeta, 7.0)
    assert np.max(np.abs(u - exact)) <= 1e-9 * np.max(np.abs(exact))


def _harmonic_response(t, w, z, amp, big_w):
    wd = w * np.sqrt(1 - z * z)
    mat = np.array([[w * w - big_w**2, -2 * z * w * big_w], [2 * z * w * big_w, w * w - big_w**2]])
    u1, u2 = np.linalg.solve(mat, [-amp, 0.0])
    c1 = -u2
    c2 = (z * w * c1 - big_w * u1) / wd
    return (
        u1 * np.sin(big_w * t)
        + u2 * np.cos(big_w * t)
        + np.exp(-z * w * t) * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    )


def test_harmonic_input_converges_at_second_order():
    # A sine is not piecewise linear: the recurrence solves the exact problem for the linear
    # interpolant, whose error is O(dt^2).  Closed-form response from rest; halving dt must cut
    # the error by 4 (+-10 %), and at dt = 1 ms (Omega dt = 0.0126) it is below 1e-4 of the peak.
    period, zeta, f_in = 0.5, 0.05, 2.0
    w, big_w = TWO_PI / period, TWO_PI * f_in
    errors = []
    for dt in (0.004, 0.002, 0.001):
        t = np.arange(int(round(10 / dt)) + 1) * dt
        u, _ = oscillator_response(50.0 * np.sin(big_w * t), dt, period, zeta)
        exact = _harmonic_response(t, w, zeta, 50.0, big_w)
        errors.append(np.max(np.abs(u - exact)) / np.max(np.abs(exact)))
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.1)
    assert errors[1] / errors[2] == pytest.approx(4.0, rel=0.1)
    assert errors[2] < 1e-4


@pytest.mark.parametrize("zeta", [0.0, 0.05, 1.0, 2.0])
def test_matches_scipy_lsim_first_order_hold(zeta):
    # scipy.signal.lsim interpolates the input linearly (an independent exact method, via its own
    # matrix exponential); histories agree to 1e-8 of the peak on the El Centro record,
    # including critical and over-damped oscillators.
    gm = builtin_motion("elcentro").trimmed(0.0, 15.0)
    for period in (0.05, 0.7, 4.0):
        w = TWO_PI / period
        _, y, _ = lsim(([-1.0], [1.0, 2 * zeta * w, w * w]), gm.accel, gm.time)
        u, _ = oscillator_response(gm.accel, gm.time_step, period, zeta)
        assert np.max(np.abs(u - y)) <= 1e-8 * np.max(np.abs(y))


def test_psa_tends_to_pga_at_short_period():
    # For T << dt the oscillator follows the ground: PSA -> PGA.  At T = 1 ms and dt = 10 ms the
    # lag term is 2 zeta / (omega dt) ~ 2e-3 of the sample jump; 1 % tolerance.
    gm = builtin_motion("elcentro")
    spec = response_spectrum(gm.accel, gm.time_step, [0.001], damping=0.05)
    assert spec.psa_g[0] == pytest.approx(gm.pga_g, rel=0.01)


def test_coarse_and_fine_sampling_of_same_piecewise_linear_input():
    # Interpolating the record linearly onto a 10x finer grid does not change the input function,
    # so the responses at the coarse instants are identical (1e-9 of the peak).  The fine spectrum
    # takes peaks over more instants: never smaller, and a peak of a near-harmonic response is at
    # most dt/2 from a coarse sample, so coarse >= fine * cos(pi dt / T) (0.1 % slack for the
    # damped envelope).
    gm = builtin_motion("elcentro-chopra")
    fine_t = np.arange((gm.npts - 1) * 10 + 1) * (gm.time_step / 10)
    fine = np.interp(fine_t, gm.time, gm.accel)
    u_c, _ = oscillator_response(gm.accel, gm.time_step, 0.3, 0.05)
    u_f, _ = oscillator_response(fine, gm.time_step / 10, 0.3, 0.05)
    assert np.max(np.abs(u_f[::10] - u_c)) <= 1e-9 * np.max(np.abs(u_c))
    periods = np.logspace(np.log10(0.2), 1, 30)
    coarse = response_spectrum(gm.accel, gm.time_step, periods)
    finer = response_spectrum(fine, gm.time_step / 10, periods)
    assert np.all(finer.sd >= coarse.sd * (1 - 1e-12))
    assert np.all(coarse.sd >= finer.sd * np.cos(np.pi * gm.time_step / periods) * (1 - 1e-3))


def test_spectrum_relations_and_units():
    gm = builtin_motion("elcentro")
    spec = response_spectrum(gm.accel, gm.time_step, [0.5, 1.0], damping=0.05)
    w = TWO_PI / spec.period_s
    np.testing.assert_allclose(spec.psa, w**2 * spec.sd, rtol=1e-15)
    np.testing.assert_allclose(spec.sv, w * spec.sd, rtol=1e-15)
    np.testing.assert_allclose(spec.psa_g, spec.psa / 386.08858267716535, rtol=1e-15)
    assert spec.damping == 0.05 and spec.frequency_hz[1] == pytest.approx(1.0)


def test_linearity_and_time_scaling_invariant():
    # Linear in the input; compressing time by s maps period T to T/s with the same PSA (exact).
    gm = builtin_motion("elcentro-chopra")
    base = response_spectrum(gm.accel, gm.time_step, [0.4, 1.0, 2.0])
    double = response_spectrum(2 * gm.accel, gm.time_step, [0.4, 1.0, 2.0])
    np.testing.assert_allclose(double.psa, 2 * base.psa, rtol=1e-12)
    fast = gm.time_scaled(2.0)
    compressed = response_spectrum(fast.accel, fast.time_step, [0.2, 0.5, 1.0])
    np.testing.assert_allclose(compressed.psa, base.psa, rtol=1e-10)


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"damping": -0.1}, "damping"),
        ({"periods": [0.0, 1.0]}, "periods"),
        ({"periods": []}, "periods"),
        ({"time_step": 0.0}, "time_step"),
    ],
)
def test_invalid_arguments(kwargs, key):
    args = {"accel": np.ones(10), "time_step": 0.01, "periods": [1.0], "damping": 0.05} | kwargs
    with pytest.raises(ConfigError, match=key):
        response_spectrum(**args)
