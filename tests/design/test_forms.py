"""Controller forms (Eq 1-4, 1-6, 6-3, 6-6, 6-7) and the coefficients of Eq 6-8."""

import numpy as np
import pytest

from impedance_mil.design import (
    TableModel,
    VirtualModel,
    controlled_table,
    design_controller,
    ideal_controller,
)
from impedance_mil.design.filters import LowpassFilter
from impedance_mil.errors import ConfigError, UnstableDesignError, UnstableSystemError
from impedance_mil.systems import TransferFunction

from .conftest import AP, KE, KP, KV, W_OIL, ZETA_OIL, D, closed_form_table, fp_model, lr_model
from .printed import assert_printed, half_unit

F_LOW = np.logspace(-1, 1.5, 60)  # 0.1-31.6 Hz


def test_eq_6_8a_standardized_H_uz(table):
    # Eq 6-8a, printed to 3 significant digits; tolerance half a unit in the last digit.
    H = ideal_controller("standardized", table).H_uz
    assert H.relative_degree == -3
    np.testing.assert_array_equal(H.den, [1.0, 0.0, 0.0])
    assert_printed(H.num, ["4.32e-12", "5.02e-9", "1.39e-6", "5.75e-4", "3.73e-2", "1.00"], "Eq 6-8a")


def test_eq_6_8b_H_uw_and_its_misprinted_constant(table):
    # Eq 6-8b is H_zw/H_zu; our H_uw carries the minus sign of Eq 6-7 (u = ... + H_uw w).
    H = -ideal_controller("standardized", table).H_uw
    assert H.relative_degree == -3 and H.den.tolist() == [1.0]
    assert_printed(H.num[:3], ["1.04e-12", "1.21e-9", "3.06e-7"], "Eq 6-8b")
    # Constant term: closed form (eps + d Kv Kp)/(d Ap Kv Ke) from Eq 4-15a/d = 1.0493e-4 s^0.
    closed = (2 * ZETA_OIL * W_OIL + D * KV * KP) / (D * AP * KV * KE)
    assert H.num[3] == pytest.approx(closed, rel=1e-12)
    assert abs(H.num[3] - 1.05e-4) <= half_unit("1.05e-4")
    # The report prints 1.04 x 10^4: exponent sign lost (and 1.049 truncated); see docs/errata.md.
    assert H.num[3] / 1.04e4 < 1e-7


@pytest.mark.parametrize("form", ["standardized", "general", "vs-specific", "tracking"])
def test_ideal_controller_matches_the_vs_impedance_exactly(form, table, sd2):
    vs = lr_model() if form == "vs-specific" else sd2
    env = VirtualModel.rigid() if form == "tracking" else vs
    ideal = ideal_controller(form, table, env)
    ct = controlled_table(table, env, ideal.H_uz, ideal.H_uw, form)
    target = env.H_zw.frequency_response(F_LOW)
    got = ct.impedance(F_LOW)
    # Unfiltered: z_st = z_vs identically (Eq 6-5 = 6-4); rounding-level tolerance relative to |H_zw^st|.
    scale = np.abs(table.H_zw.frequency_response(F_LOW))
    assert np.all(np.abs(got - target) <= 1e-9 * scale)


@pytest.mark.parametrize("form", ["standardized", "general", "vs-specific", "tracking"])
def test_filtered_controller_matches_below_fc(form, table, sd2):
    # Exact identity H_c - H_vs = (H_st - H_vs)(1 - F_w) for every form (F_z = F_w), and
    # |1 - F| ~ 2 f/fc for a 3rd-order Butterworth (1 - F = 2s/wc + O(s^2)): below fc/40 the error
    # is at most 6% of |H_st - H_vs| (0.05 plus 20% allowance for the higher-order terms).
    fc = 80.0
    vs = lr_model() if form == "vs-specific" else sd2
    env = VirtualModel.rigid() if form == "tracking" else vs
    d = design_controller(table, env, form=form, fc_hz=fc, emit_warnings=False)
    ct = controlled_table(table, env, d.H_uz, d.H_uw, form)
    f = np.logspace(-1, np.log10(fc / 40), 40)
    F = LowpassFilter("butterworth", 3, fc).tf().frequency_response(f)
    Hst, Hvs = table.H_zw.frequency_response(f), env.H_zw.frequency_response(f)
    Hc = ct.impedance(f)
    # The polynomial form of H_c agrees with the factor-by-factor response to 1e-6 of |H_c|.
    assert np.all(np.abs(ct.H_c.frequency_response(f) - Hc) <= 1e-6 * np.abs(Hc))
    np.testing.assert_allclose(Hc - Hvs, (Hst - Hvs) * (1 - F), rtol=1e-6, atol=1e-9 * np.max(np.abs(Hst)))
    assert np.all(np.abs(Hc - Hvs) <= 0.06 * np.abs(Hst - Hvs))


def test_vs_specific_reproduces_each_vs_input(table):
    # Eq 6-6: with u = H_uz a_g + H_uw w + H_ufh f_h, z_st = H_zag a_g + H_zw w + H_zfh f_h (unfiltered).
    for vs in (lr_model(), fp_model()):
        ideal = ideal_controller("vs-specific", table, vs)
        for H_u, H_vs in ((ideal.H_uz, vs.H_zag), (ideal.H_ufh, vs.H_zfh)):
            got = (table.H_zu * H_u).frequency_response(F_LOW)
            np.testing.assert_allclose(got, H_vs.frequency_response(F_LOW), rtol=1e-8)


def test_general_and_standardized_agree_for_a_linear_vs(table, sd2):
    # Same filter on both paths: the two forms give the same controlled impedance (Section 6.2).
    a = design_controller(table, sd2, form="general", fc_hz=100.0, order=3, emit_warnings=False)
    b = design_controller(table, sd2, form="standardized", fc_hz=100.0, emit_warnings=False)
    Ha = controlled_table(table, sd2, a.H_uz, a.H_uw, "general").impedance(F_LOW)
    Hb = controlled_table(table, sd2, b.H_uz, b.H_uw, "standardized").impedance(F_LOW)
    np.testing.assert_allclose(Ha, Hb, rtol=1e-7)


def test_standardized_depends_on_the_table_only(table, sd2):
    a = design_controller(table, sd2, form="standardized", fc_hz=80.0, emit_warnings=False)
    b = design_controller(table, lr_model(), form="standardized", fc_hz=80.0, emit_warnings=False)
    assert a.H_uz.isclose(b.H_uz) and a.H_uw.isclose(b.H_uw)


def test_tracking_is_standardized_with_rigid_environment(table):
    s = ideal_controller("standardized", table)
    t = ideal_controller("tracking", table)
    assert t.reference == "a_g" and s.reference == "z_vs"
    assert s.H_uz.isclose(t.H_uz) and s.H_uw.isclose(t.H_uw)


def test_filter_order_follows_relative_degree(table, sd2):
    d = design_controller(table, sd2, form="general", fc_hz=80.0, emit_warnings=False)
    assert (d.filter.order_z, d.filter.order_w) == (2, 3)  # H_zag/H_zu: -2, (H_vs - H_st)/H_zu: -3
    d = design_controller(table, fp_model(), form="vs-specific", fc_hz=80.0, emit_warnings=False)
    assert d.filter.order_fh == 3  # H_zfh^fp = -s^2/(...) has relative degree 0
    assert all(H.is_proper for H in (d.H_uz, d.H_uw, d.H_ufh))


def test_bad_designs_are_refused(table, sd2):
    with pytest.raises(ConfigError, match="filter order"):
        design_controller(table, sd2, fc_hz=80.0, order=2)
    for fc in (0.0, -5.0, float("nan")):
        with pytest.raises(ConfigError, match="fc"):
            design_controller(table, sd2, fc_hz=fc)
    with pytest.raises(UnstableSystemError):
        design_controller(closed_form_table(Kp=0.02), sd2, fc_hz=80.0)  # unstable table loop
    rhp = TableModel(TransferFunction([1.0, -5.0], [1.0, 3.0, 2.0]), table.H_zw, table.loop_time_s)
    with pytest.raises(UnstableDesignError, match="right-half-plane zero"):
        design_controller(rhp, sd2, fc_hz=80.0)
    improper = VirtualModel(sd2.H_zag, TransferFunction([1.0, 0.0, 0.0], [1.0, 1.0]))
    with pytest.raises(UnstableDesignError, match="improper"):
        design_controller(table, improper, form="general", fc_hz=80.0)
    unstable = VirtualModel(sd2.H_zag, TransferFunction([1.0, 0.0, 0.0], [1.0, -1.0, 4.0]))
    with pytest.raises(UnstableDesignError, match="unstable pole"):
        design_controller(table, unstable, form="general", fc_hz=80.0)
    with pytest.raises(ConfigError, match="form"):
        design_controller(table, sd2, form="vs-specific", fc_hz=80.0)  # SD has no f_h
