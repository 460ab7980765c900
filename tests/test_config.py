"""Tests of configuration parsing with units (impedance_mil.config)."""

import math

import pytest

from impedance_mil.config import Field, parse_fields, parse_overrides, quantity, read_toml
from impedance_mil.errors import ConfigError, DataFileError
from impedance_mil.units import G0

FIELDS = {
    "mass": Field("force_pound * second**2 / inch"),
    "piston_area": Field("inch**2"),
    "Kp": Field("volt / psi", check="nonnegative"),
    "valve_poles_hz": Field("hertz", count=2, default=(70.0, 110.0)),
}


def test_bare_numbers_mean_report_units():
    out = parse_fields(FIELDS, {"mass": 4.14, "piston_area": 2.1, "Kp": 0.001})
    assert out == {"mass": 4.14, "piston_area": 2.1, "Kp": 0.001, "valve_poles_hz": (70.0, 110.0)}


def test_units_convert_to_internal():
    # 1600 lb (mass) = 1600 / 386.089 lbf s^2/in = 4.144 (report: 4.14)
    assert quantity("mass", "1600 lb", "force_pound * second**2 / inch") == pytest.approx(1600 / G0, rel=1e-9)
    assert quantity("a", "1 g0", "inch / second**2") == pytest.approx(G0, rel=1e-12)
    assert quantity("area", "13.548 cm**2", "inch**2") == pytest.approx(2.1, rel=1e-4)
    assert quantity("Kp", "0.001 V/psi", "volt / psi") == pytest.approx(0.001)


@pytest.mark.parametrize(
    "mapping, key",
    [
        ({"mass": -1, "piston_area": 2.1, "Kp": 0}, "mass"),
        ({"mass": "1 in", "piston_area": 2.1, "Kp": 0}, "mass"),
        ({"mass": math.nan, "piston_area": 2.1, "Kp": 0}, "mass"),
        ({"mass": 4, "piston_area": 2.1}, "Kp"),
        ({"mass": 4, "piston_area": 2.1, "Kp": 0, "colour": 1}, "colour"),
        ({"mass": 4, "piston_area": 2.1, "Kp": 0, "valve_poles_hz": [70]}, "valve_poles_hz"),
        ({"mass": "four", "piston_area": 2.1, "Kp": 0}, "mass"),
    ],
)
def test_bad_values_name_the_key(mapping, key):
    with pytest.raises(ConfigError) as info:
        parse_fields(FIELDS, mapping)
    assert str(info.value).startswith(key)


def test_overrides_and_lists():
    o = parse_overrides(["Ke=5", "valve_poles_hz=60,100", "mass=1600 lb"])
    assert o["Ke"] == 5.0 and o["mass"] == "1600 lb"

    out = parse_fields(FIELDS, {"mass": 4, "piston_area": 2, "Kp": 0, "valve_poles_hz": o["valve_poles_hz"]})
    assert out["valve_poles_hz"] == (60.0, 100.0)
    with pytest.raises(ConfigError):
        parse_overrides(["novalue"])


def test_read_toml_errors(tmp_path):
    with pytest.raises(DataFileError, match="not found"):
        read_toml(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("mass = = 3")
    with pytest.raises(DataFileError, match="not valid TOML"):
        read_toml(bad)
