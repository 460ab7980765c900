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
(``k_s``, ``c``, ...).  Keys, units, ranges and labels come from each type's
definition (:mod:`impedance_mil.virtual.types`).

A user's own type (a Python file defining ``TYPE`` or ``DEFINITION``, see
:mod:`impedance_mil.virtual.registry`) is named by ``type_file`` (a path
relative to the VS file) instead of ``kind``, with its parameters or one of
its presets.  ``--vs my_type.py`` alone takes the file's only preset.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..config import Field, parse_fields, quantity, read_toml
from ..errors import ConfigError
from ..units import G0, INTERNAL_UNITS
from . import presets
from .base import VirtualSystem
from .definition import Parameter
from .registry import BUILTIN, get_type, load_type_file
from .system import DefinedVS
from .vstype import VSType


def _keys(vstype: VSType) -> dict[str, Parameter]:
    """Every key of a type: parameters, derived values and target fields (later ones do not replace)."""
    d = vstype.definition
    table: dict[str, Parameter] = {p.name: p for p in d.parameters}
    for x in d.derived:
        table.setdefault(x.name, Parameter(x.name, x.unit, x.label, "any"))
    for f in vstype.target_fields:
        table.setdefault(f.name, f)
    return table


def _merged(attr: str) -> dict[str, str]:
    out: dict[str, str] = {}
    for t in BUILTIN.values():
        for key, p in _keys(t).items():
            out.setdefault(key, getattr(p, attr))
    return out


#: Internal unit of every key of the built-in types (pint expression).
UNITS: dict[str, str] = {**_merged("unit"), "m_ps": INTERNAL_UNITS["mass"]}
#: Human-readable label of every key of the built-in types.
LABELS: dict[str, str] = {**_merged("label"), "m_ps": "Mass of the test article"}


@dataclass(frozen=True)
class VSSpec:
    """A virtual system with where it came from.

    Attributes
    ----------
    name : str
        Preset name or file stem.
    vs : VirtualSystem
        The system.
    targets : object or None
        Design targets it was built from (None for model parameters given directly).
    model_overrides : dict
        Model parameters set after building from the targets (internal units).
    vstype : VSType or None
        The VS's type (None for a VS written in Python).
    notes : tuple of str
        What a run should say about the VS (:func:`fitted_to_article`: targets
        that assume another article than the one carried).
    """

    name: str
    vs: VirtualSystem
    targets: Any = None
    model_overrides: dict = dataclasses.field(default_factory=dict)
    vstype: VSType | None = None
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class Property:
    """One line of the property listing: key (as in Tables 9.1-9.3), value, unit, label."""

    key: str
    value: float
    unit: str
    label: str


def _fields(params: tuple[Parameter, ...]) -> dict[str, Field]:
    return {p.name: Field(unit=p.unit, check=p.check, default=p.default, help=p.label) for p in params}


def _convert(
    raw: Mapping[str, Any], table: Mapping[str, Parameter], kind: str, where: str
) -> dict[str, float]:
    for key in raw:
        if key not in table:
            raise ConfigError(f"{where}{key}", f"a {kind} parameter or target: " + ", ".join(sorted(table)))
    return {k: quantity(f"{where}{k}", v, table[k].unit, table[k].check) for k, v in raw.items()}


def spec_from_mapping(
    mapping: Mapping[str, Any], name: str = "file", where: str = "", folder: Path | None = None
) -> VSSpec:
    """Build a :class:`VSSpec` from a parsed VS file (see the module docstring).

    ``folder`` is where a ``type_file`` is looked up (the VS file's folder).

    Raises
    ------
    ConfigError
        Missing or unknown ``kind``, unknown key, missing required value, or
        a value of the wrong dimension or out of range (the key is named).
    """
    data = dict(mapping)
    preset = data.pop("preset", None)
    kind = data.pop("kind", None)
    type_file = data.pop("type_file", None)
    if type_file is not None:
        if kind is not None:
            raise ConfigError(f"{where}kind", "either kind (a built-in type) or type_file, not both", kind)
        vstype = load_type_file((folder or Path(".")) / str(type_file))
        if preset is not None:
            return with_overrides(_preset_spec(vstype, str(preset), where), data, where)
        return _parameters_spec(vstype, name, data, where)
    if preset is not None:
        design = presets.targets(str(preset))
        vstype = presets.vs_type(str(preset))
        if kind is not None and str(kind).strip().upper() != vstype.kind:
            raise ConfigError(f"{where}kind", f"'{vstype.kind}' (the kind of preset {preset})", kind)
        return with_overrides(_preset_spec(vstype, str(preset).strip().upper(), where), data, where)
    if not isinstance(kind, str):
        raise ConfigError(
            f"{where}kind", "one of " + ", ".join(f"'{k}'" for k in BUILTIN) + " (or type_file)", kind
        )
    try:
        vstype = get_type(kind)
    except ConfigError as exc:
        raise ConfigError(f"{where}kind", exc.expected, kind) from None
    if vstype.targets is not None and vstype.target_only & set(data):
        target_fields = _fields(vstype.target_fields)
        extra = {k: v for k, v in data.items() if k not in target_fields}
        design = vstype.targets(
            **parse_fields(target_fields, {k: v for k, v in data.items() if k in target_fields}, where=where)
        )
        return with_overrides(VSSpec(name, design.build(), design, vstype=vstype), extra, where)
    return _parameters_spec(vstype, name, data, where)


def _parameters_spec(vstype: VSType, name: str, data: Mapping[str, Any], where: str) -> VSSpec:
    values = parse_fields(_fields(vstype.definition.parameters), data, where=where)
    return VSSpec(name, DefinedVS(vstype.definition, values, where), vstype=vstype)


def _preset_spec(vstype: VSType, preset: str, where: str) -> VSSpec:
    if preset not in vstype.presets:
        raise ConfigError(
            f"{where}preset", f"a preset of {vstype.kind}: " + ", ".join(vstype.presets), preset
        )
    design = vstype.presets[preset]
    targets = None if isinstance(design, Mapping) else design
    return VSSpec(preset, vstype.build_preset(preset), targets, vstype=vstype)


def load(path: str | Path) -> VSSpec:
    """Read a VS file (TOML), or a user's type file (``.py``) with exactly one preset.

    Raises
    ------
    DataFileError
        Missing or unreadable file, invalid TOML.
    ConfigError
        Invalid content (see :func:`spec_from_mapping`).
    """
    p = Path(path)
    where = f"{p.name}: "
    if p.suffix == ".py":
        vstype = load_type_file(p)
        if len(vstype.presets) != 1:
            raise ConfigError(
                f"{where}presets",
                "exactly one preset to run the type file alone (or a VS TOML "
                "file with type_file and its parameters)",
                len(vstype.presets),
            )
        return _preset_spec(vstype, next(iter(vstype.presets)), where)
    try:
        return spec_from_mapping(read_toml(p), name=p.stem, where=where, folder=p.parent)
    except ConfigError as exc:
        if exc.key.startswith(where):
            raise
        raise ConfigError(where + exc.key, exc.expected, exc.got) from None


def resolve(
    preset_or_file: str, overrides: Mapping[str, Any] | None = None, article_weight_lbf: float | None = None
) -> VSSpec:
    """A preset name (``SD1`` .. ``FP3`` ...) or a VS file, with ``--set`` overrides applied.

    With ``article_weight_lbf`` [lbf] (the specimen the run carries), a preset
    is :func:`fitted_to_article`; a VS file keeps the values it states.

    Raises
    ------
    ConfigError
        Neither a preset nor an existing file, or a bad override.
    DataFileError
        An unreadable file.
    """
    text = str(preset_or_file)
    if text.strip().upper() in presets.names():
        spec = with_overrides(_preset_spec(presets.vs_type(text), text.strip().upper(), ""), overrides or {})
        if article_weight_lbf is None:
            return spec
        return fitted_to_article(spec, article_weight_lbf, set(overrides or {}))
    if Path(text).exists():
        spec = load(text)
    else:
        raise ConfigError(
            "preset", "a preset (" + ", ".join(presets.names()) + ") or a VS file", preset_or_file
        )
    return with_overrides(spec, overrides or {})


def fitted_to_article(spec: VSSpec, weight_lbf: float, chosen: Collection[str] = ()) -> VSSpec:
    """``spec`` carrying the article actually used: its axial load follows ``weight_lbf`` [lbf].

    A type whose ``article_weight`` parameter sets the axial load (FP, TFP:
    ``W = m_vs g + w_ps``, hence the friction force) gets ``weight_lbf`` there
    unless the user chose that parameter (``chosen``: the keys set).  The
    design targets (Tables 9.1-9.3: SD/LR frequency and damping, FP ``T_s``
    through ``k_s``) stay as designed; where they assume an article
    (``w_ps`` of the targets) other than ``weight_lbf``, a note says so
    (:attr:`VSSpec.notes`).

    Parameters
    ----------
    spec : VSSpec
        A preset with its overrides.
    weight_lbf : float
        Weight of the specimen the run carries [lbf] (0: the bare table).
    chosen : collection of str
        Keys the user set (``--set-vs``); they are kept.
    """
    vs = spec.vs
    if not isinstance(vs, DefinedVS):
        return spec
    key = vs.definition.article_weight
    axial = ""
    if key is not None and key not in chosen:
        axial = f"; its axial load ({key}) is the specimen's"
        if spec.targets is not None:
            model = {**spec.model_overrides, key: float(weight_lbf)}
            built = presets.apply_overrides(spec.targets, model)
            spec = dataclasses.replace(spec, vs=built, model_overrides=model)
        else:
            spec = dataclasses.replace(spec, vs=vs.replace(**{key: float(weight_lbf)}))
    designed = getattr(spec.targets, "w_ps", None)
    if designed is None or "w_ps" in chosen or math.isclose(designed, weight_lbf, rel_tol=1e-9):
        return spec
    note = (
        f"{spec.name}'s targets assume the report's article of {designed:g} lbf (Tables 9.1-9.3), "
        f"the specimen weighs {weight_lbf:.0f} lbf{axial}"
    )
    return dataclasses.replace(spec, notes=(*spec.notes, note))


def with_overrides(spec: VSSpec, overrides: Mapping[str, Any], where: str = "") -> VSSpec:
    """Apply overrides with units (strings or bare numbers in the report's unit).

    With design targets, :func:`presets.apply_overrides` decides what each key
    changes; without, only model parameters can be set.
    """
    if not overrides:
        return spec
    vs = spec.vs
    if not isinstance(vs, DefinedVS):
        raise ConfigError(
            f"{where}--set", f"a VS of a defined type ({type(vs).__name__} is written in Python)"
        )
    table = {p.name: p for p in vs.definition.parameters}
    if spec.targets is not None and spec.vstype is not None:
        table.update({f.name: f for f in spec.vstype.target_fields if f.name not in table})
    values = _convert(overrides, table, vs.kind, where)
    model_keys = set(vs.definition.parameter_names)
    if spec.targets is not None:
        targets = dataclasses.replace(
            spec.targets, **{k: v for k, v in values.items() if k not in model_keys}
        )
        model = {**spec.model_overrides, **{k: v for k, v in values.items() if k in model_keys}}
        return VSSpec(spec.name, presets.apply_overrides(targets, model), targets, model, spec.vstype)
    return VSSpec(spec.name, vs.replace(**values), vstype=spec.vstype)


def from_parameters(kind: Any, parameters: Any, where: str = "", vstype: VSType | None = None) -> DefinedVS:
    """Rebuild a VS from its kind and parameters in internal units (as a design file stores them).

    ``parameters`` is :meth:`VirtualSystem.to_dict`: the model parameters and,
    optionally, ``kind`` and the derived values.  Derived values that disagree with
    the ones the parameters give (a hand edit of a derived value) are refused, so
    that what is rebuilt is exactly what the mapping describes.  ``vstype`` gives
    the type when it is not a built-in one.

    Raises
    ------
    ConfigError
        Unknown kind, a missing, non-numeric or unknown parameter, or a derived
        value that disagrees with the parameters (the key is named).
    """
    if vstype is None:
        if not isinstance(kind, str) or kind.strip().upper() not in BUILTIN:
            raise ConfigError(f"{where}kind", "one of " + ", ".join(f"'{k}'" for k in BUILTIN), kind)
        vstype = BUILTIN[kind.strip().upper()]
    if not isinstance(parameters, Mapping):
        raise ConfigError(f"{where}parameters", "a table of the VS parameters", parameters)
    d = vstype.definition
    values: dict[str, float] = {}
    for key in d.parameter_names:
        value = parameters.get(key)
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(f"{where}parameters.{key}", "a number in internal units", value)
        values[key] = float(value)
    vs = DefinedVS(d, values, where=f"{where}parameters.")
    derived = vs.derived()
    for key, value in parameters.items():
        if key in values or key == "kind":
            continue
        if key not in derived:
            raise ConfigError(
                f"{where}parameters.{key}", f"a {vs.kind} parameter: " + ", ".join(d.parameter_names)
            )
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
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
    table = _keys(spec.vstype) if spec.vstype is not None else {}
    units = {k: p.unit for k, p in table.items()} | {"m_ps": INTERNAL_UNITS["mass"]}
    labels = {k: p.label for k, p in table.items()} | {"m_ps": "Mass of the test article"}
    return [
        Property(k, float(v), units.get(k, UNITS.get(k, "dimensionless")), labels.get(k, LABELS.get(k, k)))
        for k, v in values.items()
    ]
