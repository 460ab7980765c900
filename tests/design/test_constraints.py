"""Constraints I, II, III (Sections 6.4, 9.4) and Table 9.5."""

import numpy as np
import pytest

from impedance_mil.design import DesignCriteria, delay_model_tolerance_deg, design_controller, passivity
from impedance_mil.design.passivity import is_passive_stable
from impedance_mil.errors import DesignWarning
from impedance_mil.systems import TransferFunction

from .conftest import MST, sd_model

# Table 9.5: SD2 with m_vs = 1.25 m_st, Ke = 5 V/in, Kp = 0.001 V/psi, tau = 500 us.
TABLE_9_5 = {
    1000.0: (True, False, True),
    250.0: (True, True, True),
    100.0: (True, True, True),
    50.0: (False, True, False),
}


def test_table_9_5(table):
    vs = sd_model(m_vs=1.25 * MST)
    d = design_controller(table, vs, fc_hz=1000.0, evaluate_fc_hz=[250.0, 100.0, 50.0], emit_warnings=False)
    for fc, expected in TABLE_9_5.items():
        r = d.constraint_at(fc)
        assert (r.I, r.II, r.III) == expected, f"fc = {fc} Hz: {r}"
    # Not a knife edge: each verdict holds with some room (default thresholds 0.292, 1, 0 deg).
    r = {fc: d.constraint_at(fc) for fc in TABLE_9_5}
    assert r[100.0].performance_error < 0.8 * 0.292 and r[50.0].performance_error > 1.4 * 0.292
    assert r[250.0].effort_ratio < 0.7 and r[1000.0].effort_ratio > 10
    assert r[50.0].passivity_tolerant_margin_deg < -3.0 and r[100.0].passivity_tolerant_margin_deg > 0.2
    # Fig 9.31l: the fc = 50 Hz Nyquist plot enters the LHP at low frequency (near the band of interest).
    assert r[50.0].passivity_worst_hz < 20.0


def test_warnings_are_never_silent(table, sd2):
    d = design_controller(table, sd2, fc_hz=1000.0, emit_warnings=False)
    text = " ".join(d.warnings)
    assert "Nyquist" in text and "constraint II" in text
    with pytest.warns(DesignWarning) as record:
        design_controller(table, sd2, fc_hz=1000.0)
    assert sorted(str(w.message) for w in record) == sorted(d.warnings)


def test_delay_model_tolerance_values():
    # omega tau - atan(omega tau) in deg for tau = 500 us: 0.56 deg at 100 Hz, 3.86 deg at 200 Hz.
    tol = delay_model_tolerance_deg([100.0, 200.0], 500e-6)
    x = 2 * np.pi * np.array([100.0, 200.0]) * 500e-6
    np.testing.assert_allclose(tol, np.degrees(x - np.arctan(x)), rtol=1e-12)
    assert tol[0] == pytest.approx(0.559, abs=1e-3) and tol[1] == pytest.approx(3.86, abs=1e-2)
    assert delay_model_tolerance_deg(100.0, 0.0) == 0.0


def test_bare_table_is_marginally_non_passive_within_tolerance(table):
    # The linear table alone (H_zw^st/s) leaves +-90 deg by about 0.23 deg near 99 Hz.
    H = table.H_zw.div_cancel(TransferFunction.s())
    r = passivity(H, (0.01, 1000.0), table.loop_time_s)
    assert -0.3 < r.margin_deg < -0.15 and 85 < r.worst_hz < 115
    assert r.passive and r.tolerant_margin_deg >= 0
    assert not passivity(H, (0.01, 1000.0), 0.0).passive  # without the model tolerance it fails


def test_passivity_of_known_systems():
    # SD2 force-velocity s/(m s^2 + c s + k) (Fig 9.30): passive, margin > 0 in any finite band.
    vs = sd_model()
    H = vs.H_zw.div_cancel(TransferFunction.s())
    assert passivity(H, (0.01, 1000.0)).passive
    # 1/(s+1)^2 has phase beyond -90 deg above 1 rad/s: margin -> -90 deg.
    r = passivity(TransferFunction([1.0], [1.0, 2.0, 1.0]), (0.01, 1000.0))
    assert not r.passive and r.margin_deg < -80
    # A lead k(s+a)/(s+b): phase atan(w/a) - atan(w/b), max at w = sqrt(ab); margin = 90 - that.
    a, b = 1.0, 100.0
    r = passivity(TransferFunction([1.0, a], [1.0, b]), (1e-3, 1e4))
    expected = 90 - np.degrees(np.arctan(np.sqrt(b / a)) - np.arctan(np.sqrt(a / b)))
    assert r.margin_deg == pytest.approx(expected, abs=1e-6)
    assert r.worst_hz == pytest.approx(np.sqrt(a * b) / (2 * np.pi), rel=1e-3)
    # Unstable -> not passive regardless of phase; simple imaginary-axis poles are allowed.
    assert not passivity(TransferFunction([1.0, 0.0], [1.0, -1.0, 4.0]), (0.01, 100.0)).passive
    assert is_passive_stable(TransferFunction([1.0, 0.0], [1.0, 0.0, 4.0]))
    assert not is_passive_stable(TransferFunction([1.0], [1.0, 0.0, 8.0, 0.0, 16.0]))


def test_extra_tolerance_and_band_are_user_settable(table, sd2):
    strict = DesignCriteria(band_hz=(0.25, 30.0))
    d = design_controller(table, sd2, fc_hz=80.0, criteria=strict, emit_warnings=False)
    assert not d.constraints[0].I  # 80 Hz no longer meets I up to 30 Hz
    loose = DesignCriteria(passivity_extra_tolerance_deg=5.0)
    d = design_controller(table, sd2, fc_hz=50.0, criteria=loose, emit_warnings=False)
    assert d.constraints[0].III
