"""Low-pass filters (Section 6.4): Eq 6-10, 6-11a/b, families and orders."""

import numpy as np
import pytest

from impedance_mil.design import LowpassFilter, apply_filter, design_controller, required_order
from impedance_mil.errors import ConfigError

from .printed import assert_printed


def test_eq_6_10_butterworth_80_hz():
    # Eq 6-10 (MATLAB butter(3, 2*pi*80, 'low', 's')), 3 significant digits.
    F = LowpassFilter("butterworth", 3, 80.0).tf()
    assert_printed(F.num, ["1.27e8"], "Eq 6-10 num")
    assert_printed(F.den, ["1", "1.01e3", "5.05e5", "1.27e8"], "Eq 6-10 den")


def test_eq_6_11a_b_filtered_controllers(table):
    d = design_controller(table, form="standardized", fc_hz=80.0, emit_warnings=False)
    # Eq 6-11a, printed with 2 significant digits (den "1 x 10^3" with one).
    assert_printed(d.H_uz.num, ["5.5e-4", "6.4e-1", "1.8e2", "7.3e4", "4.7e6", "1.3e8"], "Eq 6-11a num")
    assert_printed(d.H_uz.den[:4], ["1", "1e3", "5.1e5", "1.3e8"], "Eq 6-11a den")
    np.testing.assert_array_equal(d.H_uz.den[4:], [0.0, 0.0])  # the double integrator of 1/H_zu
    # Eq 6-11b is H_w^filter H_zw/H_zu; our H_uw carries the minus sign of Eq 6-9.
    H = -d.H_uw
    assert_printed(H.num, ["1.33e-4", "1.54e-1", "3.9e1", "1.3e4"], "Eq 6-11b num")
    assert_printed(H.den, ["1", "1.01e3", "5.05e5", "1.27e8"], "Eq 6-11b den")
    assert d.H_uz.is_proper and d.H_uw.is_proper and d.H_uz.relative_degree == 0


@pytest.mark.parametrize("family", ["butterworth", "bessel", "chebyshev1"])
@pytest.mark.parametrize("order", [3, 4, 5])
def test_families_have_unit_dc_gain_and_cut_off(family, order):
    F = LowpassFilter(family, order, 100.0, ripple_db=1.0).tf()
    assert F.dcgain() == pytest.approx(1.0, rel=1e-12)
    assert F.order == order and F.relative_degree == order and F.is_stable()
    g = abs(F.frequency_response([100.0])[0])
    if family == "chebyshev1":
        # Edge of the ripple band: |F(fc)| = -ripple relative to the pass-band maximum.
        peak = np.max(np.abs(F.frequency_response(np.linspace(0, 100.0, 2001))))
        assert 20 * np.log10(g / peak) == pytest.approx(-1.0, abs=1e-6)
    else:
        assert 20 * np.log10(g) == pytest.approx(-3.0103, abs=1e-3)  # -3 dB at fc (bessel norm='mag')


def test_order_follows_relative_degree_and_can_be_raised(table):
    from impedance_mil.design import ideal_controller

    H = ideal_controller("standardized", table).H_uz
    assert required_order(H) == 3
    Hf, n = apply_filter(H, "butterworth", 80.0)
    assert n == 3 and Hf.relative_degree == 0
    Hf, n = apply_filter(H, "bessel", 80.0, order=5)
    assert n == 5 and Hf.relative_degree == 2
    with pytest.raises(ConfigError, match="at least 3"):
        apply_filter(H, "butterworth", 80.0, order=2)


def test_separate_w_cut_off(table, sd2):
    d = design_controller(table, sd2, fc_hz=80.0, fc_w_hz=120.0, emit_warnings=False)
    a = design_controller(table, sd2, fc_hz=80.0, emit_warnings=False)
    b = design_controller(table, sd2, fc_hz=120.0, emit_warnings=False)
    assert d.H_uz.isclose(a.H_uz) and d.H_uw.isclose(b.H_uw, rtol=1e-7)
    assert d.filter.fc_w_hz == 120.0


@pytest.mark.parametrize(
    "bad",
    [
        dict(family="elliptic"),
        dict(order=0),
        dict(order=11),
        dict(fc_hz=0.0),
        dict(fc_hz=-1.0),
        dict(family="chebyshev1", ripple_db=0.0),
    ],
)
def test_bad_filters_are_refused(bad):
    kw = dict(family="butterworth", order=3, fc_hz=80.0) | bad
    with pytest.raises(ConfigError):
        LowpassFilter(**kw)
