"""The units the generated controller reads and writes (its I/O units), and their factors.

Inside, the generated C and ST compute in the report's units
(:mod:`impedance_mil.units`): they read ``z_vs`` and ``a_g`` [in/s^2] and ``w``
[lbf] and write ``u`` [in].  A lab whose sensors and actuator speak other
units exports the code with I/O units (``imil export --io-units si``, or a lab
file's ``[controller] io_units``); the code then scales at its edges:

* each input times its factor ``to_internal`` is in the internal unit, before
  the guards and the controller;
* the safe command [in] (and, in the MIL step, ``z_vs`` [in/s^2]) times its
  factor ``from_internal`` is in the lab's unit, on output.

The guard limits stay in the internal units; the generated header states the
input ranges in both.

A specification is ``"us"`` (the internal units: no scaling, the code is what
it was without I/O units), ``"si"`` (:data:`SI_UNITS`: m/s**2, N, mm), or a
comma list ``accel=m/s**2,force=kN,disp=mm`` of pint units (``g0`` is standard
gravity, pint's ``g`` is the gram), optionally after ``us`` or ``si`` as the
base (``si,force=kN``).  Without a base every quantity must be named.  A lab
file may also give an inline table ``{accel = "m/s**2", force = "kN", disp = "mm"}``.

>>> io = IOUnits.parse("accel=g0,force=kN,disp=mm")
>>> round(io.accel.to_internal, 4), round(io.force.to_internal, 4), io.disp.from_internal
(386.0886, 224.8089, 25.4)
>>> IOUnits.parse("si").spec, IOUnits.parse("us").is_internal
('si', True)
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..config import quantity
from ..errors import ConfigError
from .renderable import check_renderable

if TYPE_CHECKING:  # the limits' type only: the command limits are not read with a lab file
    from .safety import CommandLimits

__all__ = ["INTERNAL_IO", "IO_QUANTITIES", "SI_UNITS", "IOUnit", "IOUnits"]


@dataclass(frozen=True)
class _Quantity:
    """One I/O quantity: its internal unit (pint and as shown), what it means, the values it covers."""

    pint_unit: str
    shown: str
    dimension: str
    examples: str
    values: str


#: The three I/O quantities of the generated code, by key of the specification.
IO_QUANTITIES = {
    "accel": _Quantity("inch / second ** 2", "in/s^2", "acceleration", "m/s**2, g0, in/s**2", "z_vs, a_g"),
    "force": _Quantity("force_pound", "lbf", "force", "N, kN, lbf, kip", "w"),
    "disp": _Quantity("inch", "in", "length", "mm, m, in", "u"),
}

#: The internal units as a specification (``us``): no scaling.
INTERNAL_IO = {key: q.shown for key, q in IO_QUANTITIES.items()}

#: The units of ``si``.
SI_UNITS = {"accel": "m/s**2", "force": "N", "disp": "mm"}

#: What a unit may be written with: it is copied into C and ST comments, so no comment
#: delimiter (``/*``, ``*/``, ``(*``, ``*)``), no line break, and it starts with a letter
#: (a bare number or a factor such as ``1000 N`` is not a unit).
_UNIT_TEXT = re.compile(r"(?!.*(/\*|\*/|\(\*|\*\)))[^\W\d][\w */^().-]*")

#: Named specifications.
_NAMED = {"us": INTERNAL_IO, "si": SI_UNITS}


@dataclass(frozen=True)
class IOUnit:
    """One I/O quantity of the generated code in the lab's unit.

    Attributes
    ----------
    key : str
        ``accel``, ``force`` or ``disp``.
    unit : str
        The lab's unit, as written (``"m/s**2"``).
    internal : str
        The internal unit (``"in/s^2"``, ``"lbf"``, ``"in"``).
    to_internal : float
        Internal units per lab unit: ``value [internal] = value [lab] * to_internal``.
    from_internal : float
        Lab units per internal unit, converted on its own (not ``1 / to_internal``,
        so that 1 in is exactly 25.4 mm).
    """

    key: str
    unit: str
    internal: str
    to_internal: float
    from_internal: float

    @property
    def is_internal(self) -> bool:
        """Whether the lab's unit is the internal one (both factors exactly 1)."""
        return self.to_internal == 1.0 and self.from_internal == 1.0

    @property
    def values(self) -> str:
        """The values of the generated code in this unit (``"z_vs, a_g"``, ``"w"``, ``"u"``)."""
        return IO_QUANTITIES[self.key].values


@dataclass(frozen=True)
class IOUnits:
    """The I/O units of the generated controller: acceleration, force and displacement.

    Build with :meth:`parse`; :data:`INTERNAL_IO` (``IOUnits.parse("us")``) is no scaling.
    """

    accel: IOUnit
    force: IOUnit
    disp: IOUnit

    @classmethod
    def parse(cls, value: Any = "us", key: str = "--io-units") -> IOUnits:
        """The I/O units of a specification (module docstring) or a mapping ``{accel, force, disp}``.

        Parameters
        ----------
        value : str or Mapping
            ``"us"``, ``"si"``, ``"accel=m/s**2,force=kN,disp=mm"`` (optionally after a
            base ``us`` or ``si``), or a mapping of those keys to units.
        key : str
            The option or configuration key, for the messages (``"--io-units"``,
            ``"lab.toml: controller.io_units"``).

        Raises
        ------
        ConfigError
            Naming ``key`` and the quantity: a malformed specification, an unknown
            or repeated quantity, a missing one (without a base), a unit that is not
            a unit or not of the quantity's dimension (``force=mm``).
        """
        base, given = _units(value, key)
        parts = {name: _unit(name, text, key) for name, text in given.items()}  # each checked first
        missing = [name for name in IO_QUANTITIES if name not in given and name not in base]
        if missing:
            raise ConfigError(
                f"{key} {missing[0]}",
                "a unit for each of accel, force and disp (or a base us or si first)",
                value,
            )
        for name in IO_QUANTITIES:
            if name not in parts:
                parts[name] = _unit(name, base[name], key)
        return cls(parts["accel"], parts["force"], parts["disp"])

    @classmethod
    def internal(cls) -> IOUnits:
        """The internal units (``us``): no scaling."""
        return cls.parse("us")

    @property
    def units(self) -> tuple[IOUnit, IOUnit, IOUnit]:
        """``(accel, force, disp)``."""
        return (self.accel, self.force, self.disp)

    @property
    def is_internal(self) -> bool:
        """Whether no quantity is scaled: the generated code is the one without I/O units."""
        return all(u.is_internal for u in self.units)

    @property
    def spec(self) -> str:
        """``us``, ``si``, or the comma list ``accel=...,force=...,disp=...``."""
        if self.is_internal:
            return "us"
        given = {u.key: u.unit for u in self.units}
        if given == SI_UNITS:
            return "si"
        return ",".join(f"{k}={v}" for k, v in given.items())

    def describe(self) -> str:
        """One phrase: ``z_vs, a_g in m/s**2, w in N, u in mm``."""
        return ", ".join(f"{u.values} in {u.unit}" for u in self.units)

    def input_ranges(self, limits: CommandLimits) -> str:
        """The guards' input ranges in these units: ``|z_vs|, |a_g| <= 386.5 m/s**2, |w| <= ...``."""
        accel = limits.accel_limit_in_s2 * self.accel.from_internal
        force = limits.force_limit_lbf * self.force.from_internal
        return f"|z_vs|, |a_g| <= {accel:.6g} {self.accel.unit}, |w| <= {force:.6g} {self.force.unit}"

    def check(self, precision: str) -> None:
        """Refuse a factor the precision cannot hold (:func:`~impedance_mil.implement.safety.check_renderable`)."""
        for u in self.units:
            for name, factor in (("to_internal", u.to_internal), ("from_internal", u.from_internal)):
                check_renderable(
                    f"io_units {u.key} ({u.unit}) {name}", factor, precision, "an I/O unit factor"
                )

    def to_dict(self) -> dict[str, Any]:
        """The ``io_units`` block of the coefficient file: each input and output, its unit, its factor."""
        a, f, d = self.units
        return {
            "spec": self.spec,
            "z_vs": {"unit": a.unit, "internal_unit": a.internal, "to_internal": a.to_internal},
            "w": {"unit": f.unit, "internal_unit": f.internal, "to_internal": f.to_internal},
            "u": {"unit": d.unit, "internal_unit": d.internal, "from_internal": d.from_internal},
            "note": "the coefficients are in the internal units: multiply z_vs and w by to_internal "
            "before the controller, and its command u by from_internal after it",
        }


def _units(value: Any, key: str) -> tuple[dict[str, str], dict[str, str]]:
    """The base (``us``, ``si`` or none) and the units given, of a specification or a mapping."""
    base: dict[str, str] = {}
    if isinstance(value, Mapping):
        items = list(value.items())
    elif isinstance(value, str):
        parts = [p.strip() for p in value.split(",")]
        if parts[0] in _NAMED:
            base = dict(_NAMED[parts.pop(0)])
        items = []
        for part in parts:
            name, eq, unit = part.partition("=")
            if not eq:
                raise ConfigError(key, "us, si or a list accel=UNIT,force=UNIT,disp=UNIT", value)
            items.append((name.strip(), unit.strip()))
    else:
        raise ConfigError(key, "us, si or a table {accel, force, disp} of units", value)
    given: dict[str, str] = {}
    for name, unit in items:
        if name not in IO_QUANTITIES:
            raise ConfigError(f"{key} {name}", "one of the quantities " + ", ".join(IO_QUANTITIES))
        if name in given:
            raise ConfigError(f"{key} {name}", "each quantity once", value)
        given[name] = unit
    return base, given


def _unit(name: str, text: Any, key: str) -> IOUnit:
    """One quantity's unit, converted by dimension both ways with the configuration's registry."""
    q = IO_QUANTITIES[name]
    where = f"{key} {name}"
    expected = f"a unit of {q.dimension} ({q.examples})"
    unit = text.strip() if isinstance(text, str) else text
    if not isinstance(unit, str) or not _UNIT_TEXT.fullmatch(unit):
        raise ConfigError(where, expected, text)
    try:
        to_internal = quantity(where, f"1 {unit}", q.pint_unit, "positive")
        from_internal = quantity(where, f"1 {q.pint_unit}", unit, "positive")
    except ConfigError:
        raise ConfigError(where, expected, unit) from None
    return IOUnit(name, unit, q.shown, to_internal, from_internal)
