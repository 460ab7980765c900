"""VS files (TOML with units), ``--set`` overrides, and the property listing.

A VS file names its ``kind`` and gives either design targets (Section 9.2)
or the model parameters, bare numbers in the report's units or strings with
units::

    kind = "LR"
    q_ratio = 0.15
    T_s = "1.5 s"
    u_y = "10 mm"
    c = 0.15            # lbf*s/in
    m_vs = "2000 lb"

or ``preset = "LR2"`` plus changed values.  A file is read as design
targets when it has a target-only key (SD: ``f``, ``zeta``; LR:
``q_ratio``, ``T_s``, ``u_y``; FP: ``T_s``); otherwise as model parameters
(``k_s``, ``c``, ...).  Keys, units and ranges: :data:`UNITS`, :data:`CHECKS`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..config import Field, parse_fields, quantity, read_toml
from ..errors import ConfigError
from ..units import G0, INTERNAL_UNITS
from . import presets
from .base import VirtualSystem
from .models import FrictionPendulum, LeadRubber, SpringDamper
from .targets import TARGETS

_MASS = INTERNAL_UNITS["mass"]

#: Internal unit of every key (pint expression) that a VS file, ``--set`` or the listing uses.
UNITS: dict[str, str] = {
    "m_vs": _MASS,
    "m_ps": _MASS,
    "w_ps": "force_pound",
    "W": "force_pound",
    "q_d": "force_pound",
    "f_y": "force_pound",
    "k_s": "force_pound / inch",
    "k_i": "force_pound / inch",
    "c": "force_pound * second / inch",
    "u_y": "inch",
    "R_eff": "inch",
    "f": "hertz",
    "f_vs": "hertz",
    "f_post_vs": "hertz",
    "T_s": "second",
    "a": "second / inch",
    "zeta": "dimensionless",
    "zeta_vs": "dimensionless",
    "alpha": "dimensionless",
    "q_ratio": "dimensionless",
    "mu_max": "dimensionless",
    "mu_min": "dimensionless",
    "n": "dimensionless",
}

#: Range check of each input key (see :data:`impedance_mil.config.CHECKS`); others are positive.
CHECKS: dict[str, str] = {
    "c": "nonnegative",
    "zeta": "nonnegative",
    "alpha": "fraction",
    "a": "nonnegative",
    "w_ps": "nonnegative",
}

#: Human-readable label of each key, for the listing.
LABELS: dict[str, str] = {
    "f": "Target frequency",
    "zeta": "Target damping ratio",
    "q_ratio": "Characteristic strength ratio",
    "T_s": "Post-elastic period",
    "m_vs": "Mass of the basemat",
    "m_ps": "Mass of the test article",
    "w_ps": "Weight of the test article",
    "k_s": "Post-elastic (horizontal) stiffness",
    "c": "Damping coefficient",
    "q_d": "Characteristic strength",
    "k_i": "Initial stiffness",
    "alpha": "Stiffness ratio",
    "u_y": "Yield displacement",
    "f_y": "Yield strength",
    "n": "Smoothing parameter",
    "mu_max": "Fast friction coefficient",
    "mu_min": "Slow friction coefficient",
    "a": "Rate parameter",
    "W": "Axial load",
    "R_eff": "Effective radius",
    "f_vs": "Frequency of the basemat alone",
    "zeta_vs": "Damping ratio of the basemat alone",
    "f_post_vs": "Post-elastic frequency of the basemat alone",
}

_MODELS = {"SD": SpringDamper, "LR": LeadRubber, "FP": FrictionPendulum}
_TARGET_ONLY = {"SD": {"f", "zeta"}, "LR": {"q_ratio", "T_s", "u_y"}, "FP": {"T_s"}}


@dataclass(frozen=True)
class VSSpec:
    """A virtual system with where it came from.

    Attributes
    ----------
    name : str
        Preset name or file stem.
    vs : VirtualSystem
        The system.
    targets : SDTargets, LRTargets, FPTargets or None
        Design targets it was built from (None for model parameters given directly).
    model_overrides : dict
        Model parameters set after building from the targets (internal units).
    """

    name: str
    vs: VirtualSystem
    targets: Any = None
    model_overrides: dict = dataclasses.field(default_factory=dict)


@dataclass(frozen=True)
class Property:
    """One line of the property listing: key (as in Tables 9.1-9.3), value, unit, label."""

    key: str
    value: float
    unit: str
    label: str


def _fields_of(cls) -> dict[str, Field]:
    out = {}
    for f in dataclasses.fields(cls):
        default = None if f.default is dataclasses.MISSING else f.default
        out[f.name] = Field(
            unit=UNITS[f.name],
            check=CHECKS.get(f.name, "positive"),
            default=default,
            help=LABELS.get(f.name, ""),
        )
    return out


def _convert(raw: Mapping[str, Any], known: set[str], kind: str, where: str) -> dict[str, float]:
    for key in raw:
        if key not in known:
            raise ConfigError(f"{where}{key}", f"a {kind} parameter or target: " + ", ".join(sorted(known)))
    return {k: quantity(f"{where}{k}", v, UNITS[k], CHECKS.get(k, "positive")) for k, v in raw.items()}


def spec_from_mapping(mapping: Mapping[str, Any], name: str = "file", where: str = "") -> VSSpec:
    """Build a :class:`VSSpec` from a parsed VS file (see the module docstring).

    Raises
    ------
    ConfigError
        Missing or unknown ``kind``, unknown key, missing required value, or
        a value of the wrong dimension or out of range (the key is named).
    """
    data = dict(mapping)
    preset = data.pop("preset", None)
    kind = data.pop("kind", None)
    if preset is not None:
        design = presets.targets(str(preset))
        if kind is not None and str(kind).upper() != design.kind:
            raise ConfigError(f"{where}kind", f"'{design.kind}' (the kind of preset {preset})", kind)
        return with_overrides(VSSpec(str(preset).upper(), design.build(), design), data, where)
    if not isinstance(kind, str) or kind.strip().upper() not in _MODELS:
        raise ConfigError(f"{where}kind", "one of 'SD', 'LR', 'FP'", kind)
    kind = kind.strip().upper()
    model, target_cls = _MODELS[kind], TARGETS[kind]
    if _TARGET_ONLY[kind] & set(data):
        target_fields = _fields_of(target_cls)
        extra = {k: v for k, v in data.items() if k not in target_fields}
        design = target_cls(
            **parse_fields(target_fields, {k: v for k, v in data.items() if k in target_fields}, where=where)
        )
        return with_overrides(VSSpec(name, design.build(), design), extra, where)
    return VSSpec(name, model(**parse_fields(_fields_of(model), data, where=where)))


def load(path: str | Path) -> VSSpec:
    """Read a VS file (TOML).

    Raises
    ------
    DataFileError
        Missing or unreadable file, invalid TOML.
    ConfigError
        Invalid content (see :func:`spec_from_mapping`).
    """
    p = Path(path)
    where = f"{p.name}: "
    try:
        return spec_from_mapping(read_toml(p), name=p.stem, where=where)
    except ConfigError as exc:
        if exc.key.startswith(where):
            raise
        raise ConfigError(where + exc.key, exc.expected, exc.got) from None


def resolve(preset_or_file: str, overrides: Mapping[str, Any] | None = None) -> VSSpec:
    """A preset name (``SD1`` .. ``FP3``) or a VS file, with ``--set`` overrides applied.

    Raises
    ------
    ConfigError
        Neither a preset nor an existing file, or a bad override.
    DataFileError
        An unreadable file.
    """
    text = str(preset_or_file)
    if text.strip().upper() in presets.names():
        design = presets.targets(text)
        spec = VSSpec(text.strip().upper(), design.build(), design)
    elif Path(text).exists():
        spec = load(text)
    else:
        raise ConfigError(
            "preset", "a preset (" + ", ".join(presets.names()) + ") or a VS file", preset_or_file
        )
    return with_overrides(spec, overrides or {})


def with_overrides(spec: VSSpec, overrides: Mapping[str, Any], where: str = "") -> VSSpec:
    """Apply overrides with units (strings or bare numbers in the report's unit).

    With design targets, :func:`presets.apply_overrides` decides what each key
    changes; without, only model parameters can be set.
    """
    if not overrides:
        return spec
    known = {f.name for f in dataclasses.fields(spec.vs)}
    if spec.targets is not None:
        known |= {f.name for f in dataclasses.fields(spec.targets)}
    values = _convert(overrides, known, spec.vs.kind, where)
    if spec.targets is not None:
        model_keys = {f.name for f in dataclasses.fields(spec.vs)}
        targets = dataclasses.replace(
            spec.targets, **{k: v for k, v in values.items() if k not in model_keys}
        )
        model = {**spec.model_overrides, **{k: v for k, v in values.items() if k in model_keys}}
        return VSSpec(spec.name, presets.apply_overrides(targets, model), targets, model)
    return VSSpec(spec.name, dataclasses.replace(spec.vs, **values))


def from_parameters(kind: Any, parameters: Any, where: str = "") -> VirtualSystem:
    """Rebuild a VS from its kind and parameters in internal units (as a design file stores them).

    ``parameters`` is :meth:`VirtualSystem.to_dict`: the model parameters and,
    optionally, ``kind`` and the derived values.  Derived values that disagree with
    the ones the parameters give (a hand edit of a derived value) are refused, so
    that what is rebuilt is exactly what the mapping describes.

    Raises
    ------
    ConfigError
        Unknown kind, a missing, non-numeric or unknown parameter, or a derived
        value that disagrees with the parameters (the key is named).
    """
    if not isinstance(kind, str) or kind.strip().upper() not in _MODELS:
        raise ConfigError(f"{where}kind", "one of " + ", ".join(f"'{k}'" for k in _MODELS), kind)
    if not isinstance(parameters, Mapping):
        raise ConfigError(f"{where}parameters", "a table of the VS parameters", parameters)
    model = _MODELS[kind.strip().upper()]
    names = [f.name for f in dataclasses.fields(model)]
    values: dict[str, float] = {}
    for key in names:
        value = parameters.get(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ConfigError(f"{where}parameters.{key}", "a number in internal units", value)
        values[key] = float(value)
    try:
        vs = model(**values)
    except ConfigError as exc:
        raise ConfigError(f"{where}parameters.{exc.key}", exc.expected, exc.got) from None
    derived = vs.derived()
    for key, value in parameters.items():
        if key in values or key == "kind":
            continue
        if key not in derived:
            raise ConfigError(f"{where}parameters.{key}", f"a {vs.kind} parameter: " + ", ".join(names))
        if (
            isinstance(value, bool)
            or not isinstance(value, (int, float))
            or not math.isclose(float(value), derived[key], rel_tol=1e-9, abs_tol=1e-300)
        ):
            raise ConfigError(
                f"{where}parameters.{key}",
                f"{derived[key]!r}, the value its parameters give (edit the parameters, not derived values)",
                value,
            )
    return vs


def describe(spec: VSSpec) -> list[Property]:
    """All properties of a VS: design targets, parameters and derived values, with units."""
    values: dict[str, float] = {}
    if spec.targets is not None:
        values.update({f.name: getattr(spec.targets, f.name) for f in dataclasses.fields(spec.targets)})
    values.update({k: v for k, v in spec.vs.to_dict().items() if k != "kind"})
    if "w_ps" in values:
        values["m_ps"] = values["w_ps"] / G0
    return [Property(k, float(v), UNITS.get(k, "dimensionless"), LABELS.get(k, k)) for k, v in values.items()]
