"""The ``[calibration]`` record of a calibrated lab file (written by ``imil lab calibrate``).

It says which claim of the reproduction suite the lab was calibrated on, so that the
reproduction page counts agreement on that claim as calibration, not as prediction
(issue 17, item 2).  The calibration itself is :mod:`impedance_mil.campaign.calibration`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..errors import ConfigError

_KEYS = ("claim", "parameter", "keys", "value", "reproduced", "protocol")


@dataclass(frozen=True)
class CalibrationRecord:
    """What a lab was calibrated on.

    Attributes
    ----------
    claim : str
        Id of the claim calibrated on.
    parameter : str
        The calibrated parameter, in words.
    keys : tuple of str
        The lab-file keys it set.
    value : str
        Its value with its unit.
    reproduced : bool
        Whether the calibrating observation was reproduced inside the sources' range.
    protocol : str
        The protocol file's name.
    """

    claim: str
    parameter: str
    keys: tuple[str, ...]
    value: str
    reproduced: bool
    protocol: str

    def to_dict(self) -> dict[str, Any]:
        return {
            "claim": self.claim,
            "parameter": self.parameter,
            "keys": list(self.keys),
            "value": self.value,
            "reproduced": self.reproduced,
            "protocol": self.protocol,
        }


def parse_calibration(section: Any, where: str) -> CalibrationRecord | None:
    """The ``[calibration]`` section (None without it); errors name the key."""
    if section is None:
        return None
    if not isinstance(section, Mapping):
        raise ConfigError(f"{where}calibration", "a TOML table", section)
    for key in _KEYS:
        if key not in section:
            raise ConfigError(f"{where}calibration.{key}", "present (the record `imil lab calibrate` writes)")
    if unknown := sorted(set(section) - set(_KEYS)):
        raise ConfigError(f"{where}calibration.{unknown[0]}", "one of " + ", ".join(_KEYS))
    keys = section["keys"]
    if not isinstance(keys, list) or not all(isinstance(k, str) for k in keys):
        raise ConfigError(f"{where}calibration.keys", "a list of lab-file keys", keys)
    if not isinstance(section["reproduced"], bool):
        raise ConfigError(f"{where}calibration.reproduced", "true or false", section["reproduced"])
    texts = {k: section[k] for k in ("claim", "parameter", "value", "protocol")}
    for key, value in texts.items():
        if not isinstance(value, str) or not value:
            raise ConfigError(f"{where}calibration.{key}", "a non-empty string", value)
    return CalibrationRecord(
        texts["claim"],
        texts["parameter"],
        tuple(keys),
        texts["value"],
        section["reproduced"],
        texts["protocol"],
    )
