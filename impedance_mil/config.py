"""Configuration files and values with units: the edge where pint lives.

A configuration value is either a bare number, meaning the report's unit of
that key (see :mod:`impedance_mil.units`), or a string with a unit that pint
understands, e.g. ``"1600 lb"`` (a mass), ``"2.1 in**2"``, ``"0.001 V/psi"``,
``"0.8 g0"`` (``g0`` is standard gravity; pint's ``g`` is the gram).

Domain packages describe their keys with a plain mapping
``{key: Field(unit=..., check=...)}`` and call :func:`parse_fields`; they
never import pint themselves.  A mass may be given as a weight-like mass
(``"1600 lb"``); pint converts pound-mass to lbf*s**2/in exactly.

A value is converted by its dimension; nothing is taken as a bare number
because pint calls it "unitless":

* a string without a unit (``"5"``) is a bare number, in the report's unit;
* a dimensionless ratio may be given in percent (``"20 percent"`` or
  ``"20 %"`` is 0.2), per mille or ppm; a key with a dimension given in
  percent, or in any other wrong dimension, is refused naming the key;
* pint takes the radian as dimensionless, which would read ``"169.6 rad/s"``
  as 169.6 Hz.  Angles are therefore counted: a frequency key [Hz] given as
  an angular frequency (``rad/s``, ``deg/s``, ``rpm``, ``turn/s``) is divided
  by one cycle (2 pi rad), so ``"169.6 rad/s"`` is 26.99 Hz; an angle
  anywhere else (``zeta = "5 deg"``) is refused.  ``"1/s"`` for a frequency
  key is read as Hz (cycles per second);
* an integer key (``Field(integer=True)``) refuses a value that is not a
  whole number (2.5 is not 2).

Bounded work (``docs/limits.md``): a value with a unit has at most
:data:`MAX_QUANTITY_CHARS` characters and no run of more than
:data:`MAX_NUMBER_DIGITS` digits, and :func:`read_toml` refuses a file larger
than :data:`MAX_TOML_BYTES` or nested deeper than :data:`MAX_TOML_DEPTH`
before parsing it.
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .errors import ConfigError, DataFileError
from .fileio import MAX_NUMBER_DIGITS, read_text
from .lazy import LazyModule
from .unit_names import quick_quantity
from .units import PINT_DEFINITIONS

if TYPE_CHECKING:
    import pint
else:
    # Imported, and its registry built, on the first value that needs it (about 0.5 s):
    # the units of the shipped files are read by unit_names without it (issue 16, goal 1).
    pint = LazyModule("pint")


@cache
def unit_registry() -> pint.UnitRegistry:
    """The package's pint registry (with ``g0``): the one that reads and shows units.

    Built on the first call (pint's import and registry take about 0.5 s); the same
    registry afterwards.
    """
    registry: pint.UnitRegistry = pint.UnitRegistry()
    for definition in PINT_DEFINITIONS:
        registry.define(definition)
    return registry


#: Allowed checks for a field value.
CHECKS = ("positive", "nonnegative", "any", "fraction")

#: Longest value with a unit [characters]; pint's parser takes minutes over very long strings.
MAX_QUANTITY_CHARS = 200

#: Largest TOML file read [bytes]; the largest shipped configuration is a few kB.
MAX_TOML_BYTES = 1 << 20

#: Deepest nesting of tables and arrays in a TOML file; configurations use 4 or 5 levels.
MAX_TOML_DEPTH = 32

_LONG_DIGITS = f"(?<![0-9_])[0-9][0-9_]{{{MAX_NUMBER_DIGITS},}}"  # tried only where a run starts
_LONG_DIGITS_RE = re.compile(_LONG_DIGITS)

#: What the checks before parsing look at in a TOML text: the start of a string or a
#: comment (skipped whole), a bracket (nesting) and a long run of digits (number size).
_TOML_SCAN_RE = re.compile(r"[\"'#\[\]{}]|" + _LONG_DIGITS)

#: Longest raw value echoed in an error message [characters].
_SHOWN_CHARS = 60


@dataclass(frozen=True)
class Field:
    """Description of one configuration key.

    Parameters
    ----------
    unit : str
        Internal unit as a pint expression (the report's unit of the key);
        ``"dimensionless"`` for pure numbers.
    check : str
        ``"positive"``, ``"nonnegative"``, ``"fraction"`` (0 <= v < 1) or ``"any"``.
    count : int
        1 for a scalar, n for a list of exactly n numbers.
    default : float or tuple or None
        Value used when the key is absent; ``None`` makes the key required.
    help : str
        One-line description used in error messages and docs.
    integer : bool
        The value must be a whole number (a count, such as a number of modes).
    """

    unit: str
    check: str = "positive"
    count: int = 1
    default: Any = None
    help: str = ""
    integer: bool = False


def quantity(key: str, value: Any, unit: str, check: str = "any", *, integer: bool = False) -> float:
    """Convert one configuration value to the internal unit, by its dimension.

    Parameters
    ----------
    key : str
        Name of the key (used in error messages).
    value : float or str
        Bare number in the report's unit, or a string with a unit (see the
        module docstring for percent, angular frequencies and angles).
    unit : str
        Target internal unit (pint expression).
    check : str
        Range check, one of :data:`CHECKS`.
    integer : bool
        Require a whole number.

    Returns
    -------
    float
        The value in the internal unit.

    Raises
    ------
    ConfigError
        Wrong dimension, unparsable or overlong string, NaN/inf, out of
        range, or not a whole number when ``integer``.

    Examples
    --------
    >>> round(quantity("f_oil_hz", "169.6 rad/s", "hertz"), 3)
    26.993
    >>> quantity("zeta", "20 percent", "dimensionless")
    0.2
    >>> quantity("Ke", "500 percent", "volt / inch")
    Traceback (most recent call last):
    ...
    impedance_mil.errors.ConfigError: Ke: expected a quantity with the dimension of volt / inch, got '500 percent'
    """
    if isinstance(value, bool):
        raise ConfigError(key, f"a number in {unit}", value)
    if isinstance(value, (int, float)):
        number = _as_float(key, value)
    elif isinstance(value, str):
        number = _parse_text(key, value, unit)
    else:
        raise ConfigError(key, f"a number in {unit}", _shown(value))
    if not math.isfinite(number):
        raise ConfigError(key, "a finite number", _shown(value))
    _check_range(key, number, check, _shown(value))
    if integer and number != math.floor(number):
        raise ConfigError(key, "a whole number", _shown(value))
    return number


def _shown(value: Any) -> Any:
    """``value`` as echoed in an error message: a long value is cut to about :data:`_SHOWN_CHARS`."""
    text = value if isinstance(value, str) else repr(value)
    if len(text) <= _SHOWN_CHARS:
        return value
    return f"{text[: _SHOWN_CHARS // 2]}...{text[-10:]} ({len(text)} characters)"


def _as_float(key: str, value: Any) -> float:
    try:
        return float(value)
    except OverflowError:  # an int beyond the range of a double
        raise ConfigError(key, "a finite number", _shown(value)) from None


def _parse_text(key: str, value: str, unit: str) -> float:
    """A string with or without a unit, converted to ``unit`` by dimension (see the module docstring)."""
    text = value.strip()
    if len(text) > MAX_QUANTITY_CHARS:
        raise ConfigError(key, f"a value of at most {MAX_QUANTITY_CHARS} characters", _shown(value))
    if _LONG_DIGITS_RE.search(text):
        raise ConfigError(key, f"a number of at most {MAX_NUMBER_DIGITS} digits", _shown(value))
    quick = quick_quantity(text, unit)
    if quick is not None:  # a bare number, or a value in the key's own unit: pint's float, without pint
        return quick
    ureg = unit_registry()
    try:
        parsed = ureg.Quantity(text)
    except Exception:  # pint raises many types for bad strings
        raise ConfigError(key, f"a number or a quantity in {unit}", value) from None
    if not isinstance(parsed, ureg.Quantity):  # pint may hand back a plain number
        return _as_float(key, parsed)
    if not dict(parsed.unit_items()):
        # A number written as a string is still a bare number: the report's unit.
        return _as_float(key, parsed.magnitude)
    target = ureg.Quantity(1.0, unit)
    extra_angle = _angle_power(parsed) - _angle_power(target)
    try:
        if extra_angle == 0:
            return _as_float(key, parsed.to(unit).magnitude)
        if extra_angle == 1 and target.dimensionality == ureg.get_dimensionality("1 / second"):
            # An angular frequency for a key in Hz: cycles per second, one cycle = 2 pi rad.
            return _as_float(key, (parsed / ureg.turn).to(unit).magnitude)
    except pint.DimensionalityError:
        pass
    raise ConfigError(key, f"a quantity with the dimension of {unit}", value)


def _angle_power(q: Any) -> int:
    """Power of the radian in a quantity's root units: 1 for rad/s and rpm, 0 for Hz and percent."""
    return int(dict(q.to_root_units().unit_items()).get("radian", 0))


def _check_range(key: str, number: float, check: str, raw: Any) -> None:
    if check == "positive" and not number > 0:
        raise ConfigError(key, "a positive value", raw)
    if check == "nonnegative" and not number >= 0:
        raise ConfigError(key, "a non-negative value", raw)
    if check == "fraction" and not 0 <= number < 1:
        raise ConfigError(key, "a value in [0, 1)", raw)


def parse_fields(
    fields: Mapping[str, Field], mapping: Mapping[str, Any], *, where: str = ""
) -> dict[str, Any]:
    """Validate and convert a mapping of configuration values.

    Parameters
    ----------
    fields : mapping of str to Field
        The known keys.
    mapping : mapping
        Raw values (from TOML or ``--set`` overrides).
    where : str
        Prefix for error messages (e.g. the file name or ``"table."``).

    Returns
    -------
    dict
        Every known key, converted to internal units (floats or tuples of floats).

    Raises
    ------
    ConfigError
        Unknown key, missing required key, or an invalid value.
    """
    unknown = sorted(set(mapping) - set(fields))
    if unknown:
        raise ConfigError(f"{where}{unknown[0]}", "one of the known keys " + ", ".join(sorted(fields)))
    out: dict[str, Any] = {}
    for key, spec in fields.items():
        name = f"{where}{key}"
        if key not in mapping:
            if spec.default is None:
                raise ConfigError(name, f"a value in {spec.unit} ({spec.help or 'required'})")
            out[key] = spec.default
            continue
        raw = mapping[key]
        if spec.count == 1:
            out[key] = quantity(name, raw, spec.unit, spec.check, integer=spec.integer)
        else:
            if isinstance(raw, str) and "," in raw:
                raw = [part for part in raw.split(",")]
            if not isinstance(raw, (list, tuple)) or len(raw) != spec.count:
                raise ConfigError(name, f"a list of {spec.count} values in {spec.unit}", _shown(raw))
            out[key] = tuple(quantity(name, v, spec.unit, spec.check, integer=spec.integer) for v in raw)
    return out


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file, refusing an oversized or overdeep file before parsing it.

    Checked before parsing (``docs/limits.md``): at most :data:`MAX_TOML_BYTES`
    bytes, arrays and inline tables nested at most :data:`MAX_TOML_DEPTH`
    deep, and no run of more than :data:`MAX_NUMBER_DIGITS` digits outside
    strings (Python's TOML parser recurses once per level, and takes minutes
    over a number of millions of digits).  After parsing, tables (dotted keys
    included) may nest at most :data:`MAX_TOML_DEPTH` deep.

    Raises
    ------
    DataFileError
        The file is missing, unreadable, too large, nested too deep, holds an
        overlong number, or is not valid TOML.
    """
    text = read_text(path, "a TOML file", max_bytes=MAX_TOML_BYTES)
    _check_toml_text(path, text)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise DataFileError(path, f"not valid TOML ({exc})") from None
    except (RecursionError, ValueError):  # a case the checks above missed
        raise DataFileError(path, "not valid TOML (nested too deep or a number too large)") from None
    if _nesting_depth(data) > MAX_TOML_DEPTH:
        raise DataFileError(path, f"tables nested more than {MAX_TOML_DEPTH} deep")
    return data


def _check_toml_text(path: str | Path, text: str) -> None:
    """Nesting depth and number length of a TOML text, in one linear pass (strings and comments skipped).

    An unclosed string ends the pass: the parser then reports the file as invalid.
    """
    depth, pos = 0, 0
    while (match := _TOML_SCAN_RE.search(text, pos)) is not None:
        token, start = match.group(), match.start()
        pos = match.end()
        if token in ("[", "{"):
            depth += 1
            if depth > MAX_TOML_DEPTH:
                raise DataFileError(
                    path,
                    f"line {_line(text, start)}: arrays or tables nested more than {MAX_TOML_DEPTH} deep",
                )
        elif token in ("]", "}"):
            depth = max(depth - 1, 0)
        elif token == "#":
            pos = _after(text, "\n", start)
        elif token in ('"', "'"):
            pos = _string_end(text, start)
        else:
            raise DataFileError(
                path, f"line {_line(text, start)}: a number of more than {MAX_NUMBER_DIGITS} digits"
            )
        if pos < 0:
            return


def _line(text: str, index: int) -> int:
    return text.count("\n", 0, index) + 1


def _after(text: str, needle: str, start: int) -> int:
    """Index just past the next ``needle`` at or after ``start``, or -1."""
    found = text.find(needle, start)
    return -1 if found < 0 else found + len(needle)


def _string_end(text: str, start: int) -> int:
    """Index just past the TOML string opening at ``start``, or -1 when it is not closed.

    Basic strings (``"``) honour backslash escapes; literal strings (``'``) have none.
    A one-line string that reaches the end of its line is unclosed: scanning goes on
    on the next line (the parser will refuse the file).
    """
    quote = text[start]
    triple = text.startswith(quote * 3, start)
    closing = quote * 3 if triple else quote
    pos = start + len(closing)
    line_end = -1 if triple else text.find("\n", pos)
    while True:
        end = text.find(closing, pos)
        if end < 0 or 0 <= line_end < end:
            return -1 if triple or line_end < 0 else line_end + 1
        backslashes = 0
        while quote == '"' and end - backslashes - 1 >= pos and text[end - backslashes - 1] == "\\":
            backslashes += 1
        if backslashes % 2 == 0:
            end += len(closing)
            if triple:  # one or two quotes just before the closing ones belong to the content
                end += len(text[end : end + 2]) - len(text[end : end + 2].lstrip(quote))
            return end
        pos = end + 1


def _nesting_depth(data: Any) -> int:
    """Deepest nesting of dicts and lists in ``data``, walked without recursion (capped just past the limit)."""
    deepest = 0
    stack = [(data, 1)]
    while stack:
        node, depth = stack.pop()
        if isinstance(node, (dict, list)):
            deepest = max(deepest, depth)
            if depth > MAX_TOML_DEPTH:
                return depth
            stack.extend((child, depth + 1) for child in (node.values() if isinstance(node, dict) else node))
    return deepest


def parse_overrides(items: Sequence[str] | None, *, option: str = "--set") -> dict[str, Any]:
    """Turn repeated ``KEY=VALUE`` options into a mapping.

    Values stay strings (``"5"``, ``"2 in"``, ``"70,110"``) except that plain
    numbers become floats, so bare numbers mean the report's unit.

    Raises
    ------
    ConfigError
        An item without ``=`` or with an empty key.
    """
    out: dict[str, Any] = {}
    for item in items or ():
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise ConfigError(option, "KEY=VALUE", _shown(item))
        value = value.strip()
        try:
            out[key] = float(value)
        except ValueError:
            out[key] = value
    return out
