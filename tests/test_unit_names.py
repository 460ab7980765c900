"""The units read without pint (``impedance_mil/unit_names.py``, issue 16 goal 1) read as pint reads them.

Reference: pint itself (the registry of ``config.unit_registry``).  Every symbol is
the pint unit it names, every scaled factor is pint's factor, every short name is
pint's short form, and a value read here is pint's float bit for bit (compared with
``==`` and by its sign, not to a tolerance: the fast path must change no result).
"""

from __future__ import annotations

import itertools
import math
import tomllib
from pathlib import Path

import pytest

import impedance_mil
from impedance_mil import config
from impedance_mil.config import quantity, unit_registry
from impedance_mil.display import UnitSystem, display_unit, short_name, si_display_by_pint
from impedance_mil.errors import ConfigError
from impedance_mil.lab.labfile import load_lab
from impedance_mil.plant.parameters import FIELDS
from impedance_mil.plant.table_files import is_lti_table_file, read_table_file
from impedance_mil.unit_names import (
    SCALED,
    SHORT_NAMES_BY_EXPRESSION,
    SI_DISPLAY_BY_EXPRESSION,
    SYMBOLS,
    parse_units,
    quick_quantity,
    quick_short_name,
)

DATA = Path(impedance_mil.__file__).parent / "data"


def pint_float(text: str, unit: str) -> float:
    """``text`` in ``unit`` by pint alone (the reference)."""
    parsed = unit_registry().Quantity(text)
    if not isinstance(parsed, unit_registry().Quantity):
        return float(parsed)
    if not dict(parsed.unit_items()):  # a number alone: the key's unit (config._parse_text)
        return float(parsed.magnitude)
    return float(parsed.to(unit).magnitude)


def same_float(a: float, b: float) -> bool:
    """Equal bit for bit, the sign of zero included."""
    return a == b and math.copysign(1.0, a) == math.copysign(1.0, b)


@pytest.mark.parametrize("symbol", list(SYMBOLS))
def test_each_symbol_is_the_pint_unit_it_names(symbol):
    ureg = unit_registry()
    assert ureg.parse_units(symbol) == ureg.parse_units(SYMBOLS[symbol])
    assert ureg.Quantity(1.0, symbol).to(SYMBOLS[symbol]).magnitude == 1.0


@pytest.mark.parametrize(("pair", "factor"), list(SCALED.items()))
def test_each_scaled_factor_is_pints(pair, factor):
    # pint multiplies the number by its factor: 1.0 gives the factor itself, so any number gives
    # the same product here and in pint.
    assert unit_registry().Quantity(1.0, pair[0]).to(pair[1]).magnitude == factor
    for number in (500, 0.1, 3.7e-3, 123456.789):
        assert same_float(
            quick_quantity(f"{number} {pair[0]}", pair[1]), pint_float(f"{number} {pair[0]}", pair[1])
        )


@pytest.mark.parametrize("expression", list(SHORT_NAMES_BY_EXPRESSION))
def test_each_short_name_is_pints_in_any_order(expression):
    ureg = unit_registry()
    expected = f"{ureg.parse_units(expression):~C}"
    assert SHORT_NAMES_BY_EXPRESSION[expression] == expected
    units = parse_units(expression)
    assert units is not None
    # pint sorts the factors: any order of writing them has the same short name
    numerator = [f"{n}**{p}" for n, p in units if p > 0]
    denominator = [f"{n}**{-p}" for n, p in units if p < 0]
    for order in itertools.permutations(numerator):
        if not order:
            continue
        written = "*".join(order) + "".join("/" + d for d in reversed(denominator))
        assert f"{ureg.parse_units(written):~C}" == expected
        assert quick_short_name(written) == expected


@pytest.mark.parametrize("expression", list(SI_DISPLAY_BY_EXPRESSION))
def test_each_si_display_unit_is_pints(expression):
    # Name and factor as pint finds them for this spelling (the factor bit for bit: a value
    # shown is the same float with or without pint).
    name, factor = SI_DISPLAY_BY_EXPRESSION[expression]
    by_pint = si_display_by_pint(expression)
    assert (name, factor) == (by_pint.name, by_pint.factor)
    assert math.copysign(1.0, factor) == 1.0 and display_unit(expression, UnitSystem.SI) == by_pint


def test_an_si_display_unit_not_listed_is_pints():
    # The SI name follows the order the factors are written in: another spelling is pint's.
    assert "in**3/mA/s" not in SI_DISPLAY_BY_EXPRESSION
    assert display_unit("in**3/mA/s", UnitSystem.SI).name == "mm**3/mA/s"
    assert display_unit("inch**3 / second / milliampere", UnitSystem.SI).name == "mm**3/s/mA"
    assert display_unit("kilonewton / meter", UnitSystem.SI) == si_display_by_pint("kilonewton / meter")


def test_short_name_of_a_unit_not_listed_is_pints():
    assert quick_short_name("kilonewton / meter") is None
    assert short_name("kilonewton / meter") == "kN/m"


@pytest.mark.parametrize(
    "text",
    [
        "in*in",
        "in**0",
        "in**-1",
        "(in)",
        "2 in",
        "in/",
        "*in",
        "in s",
        "in**2.5",
        "",
        "percent",
        "rad/",
        "in**",
    ],
)
def test_what_is_not_read_here_goes_to_pint(text):
    assert parse_units(text) is None


def shipped_unit_values() -> list[str]:
    """Every string of the shipped TOML files that starts with a number and goes on with more."""
    found: list[str] = []

    def walk(node):
        if isinstance(node, dict):
            for child in node.values():
                walk(child)
        elif isinstance(node, list):
            for child in node:
                walk(child)
        elif isinstance(node, str) and node[:1].isdigit() and " " in node.strip():
            found.append(node.strip())

    for path in sorted(DATA.rglob("*.toml")):
        walk(tomllib.loads(path.read_text()))
    return sorted(set(found))


def test_the_shipped_files_have_values_with_units():
    values = shipped_unit_values()
    assert len(values) > 30  # the scan is not blind
    assert "3000 psi" in values and "500 us" in values


@pytest.mark.parametrize("text", shipped_unit_values())
def test_every_shipped_value_in_its_own_unit_is_pints_float(text):
    # The unit written is the target: the fast path's one case besides SCALED.
    number, _, unit = text.partition(" ")
    quick = quick_quantity(text, unit)
    if parse_units(unit) is None:
        assert quick is None  # left to pint (kPa, kN*s/m, tonne, expressions)
    else:
        assert quick is not None
        assert same_float(quick, pint_float(text, unit))


@pytest.mark.parametrize(
    ("text", "unit"),
    [
        ("5", "inch"),
        ("-0", "inch"),
        ("-0.0 in", "inch"),
        ("-0 in", "inch"),
        ("- 3 in", "inch"),
        ("1e5 psi/s/mA", "psi / second / milliampere"),
        ("1E-3 V/psi", "volt / psi"),
        (".5 in", "inch"),
        ("5. in", "inch"),
        ("2.5e+2 lbf*s**2/in", "force_pound * second**2 / inch"),
        ("1 in/s^2", "inch / second ** 2"),
        ("12345678901234567 in", "inch"),
        ("0.1 ms", "second"),
        ("2 Hz", "hertz"),
        ("3 mA / V", "milliampere / volt"),
        ("0 in", "inch"),
        ("1e05 in", "inch"),  # leading zeros of an exponent are one number for pint too
        ("1.e5 in", "inch"),
        ("3 in ** 2", "inch**2"),
    ],
)
def test_numbers_read_as_pint_reads_them(text, unit):
    quick = quick_quantity(text, unit)
    assert quick is not None
    assert same_float(quick, pint_float(text, unit))


@pytest.mark.parametrize(
    ("text", "unit"),
    [
        ("169.6 rad/s", "hertz"),  # an angular frequency: cycles times 2 pi, by pint
        ("1/s", "hertz"),
        ("20 percent", "dimensionless"),
        ("3 in", "force_pound"),  # wrong dimension: pint refuses it naming the key
        ("3 s", "millisecond"),  # scaled the other way
        ("76.2 mm", "inch"),
        ("1_000 in", "inch"),
        ("3in", "inch"),
        ("nan", "inch"),
        ("+3 in", "inch"),
        ("0x10 in", "inch"),
        ("3 dB", "decibel"),  # logarithmic: pint refuses it, so must this
        ("007 in", "inch"),  # pint's tokenizer reads 0 and 7 (and gives 0): left to it
        ("3 in**02", "inch**2"),  # pint reads in**0 times 2 (a dimensionless 3): left to it
        ("0.5 in**0", "inch"),
        ("01.5 in", "inch"),
    ],
)
def test_other_values_are_left_to_pint(text, unit):
    assert quick_quantity(text, unit) is None


def test_the_key_errors_are_pints():
    # Values the fast path leaves to pint keep their checks (issue 18).
    assert quantity("f", "169.6 rad/s", "hertz") == pytest.approx(169.6 / (2 * math.pi), rel=1e-15)
    with pytest.raises(ConfigError, match="Ke: expected a quantity with the dimension of volt / inch"):
        quantity("Ke", "500 percent", "volt / inch")
    with pytest.raises(ConfigError, match="stroke: expected a quantity with the dimension of inch"):
        quantity("stroke", "3 lbf", "inch")


def loaded_with(monkeypatch, quick: bool) -> str:
    """The report's lab and each shipped table file as loaded, with or without the fast path (their repr)."""
    if not quick:
        monkeypatch.setattr(config, "quick_quantity", lambda text, unit: None)
    shown = [repr(load_lab(None))]
    for path in sorted((DATA / "tables").glob("*.toml")):
        table = read_table_file(path, {}) if is_lti_table_file(path) else load_lab(table=path)
        shown.append(repr(table))
    monkeypatch.undo()
    return "\n".join(shown)


def test_the_shipped_labs_load_the_same_with_and_without_pint(monkeypatch):
    # repr shows every float exactly (shortest round trip): equal text is equal bits.
    with_quick = loaded_with(monkeypatch, quick=True)
    assert with_quick == loaded_with(monkeypatch, quick=False)
    assert "3000.0" in with_quick  # the report's supply pressure [psi] is in what is compared


@pytest.mark.parametrize("key", sorted(FIELDS))
def test_every_table_key_in_its_own_unit_is_pints_float(key):
    unit = FIELDS[key].unit
    if parse_units(unit) is None:
        pytest.skip(f"{unit} is left to pint")
    for number in ("0.37", "42", "1.5e3"):
        text = f"{number} {unit}"
        assert same_float(quick_quantity(text, unit), pint_float(text, unit))


NUMBERS = ("0", "-0", "3", "-2.5", ".5", "5.", "1e-3", "2.5E+4", "123456789012", "0.1", "007", "1_0")


def spelled_values() -> list[tuple[str, str]]:
    """A number and each symbol, alone and in products and quotients, with the target spelled otherwise."""
    full = {symbol: name for symbol, name in SYMBOLS.items() if name != "decibel"}
    cases = []
    for number in NUMBERS:
        for symbol, name in full.items():
            cases.append((f"{number} {symbol}", name))
        for (s1, n1), (s2, n2) in itertools.combinations(list(full.items())[::3], 2):
            if n1 != n2:
                cases.append((f"{number} {s1}*{s2}**2", f"{n2}**2 * {n1}"))
                cases.append((f"{number} {s1} / {s2}", f"{n1} / {n2}"))
    return cases


def test_every_value_read_here_is_pints_float():
    # Wherever the fast path gives a number, pint gives the same float (and no error).
    read = 0
    for text, unit in spelled_values():
        quick = quick_quantity(text, unit)
        if quick is None:
            continue
        read += 1
        assert same_float(quick, pint_float(text, unit)), (text, unit)
    assert read > 500  # not blind: most of these are read here
