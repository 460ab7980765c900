"""The nine isolation systems of the report's MIL experiments (Tables 9.1-9.3).

>>> from impedance_mil.virtual import presets
>>> presets.names()
('SD1', 'SD2', 'SD3', 'LR1', 'LR2', 'LR3', 'FP1', 'FP2', 'FP3')
>>> round(presets.get("SD2").k_s)
895

Overrides (``presets.get("SD2", m_vs=...)``), in internal units, apply to
the built system when the key is one of its parameters (so ``m_vs`` keeps
the table's stiffness, as in the basemat-mass study of Section 9.4.4), and
to the design targets otherwise (``f``, ``zeta``, ``q_ratio``, ``T_s``, LR's
``u_y``, SD/LR ``w_ps``), which are then rebuilt.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from ..errors import ConfigError
from .base import VirtualSystem
from .targets import FPTargets, LRTargets, SDTargets

Targets = SDTargets | LRTargets | FPTargets

# Table 9.1: [f (Hz), zeta]; Table 9.2: [q_ratio, T_s, c]; Table 9.3: [mu_max, mu_min, T_s].
_PRESETS: dict[str, Targets] = {
    "SD1": SDTargets(f=0.75, zeta=0.30),
    "SD2": SDTargets(f=1.25, zeta=0.25),
    "SD3": SDTargets(f=1.75, zeta=0.20),
    "LR1": LRTargets(q_ratio=0.09, T_s=2.0, u_y=0.4, c=0.11, n=2.0),
    "LR2": LRTargets(q_ratio=0.15, T_s=1.5, u_y=0.4, c=0.15, n=2.0),
    "LR3": LRTargets(q_ratio=0.21, T_s=1.0, u_y=0.4, c=0.22, n=2.0),
    "FP1": FPTargets(mu_max=0.06, mu_min=0.03, T_s=2.25, a=2.54),
    "FP2": FPTargets(mu_max=0.12, mu_min=0.06, T_s=1.75, a=2.54),
    "FP3": FPTargets(mu_max=0.18, mu_min=0.09, T_s=1.25, a=2.54),
}


def names() -> tuple[str, ...]:
    """Names of the presets, in the report's order."""
    return tuple(_PRESETS)


def targets(name: str) -> Targets:
    """Design targets of a preset (Section 9.2).

    Raises
    ------
    ConfigError
        Unknown preset name.
    """
    key = name.strip().upper() if isinstance(name, str) else name
    if key not in _PRESETS:
        raise ConfigError("preset", "one of " + ", ".join(_PRESETS), name)
    return _PRESETS[key]


def apply_overrides(design: Targets, overrides: dict[str, Any]) -> VirtualSystem:
    """Build ``design`` with overrides (internal units), see the module docstring.

    Raises
    ------
    ConfigError
        A key that is neither a parameter of the system nor a design target,
        or an invalid value.
    """
    target_keys = {f.name for f in dataclasses.fields(design)}
    model_keys = {f.name for f in dataclasses.fields(design.build())}
    for key in overrides:
        if key not in target_keys | model_keys:
            raise ConfigError(
                key, f"a {design.kind} parameter or target: " + ", ".join(sorted(target_keys | model_keys))
            )
    for_targets = {k: float(v) for k, v in overrides.items() if k not in model_keys}
    for_model = {k: float(v) for k, v in overrides.items() if k in model_keys}
    vs = dataclasses.replace(design, **for_targets).build()
    return dataclasses.replace(vs, **for_model) if for_model else vs


def get(name: str, **overrides: float) -> VirtualSystem:
    """The virtual system of a preset, optionally with parameters changed.

    Parameters
    ----------
    name : str
        ``SD1`` .. ``SD3``, ``LR1`` .. ``LR3``, ``FP1`` .. ``FP3`` (case-insensitive).
    **overrides : float
        Values in internal units (see the module docstring).

    Raises
    ------
    ConfigError
        Unknown preset or key, or an invalid value.
    """
    return apply_overrides(targets(name), overrides)
