"""Named virtual systems: the report's nine (Tables 9.1-9.3) and the presets of every other type.

>>> from impedance_mil.virtual import presets
>>> presets.names()[:9]
('SD1', 'SD2', 'SD3', 'LR1', 'LR2', 'LR3', 'FP1', 'FP2', 'FP3')
>>> round(presets.get("SD2").k_s)
895

Each type module of :mod:`impedance_mil.virtual.types` lists its presets
(with their sources).  Overrides (``presets.get("SD2", m_vs=...)``), in
internal units, apply to the built system when the key is one of its
parameters (so ``m_vs`` keeps the table's stiffness, as in the basemat-mass
study of Section 9.4.4), and to the design targets otherwise (``f``, ``zeta``,
``q_ratio``, ``T_s``, LR's ``u_y``, SD/LR ``w_ps``), which are then rebuilt.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from ..errors import ConfigError
from .registry import BUILTIN
from .system import DefinedVS
from .vstype import VSType


def _index() -> dict[str, tuple[VSType, Any]]:
    return {name: (t, preset) for t in BUILTIN.values() for name, preset in t.presets.items()}


_PRESETS = _index()


def names() -> tuple[str, ...]:
    """Names of the presets, type by type in listing order (the report's nine first)."""
    return tuple(_PRESETS)


def vs_type(name: str) -> VSType:
    """The type of a preset."""
    return _PRESETS[_key(name)][0]


def _key(name: str) -> str:
    key = name.strip().upper() if isinstance(name, str) else name
    if key not in _PRESETS:
        raise ConfigError("preset", "one of " + ", ".join(_PRESETS), name)
    return key


def targets(name: str) -> Any:
    """Design targets of a preset (Section 9.2), or its parameter mapping for a type without targets.

    Raises
    ------
    ConfigError
        Unknown preset name.
    """
    return _PRESETS[_key(name)][1]


def apply_overrides(design: Any, overrides: Mapping[str, Any], vstype: VSType | None = None) -> DefinedVS:
    """Build ``design`` (targets or a parameter mapping) with overrides (internal units).

    See the module docstring.

    Raises
    ------
    ConfigError
        A key that is neither a parameter of the system nor a design target,
        or an invalid value.
    """
    if isinstance(design, Mapping):
        if vstype is None:
            raise ConfigError("preset", "the type of a preset given as parameter values")
        return DefinedVS(vstype.definition, {**design, **{k: float(v) for k, v in overrides.items()}})
    target_keys = {f.name for f in dataclasses.fields(design)}
    model_keys = set(design.build().definition.parameter_names)
    for key in overrides:
        if key not in target_keys | model_keys:
            raise ConfigError(
                key, f"a {design.kind} parameter or target: " + ", ".join(sorted(target_keys | model_keys))
            )
    for_targets = {k: float(v) for k, v in overrides.items() if k not in model_keys}
    for_model = {k: float(v) for k, v in overrides.items() if k in model_keys}
    vs = dataclasses.replace(design, **for_targets).build()
    return vs.replace(**for_model) if for_model else vs


def listing(name: str) -> dict[str, Any]:
    """One row of the preset listing: name, kind, the design targets (or the parameters of a
    type without targets, in internal units) and the post-elastic stiffness ``k_s`` where the
    type has one."""
    vstype, design = _PRESETS[_key(name)]
    vs = vstype.build_preset(_key(name))
    values = dict(design) if isinstance(design, Mapping) else dataclasses.asdict(design)
    return {"name": _key(name), "kind": vs.kind, **values, "k_s": vs.to_dict().get("k_s")}


def get(name: str, **overrides: float) -> DefinedVS:
    """The virtual system of a preset, optionally with parameters changed.

    Parameters
    ----------
    name : str
        A preset name (case-insensitive): ``SD1`` .. ``FP3`` and those of :func:`names`.
    **overrides : float
        Values in internal units (see the module docstring).

    Raises
    ------
    ConfigError
        Unknown preset or key, or an invalid value.
    """
    vstype, design = _PRESETS[_key(name)]
    return apply_overrides(design, overrides, vstype)
