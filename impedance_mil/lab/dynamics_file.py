"""The lab file's ``[dynamics]`` section: optional physical additions to the virtual table.

``[dynamics]`` holds one sub-table per addition.  Each sub-table has its own
parser in :data:`DYNAMICS_PARSERS` (a dispatch keyed by the sub-table's name);
this module owns ``[dynamics.platen]`` and ``[dynamics.load_cells]``
(:mod:`impedance_mil.specimens.mounting`).  The names in :data:`PASSED_THROUGH`
belong to other parts of the lab (foundation, valve, friction): their raw
tables are kept in :attr:`DynamicsSetup.others`, unvalidated here, for their
own parser.  Any other name is refused, naming it.

``[dynamics.platen]``::

    modal_mass = "160 lb"      # or mass_fraction = "10 %" (of the table's m_st); below m_st
    frequency = "150 Hz"
    damping = "3 %"            # damping ratio, default 0

``[dynamics.load_cells]``::

    stiffness = "2e6 lbf/in"   # total axial stiffness of the cells and their frame
    damping = "5 %"            # a ratio of the carried mass, or "20 lbf*s/in"; default 0
    base_mass = "200 lb"       # base plate above the cells, default 0
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from ..config import quantity
from ..errors import ConfigError
from ..lazy import LazyModule

if TYPE_CHECKING:
    from ..specimens.mounting import LoadCells, Mounting, PlatenMode

#: The mounting's models, imported when a lab has ``[dynamics.platen]`` or ``[dynamics.load_cells]``:
#: reading a lab without them (``imil lab show``) does not need them (issue 16, start-up).
specimens_mounting = LazyModule("impedance_mil.specimens.mounting")

#: Unit of a mass key (pint): a mass given as ``"200 lb"`` or ``"90 kg"`` converts exactly.
MASS_UNIT = "force_pound * second ** 2 / inch"

#: Sub-tables of ``[dynamics]`` another part of the lab parses (kept raw in DynamicsSetup.others).
PASSED_THROUGH = ("foundation", "valve", "friction")

PLATEN_KEYS = ("modal_mass", "mass_fraction", "frequency", "damping")
LOAD_CELL_KEYS = ("stiffness", "damping", "base_mass")


@dataclass(frozen=True)
class DynamicsSetup:
    """What ``[dynamics]`` sets: the mounting, and the raw sub-tables parsed elsewhere.

    Attributes
    ----------
    mounting : Mounting or None
        Platen mode and load cells (None: neither given).
    others : mapping of str to mapping
        The raw sub-tables of :data:`PASSED_THROUGH` that were given.
    """

    mounting: Mounting | None = None
    others: Mapping[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        m = self.mounting
        return {
            "platen": None if m is None or m.platen is None else m.platen.to_dict(),
            "load_cells": None if m is None or m.load_cells is None else m.load_cells.to_dict(),
        } | {k: dict(v) for k, v in self.others.items()}


def _table(raw: Any, key: str) -> Mapping[str, Any]:
    if not isinstance(raw, Mapping):
        raise ConfigError(key, "a TOML table", raw)
    return raw


def _unknown(section: Mapping[str, Any], known: tuple[str, ...], key: str) -> None:
    unknown = sorted(set(section) - set(known))
    if unknown:
        raise ConfigError(f"{key}.{unknown[0]}", "one of the keys " + ", ".join(known))


def parse_platen(raw: Any, table_mass: float, key: str) -> PlatenMode:
    """``[dynamics.platen]``: a :class:`PlatenMode` for a table of moving mass ``table_mass`` [lbf*s^2/in]."""
    section = _table(raw, key)
    _unknown(section, PLATEN_KEYS, key)
    if ("modal_mass" in section) == ("mass_fraction" in section):
        raise ConfigError(f"{key}.modal_mass", "either modal_mass or mass_fraction (one of them)")
    if "modal_mass" in section:
        mass = quantity(f"{key}.modal_mass", section["modal_mass"], MASS_UNIT, "positive")
        where = f"{key}.modal_mass"
    else:
        mass = table_mass * quantity(
            f"{key}.mass_fraction", section["mass_fraction"], "dimensionless", "positive"
        )
        where = f"{key}.mass_fraction"
    if mass >= table_mass:
        raise ConfigError(
            where, f"a modal mass below the table's moving mass m_st = {table_mass:.6g} lbf*s^2/in", mass
        )
    if "frequency" not in section:
        raise ConfigError(f"{key}.frequency", "the platen mode's frequency (e.g. '150 Hz')")
    f = quantity(f"{key}.frequency", section["frequency"], "hertz", "positive")
    zeta = quantity(f"{key}.damping", section.get("damping", 0.0), "dimensionless", "nonnegative")
    return specimens_mounting.PlatenMode(mass, f, zeta)


def parse_load_cells(raw: Any, key: str) -> LoadCells:
    """``[dynamics.load_cells]``: :class:`LoadCells` (damping a ratio, or a coefficient in lbf*s/in)."""
    section = _table(raw, key)
    _unknown(section, LOAD_CELL_KEYS, key)
    if "stiffness" not in section:
        raise ConfigError(f"{key}.stiffness", "the load cells' total axial stiffness (e.g. '2e6 lbf/in')")
    k = quantity(f"{key}.stiffness", section["stiffness"], "force_pound / inch", "positive")
    raw_damping = section.get("damping", 0.0)
    try:
        c, is_ratio = quantity(f"{key}.damping", raw_damping, "dimensionless", "nonnegative"), True
    except ConfigError:
        try:
            c, is_ratio = (
                quantity(f"{key}.damping", raw_damping, "force_pound * second / inch", "nonnegative"),
                False,
            )
        except ConfigError:
            raise ConfigError(
                f"{key}.damping",
                "a damping ratio >= 0 (e.g. '5 %') or a coefficient (e.g. '20 lbf*s/in')",
                raw_damping,
            ) from None
    base = quantity(f"{key}.base_mass", section.get("base_mass", 0.0), MASS_UNIT, "nonnegative")
    return specimens_mounting.LoadCells(k, c, base, is_ratio)


#: The sub-tables of ``[dynamics]`` this module parses: name -> parser(raw, table mass, key).
DYNAMICS_PARSERS: dict[str, Callable[[Any, float, str], Any]] = {
    "platen": parse_platen,
    "load_cells": lambda raw, _mass, key: parse_load_cells(raw, key),
}


def parse_dynamics(section: Any, table_mass: float | None, where: str = "") -> DynamicsSetup:
    """The ``[dynamics]`` section (None: no section, nothing added).

    Parameters
    ----------
    section : mapping or None
        The raw TOML table.
    table_mass : float or None
        The table's moving mass m_st [lbf*s^2/in]; None for a table given as an
        LTI model, which takes no mounting (its model is the whole table).
    where : str
        Prefix of error messages (the lab file's name).

    Raises
    ------
    ConfigError
        Naming ``dynamics.SUBTABLE.KEY``.
    """
    if section is None:
        return DynamicsSetup()
    section = _table(section, f"{where}dynamics")
    known = (*DYNAMICS_PARSERS, *PASSED_THROUGH)
    unknown = sorted(set(section) - set(known))
    if unknown:
        raise ConfigError(f"{where}dynamics.{unknown[0]}", "one of the sub-tables " + ", ".join(known))
    parsed: dict[str, Any] = {}
    for name, parser in DYNAMICS_PARSERS.items():
        if name not in section:
            continue
        key = f"{where}dynamics.{name}"
        if table_mass is None:
            raise ConfigError(
                key, "a physical table (an LTI table's model is the whole table, mounting included)"
            )
        parsed[name] = parser(section[name], table_mass, key)
    others = {
        name: _table(section[name], f"{where}dynamics.{name}") for name in PASSED_THROUGH if name in section
    }
    mounting = specimens_mounting.Mounting(parsed.get("platen"), parsed.get("load_cells")) if parsed else None
    return DynamicsSetup(mounting, others)


__all__ = [
    "DYNAMICS_PARSERS",
    "DynamicsSetup",
    "PASSED_THROUGH",
    "parse_dynamics",
    "parse_load_cells",
    "parse_platen",
]
