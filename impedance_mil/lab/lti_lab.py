"""The lab of a table given as a linear model: interlocks and sensor ranges from its stated capacity.

A physical table implies its capacity (mid-stroke, no-load velocity, stall
force, moving mass), and a lab file's generic defaults are sized from it
(:data:`~impedance_mil.lab.labfile.GENERIC_DEFAULTS`).  A transfer-function,
zpk or state-space table states only what its ``[capacity]`` section says
(:mod:`impedance_mil.plant.capacity`).  So, for such a table:

* the stroke and velocity interlocks are the lab's ``[limits]``, else the
  table's stated ``stroke`` and ``velocity``, else the lab refuses, naming
  ``limits.stroke`` (``limits.velocity``): nothing is assumed;
* the actuator-force interlock defaults to 95 % of the stated stall force, as
  for a physical table (:func:`~impedance_mil.lab.lti_plant.lti_limits`), and
  the valve interlocks do not apply (no valve in the model);
* the generic sensors (no ``[sensors]`` section) are sized as for a physical
  table from the stated stroke, stall force, moving mass and piston area, and
  the lab refuses, naming ``sensors``, what it cannot size.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from ..config import Field, parse_fields
from ..errors import ConfigError
from ..plant.lti_table import LTITable
from .setup import SafetyLimits

#: How a lab of an LTI table fills the keys its file leaves out (docs/your-lab.md).
LTI_DEFAULTS = {
    "limits.stroke": "the table's capacity.stroke (else refused)",
    "limits.velocity": "the table's capacity.velocity (else refused)",
    "limits.divergence": "the larger of 20 in and 4 strokes",
    "limits.actuator_force": "95 % of the table's capacity.force (none without a dP output and piston_area)",
    "limits.(valve)": "none: an LTI table has no valve",
    "sensors": "one channel per quantity sized from the table's [capacity] (else refused)",
    "controller.dac_range": "the analog-input range (no valve command)",
}

#: ``[limits]`` keys an LTI table's lab can enforce (the valve's cannot be: no valve).
LTI_LIMIT_KEYS = (
    "stroke",
    "velocity",
    "acceleration",
    "actuator_force",
    "pressure",
    "divergence",
    "interlock_window",
)


def lti_lab_limits(
    section: Mapping[str, Any], table: LTITable, where: str, sources: dict, fields: Mapping[str, Field]
) -> SafetyLimits:
    """The interlocks of a lab of ``table`` (module docstring); ``fields`` are the lab file's limit keys.

    Raises
    ------
    ConfigError
        A valve limit (the model has no valve), a stroke or velocity neither
        given nor stated by the table, or a non-positive value; named
        ``{where}limits.KEY``.
    """
    valve = sorted(set(section) - set(LTI_LIMIT_KEYS))
    known = [k for k in valve if k in fields]
    if known:
        raise ConfigError(
            f"{where}limits.{known[0]}", "no valve limit for an LTI table (its model has no valve)"
        )
    given = {k: v for k, v in parse_fields(fields, section, where=f"{where}limits.").items() if k in section}
    for key in fields:
        if key not in LTI_LIMIT_KEYS:
            sources[f"limits.{key}"] = "none (no valve)"
        else:
            sources[f"limits.{key}"] = "file" if key in given else "default"
    for key, value in given.items():
        if not value > 0:
            raise ConfigError(f"{where}limits.{key}", "a positive value", value)
    capacity = table.capacity
    stated = {"stroke": capacity.stroke, "velocity": capacity.velocity}
    for key, value in stated.items():
        if key not in given and value is None:
            raise ConfigError(
                f"{where}limits.{key}",
                f"the {key} interlock: the LTI table states no capacity.{key} to default to",
            )
        if key not in given:
            sources[f"limits.{key}"] = "table"
    stroke = given.pop("stroke", capacity.stroke)
    if capacity.stroke is not None and stroke > capacity.stroke:
        raise ConfigError(
            f"{where}limits.stroke",
            f"at most the table's capacity.stroke ({capacity.stroke:g} in)",
            f"{stroke:g} in",
        )
    velocity = given.pop("velocity", capacity.velocity)
    divergence = given.pop("divergence", max(20.0, 4.0 * stroke))
    if divergence <= stroke:
        raise ConfigError(f"{where}limits.divergence", f"more than the stroke ({stroke:g} in)", divergence)
    try:
        return SafetyLimits(stroke=stroke, velocity=velocity, divergence=divergence, **given)
    except ConfigError as exc:
        raise ConfigError(f"{where}{exc.key}", exc.expected, exc.got) from None


def lti_sensor_ranges(table: LTITable, where: str) -> dict[str, float]:
    """Full scale of each generic channel of ``table`` (internal units), sized as for a physical table.

    Displacement 1.25 strokes; acceleration twice the stall force over the
    moving mass; load cell twice the stall force; dP 1.25 times the stall
    force over the piston area, only for a model with a ``dp`` output.

    Raises
    ------
    ConfigError
        ``{where}sensors``: the table's ``[capacity]`` lacks stroke, force or mass.
    """
    c = table.capacity
    missing = [k for k in ("stroke", "force", "mass") if getattr(c, k) is None]
    if missing:
        raise ConfigError(
            f"{where}sensors",
            "a [sensors] section: the LTI table's [capacity] states no "
            + ", ".join(missing)
            + " to size generic channels from",
        )
    stroke, force, mass = float(c.stroke), float(c.force), float(c.mass)  # type: ignore[arg-type]
    ranges = {
        "acceleration": 2.0 * force / mass,
        "displacement": 1.25 * stroke,
        "load_cell": 2.0 * force,
    }
    if "dp" in table.outputs and c.piston_area is not None:
        ranges["differential_pressure"] = 1.25 * force / c.piston_area
    if not all(math.isfinite(v) and v > 0 for v in ranges.values()):
        raise ConfigError(f"{where}sensors", "positive finite channel ranges", ranges)
    return ranges


__all__ = ["LTI_DEFAULTS", "LTI_LIMIT_KEYS", "lti_lab_limits", "lti_sensor_ranges"]
