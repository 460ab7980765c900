"""Configuration files and values with units: the edge where pint lives.

A configuration value is either a bare number, meaning the report's unit of
that key (see :mod:`impedance_mil.units`), or a string with a unit that pint
understands, e.g. ``"1600 lb"`` (a mass), ``"2.1 in**2"``, ``"0.001 V/psi"``,
``"0.8 g0"`` (``g0`` is standard gravity; pint's ``g`` is the gram).

Domain packages describe their keys with a plain mapping
``{key: Field(unit=..., check=...)}`` and call :func:`parse_fields`; they
never import pint themselves.  A mass may be given as a weight-like mass
(``"1600 lb"``); pint converts pound-mass to lbf*s**2/in exactly.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pint

from .errors import ConfigError, DataFileError
from .fileio import read_text
from .units import PINT_DEFINITIONS

_UREG = pint.UnitRegistry()
for _definition in PINT_DEFINITIONS:
    _UREG.define(_definition)

#: Allowed checks for a field value.
CHECKS = ("positive", "nonnegative", "any", "fraction")


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
    """

    unit: str
    check: str = "positive"
    count: int = 1
    default: Any = None
    help: str = ""


def quantity(key: str, value: Any, unit: str, check: str = "any") -> float:
    """Convert one configuration value to the internal unit.

    Parameters
    ----------
    key : str
        Name of the key (used in error messages).
    value : float or str
        Bare number in the report's unit, or a string with a unit.
    unit : str
        Target internal unit (pint expression).
    check : str
        Range check, one of :data:`CHECKS`.

    Returns
    -------
    float
        The value in the internal unit.

    Raises
    ------
    ConfigError
        Wrong dimension, unparsable string, NaN/inf, or out of range.
    """
    if isinstance(value, bool):
        raise ConfigError(key, f"a number in {unit}", value)
    if isinstance(value, (int, float)):
        number = float(value)
    elif isinstance(value, str):
        text = value.strip()
        try:
            parsed = _UREG.Quantity(text)
        except Exception:  # pint raises many types for bad strings
            raise ConfigError(key, f"a number or a quantity in {unit}", value) from None
        try:
            if isinstance(parsed, (int, float)) or parsed.unitless:
                # A number written as a string is still a bare number: the report's unit.
                number = float(getattr(parsed, "magnitude", parsed))
            else:
                number = float(parsed.to(unit).magnitude)
        except pint.DimensionalityError:
            raise ConfigError(key, f"a quantity with the dimension of {unit}", value) from None
    else:
        raise ConfigError(key, f"a number in {unit}", value)
    if not math.isfinite(number):
        raise ConfigError(key, "a finite number", value)
    _check_range(key, number, check, value)
    return number


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
            out[key] = quantity(name, raw, spec.unit, spec.check)
        else:
            if isinstance(raw, str) and "," in raw:
                raw = [part for part in raw.split(",")]
            if not isinstance(raw, (list, tuple)) or len(raw) != spec.count:
                raise ConfigError(name, f"a list of {spec.count} values in {spec.unit}", raw)
            out[key] = tuple(quantity(name, v, spec.unit, spec.check) for v in raw)
    return out


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file.

    Raises
    ------
    DataFileError
        The file is missing, unreadable or not valid TOML.
    """
    text = read_text(path, "a TOML file")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise DataFileError(path, f"not valid TOML ({exc})") from None


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
            raise ConfigError(option, "KEY=VALUE", item)
        value = value.strip()
        try:
            out[key] = float(value)
        except ValueError:
            out[key] = value
    return out
