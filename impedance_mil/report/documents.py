"""JSON documents in the user's units, with a ``units`` block naming the unit of every number.

Every JSON document a command prints or writes for a person (a run's summary,
a design, a lab's setup ...) is built in internal units
(:mod:`impedance_mil.units`).  :func:`express` converts it at the edge into the
chosen :class:`~impedance_mil.display.UnitSystem` and adds

* ``unit_system``: ``"us"`` or ``"si"``;
* ``units``: the unit of every numeric field, by its path (``pretest.input.checks[0].peak``;
  a list of numbers has one entry), ``"1"`` for pure numbers and counts.

The unit of a field is found, in this order, from

0. the document's own ``units`` block, if it has one (internal units by path: a
   command that knows its fields' units says so, e.g. ``imil vs describe``);
1. its path in :data:`PATH_UNITS` (``trip.value`` has the unit the record names);
2. the unit suffix of its key (``peak_table_disp_in``, ``time_s``, ``fc_hz``,
   ``max_pga_g``): in SI the suffix follows the unit, ``peak_table_disp_mm``;
3. :data:`DIMENSIONLESS` (``ratio``, ``nrms_error`` ...);
4. a ``unit`` string beside it in the same object (the pre-test checks, the
   sensor channels, a trip), which is converted along with it, or the unit
   suffix of the object's own key (``comparison.peak_table_disp_in.measured``);
5. the package's key registries (:func:`key_units`: table file keys, VS
   parameters, lab-file keys).  The VS types' registry is read only for a key the
   others do not name (building it imports every VS type; a lab's or a table's
   document does not need it: issue 16, start-up); the registries name disjoint keys
   (tests/report/test_documents.py), so the order does not change a unit.

A number none of these names is listed as ``"unknown"``;
``tests/report/test_documents.py`` runs every command's JSON and requires none.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from functools import cache
from typing import Any

from ..display import UnitSystem, display_unit, key_suffix, short_name
from ..fileio import json_safe
from ..lab.lab_units import LAB_OBJECTS, LAB_UNITS
from ..lazy import LazyModule

#: The table file's keys (``plant.parameters.FIELDS``, ``ALTERNATIVES``), imported when a key of a
#: document is first looked up in the registries (listing the VS presets needs none).
table_keys = LazyModule("impedance_mil.plant.parameters")
#: The VS types' key registry (``virtual.files.UNITS``), imported when a key of a document is
#: in no other registry (see the module).
vs_files = LazyModule("impedance_mil.virtual.files")

#: The unit name of pure numbers and counts in a ``units`` block.
PURE = "1"

#: Unit name of a number no rule names.
UNKNOWN = "unknown"

#: Internal units a key suffix names (``_in``, ``_in_s`` ...), by the suffix (lower case).
_SUFFIX_UNITS: dict[str, str] = {
    key_suffix(short_name(u)).lower(): u
    for u in (
        "inch",
        "inch / second",
        "inch / second**2",
        "inch**2",
        "inch**3 / second",
        "inch**3 / second / psi",
        "inch**3 / second / milliampere",
        "force_pound",
        "force_pound / inch",
        "force_pound * second / inch",
        "psi",
        "second",
        "millisecond",
        "hertz",
        "radian / second",
        "degree",
        "volt",
        "milliampere",
        "g0",
    )
}
_SUFFIX_UNITS.update(
    {"g": "g0", "db": "dB", "pct": "percent", "percent": "percent", "in3_s_psi": "inch**3 / second / psi"}
)
_SUFFIX_UNITS.update({"in3_s_ma": "inch**3 / second / milliampere"})  # the order JSON keys use

#: Suffixes, longest first (``_in_s2`` before ``_s2``, ``_in3_s_psi`` before ``_psi``).
_SUFFIXES = sorted(_SUFFIX_UNITS, key=len, reverse=True)

#: Fields whose unit depends on where they are (dotted path, list indices dropped): the
#: lab file's keys (``limits.stroke``, ``controller.loop_time`` ...).
PATH_UNITS: dict[str, str] = {
    key: (unit or "1")
    for key, unit in LAB_UNITS.items()
    if unit not in ("unit of the channel",) and "." in key
} | {"multisine.peak": "inch", "frf.peak": "inch"}

#: What a ``units`` block says of transfer-function coefficients: they stay in internal units.
TF_COEFFICIENTS = "coefficients in internal units (in, in/s**2, lbf, psi; s in rad/s)"

#: Fields whose unit a pattern of their path names (list indices dropped).
_PATH_PATTERNS: tuple[tuple[re.Pattern[str], str], ...] = (
    (re.compile(r"(^|\.)(H_\w+\.)?(num|den)$"), TF_COEFFICIENTS),
    (re.compile(r"(^|\.)poles\.(real|imag)$"), "radian / second"),
    # a transfer function as zeros, poles ([re, im] pairs) and gain (TransferFunction.to_zpk)
    (re.compile(r"(^|\.)H_\w+\.(zeros|poles)$"), "radian / second"),
    (re.compile(r"(^|\.)H_\w+\.gain$"), TF_COEFFICIENTS),
)

#: The interlocks of a run or a drive file (``provenance.interlocks.stroke``): the lab file's limits.
_INTERLOCK_RE = re.compile(r"(?:^|\.)interlocks\.(\w+)$")

#: Keys whose unit a pattern of the key names (the gains of a table: ``Ke_limit``, ``recommended_Kp``).
_KEY_PATTERNS: tuple[tuple[re.Pattern[str], str], ...] = (
    (re.compile(r"^(Ke(_.*)?|.*_Ke)$"), "volt / inch"),
    (re.compile(r"^(Kp(_.*)?|.*_Kp)$"), "volt / psi"),
    (re.compile(r"^pgv_in_s(_.*)?$"), "inch / second"),
    (re.compile(r"^pgd_in(_.*)?$"), "inch"),
    (re.compile(r"^.*_loops$"), "loops"),  # a delay in controller loops (``extra_delay_loops``)
    # min Re 1/H_vw of a controlled table: an equivalent damping (design/optimized/indices.py)
    (re.compile(r"^passivity_index$"), "force_pound * second / inch"),
)

#: Keys of pure numbers: errors and ratios, counts, seeds, orders, flags as numbers.
DIMENSIONLESS = frozenset(
    {
        "ratio",
        "share",
        "seed",
        "count",
        "order",
        "cause",
        "damping",
        "zeta",
        "zeta_oil",
        "nrms_error",
        "peak_error",
        "energy_error",
        "performance_error",
        "effort_ratio",
        "time_scale",
        "scale",
        "bits",
        "periods",
        "version",
        "index",
        "lines",
        "discard_periods",
        "n_periods",
    }
)

#: Key patterns of pure numbers (``spectral_error_0p25_15hz``, ``n_samples``, ``coherence_min``).
_DIMENSIONLESS_RE = re.compile(
    r"^(n_.*|npts|.*_count|.*bits|order_.*|.*_order|.*time_scale|.*_oil_damping|spectral_error_.*|"
    r"(.*_)?(error|errors|ratio|fraction|factor|coherence|misfit)(_.*)?)$"
)


@cache
def own_key_units() -> dict[str, str]:
    """Internal unit of every key of the registries other than the VS types' (table file, motion, VS loop)."""
    units = {key: field.unit for key, field in table_keys.FIELDS.items()}
    units.update({key: field.unit for key, (_, field) in table_keys.ALTERNATIVES.items()})
    units.update({"pga": "g0", "pga_original": "g0", "fc": "hertz"})
    units.update(_VS_LOOP_UNITS)
    return units


def key_units() -> dict[str, str]:
    """Internal unit of every key the package's registries know (table, VS, lab file)."""
    return {**vs_files.UNITS, **own_key_units()}


def registry_unit(key: str) -> str | None:
    """The unit :func:`key_units` names for ``key``; the VS types' registry is read only when no other names it."""
    own = own_key_units()
    return own[key] if key in own else vs_files.UNITS.get(key)


#: The keys of a VS loop's summary (``imil vs loops``).
_VS_LOOP_UNITS = {
    "dt": "second",
    "peak_displacement": "inch",
    "peak_force": "force_pound",
    "peak_z_vs": "inch / second**2",
    "dissipated_energy": "force_pound * inch",
    "axial_load": "force_pound",
}


def express(doc: Mapping[str, Any], system: UnitSystem) -> dict[str, Any]:
    """``doc`` (internal units) in ``system``, with ``unit_system`` and ``units`` (see the module)."""
    doc = json_safe(doc)  # arrays as lists, NaN and inf as null, as the JSON will carry them
    units: dict[str, str] = {}
    raw = doc.get("units")
    given: Mapping[str, str] = raw if isinstance(raw, Mapping) else {}
    body = {k: v for k, v in doc.items() if k not in ("units", "unit_system")}
    out = _object(body, "", system, units, given)
    return {**out, "unit_system": system.value, "units": units}


def _object(
    obj: Mapping[str, Any],
    path: str,
    system: UnitSystem,
    units: dict[str, str],
    given: Mapping[str, str],
    inherited: str | None = None,
) -> dict[str, Any]:
    """``obj`` converted; ``inherited``: the unit its own key names (``comparison.peak_table_disp_in``)."""
    sibling = obj.get("unit") if isinstance(obj.get("unit"), str) else inherited
    out: dict[str, Any] = {}
    sibling_used = False
    for key, value in obj.items():
        here = f"{path}.{key}" if path else str(key)
        if _numeric(value) or value is None:
            rule, unit = (
                ("path", _pint(given[here]))
                if here in given
                else _field_unit(str(key), _plain(here), sibling)
            )
            if value is None and rule in ("pure", "unknown"):
                out[key] = value  # a null no rule names is not a number
                continue
            sibling_used |= rule == "sibling"
            shown_value, name = _convert(value, unit, system)
            new_key = _renamed(str(key), unit, name) if rule == "suffix" else str(key)
            out[new_key] = shown_value
            units[f"{path}.{new_key}" if path else new_key] = name
        elif isinstance(value, Mapping):
            suffix = _suffix(str(key))
            inner = _SUFFIX_UNITS[suffix] if suffix is not None else None
            out[key] = _object(value, here, system, units, given, inner)
        elif isinstance(value, list) and value and all(isinstance(v, Mapping) for v in value):
            out[key] = [_object(v, f"{here}[{i}]", system, units, given) for i, v in enumerate(value)]
        else:
            out[key] = value
    if sibling is not None and sibling_used and "unit" in obj and system is not UnitSystem.US:
        out["unit"] = _shown_name(display_unit(_pint(sibling), system).name)
    return out


def _renamed(key: str, unit: str, unit_name: str) -> str:
    """``peak_table_disp_in`` shown in ``mm`` -> ``peak_table_disp_mm``: a key whose suffix names
    ``unit`` follows it when it is shown as ``unit_name`` (unchanged where the unit reads the same
    in both systems: ``fc_hz``, ``pga_g``)."""
    suffix = _suffix(key)
    if suffix is None or unit_name == _shown_name(display_unit(unit, UnitSystem.US).name):
        return key
    return key[: len(key) - len(suffix)] + key_suffix(unit_name)


def _field_unit(key: str, path: str, sibling: str | None) -> tuple[str, str]:
    """(rule, internal unit or PURE/UNKNOWN) of one numeric field; the rules as the module lists them."""
    if path in PATH_UNITS:
        return "path", PATH_UNITS[path]
    for pattern, unit in _PATH_PATTERNS:
        if pattern.search(path):
            return "path", unit
    interlock = _INTERLOCK_RE.search(path)  # a run's or a drive's interlocks, named as the lab file's limits
    if interlock is not None and f"limits.{interlock.group(1)}" in PATH_UNITS:
        return "path", PATH_UNITS[f"limits.{interlock.group(1)}"]
    if "." in key:  # a configuration key as a value's name (``from_report``: ``limits.stroke``)
        if key in PATH_UNITS:
            return "path", PATH_UNITS[key]
        return _field_unit(key.rsplit(".", 1)[1], path, sibling)
    suffix = _suffix(key)
    if suffix is not None:
        return "suffix", _SUFFIX_UNITS[suffix]
    if _is_pure(key):
        return "pure", PURE
    if sibling is not None:
        return "sibling", _pint(sibling)
    if path in LAB_OBJECTS:  # a lab's optional section: an object, null when the lab has none
        return "unknown", UNKNOWN
    found = registry_unit(key) or next((u for p, u in _KEY_PATTERNS if p.match(key)), None)
    return ("registry", found) if found is not None else ("unknown", UNKNOWN)


def _suffix(key: str) -> str | None:
    lowered = key.lower()
    for suffix in _SUFFIXES:
        if lowered.endswith("_" + suffix) and len(lowered) > len(suffix) + 1:
            return suffix
    return None


def _is_pure(key: str) -> bool:
    return key in DIMENSIONLESS or bool(_DIMENSIONLESS_RE.match(key))


def _plain(path: str) -> str:
    return re.sub(r"\[\d+\]", "", path)


def _pint(unit: str) -> str:
    """A unit string as JSON carries it (``in^3/s``, ``g``) as a pint expression."""
    text = unit.replace("^", "**").strip()
    return {"g": "g0", "": "dimensionless", "-": "dimensionless"}.get(text, text)


def _shown_name(name: str) -> str:
    return name or PURE


def _numeric(value: Any) -> bool:
    if isinstance(value, bool):
        return False
    if isinstance(value, int | float):
        return True
    # a list of numbers, or of lists of numbers (pairs, rows), is one field
    return isinstance(value, list) and bool(value) and all(_numeric(v) or v is None for v in value)


def _convert(value: Any, unit: str, system: UnitSystem) -> tuple[Any, str]:
    if unit in (PURE, UNKNOWN, "loops", TF_COEFFICIENTS):
        return value, unit
    shown = display_unit(unit, system)
    return _scaled(value, shown.factor), _shown_name(shown.name)


def _scaled(value: Any, factor: float) -> Any:
    if factor == 1.0 or value is None:
        return value
    if isinstance(value, list):
        return [_scaled(v, factor) for v in value]
    return value * factor
