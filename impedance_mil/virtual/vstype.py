"""A VS type: its definition, design targets and presets (:class:`VSType`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from .definition import Parameter, VSDefinition
from .system import DefinedVS


@dataclass(frozen=True)
class VSType:
    """A VS type: its definition, design targets and presets.

    Attributes
    ----------
    definition : VSDefinition
    targets : type or None
        Frozen dataclass of design targets with ``build() -> DefinedVS`` and ``kind``.
    target_fields : tuple of Parameter
        Unit, label and check of every target field (for files and listings).
    target_only : frozenset of str
        Keys that only the targets have: a VS file with one of them is read as targets.
    presets : Mapping[str, Any]
        Preset name -> targets object (or a mapping of parameter values).
    """

    definition: VSDefinition
    targets: type | None = None
    target_fields: tuple[Parameter, ...] = ()
    target_only: frozenset[str] = frozenset()
    presets: Mapping[str, Any] = field(default_factory=dict)

    @property
    def kind(self) -> str:
        """The type's short name."""
        return self.definition.kind

    def __call__(self, **values: float) -> DefinedVS:
        """A system of this type from parameter values (internal units)."""
        return DefinedVS(self.definition, values)

    def build_preset(self, name: str) -> DefinedVS:
        """The system of the preset ``name``."""
        preset = self.presets[name]
        if isinstance(preset, Mapping):
            return DefinedVS(self.definition, preset, where=f"preset {name}: ")
        return preset.build()
