"""Campaign parameters: what a campaign file may vary, with units and checks.

A campaign *kind* (see :mod:`impedance_mil.campaign.kinds`) declares the
parameters it accepts as a mapping ``{name: Param(...)}``.  Each parameter
says where its value goes in the run configuration (a dotted path) and how a
raw TOML value is validated: a physical quantity in the report's unit
(converted with :func:`impedance_mil.config.quantity`, so ``"30 in"`` and
``"0.76 m"`` both work and ``"30 lb"`` is refused), one of a fixed set of
names (e.g. the VS presets ``SD1 ... FP3``), free text (a file path), an
integer or a boolean.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ..config import quantity
from ..errors import ConfigError

#: The value types a parameter may have.
PARAM_TYPES = ("quantity", "choice", "text", "integer", "boolean")


@dataclass(frozen=True)
class Param:
    """One parameter a campaign may set or vary.

    Parameters
    ----------
    path : str
        Dotted path of the value in the run configuration, e.g. ``"table.K_p"``.
    type : str
        One of :data:`PARAM_TYPES`.
    unit : str
        For ``"quantity"``: the internal unit as a pint expression (the
        report's unit of the key, e.g. ``"volt / psi"`` for K_p).
    check : str
        For ``"quantity"``: range check passed to :func:`impedance_mil.config.quantity`.
    choices : tuple of str
        For ``"choice"``: the allowed names.
    aliases : mapping of str to str
        For ``"choice"``: older spellings still read, each as the name it stands for.
    help : str
        One-line description (shown by ``imil campaign params KIND``).
    """

    path: str
    type: str = "quantity"
    unit: str = "dimensionless"
    check: str = "any"
    choices: tuple[str, ...] = ()
    aliases: Mapping[str, str] = field(default_factory=dict, hash=False)
    help: str = ""

    def convert(self, key: str, raw: Any) -> Any:
        """Validate one raw value and return it in the internal unit.

        Parameters
        ----------
        key : str
            Where the value came from, for error messages (e.g. ``"study.fc.product.f_c"``).
        raw : object
            The TOML value.

        Raises
        ------
        ConfigError
            The value has the wrong type, dimension or range, or is not one of the choices.
        """
        if self.type == "quantity":
            return quantity(key, raw, self.unit, self.check)
        if self.type == "choice":
            raw = self.aliases.get(raw, raw) if isinstance(raw, str) else raw
            if not isinstance(raw, str) or raw not in self.choices:
                raise ConfigError(key, "one of " + ", ".join(self.choices), raw)
            return raw
        if self.type == "text":
            if not isinstance(raw, str) or not raw.strip():
                raise ConfigError(key, "a non-empty string", raw)
            return raw
        if self.type == "integer":
            if isinstance(raw, bool) or not isinstance(raw, int):
                raise ConfigError(key, "an integer", raw)
            if self.check == "positive" and raw <= 0:
                raise ConfigError(key, "a positive integer", raw)
            if self.check == "nonnegative" and raw < 0:
                raise ConfigError(key, "a non-negative integer", raw)
            return raw
        if self.type == "boolean":
            if not isinstance(raw, bool):
                raise ConfigError(key, "true or false", raw)
            return raw
        raise ConfigError(key, "a parameter type among " + ", ".join(PARAM_TYPES), self.type)

    def describe(self) -> str:
        """Short description of the accepted values, for listings."""
        if self.type == "quantity":
            return f"quantity in {self.unit}"
        if self.type == "choice":
            return "one of " + ", ".join(self.choices)
        return self.type


def convert_settings(
    params: Mapping[str, Param], settings: Mapping[str, Any], *, where: str
) -> dict[str, Any]:
    """Validate a mapping ``{parameter name: raw value}``.

    Parameters
    ----------
    params : mapping of str to Param
        The parameters the campaign kind accepts.
    settings : mapping
        Raw values from the campaign file.
    where : str
        Prefix for error messages, e.g. ``"base."``.

    Returns
    -------
    dict
        The converted values, same keys.

    Raises
    ------
    ConfigError
        An unknown parameter name or an invalid value.
    """
    out: dict[str, Any] = {}
    for name, raw in settings.items():
        spec = params.get(name)
        if spec is None:
            raise ConfigError(f"{where}{name}", "a known parameter (" + ", ".join(sorted(params)) + ")")
        out[name] = spec.convert(f"{where}{name}", raw)
    return out


def set_path(config: dict[str, Any], path: str, value: Any) -> None:
    """Set ``config[a][b][c] = value`` for ``path = "a.b.c"``, creating tables as needed.

    Raises
    ------
    ConfigError
        An intermediate key holds a value that is not a table.
    """
    parts = path.split(".")
    node = config
    for part in parts[:-1]:
        child = node.setdefault(part, {})
        if not isinstance(child, dict):
            raise ConfigError(path, f"'{part}' to be a table in the base configuration", child)
        node = child
    node[parts[-1]] = value


def deep_merge(base: Mapping[str, Any], update: Mapping[str, Any]) -> dict[str, Any]:
    """Return a copy of ``base`` with ``update`` merged in, table by table."""
    out: dict[str, Any] = {}
    for key, value in base.items():
        out[key] = deep_merge(value, {}) if isinstance(value, Mapping) else value
    for key, value in update.items():
        if isinstance(value, Mapping) and isinstance(out.get(key), dict):
            out[key] = deep_merge(out[key], value)
        elif isinstance(value, Mapping):
            out[key] = deep_merge(value, {})
        else:
            out[key] = value
    return out
