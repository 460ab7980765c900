"""TableParameters: the report's Table 4.1, units at the edge, physical formulas (Eq 4-10, 4-12)."""

import math

import pytest

from impedance_mil.errors import ConfigError, DataFileError
from impedance_mil.plant import (
    TableParameters,
    default_table_path,
    model_constant_d,
    oil_column_damping,
    oil_column_frequency,
)
from impedance_mil.plant.parameters import bulk_modulus_from_frequency


def test_report_default_is_table_4_1_with_corrected_d():
    # Source: report Table 4.1 (values exact as printed) and Section 4.3.5 text for d = 1e5.
    p = TableParameters.report_default()
    assert (p.Ke, p.Kp, p.Kv) == (5.0, 0.001, 3.0)
    assert p.loop_time == pytest.approx(500e-6, rel=1e-12)
    assert (p.piston_area, p.mid_stroke, p.mass) == (2.1, 3.2, 4.14)
    assert p.d == 1e5
    assert p.valve_poles_hz == (70.0, 110.0)
    assert (p.zeta_oil, p.f_oil_hz) == (0.09, 27.0)
    # Section 3.4: 57.75 in^3/s at 1000 psi; K_r = 57/25 ~ 2.3 in^3/s/mA (Section 4.3.2).
    assert p.valve_flow_gain == pytest.approx(2.3, abs=0.02)


def test_oil_column_frequency_eq_4_10a_reproduces_report_178_rad_s():
    # Source: Section 4.3.5, kappa = 1e5 psi -> 178 rad/s = 28.3 Hz (printed to 3 digits).
    w = oil_column_frequency(1e5, 2.1, 4.14, 3.2)
    assert w == pytest.approx(178.0, abs=0.5)
    assert w / (2 * math.pi) == pytest.approx(28.3, abs=0.05)


def test_bulk_modulus_and_leakage_round_trip():
    # Invariant: Eq 4-10a/b inverted by the derived properties.
    p = TableParameters.report_default()
    w = oil_column_frequency(p.bulk_modulus, p.piston_area, p.mass, p.mid_stroke)
    assert w == pytest.approx(p.omega_oil, rel=1e-12)
    z = oil_column_damping(p.leakage_coefficient, p.bulk_modulus, p.piston_area, p.mass, p.mid_stroke)
    assert z == pytest.approx(p.zeta_oil, rel=1e-12)


def test_physical_alternatives_in_mapping():
    p = TableParameters.report_default()
    q = TableParameters.from_toml(default_table_path(), {"bulk_modulus": "1e5 psi"})
    assert q.f_oil_hz == pytest.approx(28.34, abs=0.01)  # Eq 4-10a, as above
    kl = p.leakage_coefficient
    r = TableParameters.from_toml(default_table_path(), {"leakage_coefficient": kl})
    assert r.zeta_oil == pytest.approx(0.09, rel=1e-9)
    with pytest.raises(ConfigError, match="bulk_modulus"):
        TableParameters.from_mapping({**p.to_dict(), "bulk_modulus": 1e5})


def test_model_constant_d_eq_4_12_scales_as_derived():
    # d is linear in C_d G, K_r and 1/K_s, and goes with sqrt(P_S): Eq 4-12 (corrected form).
    base = model_constant_d(1e5, 2.1, 3.2, 0.01, 3000.0, 8e-5, 2.31, 50.0)
    assert model_constant_d(1e5, 2.1, 3.2, 0.02, 3000.0, 8e-5, 2.31, 50.0) == pytest.approx(2 * base)
    assert model_constant_d(1e5, 2.1, 3.2, 0.01, 12000.0, 8e-5, 2.31, 50.0) == pytest.approx(2 * base)
    assert model_constant_d(1e5, 2.1, 3.2, 0.01, 3000.0, 8e-5, 4.62, 50.0) == pytest.approx(2 * base)
    expected = 2e5 / (2.1 * 3.2) * 0.01 * math.sqrt(3000.0 / 8e-5) * 2.31 / 50.0
    assert base == pytest.approx(expected, rel=1e-12)


def test_units_at_the_edge():
    p = TableParameters.from_toml(
        default_table_path(),
        {"mass": "1600 lb", "loop_time": "1 ms", "Ke": "0.2 V/mm", "valve_poles_hz": "60,100"},
    )
    assert p.mass == pytest.approx(1600 / 386.0886, rel=1e-5)  # pound-mass to lbf*s^2/in
    assert p.loop_time == pytest.approx(1e-3)
    assert p.Ke == pytest.approx(0.2 * 25.4)
    assert p.valve_poles_hz == (60.0, 100.0)


@pytest.mark.parametrize(
    "key, value, match",
    [
        ("mass", -1.0, "mass"),
        ("piston_area", 0.0, "piston_area"),
        ("Ke", 0.0, "Ke"),
        ("Kv", "-3 mA/V", "Kv"),
        ("Kp", float("nan"), "Kp"),
        ("mass", "3 in", "mass"),
        ("loop_time", "1 V", "loop_time"),
        ("nonsense", 1.0, "nonsense"),
        ("valve_poles_hz", [70.0], "valve_poles_hz"),
    ],
)
def test_bad_values_name_the_key(key, value, match):
    with pytest.raises(ConfigError, match=match):
        TableParameters.from_toml(default_table_path(), {key: value})


def test_missing_key_and_bad_file(tmp_path):
    data = default_table_path().read_text().replace('Ke = "5 V/in"', "")
    f = tmp_path / "t.toml"
    f.write_text(data)
    with pytest.raises(ConfigError, match="Ke"):
        TableParameters.from_toml(f)
    with pytest.raises(DataFileError, match="nope.toml"):
        TableParameters.from_toml(tmp_path / "nope.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("Ke = = 5")
    with pytest.raises(DataFileError, match="bad.toml"):
        TableParameters.from_toml(bad)


def test_direct_construction_validates_and_replace():
    p = TableParameters.report_default()
    assert p.replace(Ke=0.0).Ke == 0.0  # allowed for root loci
    with pytest.raises(ConfigError, match="mass"):
        p.replace(mass=0.0)
    with pytest.raises(ConfigError, match="d"):
        p.replace(d=float("inf"))
    assert TableParameters.from_mapping(p.to_dict()) == p
    assert bulk_modulus_from_frequency(p.omega_oil, 2.1, 4.14, 3.2) == pytest.approx(p.bulk_modulus)
