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


# ---------------------------------------------------------------- bounded parsing (issue 18, finding 5)
def test_toml_nested_3000_deep_is_refused_before_parsing(tmp_path):
    # The audit's case: Python's TOML parser recursed 3000 times and raised RecursionError.
    deep = tmp_path / "deep.toml"
    deep.write_text("[table]\nKe = " + "[" * 3000 + "]" * 3000 + "\n")
    with pytest.raises(DataFileError, match=r"deep\.toml: line 2: arrays or tables nested more than 32 deep"):
        read_toml(deep)
    inline = tmp_path / "inline.toml"
    inline.write_text("a = " + "{b = " * 40 + "1" + "}" * 40 + "\n")
    with pytest.raises(DataFileError, match="nested more than 32 deep"):
        read_toml(inline)


def test_toml_depth_through_dotted_keys_is_capped_after_parsing(tmp_path):
    dotted = tmp_path / "dotted.toml"
    dotted.write_text("[" + ".".join(["a"] * 40) + "]\nx = 1\n")
    with pytest.raises(DataFileError, match="tables nested more than 32 deep"):
        read_toml(dotted)
    ok = tmp_path / "ok.toml"
    ok.write_text("[" + ".".join(["a"] * 20) + "]\nx = [[1, 2], [3]]\n")
    assert read_toml(ok)["a"]["a"]["a"]  # 20 levels is fine


def test_brackets_and_digits_inside_strings_and_comments_do_not_count(tmp_path):
    text = (
        'a = "' + "[" * 100 + '"\n'
        "b = '" + "{" * 100 + "'\n"
        'c = """\n' + "[" * 100 + "\n" + "1" * 300 + '\n"""\n'
        "# " + "[" * 100 + " " + "9" * 300 + "\n"
        'd = "' + "7" * 150 + ' is text"\n'
        'e = "escaped \\" ' + "[" * 100 + '"\n'  # an escaped quote does not end the string
        'f = """x""""\n'  # one quote before the closing ones is content
        "g = [" + "'[', " * 50 + "]\n"
    )
    path = tmp_path / "strings.toml"
    path.write_text(text)
    data = read_toml(path)
    assert data["a"] == "[" * 100 and data["d"].startswith("7" * 150)
    assert data["e"] == 'escaped " ' + "[" * 100 and data["f"] == 'x"' and data["g"] == ["["] * 50


def test_overlong_numbers_are_refused_with_one_line(tmp_path):
    # 400 digits: an int too large for a double (OverflowError in the audit); 200 000 digits:
    # Python's int conversion limit (ValueError) after seconds of parsing.
    for digits in (400, 200_000):
        path = tmp_path / f"n{digits}.toml"
        path.write_text("[table]\nKe = " + "1" * digits + "\n")
        with pytest.raises(DataFileError, match=r"line 2: a number of more than 100 digits"):
            read_toml(path)
    # A Python int beyond a double (from code, not TOML) is refused too.
    with pytest.raises(ConfigError, match="^Ke: expected a finite number"):
        quantity("Ke", 10**400, "volt / inch")


def test_oversized_toml_files_are_refused_before_reading(tmp_path):
    # The audit's 2-million-digit number: the file is refused by size at once.
    path = tmp_path / "big.toml"
    path.write_text("[table]\nKe = " + "1" * 2_000_000 + "\n")
    with pytest.raises(DataFileError, match=r"big\.toml: 2000014 bytes, larger than a TOML file may be"):
        read_toml(path)


def test_overlong_quantity_strings_are_refused():
    with pytest.raises(ConfigError, match=r"^Ke: expected a value of at most 200 characters, got '1111"):
        quantity("Ke", "1" * 1000 + " V/in", "volt / inch")
    with pytest.raises(ConfigError, match=r"^Ke: expected a number of at most 100 digits"):
        quantity("Ke", "1" * 150 + " V/in", "volt / inch")
    # The echoed value is cut, so the error stays one short line.
    with pytest.raises(ConfigError) as info:
        quantity("Ke", "2" * 5000, "volt / inch")
    assert len(str(info.value)) < 200


def test_integer_fields_refuse_fractions():
    assert parse_fields({"n": Field("dimensionless", integer=True)}, {"n": 3}) == {"n": 3.0}
    with pytest.raises(ConfigError, match="^n: expected a whole number, got 2.5"):
        parse_fields({"n": Field("dimensionless", integer=True)}, {"n": 2.5})
