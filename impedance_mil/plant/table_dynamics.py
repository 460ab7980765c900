"""Optional table dynamics beyond the report's model (issue 17): seal friction, spool rate, mount.

Each is off unless a lab file's ``[dynamics]`` sub-table (or a caller) sets it, and
with all of them off the virtual table is the one of :mod:`impedance_mil.plant.nonlinear`
to the last bit.  The physics lives in the kernels
(:mod:`impedance_mil.plant.nonlinear_kernels`); this module holds the definitions, their
validation and the parser of the lab file's sub-tables:

* ``[dynamics.friction]``: seal friction that grows with the chamber pressures,
  ``F_c = F_c0 + f_s (P_1 + P_2) + f_l |P_1 - P_2|`` (Simscape's Cylinder Friction
  block and Modelica's ``Hydraulic.Utilities.PressureDependentFriction`` use the
  ``(p_A + p_B)`` form; the ``|P_1 - P_2|`` term is the piston seal, pressed by the
  pressure across it);
* ``[dynamics.valve]``: the pilot stage of a two-stage servovalve limits the main
  spool's velocity (``spool_rate_limit`` [mA/s] or ``full_stroke_time`` [s]);
* ``[dynamics.foundation]``: a massless compliant mount of stiffness k_f [lbf/in]
  between the cylinder body and ground.

Sources and typical ranges: ``docs/lab.md`` Section 1.1.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..config import Field, parse_fields
from ..errors import ConfigError

#: Keys of each sub-table of ``[dynamics]`` this module reads (internal unit, meaning).
FRICTION_FIELDS = {
    "pressure_coefficient": Field(
        "force_pound / psi", "positive", default=0.0, help="Coulomb friction per psi of P1 + P2 [lbf/psi]"
    ),
    "load_pressure_coefficient": Field(
        "force_pound / psi", "positive", default=0.0, help="Coulomb friction per psi of |P1 - P2| [lbf/psi]"
    ),
}
VALVE_FIELDS = {
    "spool_rate_limit": Field(
        "milliampere / second", "positive", default=0.0, help="largest main-spool velocity [mA/s]"
    ),
    "full_stroke_time": Field(
        "second", "positive", default=0.0, help="spool travel time from null to full opening [s]"
    ),
}
FOUNDATION_FIELDS = {
    "stiffness": Field("force_pound / inch", "positive", default=0.0, help="mount stiffness k_f [lbf/in]"),
}

#: The sub-tables of ``[dynamics]`` read here, and their keys.
TABLE_DYNAMICS_SECTIONS: dict[str, dict[str, Field]] = {
    "friction": FRICTION_FIELDS,
    "valve": VALVE_FIELDS,
    "foundation": FOUNDATION_FIELDS,
}

#: Keys refused with the reason (not modelled), rather than as unknown.
_NOT_MODELLED = {
    ("foundation", "damping"): "no damping key: a massless mount with a dashpot needs the body "
    "displacement as a state, which the 6-state table does not have (docs/lab.md, Section 1.1)",
}

#: Unit of each value of :meth:`TableDynamics.to_dict`.
DYNAMICS_UNITS = {
    "pressure_friction": "lbf/psi",
    "load_pressure_friction": "lbf/psi",
    "spool_rate_limit": "mA/s",
    "foundation_stiffness": "lbf/in",
}


def smooth_saturation(u: float, limit: float) -> float:
    """The spool-velocity saturation ``u / (1 + (u/L)^4)^(1/4)`` [unit of ``u``].

    Smooth (analytic) for RK4, slope 1 and curvature 0 at ``u = 0`` (so the
    linearization is the unlimited valve's), within 0.2 % of ``u`` for
    ``|u| <= 0.3 L`` and tending to ``+-L`` (0.84 L at ``u = L``).  Plain
    Python; compiled in :mod:`impedance_mil.plant.nonlinear_kernels`.
    ``limit`` L > 0 in the unit of ``u``.
    """
    r = u / limit
    r2 = r * r
    return u / math.sqrt(math.sqrt(1.0 + r2 * r2))


@dataclass(frozen=True)
class TableDynamics:
    """The optional dynamics of the virtual table (issue 17); zero or None: off.

    Parameters
    ----------
    pressure_friction : float
        f_s [lbf/psi]: the Coulomb friction grows by ``f_s (P_1 + P_2)``
        (rod seals, pressed by each chamber's pressure; gauge pressures).
    load_pressure_friction : float
        f_l [lbf/psi]: the Coulomb friction grows by ``f_l |P_1 - P_2|``
        (piston seal), ``|.|`` smoothed over the laminar pressure of the
        orifice law as ``sqrt(dP^2 + p_lam^2) - p_lam``.
    spool_rate_limit : float or None
        Largest main-spool velocity r [mA-equivalent/s] (pilot-stage flow
        saturation); None: unlimited.
    foundation_stiffness : float or None
        Stiffness k_f [lbf/in] of a massless mount between the cylinder body
        and ground; None: rigid.
    """

    pressure_friction: float = 0.0
    load_pressure_friction: float = 0.0
    spool_rate_limit: float | None = None
    foundation_stiffness: float | None = None

    def __post_init__(self):
        for name in ("pressure_friction", "load_pressure_friction"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ConfigError(f"dynamics.{name}", "a non-negative coefficient [lbf/psi]", value)
        for name, unit in (("spool_rate_limit", "mA/s"), ("foundation_stiffness", "lbf/in")):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise ConfigError(f"dynamics.{name}", f"a positive finite value [{unit}] or None", value)

    @property
    def is_off(self) -> bool:
        """True when no dynamic is set (the table is the report's model)."""
        return self == TableDynamics()

    @property
    def foundation_compliance(self) -> float:
        """``1/k_f`` [in/lbf]; 0 for a rigid mount."""
        return 0.0 if self.foundation_stiffness is None else 1.0 / self.foundation_stiffness

    def to_dict(self) -> dict[str, float | None]:
        """The values in internal units (:data:`DYNAMICS_UNITS`)."""
        return {
            "pressure_friction": self.pressure_friction,
            "load_pressure_friction": self.load_pressure_friction,
            "spool_rate_limit": self.spool_rate_limit,
            "foundation_stiffness": self.foundation_stiffness,
        }


def series_stiffness(oil_stiffness: float, foundation_stiffness: float | None) -> float:
    """Oil column and mount in series, ``k_oil k_f / (k_oil + k_f)`` [lbf/in] (``k_f`` None: ``k_oil``)."""
    if foundation_stiffness is None:
        return oil_stiffness
    return oil_stiffness * foundation_stiffness / (oil_stiffness + foundation_stiffness)


def parse_table_dynamics(
    section: Mapping[str, Any], rated_current: float, where: str = ""
) -> TableDynamics | None:
    """Read the sub-tables :data:`TABLE_DYNAMICS_SECTIONS` of a lab file's ``[dynamics]``.

    Parameters
    ----------
    section : mapping
        The sub-tables of ``[dynamics]`` this module reads (others are the
        caller's); values with units or bare numbers in the internal unit.
    rated_current : float
        The valve's rated current [mA] (full opening): ``full_stroke_time`` T
        gives ``spool_rate_limit = rated_current / T``.
    where : str
        Prefix of error messages (``"mylab.toml: "``).

    Returns
    -------
    TableDynamics or None
        None when no sub-table was given.

    Raises
    ------
    ConfigError
        Naming ``dynamics.SUB.KEY``: unknown key, wrong dimension, value not
        positive, both ``spool_rate_limit`` and ``full_stroke_time``.
    """
    if not section:
        return None
    values: dict[str, float] = {}
    for name, sub in section.items():
        key = f"{where}dynamics.{name}"
        if name not in TABLE_DYNAMICS_SECTIONS:
            raise ConfigError(key, "one of the sub-tables " + ", ".join(TABLE_DYNAMICS_SECTIONS))
        if not isinstance(sub, Mapping):
            raise ConfigError(key, "a TOML table", sub)
        for k in sub:
            if (name, k) in _NOT_MODELLED:
                raise ConfigError(f"{key}.{k}", _NOT_MODELLED[(name, k)])
        fields = TABLE_DYNAMICS_SECTIONS[name]
        parsed = parse_fields(fields, sub, where=f"{key}.")
        values.update({f"{name}.{k}": v for k, v in parsed.items() if k in sub})
    if "valve.spool_rate_limit" in values and "valve.full_stroke_time" in values:
        raise ConfigError(
            f"{where}dynamics.valve.full_stroke_time", "either spool_rate_limit or full_stroke_time"
        )
    rate = values.get("valve.spool_rate_limit")
    if "valve.full_stroke_time" in values:
        rate = rated_current / values["valve.full_stroke_time"]
    return TableDynamics(
        pressure_friction=values.get("friction.pressure_coefficient", 0.0),
        load_pressure_friction=values.get("friction.load_pressure_coefficient", 0.0),
        spool_rate_limit=rate,
        foundation_stiffness=values.get("foundation.stiffness"),
    )
