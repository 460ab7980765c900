"""What a table given only as a linear model can do: its stroke, velocity and force capacity.

A physical table (:class:`~impedance_mil.plant.parameters.TableParameters`)
implies its capacity: the mid-stroke, the valve's no-load velocity, the stall
force ``A_p (P_S - P_R)`` and the moving mass.  A transfer-function, zpk or
state-space table (:mod:`impedance_mil.plant.lti_table`) does not, and the
virtual lab needs some of it: the stroke interlock, the default actuator-force
interlock, ``w_FE``, and the generic sensor ranges.  The optional
``[capacity]`` section of an LTI table file states it, each value with a unit::

    [capacity]
    stroke = "150 mm"          # +- from mid-stroke
    velocity = "0.7 m/s"       # velocity capacity (the default velocity interlock)
    force = "25 kN"            # stall force A_p (P_S - P_R) (95 % of it: the default force interlock)
    mass = "900 kg"            # moving mass of the bare table (w_FE, the accelerometer's range)
    piston_area = "20 cm**2"   # A_p (actuator force from a dP output)

Every key is optional; what is missing is not assumed: the lab refuses what
needs it, naming the key (:mod:`impedance_mil.lab.labfile`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any

from ..config import quantity
from ..errors import ConfigError
from ..units import INTERNAL_UNITS

#: Keys of ``[capacity]``: internal unit and description.
CAPACITY_KEYS = {
    "stroke": ("inch", "stroke from mid-stroke [in]"),
    "velocity": ("inch / second", "velocity capacity [in/s]"),
    "force": ("force_pound", "stall force A_p (P_S - P_R) [lbf]"),
    "mass": (INTERNAL_UNITS["mass"], "moving mass [lbf*s**2/in]"),
    "piston_area": ("inch ** 2", "piston area A_p [in**2]"),
}


@dataclass(frozen=True)
class TableCapacity:
    """The stated capacity of an LTI table (None: not stated).

    Attributes
    ----------
    stroke : float or None
        Stroke from mid-stroke [in].
    velocity : float or None
        Velocity capacity [in/s].
    force : float or None
        Stall force ``A_p (P_S - P_R)`` [lbf].
    mass : float or None
        Moving mass of the bare table [lbf*s**2/in].
    piston_area : float or None
        Piston area A_p [in**2].
    """

    stroke: float | None = None
    velocity: float | None = None
    force: float | None = None
    mass: float | None = None
    piston_area: float | None = None

    @classmethod
    def from_mapping(cls, section: Any, where: str = "") -> TableCapacity:
        """The ``[capacity]`` section of a file (keys named ``{where}capacity.KEY``; units by dimension).

        Raises
        ------
        ConfigError
            Not a table, an unknown key, or a value that is not a positive quantity of the key's dimension.
        """
        if not isinstance(section, Mapping):
            raise ConfigError(f"{where}capacity", "a [capacity] table", section)
        unknown = sorted(set(section) - set(CAPACITY_KEYS))
        if unknown:
            raise ConfigError(f"{where}capacity.{unknown[0]}", "one of the keys " + ", ".join(CAPACITY_KEYS))
        values = {
            key: quantity(f"{where}capacity.{key}", section[key], CAPACITY_KEYS[key][0], "positive")
            for key in section
        }
        return cls(**values)

    def to_dict(self) -> dict[str, float | None]:
        """The stated values, internal units (None: not stated)."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def stated(self) -> dict[str, float]:
        """Only the stated values (the lines of a ``[capacity]`` section, internal units)."""
        return {k: v for k, v in self.to_dict().items() if v is not None}


#: Unit of each :meth:`TableCapacity.to_dict` value (internal units).
CAPACITY_UNITS = {
    "capacity.stroke": "in",
    "capacity.velocity": "in/s",
    "capacity.force": "lbf",
    "capacity.mass": "lbf*s**2/in",
    "capacity.piston_area": "in**2",
}


__all__ = ["CAPACITY_KEYS", "CAPACITY_UNITS", "TableCapacity"]
