"""Display units: what a person reads, in US or SI units (``--units us|si``).

The library computes in one internal system, the report's (:mod:`impedance_mil.units`:
in, lbf, s, psi, V, mA).  What a person reads -- CLI text, JSON, HTML pages, plots --
is converted here, at the edge, into the user's choice:

======================  =================  ==========================
internal (= ``us``)     ``si``             note
======================  =================  ==========================
in                      mm                 strokes, displacements
in/s                    mm/s
in/s**2                 m/s**2             accelerations in g stay g
lbf                     kN                 forces and weights
psi                     MPa                pressures
lbf*s**2/in             kg                 masses
in**3/s                 L/s                flows
lbf/in, lbf*s/in        kN/m, kN*s/m       stiffness, damping
in**2                   cm**2              areas
======================  =================  ==========================

Any other unit is converted factor by factor (in -> mm, lbf -> kN, psi -> MPa; V,
mA, s and Hz are kept), so ``V/psi`` reads ``V/MPa``.  Units are matched by their
pint expression, never by dimension alone: ``V/psi`` and ``in**3/s/mA`` share
a dimension but are different quantities.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum
from functools import cache
from typing import Any

from .config import unit_registry
from .errors import ConfigError
from .unit_names import SI_DISPLAY_BY_EXPRESSION, quick_short_name


class UnitSystem(StrEnum):
    """The unit system of what a person reads."""

    US = "us"  # the report's (internal) units
    SI = "si"


#: Name of each unit system, for help texts and error messages.
UNIT_SYSTEM_NAMES = tuple(s.value for s in UnitSystem)

#: SI display unit of whole internal units (pint's short form of the internal unit).
_SI_WHOLE: dict[str, str] = {
    "lbf*s**2/in": "kg",
    "in**3/s": "L/s",
    "in/s**2": "m/s**2",
    "lbf/in": "kN/m",
    "lbf*s/in": "kN*s/m",
    "in**2": "cm**2",
    "lbf*in": "J",
}

#: SI display unit of each factor of a compound internal unit.
_SI_FACTOR: dict[str, str] = {"in": "mm", "lbf": "kN", "psi": "MPa"}

#: Short names pint gives that a lab writes otherwise.
_SHORT_NAME: dict[str, str] = {"l": "L"}


@dataclass(frozen=True)
class DisplayUnit:
    """How to show values of one internal unit: ``shown = value * factor``, in ``name``."""

    name: str
    factor: float

    def __call__(self, value: Any) -> Any:
        """``value`` [internal unit] in this unit (a number or an array)."""
        return value * self.factor


def unit_system(text: str | UnitSystem | None, key: str = "--units") -> UnitSystem:
    """``"us"`` / ``"si"`` (any case) as a :class:`UnitSystem`; ``None`` is US.

    Raises
    ------
    ConfigError
        Naming ``key`` when ``text`` is neither.
    """
    if text is None:
        return UnitSystem.US
    if isinstance(text, UnitSystem):
        return text
    try:
        return UnitSystem(str(text).strip().lower())
    except ValueError:
        raise ConfigError(key, " or ".join(UNIT_SYSTEM_NAMES), text) from None


def short_name(unit: str) -> str:
    """The short form of a pint unit expression: ``"force_pound / inch"`` -> ``"lbf/in"``.

    The units of :data:`impedance_mil.unit_names.SHORT_NAMES_BY_EXPRESSION` (those the
    toolkit shows) are named without pint, the same as pint names them; others by pint.
    """
    quick = quick_short_name(unit)
    if quick is not None:
        return _SHORT_NAME.get(quick, quick)
    parsed = unit_registry().parse_units(unit.replace("^", "**"))
    if parsed == unit_registry().parse_units("dimensionless"):
        return ""
    return _SHORT_NAME.get(f"{parsed:~C}", f"{parsed:~C}")


@cache
def display_unit(unit: str, system: UnitSystem) -> DisplayUnit:
    """The unit values of the internal ``unit`` (a pint expression) are shown in.

    ``"g0"`` (accelerations in g), ``"s"``, ``"Hz"``, ``"deg"`` and every unit
    without in, lbf or psi read the same in both systems.  The SI units of
    :data:`~impedance_mil.unit_names.SI_DISPLAY_BY_EXPRESSION` are shown without
    pint, the same as :func:`si_display_by_pint` shows them.
    """
    known = SI_DISPLAY_BY_EXPRESSION.get(unit) if system is UnitSystem.SI else None
    if known is not None:
        return DisplayUnit(*known)
    name = short_name(unit)
    if system is UnitSystem.US or name == "":
        return DisplayUnit(name, 1.0)
    return si_display_by_pint(unit)


def si_display_by_pint(unit: str) -> DisplayUnit:
    """The SI display unit of the internal ``unit`` (a pint expression), found by pint (see the module)."""
    name = short_name(unit)
    if name == "":
        return DisplayUnit(name, 1.0)
    target = _SI_WHOLE.get(name) or _factor_by_factor(unit)
    if target == name:  # no in, lbf or psi in it (and logarithmic units such as dB convert no further)
        return DisplayUnit(name, 1.0)
    factor = unit_registry().Quantity(1.0, unit.replace("^", "**")).to(target.replace("L", "liter")).magnitude
    return DisplayUnit(target, float(factor))


def _factor_by_factor(unit: str) -> str:
    """``V/psi`` -> ``V/MPa``: each factor of ``unit`` in its SI display unit."""
    parsed = unit_registry().parse_units(unit.replace("^", "**"))
    upper: list[str] = []
    lower: list[str] = []
    for name, power in unit_registry().Quantity(1.0, parsed).unit_items():
        power = float(power.real) if isinstance(power, complex) else float(power)
        symbol = f"{unit_registry().parse_units(name):~C}"
        symbol = _SI_FACTOR.get(symbol, symbol)
        text = symbol if abs(power) == 1 else f"{symbol}**{abs(power):g}"
        (upper if power > 0 else lower).append(text)
    shown = "*".join(upper) or "1"
    return shown + "".join("/" + part for part in lower)


def shown(value: float, unit: str, system: UnitSystem) -> float:
    """``value`` [internal ``unit``] in the display unit of ``system``."""
    return display_unit(unit, system)(value)


def format_value(value: float | None, unit: str, system: UnitSystem, digits: int = 4) -> str:
    """``3.0, "in", SI`` -> ``"76.2 mm"``: a value with its display unit (``digits`` significant)."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "none" if value is None or math.isnan(value) else f"{value}"
    shown_unit = display_unit(unit, system)
    text = f"{shown_unit(value):.{digits}g}"
    return f"{text} {human_name(shown_unit.name)}" if shown_unit.name else text


def human_name(unit_name: str) -> str:
    """A display unit as a person reads it: ``g0`` (standard gravity in files) is ``g``."""
    return "g" if unit_name == "g0" else unit_name


def key_suffix(unit_name: str) -> str:
    """The key suffix of a display unit, as JSON keys spell it: ``"in**3/s"`` -> ``"in3_s"``."""
    return unit_name.lower().replace("**", "").replace("*", "_").replace("/", "_")
