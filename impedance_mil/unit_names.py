"""The units a configuration spells most often, read without pint (issue 16, goal 1).

Importing pint and building its registry takes about 0.5 s, three times the
start-up of ``python -c "import numpy, scipy"``, and a command that only reads
a configuration (``imil table info``, ``imil vs list``, ``imil lab show``)
needs pint for little: every unit in the shipped files is one of a dozen
units, written in the key's own internal unit (``"3000 psi"`` for a pressure
in psi, ``"4.14 lbf*s**2/in"`` for a mass).  This module reads exactly those
cases and says "not mine" (``None``) for everything else, which
:mod:`impedance_mil.config` and :mod:`impedance_mil.display` then hand to
pint as before:

* :func:`parse_units` reads a product and quotient of the units of
  :data:`SYMBOLS` with whole powers (``"in**3/s"``, ``"psi / second / milliampere"``,
  ``"in/s^2"``); brackets, numbers and any other unit give ``None``.
* :func:`quick_quantity` converts ``"NUMBER UNIT"`` only when the unit is the
  target unit itself (the conversion factor is then exactly 1, as pint's is) or
  one of :data:`SCALED` (``"500 us"`` to seconds, by pint's own factor).  A
  value in any other unit, with an angle, in percent, or of the wrong dimension,
  goes to pint, which converts by dimension or refuses it naming the key.
* :func:`quick_short_name` is pint's short form (``"force_pound / inch"`` ->
  ``"lbf/in"``) of the units of :data:`SHORT_NAMES_BY_EXPRESSION` (``dB`` is
  named here, but a value in dB is left to pint, which refuses it).

Every symbol, scaled factor and short name is checked against pint, and the
numbers are the same bit for bit (``tests/test_unit_names.py``), so reading a
value here or with pint gives the same float.
"""

from __future__ import annotations

import re
from types import MappingProxyType

#: The symbols read here, each with the pint unit it is (pint's own name or an alias of it).
SYMBOLS: MappingProxyType[str, str] = MappingProxyType(
    {
        "in": "inch",
        "inch": "inch",
        "s": "second",
        "second": "second",
        "ms": "millisecond",
        "millisecond": "millisecond",
        "us": "microsecond",
        "microsecond": "microsecond",
        "lbf": "force_pound",
        "force_pound": "force_pound",
        "psi": "psi",
        "V": "volt",
        "volt": "volt",
        "mA": "milliampere",
        "milliampere": "milliampere",
        "Hz": "hertz",
        "hertz": "hertz",
        "g0": "g0",
        "deg": "degree",
        "degree": "degree",
        "rad": "radian",
        "radian": "radian",
        "dB": "decibel",
        "decibel": "decibel",
    }
)

#: Units named here but whose values are left to pint: a logarithmic unit is no factor
#: (pint refuses ``"3 dB"`` as ambiguous; the toolkit only prints dB).
_NAMES_ONLY = frozenset({"decibel"})

#: A unit read here: the names of :data:`SYMBOLS`' values and their whole powers, in any order.
Units = frozenset[tuple[str, int]]

#: Factors of the prefixed units converted here, ``(from, to): factor``, each pint's own
#: factor for that conversion (pint multiplies the number by it, as :func:`quick_quantity` does).
SCALED: MappingProxyType[tuple[str, str], float] = MappingProxyType(
    {("microsecond", "second"): 1e-6, ("millisecond", "second"): 1e-3}
)

#: pint's short form (``f"{units:~C}"``) of the units shown, by their pint expression.
SHORT_NAMES_BY_EXPRESSION: MappingProxyType[str, str] = MappingProxyType(
    {
        "inch": "in",
        "inch**2": "in**2",
        "inch**3 / second": "in**3/s",
        "inch**3 / second / milliampere": "in**3/mA/s",
        "inch**3 / second / psi": "in**3/psi/s",
        "inch / second": "in/s",
        "inch / second**2": "in/s**2",
        "second": "s",
        "millisecond": "ms",
        "hertz": "Hz",
        "force_pound": "lbf",
        "force_pound / inch": "lbf/in",
        "force_pound * second / inch": "lbf*s/in",
        "force_pound * second**2 / inch": "lbf*s**2/in",
        "force_pound * inch": "lbf*in",
        "psi": "psi",
        "psi / second / milliampere": "psi/mA/s",
        "volt": "V",
        "volt / second": "V/s",
        "volt / inch": "V/in",
        "volt / psi": "V/psi",
        "milliampere": "mA",
        "milliampere / volt": "mA/V",
        "g0": "g0",
        "degree": "deg",
        "decibel": "dB",
        "radian / second": "rad/s",
        "dimensionless": "",
    }
)

#: How :func:`impedance_mil.display.display_unit` shows in SI each unit the configuration
#: commands print (``imil lab show|table info --units si``): ``(name, factor)``, by the unit
#: as the package spells it (the SI name follows the order its factors are written in, so the
#: key is the spelling itself, not the unit).  Each entry is pint's, bit for bit
#: (tests/test_unit_names.py); a unit spelled otherwise is shown by pint, as before.
SI_DISPLAY_BY_EXPRESSION: MappingProxyType[str, tuple[str, float]] = MappingProxyType(
    {
        "1 / second": ("1/s", 1.0),
        "Hz": ("Hz", 1.0),
        "V": ("V", 1.0),
        "V/s": ("V/s", 1.0),
        "force_pound": ("kN", 0.0044482216152605),
        "force_pound * second / inch": ("kN*s/m", 0.17512683524647643),
        "force_pound * second**2 / inch": ("kg", 175.12683524647645),
        "force_pound / inch": ("kN/m", 0.17512683524647643),
        "hertz": ("Hz", 1.0),
        "in": ("mm", 25.4),
        "in/s": ("mm/s", 25.4),
        "in/s**2": ("m/s**2", 0.0254),
        "inch": ("mm", 25.4),
        "inch / second ** 2": ("m/s**2", 0.0254),
        "inch**2": ("cm**2", 6.4516),
        "inch**3 / second": ("L/s", 0.016387063999999993),
        "inch**3 / second / milliampere": ("mm**3/s/mA", 16387.063999999995),
        "inch**3 / second / psi": ("mm**3/s/MPa", 2376742.690600152),
        "lbf": ("kN", 0.0044482216152605),
        "lbf*s**2/in": ("kg", 175.12683524647645),
        "lbf*s/in": ("kN*s/m", 0.17512683524647643),
        "lbf/in": ("kN/m", 0.17512683524647643),
        "lbf/psi": ("kN/MPa", 0.64516),
        "mA": ("mA", 1.0),
        "mA/s": ("mA/s", 1.0),
        "milliampere": ("mA", 1.0),
        "milliampere / volt": ("mA/V", 1.0),
        "psi": ("MPa", 0.0068947572931683625),
        "psi / second / milliampere": ("MPa/s/mA", 0.0068947572931683625),
        "rad/s": ("rad/s", 1.0),
        "radian / second": ("rad/s", 1.0),
        "s": ("s", 1.0),
        "second": ("s", 1.0),
        "volt": ("V", 1.0),
        "volt / inch": ("V/mm", 0.03937007874015749),
        "volt / psi": ("V/MPa", 145.0377377302092),
    }
)

# Python's tokenizer, which pint's parser uses, splits a whole number with a leading zero
# ("007" reads as 0 and 7, "in**02" as in**0 and 2): such texts are left to pint.
_TERM = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*(?:(?:\*\*|\^)\s*([1-9][0-9]*))?\s*")
_NUMBER = re.compile(r"\s*(-?)\s*((?:(?:0|[1-9][0-9]*)(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][-+]?[0-9]+)?)(?:\s+|$)")
#: The one dimensionless spelling read here (a unit of its own, such as percent, goes to pint).
_DIMENSIONLESS = "dimensionless"


def parse_units(text: str) -> Units | None:
    """The units of ``text`` (``"lbf*s**2/in"``) as names and powers, or ``None`` when not read here.

    ``None`` for anything but ``SYMBOL[**N] (* or /) SYMBOL[**N] ...`` with symbols of
    :data:`SYMBOLS` and whole powers ``N`` (``^`` reads as ``**``), for a unit
    written twice, and for an empty text; ``"dimensionless"`` is no unit at all.
    """
    if text.strip() == _DIMENSIONLESS:
        return frozenset()
    powers: dict[str, int] = {}
    pos, sign = 0, 1
    while True:
        match = _TERM.match(text, pos)
        if match is None or match.group(1) not in SYMBOLS:
            return None
        name = SYMBOLS[match.group(1)]
        if name in powers:
            return None  # "in*in": pint merges the powers; rare enough to leave to it
        power = int(match.group(2) or 1)
        if power == 0:
            return None
        powers[name] = sign * power
        pos = match.end()
        if pos == len(text):
            return frozenset(powers.items())
        operator = text[pos]
        if operator not in "*/":
            return None
        sign = 1 if operator == "*" else -1
        pos += 1


def quick_quantity(text: str, unit: str) -> float | None:
    """``text`` (``"3000 psi"``, ``"500 us"``, ``"5"``) in ``unit`` [a pint expression], or ``None`` for pint.

    A number alone is that number.  A number and a unit give the number when the
    unit is ``unit`` itself, or the number times its :data:`SCALED` factor; any
    other text gives ``None``.  The number is read as pint reads it (a whole
    number as an integer first, then a float; a minus sign applied after), so
    the float is pint's bit for bit.
    """
    match = _NUMBER.match(text)
    if match is None:
        return None
    digits = match.group(2)
    value: int | float
    try:
        value = int(digits)
    except ValueError:
        value = float(digits)
    number = float(-value if match.group(1) else value)  # "-0" is pint's 0, not -0.0
    rest = text[match.end() :]
    if not rest.strip():
        return number
    given, target = parse_units(rest), parse_units(unit)
    if given is None or target is None or any(name in _NAMES_ONLY for name, _ in given | target):
        return None
    if given == target:
        return number
    if len(given) == 1 and len(target) == 1:
        ((source, power),) = given
        ((goal, goal_power),) = target
        factor = SCALED.get((source, goal))
        if factor is not None and power == goal_power == 1:
            return number * factor
    return None


#: :data:`SHORT_NAMES_BY_EXPRESSION` by the units each expression reads as.
_SHORT_NAMES: dict[Units | None, str] = {
    parse_units(expression): short for expression, short in SHORT_NAMES_BY_EXPRESSION.items()
}


def quick_short_name(unit: str) -> str | None:
    """pint's short form of ``unit`` (``"inch / second**2"`` -> ``"in/s**2"``), or ``None`` when not listed."""
    units = parse_units(unit)
    return None if units is None else _SHORT_NAMES.get(units)
