"""Presets SD1-SD3, LR1-LR3, FP1-FP3 against report Tables 9.1-9.3.

Source of every reference value: the printed tables (report Section 9.2).
Tolerances:
* integer columns (k_s, q_d, k_i): |computed - printed| <= 1 + 0.1% of the
  printed value.  One unit because the table sometimes truncates instead of
  rounding (SD2 k_s 894.7 printed 894); 0.1% because, computed from the
  printed inputs (2000 lb + 3600 lb), the values lie up to 0.07% above the
  printed ones (FP3 k_i 25200 printed 25183): the report evidently used a
  total weight of about 5596.4 lb;
* c (Table 9.1) is printed rounded to integers: |computed - printed| <= 0.5;
* alpha has 2 decimals: |computed - printed| <= 0.005.
"""

import math

import pytest

from impedance_mil.units import G0
from impedance_mil.virtual import FrictionPendulum, LeadRubber, SpringDamper, presets

# Table 9.1: name -> (k_s [lb/in], c [lb-s/in])
TABLE_9_1 = {"SD1": (322, 41), "SD2": (894, 57), "SD3": (1753, 64)}
# Table 9.2: name -> (q_d [lb], k_i [lb/in], k_s [lb/in], alpha, n, c [lb-s/in], u_y [in])
TABLE_9_2 = {
    "LR1": (504, 1402, 143, 0.10, 2, 0.11, 0.4),
    "LR2": (839, 2353, 254, 0.11, 2, 0.15, 0.4),
    "LR3": (1175, 3510, 572, 0.16, 2, 0.22, 0.4),
}
# Table 9.3: name -> (mu_max, mu_min, a [s/in], k_i [lb/in], k_s [lb/in])
TABLE_9_3 = {
    "FP1": (0.06, 0.03, 2.54, 8395, 113),
    "FP2": (0.12, 0.06, 2.54, 16789, 187),
    "FP3": (0.18, 0.09, 2.54, 25183, 366),
}


def _close_int(computed, printed):
    """Tolerance of the integer columns (see the module docstring)."""
    return abs(computed - printed) <= 1.0 + 1e-3 * printed


def test_names_and_kinds():
    # the report's nine first (Tables 9.1-9.3), then the presets of the types beyond the report
    assert presets.names()[:9] == ("SD1", "SD2", "SD3", "LR1", "LR2", "LR3", "FP1", "FP2", "FP3")
    assert set(presets.names()[9:]) == {"TFP1", "TFP2", "TFP3"}
    assert presets.get("sd1").definition is SpringDamper.definition
    assert presets.get("LR2").definition is LeadRubber.definition
    assert presets.get("FP3").definition is FrictionPendulum.definition


@pytest.mark.parametrize("name", sorted(TABLE_9_1))
def test_table_9_1_spring_damper(name):
    k_s, c = TABLE_9_1[name]
    vs = presets.get(name)
    assert vs.m_vs * G0 == pytest.approx(2000.0, rel=1e-12)  # Table 9.1 m_vs = 2000 lb
    assert _close_int(vs.k_s, k_s), vs.k_s
    assert abs(vs.c - c) <= 0.5, vs.c


@pytest.mark.parametrize("name", sorted(TABLE_9_2))
def test_table_9_2_lead_rubber(name):
    q_d, k_i, k_s, alpha, n, c, u_y = TABLE_9_2[name]
    vs = presets.get(name)
    assert vs.m_vs * G0 == pytest.approx(2000.0, rel=1e-12)
    assert _close_int(vs.q_d, q_d), vs.q_d
    assert _close_int(vs.k_i, k_i), vs.k_i
    assert _close_int(vs.k_s, k_s), vs.k_s
    assert abs(vs.alpha - alpha) <= 0.005, vs.alpha
    assert vs.n == n and vs.c == c
    assert vs.u_y == pytest.approx(u_y, rel=1e-12)  # u_y is an input, recovered exactly


@pytest.mark.parametrize("name", sorted(TABLE_9_3))
def test_table_9_3_friction_pendulum(name):
    mu_max, mu_min, a, k_i, k_s = TABLE_9_3[name]
    vs = presets.get(name)
    assert (vs.mu_max, vs.mu_min, vs.a) == (mu_max, mu_min, a)
    assert _close_int(vs.k_s, k_s), vs.k_s
    assert _close_int(vs.k_i, k_i), vs.k_i
    # Axial load basemat + test article (Figure 7.11 'Wa'): 2000 + 3600 lb.
    assert vs.W == pytest.approx(5600.0, rel=1e-12)


def test_table_9_3_basemat_mass_erratum():
    """Table 9.3 prints m_vs = 2150 lb, but its k_s and k_i need W = 2000 + 3600 lb.

    With 2150 lb the stiffnesses would be 2.7% above the printed values, far
    outside their rounding (see docs/errata.md).
    """
    for name, (_, _, _, k_i, k_s) in TABLE_9_3.items():
        printed_mass = presets.get(name, m_vs=2150.0 / G0)
        rebuilt = (
            presets.targets(name).__class__(**{**presets.targets(name).__dict__, "m_vs": 2150.0 / G0}).build()
        )
        assert printed_mass.k_s == presets.get(name).k_s  # model-level override keeps k_s
        assert rebuilt.k_s / k_s - 1.0 > 0.02
        assert rebuilt.k_i / k_i - 1.0 > 0.02


def test_design_targets_round_trip():
    """The built systems meet their own targets (closed forms of Section 9.2)."""
    M = 5600.0 / G0
    sd = presets.get("SD2")
    assert math.sqrt(sd.k_s / M) / (2 * math.pi) == pytest.approx(1.25, rel=1e-12)
    assert sd.c / (2 * math.sqrt(sd.k_s * M)) == pytest.approx(0.25, rel=1e-12)
    lr = presets.get("LR3")
    assert lr.q_d / (M * G0) == pytest.approx(0.21, rel=1e-12)
    assert 2 * math.pi * math.sqrt(M / lr.k_s) == pytest.approx(1.0, rel=1e-12)
    fp = presets.get("FP1")
    assert fp.derived()["T_s"] == pytest.approx(2.25, rel=1e-12)
    assert fp.R_eff == pytest.approx(G0 * (2.25 / (2 * math.pi)) ** 2, rel=1e-12)


def test_overrides():
    base = presets.get("SD2")
    heavier = presets.get("SD2", m_vs=1.25 * 4.14)  # Section 9.4.4: only m_vs varies
    assert (heavier.k_s, heavier.c) == (base.k_s, base.c)
    assert heavier.m_vs == 1.25 * 4.14
    assert presets.get("SD2", f=2.0).k_s == pytest.approx((2 * math.pi * 2.0) ** 2 * 5600 / G0)
    assert presets.get("LR1", u_y=0.2).u_y == pytest.approx(0.2)
    assert presets.get("FP1", w_ps=0.0).W == pytest.approx(2000.0)


def test_listing_fig_7_10_is_lr1_with_a_2150_lb_basemat():
    """Figure 7.10's LR block (k_i 1442.75, alp 0.102, qd 518.21, m_vs 2150/386) is LR1
    designed for a 2150-lb basemat, not Table 9.2's 2000 lb (see docs/errata.md).

    Tolerance 0.2%: the listing's k_i and q_d are both 0.14% above the design
    with 2150 + 3600 lb (a total weight of about 5758 lb, rounding of g).
    """
    listing = LeadRubber(m_vs=2150.0 / 386.0, k_i=1442.75, alpha=0.102, q_d=518.21, c=0.287, n=2.0)
    design = (
        presets.targets("LR1").__class__(**{**presets.targets("LR1").__dict__, "m_vs": 2150.0 / G0}).build()
    )
    assert design.k_i == pytest.approx(listing.k_i, rel=2e-3)
    assert design.q_d == pytest.approx(listing.q_d, rel=2e-3)
    assert design.alpha == pytest.approx(listing.alpha, abs=5e-4)
    assert presets.get("LR1").k_i / listing.k_i - 1.0 < -0.02  # Table 9.2's LR1 is 2.7% softer
