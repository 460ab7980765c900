"""Build specimens from configuration tables (with units) and from their ``to_dict`` form.

Configuration (TOML ``[specimen]`` table or ``--set specimen.key=value``), a
bare number meaning the report's unit; ``type`` defaults to ``"vessel"``, but
an empty table is refused rather than read as the report's vessel::

    [specimen]
    type = "vessel"            # "vessel", "rigid_mass" or "shear_building"
    water_depth = "36 in"      # vessel keys: see VESSEL_FIELDS

    [specimen]
    type = "rigid_mass"
    weight = "3.6 kip"

    [specimen]
    type = "shear_building"
    story_weights = ["800 lbf", "600 lbf"]
    story_stiffness = ["2000 lbf/in", "1500 lbf/in"]
    damping_ratio = 0.02
    base_weight = "300 lbf"
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..config import Field, parse_fields, quantity
from ..errors import ConfigError
from ..plausibility import check_specimen_weight
from ..report_config import report_config
from .structural import LinearMDOF, RigidMass, Specimen
from .vessel import STEEL_MODULUS, WATER_UNIT_WEIGHT, FluidVessel

#: Configuration keys of the vessel (internal units) and the FluidVessel argument each sets.
VESSEL_FIELDS: dict[str, Field] = {
    "water_depth": Field(
        "inch",
        "nonnegative",
        default=report_config().specimen.water_depth_in,
        help="depth of water (Section 3.2; default the report's setup)",
    ),
    "outer_diameter": Field("inch", default=48.0, help="outside diameter of the shell"),
    "wall_thickness": Field("inch", default=3.0 / 16.0, help="shell thickness"),
    "height": Field("inch", default=48.0, help="shell height"),
    "dry_weight": Field("force_pound", default=1200.0, help="empty vessel (Section 8.2)"),
    "water_unit_weight": Field(
        "force_pound / inch**3", default=WATER_UNIT_WEIGHT, help="unit weight of the liquid"
    ),
    "n_convective_modes": Field("dimensionless", default=3.0, help="sloshing modes kept", integer=True),
    "convective_damping": Field("dimensionless", "fraction", default=0.005, help="sloshing damping"),
    "impulsive_damping": Field("dimensionless", "fraction", default=0.02, help="impulsive damping"),
    "flexible_impulsive_fraction": Field(
        "dimensionless", "nonnegative", default=1.0, help="share of m_i on the flexible-wall mode"
    ),
    "steel_modulus": Field("psi", default=STEEL_MODULUS, help="Young's modulus of the shell"),
    "impulsive_frequency": Field(
        "hertz", "nonnegative", default=0.0, help="flexible-wall mode frequency; 0 = EN 1998-4 estimate"
    ),
}

_VESSEL_ARGS = {
    "water_depth": "water_depth_in",
    "outer_diameter": "outer_diameter_in",
    "wall_thickness": "wall_thickness_in",
    "height": "height_in",
    "dry_weight": "dry_weight_lbf",
    "steel_modulus": "steel_modulus_psi",
    "impulsive_frequency": "impulsive_frequency_hz",
}

_RIGID_FIELDS = {"weight": Field("force_pound", help="weight of the rigid specimen")}


def _vessel(cfg: Mapping[str, Any], where: str) -> FluidVessel:
    values = parse_fields(VESSEL_FIELDS, cfg, where=where)
    kwargs = {_VESSEL_ARGS.get(k, k): v for k, v in values.items()}
    kwargs["n_convective_modes"] = int(kwargs["n_convective_modes"])  # a whole number (Field.integer)
    kwargs["impulsive_frequency_hz"] = kwargs["impulsive_frequency_hz"] or None
    return FluidVessel(**kwargs)


def _number_list(key: str, raw: Any, unit: str) -> np.ndarray:
    if not isinstance(raw, (list, tuple)) or not raw:
        raise ConfigError(key, f"a non-empty list of values in {unit}", raw)
    return np.array([quantity(key, v, unit, "positive") for v in raw])


def _shear_building(cfg: Mapping[str, Any], where: str) -> LinearMDOF:
    known = {"story_weights", "story_stiffness", "damping_ratio", "base_weight"}
    unknown = sorted(set(cfg) - known)
    if unknown:
        raise ConfigError(f"{where}{unknown[0]}", "one of the known keys " + ", ".join(sorted(known)))
    for key in ("story_weights", "story_stiffness"):
        if key not in cfg:
            raise ConfigError(f"{where}{key}", "a list of values (required)")
    weights = _number_list(f"{where}story_weights", cfg["story_weights"], "force_pound")
    for weight in weights:
        check_specimen_weight(f"{where}story_weights", float(weight))
    stiffness = _number_list(f"{where}story_stiffness", cfg["story_stiffness"], "force_pound / inch")
    zeta = quantity(f"{where}damping_ratio", cfg.get("damping_ratio", 0.02), "dimensionless", "fraction")
    base = quantity(f"{where}base_weight", cfg.get("base_weight", 0.0), "force_pound", "nonnegative")
    return LinearMDOF.shear_building(weights, stiffness, zeta, base)


def specimen_from_config(cfg: Mapping[str, Any], *, where: str = "specimen.") -> Specimen:
    """Build a specimen from a configuration table (see the module docstring).

    Parameters
    ----------
    cfg : mapping
        Raw values, numbers in the report's units or strings with units.
    where : str
        Prefix of the keys in error messages.

    Raises
    ------
    ConfigError
        An empty table (it is not the report's vessel), an unknown type or
        key, an invalid value, or a weight above the plausibility bound
        (:data:`impedance_mil.plausibility.SPECIMEN_BOUNDS`).
    """
    rest = {k: v for k, v in cfg.items() if k != "type"}
    if not cfg:
        raise ConfigError(
            f"{where}type", "a specimen (type vessel, rigid_mass or shear_building), not an empty table"
        )
    kind = cfg.get("type", "vessel")
    if kind == "vessel":
        return _vessel(rest, where)
    if kind == "rigid_mass":
        weight = parse_fields(_RIGID_FIELDS, rest, where=where)["weight"]
        return RigidMass(check_specimen_weight(f"{where}weight", weight))
    if kind == "shear_building":
        return _shear_building(rest, where)
    raise ConfigError(f"{where}type", "one of vessel, rigid_mass, shear_building", kind)


def specimen_from_dict(data: Mapping[str, Any]) -> Specimen:
    """Inverse of ``to_dict`` of :class:`RigidMass`, :class:`LinearMDOF` and :class:`FluidVessel`."""
    kind = data.get("type") if isinstance(data, Mapping) else None
    try:
        if kind == "RigidMass":
            return RigidMass(float(data["weight_lbf"]))
        if kind == "LinearMDOF":
            return LinearMDOF(
                data["mass"], data["stiffness"], data["damping"], data["influence"], float(data["base_mass"])
            )
        if kind == "FluidVessel":
            names = FluidVessel.__dataclass_fields__
            return FluidVessel(**{k: v for k, v in data.items() if k in names})
    except (KeyError, TypeError) as exc:
        raise ConfigError("specimen", f"a complete {kind} dictionary", str(exc)) from None
    raise ConfigError("specimen.type", "RigidMass, LinearMDOF or FluidVessel", kind)
