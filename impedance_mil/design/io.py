"""The design file: a filtered MIL controller handed to the implementation step.

Schema (JSON, version 1)::

    {"format": "impedance-mil/design", "version": 1, "software_version": str,
     "form": "standardized"|"vs-specific"|"tracking"|"general",
     "reference": "z_vs"|"a_g",
     "sign_convention": "u = H_uz*<reference> + H_uw*w [+ H_ufh*f_h]",
     "fc_hz": float,
     "filter": {"family": str, "order_z": int, "order_w": int, "order_fh": int,
                "ripple_db": float, "fc_w_hz": float|null},
     "loop_time_s": float,
     "table": {TableParameters.to_dict()},
     "capacity": {"stroke": in, "velocity": in/s, "force": lbf, "mass": lbf*s**2/in,
                  "piston_area": in**2}   (optional: a table given as a linear model)
     "table_paths": {"H_zu": {...}, "H_zw": {...}}   (optional: that table's paths)
     "vs": {"kind": str, "name": str|null, "parameters": {...}}|null,
     "H_uz": {"num": [...], "den": [...]}, "H_uw": {...}, "H_ufh": {...}|null,
     "constraints": [...], "feasible_fc_hz": [lo, hi]|null, "warnings": [...]}

Transfer functions are in descending powers of s [rad/s]; every path is
added (``u = H_uz r + H_uw w + H_ufh f_h``), so for the standardized form
``H_uw = -F_w H_zw^st/H_zu^st`` carries the minus sign of Eq 6-9.
The file is written to a temporary name and renamed, so a failed write
leaves nothing half-written.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
from pathlib import Path
from typing import Any

from ..config import quantity
from ..errors import ConfigError, DataFileError, ImilError
from ..fileio import atomic_write_text, json_safe, parse_json, read_text
from ..plant.capacity import CAPACITY_KEYS
from ..plant.parameters import FIELDS as TABLE_FIELDS
from ..plant.parameters import VALVE_KINDS
from ..plausibility import TABLE_BOUNDS, check_table
from ..systems import TransferFunction
from .constraints import OPTIONAL_FIELDS, ConstraintResult
from .controller import ControllerDesign, FilterSpec
from .filters import FAMILIES
from .forms import FORMS, REFERENCE_INPUT

#: Value of the "format" key.
FORMAT = "impedance-mil/design"

#: Schema version of a filter design.
VERSION = 1

#: Schema version of an optimized design: version 1 plus ``"method": "optimized"`` and the
#: solver's report ``"optimization"`` (basis, coefficients, certificate, state space of each path).
VERSION_OPTIMIZED = 2

#: Versions this reader accepts.
SUPPORTED_VERSIONS = (VERSION, VERSION_OPTIMIZED)
#: ``filter.family`` of an optimized design (its paths are not a filtered standard form;
#: the orders are those of the partial-fraction basis).
OPTIMIZED_FAMILY = "optimized"

_REQUIRED = (
    "format",
    "version",
    "software_version",
    "form",
    "fc_hz",
    "filter",
    "loop_time_s",
    "table",
    "vs",
    "H_uz",
    "H_uw",
    "H_ufh",
    "constraints",
    "feasible_fc_hz",
    "warnings",
)


def design_to_dict(design: ControllerDesign) -> dict[str, Any]:
    """The design file document of ``design``."""
    version = VERSION if design.optimization is None else VERSION_OPTIMIZED
    doc = {"format": FORMAT, "version": version, "software_version": design.software_version}
    body = design.to_json()
    doc.update(
        {
            "form": body["form"],
            "reference": body["reference"],
            "sign_convention": body["sign_convention"],
            "fc_hz": body["fc_hz"],
            "filter": body["filter"],
            "loop_time_s": body["loop_time_s"],
            "table": dict(design.table),
            **({"capacity": dict(design.capacity)} if design.capacity else {}),
            **(
                {"table_paths": {k: tf.to_dict() for k, tf in design.table_paths.items()}}
                if design.table_paths
                else {}
            ),
            "vs": design.vs,
            "H_uz": body["H_uz"],
            "H_uw": body["H_uw"],
            "H_ufh": body["H_ufh"],
            "constraints": body["constraints"],
            "feasible_fc_hz": body["feasible_fc_hz"],
            "warnings": body["warnings"],
        }
    )
    if design.optimization is not None:
        doc.update({"method": "optimized", "optimization": body["optimization"]})
    if design.amplitude_certificate is not None:
        doc["passivity_amplitude_certificate"] = body["passivity_amplitude_certificate"]
    return json_safe(doc)


def save_design(design: ControllerDesign, path: str | os.PathLike) -> Path:
    """Write ``design`` as JSON to ``path`` atomically (temporary file + rename).

    Raises
    ------
    DataFileError
        The directory does not exist or is not writable.
    """
    target = Path(path)
    text = json.dumps(design_to_dict(design), indent=2, allow_nan=False)
    try:
        return atomic_write_text(target, text + "\n")
    except OSError as exc:
        raise DataFileError(target, f"cannot write the design file ({exc.strerror or exc})") from None


def load_design(path: str | os.PathLike) -> ControllerDesign:
    """Read a design file written by :func:`save_design`.

    Raises
    ------
    DataFileError
        One line naming the file and the key: missing or unreadable file, not
        JSON (or nested deeper than :data:`~impedance_mil.fileio.MAX_JSON_DEPTH`,
        or a number of more than :data:`~impedance_mil.fileio.MAX_NUMBER_DIGITS`
        digits), wrong format or version, a missing field or one of the wrong
        type (a boolean or a string where a number belongs, ``"constraints":
        "x"``), a malformed transfer function (a coefficient that is not a
        finite number, a zero denominator), or table parameters that are not
        numbers, out of range or physically impossible
        (:mod:`impedance_mil.plausibility`).
    """
    p = Path(path)
    return design_from_dict(parse_json(read_text(p, "a design file"), p), p)


def design_from_dict(doc: Any, where: str | os.PathLike = "<design>") -> ControllerDesign:
    """Validate a design document and build the :class:`ControllerDesign`.

    Raises
    ------
    DataFileError
        See :func:`load_design`.
    """
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise DataFileError(where, f"not an impedance-mil design file (expected format {FORMAT!r})")
    version = doc.get("version")
    if isinstance(version, bool) or version not in SUPPORTED_VERSIONS:  # true == 1 in Python
        raise DataFileError(
            where,
            f"design file version {_shown(version)} is not supported "
            f"(expected {' or '.join(str(v) for v in SUPPORTED_VERSIONS)})",
        )
    if doc["version"] == VERSION_OPTIMIZED and not isinstance(doc.get("optimization"), dict):
        raise DataFileError(where, "missing field 'optimization' (version 2: an optimized design)")
    missing = [k for k in _REQUIRED if k not in doc]
    if missing:
        raise DataFileError(where, f"missing field {missing[0]!r}")
    try:
        return _design(doc)
    except ConfigError as exc:
        raise DataFileError(where, str(exc)) from None


def _design(doc: dict[str, Any]) -> ControllerDesign:
    """The design of a document with every field present (ConfigError naming the key)."""
    form = doc["form"]
    if not isinstance(form, str) or form not in FORMS:
        raise ConfigError("form", "one of " + ", ".join(FORMS), _shown(form))
    reference = doc.get("reference", REFERENCE_INPUT[form])
    if reference != REFERENCE_INPUT[form]:
        raise ConfigError(
            "reference", f"{REFERENCE_INPUT[form]!r} (the {form} form's reference)", _shown(reference)
        )
    H = {key: _transfer_function(doc[key], key) for key in ("H_uz", "H_uw", "H_ufh")}
    if H["H_uz"] is None or H["H_uw"] is None:
        raise ConfigError("H_uz/H_uw", "transfer functions ({'num': [...], 'den': [...]})", None)
    # the sign convention is informative, but a file that states another one was not written
    # for this reading of H_uw's sign (Eq. 6-7): refuse it rather than flip the command
    sign = f"u = H_uz*{reference} + H_uw*w" + (" + H_ufh*f_h" if H["H_ufh"] is not None else "")
    if doc.get("sign_convention", sign) != sign:
        raise ConfigError("sign_convention", repr(sign), _shown(doc["sign_convention"]))
    for name, tf in H.items():
        if tf is not None and not tf.is_proper:
            raise ConfigError(
                name,
                "a proper transfer function, not an improper one (a design file holds filtered controllers)",
            )
    fc = _number("fc_hz", doc["fc_hz"], "positive")
    loop = _number("loop_time_s", doc["loop_time_s"], "nonnegative")
    longest = TABLE_BOUNDS["loop_time"].error_high  # a design at fc >= Nyquist is kept; export refuses it
    if longest is not None and loop > longest:
        raise ConfigError("loop_time_s", f"a loop time of at most {longest:g} s (plausibility)", loop)
    feas = doc["feasible_fc_hz"]
    if feas is not None:
        if not isinstance(feas, list) or len(feas) != 2:
            raise ConfigError("feasible_fc_hz", "null or a list [low, high] in Hz", _shown(feas))
        feas = tuple(_number(f"feasible_fc_hz[{i}]", v, "nonnegative") for i, v in enumerate(feas))
    _check_table(doc["table"])
    return ControllerDesign(
        form=form,
        reference=reference,
        fc_hz=fc,
        filter=_filter(doc["filter"]),
        loop_time_s=loop,
        H_uz=H["H_uz"],
        H_uw=H["H_uw"],
        H_ufh=H["H_ufh"],
        constraints=_constraints(doc["constraints"]),
        feasible_fc_hz=feas,
        warnings=tuple(_strings("warnings", doc["warnings"])),
        table=dict(doc["table"] or {}),
        capacity=_capacity(doc.get("capacity")),
        table_paths=_table_paths(doc.get("table_paths")),
        vs=_vs_entry(doc["vs"]),
        software_version=_string("software_version", doc["software_version"]),
        optimization=doc.get("optimization") if doc["version"] == VERSION_OPTIMIZED else None,
        amplitude_certificate=_amplitude_certificate(doc.get("passivity_amplitude_certificate")),
    )


def _amplitude_certificate(value: Any) -> dict[str, Any] | None:
    """The optional ``passivity_amplitude_certificate`` block (an object, kept as it is, or absent)."""
    if value is not None and not isinstance(value, dict):
        raise ConfigError("passivity_amplitude_certificate", "an object or null", _shown(value))
    return value


#: Longest value echoed in a message [characters].
_SHOWN_CHARS = 40


def _shown(value: Any) -> Any:
    """``value`` as echoed in a message: a scalar as it is, a long one cut, a container by its type."""
    if isinstance(value, (list, dict)):
        return f"a JSON {'array' if isinstance(value, list) else 'object'}"
    text = value if isinstance(value, str) else repr(value)
    return value if len(text) <= _SHOWN_CHARS else f"{text[:_SHOWN_CHARS]}... ({len(text)} characters)"


def _number(key: str, value: Any, check: str = "any") -> float:
    """A finite real number (not a boolean), with ``check`` ``positive``/``nonnegative``/``any``."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ConfigError(key, "a number", _shown(value))
    try:
        number = float(value)
    except OverflowError:
        number = math.inf
    if not math.isfinite(number):
        raise ConfigError(key, "a finite number", _shown(value))
    if (check == "positive" and number <= 0) or (check == "nonnegative" and number < 0):
        raise ConfigError(key, f"a {check} number", _shown(value))
    return number


def _integer(key: str, value: Any, low: int = 0) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        raise ConfigError(key, f"a whole number >= {low}", _shown(value))
    return value


def _string(key: str, value: Any) -> str:
    if not isinstance(value, str):
        raise ConfigError(key, "a string", _shown(value))
    return value


def _strings(key: str, value: Any) -> list[str]:
    if not isinstance(value, list):
        raise ConfigError(key, "a list of strings", _shown(value))
    return [_string(f"{key}[{i}]", v) for i, v in enumerate(value)]


def _transfer_function(tf: Any, key: str) -> TransferFunction | None:
    """``{"num": [...], "den": [...]}`` of finite real numbers with a non-zero denominator, or None."""
    if tf is None:
        return None
    if not isinstance(tf, dict) or set(tf) != {"num", "den"}:
        raise ConfigError(key, "null or {'num': [...], 'den': [...]} (descending powers of s)", _shown(tf))
    coefficients = {}
    for part in ("num", "den"):
        values = tf[part]
        if not isinstance(values, list) or not values:
            raise ConfigError(f"{key}.{part}", "a non-empty list of numbers", _shown(values))
        coefficients[part] = [_number(f"{key}.{part}[{i}]", v) for i, v in enumerate(values)]
    if not any(coefficients["den"]):
        raise ConfigError(f"{key}.den", "a denominator with a non-zero coefficient", "all zero")
    try:
        return TransferFunction.from_dict(coefficients)
    except ImilError as exc:  # e.g. coefficients whose products overflow
        raise ConfigError(key, f"a transfer function ({exc})") from None


#: Largest ripple of a Chebyshev I filter [dB] (``design.filters``); other families ignore it.
_MAX_RIPPLE_DB = 10.0


def _filter(flt: Any) -> FilterSpec:
    """The filter entry (a record of how H was filtered: the design is continuous, so a
    cut-off at or above the loop's Nyquist frequency is kept here and refused by export)."""
    if not isinstance(flt, dict):
        raise ConfigError("filter", "{'family': ..., 'order_z': ..., 'order_w': ...}", _shown(flt))
    for key in ("family", "order_z", "order_w"):
        if key not in flt:
            raise ConfigError(f"filter.{key}", "present")
    family = _string("filter.family", flt["family"])
    if family not in (*FAMILIES, OPTIMIZED_FAMILY):
        raise ConfigError(
            "filter.family", "one of " + ", ".join((*FAMILIES, OPTIMIZED_FAMILY)), _shown(family)
        )
    ripple = _number("filter.ripple_db", flt.get("ripple_db", 0.5), "nonnegative")
    if ripple >= _MAX_RIPPLE_DB:
        raise ConfigError("filter.ripple_db", f"a ripple below {_MAX_RIPPLE_DB:g} dB", ripple)
    fc_w = flt.get("fc_w_hz")
    if fc_w is not None:
        fc_w = _number("filter.fc_w_hz", fc_w, "positive")
    return FilterSpec(
        family,
        _integer("filter.order_z", flt["order_z"]),
        _integer("filter.order_w", flt["order_w"]),
        _integer("filter.order_fh", flt.get("order_fh", 0)),
        ripple,
        fc_w,
    )


#: Fields of a constraint entry that are verdicts (true/false); the others are numbers or null.
_VERDICTS = ("I", "II", "III", "stable", "III_design_model", "III_sampled")

#: Fields of a constraint entry that cannot be negative: frequencies, an error norm, a ratio.
_NONNEGATIVE = (
    "performance_error",
    "effort_ratio",
    *(f"{n}_worst_hz" for n in ("performance", "effort", "passivity", "passivity_tolerant")),
)


def _constraints(entries: Any) -> tuple[ConstraintResult, ...]:
    if not isinstance(entries, list):
        raise ConfigError("constraints", "a list of constraint results", _shown(entries))
    names = [f.name for f in dataclasses.fields(ConstraintResult)]
    required = [n for n in names if n not in OPTIONAL_FIELDS]  # the optional ones came with version 2
    out = []
    for i, entry in enumerate(entries):
        key = f"constraints[{i}]"
        if not isinstance(entry, dict) or not set(required) <= set(entry) <= set(names):
            raise ConfigError(key, "an object with the keys " + ", ".join(names), _shown(entry))
        values: dict[str, Any] = {}
        for name in names:
            value = entry.get(name)
            if name in OPTIONAL_FIELDS and value is None:
                values[name] = None
            elif name in _VERDICTS:
                if not isinstance(value, bool):
                    raise ConfigError(f"{key}.{name}", "true or false", _shown(value))
                values[name] = value
            elif name == "fc_hz":
                values[name] = _number(f"{key}.{name}", value, "positive")
            else:
                check = "nonnegative" if name in _NONNEGATIVE else "any"
                values[name] = math.nan if value is None else _number(f"{key}.{name}", value, check)
        out.append(ConstraintResult(**values))
    return tuple(out)


def _vs_entry(entry: Any) -> dict[str, Any] | None:
    """The VS entry: null, or an object with a string ``kind`` and a ``parameters`` object.

    Its parameters are checked when the VS is rebuilt (``implement.export.designed_vs``).
    """
    if entry is None:
        return None
    if not isinstance(entry, dict):
        raise ConfigError("vs", "null or {'kind': ..., 'name': ..., 'parameters': {...}}", _shown(entry))
    _string("vs.kind", entry.get("kind"))
    if entry.get("name") is not None:
        _string("vs.name", entry["name"])
    if not isinstance(entry.get("parameters"), dict):
        raise ConfigError("vs.parameters", "an object of parameters", _shown(entry.get("parameters")))
    return entry


def _capacity(section: Any) -> dict[str, float]:
    """The optional ``capacity`` of a design from an LTI table: known keys, positive numbers (internal units)."""
    if section is None:
        return {}
    if not isinstance(section, dict):
        raise ConfigError(
            "capacity", "the stated capacity of an LTI table (stroke, velocity, ...)", _shown(section)
        )
    for key in section:
        if key not in CAPACITY_KEYS:
            raise ConfigError(f"capacity.{key}", "one of the keys " + ", ".join(CAPACITY_KEYS))
    return {key: _number(f"capacity.{key}", value, "positive") for key, value in section.items()}


#: The paths of an LTI table a design file may record (``table_paths``).
_TABLE_PATHS = ("H_zu", "H_zw")


def _table_paths(section: Any) -> dict[str, TransferFunction]:
    """The optional ``table_paths`` of a design from an LTI table (both paths, or none)."""
    if section is None:
        return {}
    if not isinstance(section, dict) or set(section) != set(_TABLE_PATHS):
        raise ConfigError("table_paths", "the table's paths {'H_zu': {...}, 'H_zw': {...}}", _shown(section))
    paths = {key: _transfer_function(section[key], f"table_paths.{key}") for key in _TABLE_PATHS}
    return {key: tf for key, tf in paths.items() if tf is not None}


def _check_table(table: Any) -> None:
    """Refuse unknown table keys, and parameters that are not numbers, out of range or implausible (present keys only).

    A design file's table is ``TableParameters.to_dict()`` in internal units;
    a design built from closed forms may carry only some of the keys.
    """
    if table is None:
        return
    if not isinstance(table, dict):
        raise ConfigError("table", "the table parameters (TableParameters.to_dict())", _shown(table))
    for key, value in table.items():
        if key == "valve":  # the servovalve kind of a general table (issue 13), a word
            if value not in VALVE_KINDS:
                raise ConfigError("table.valve", "one of " + ", ".join(VALVE_KINDS), _shown(value))
            continue
        spec = TABLE_FIELDS.get(key)
        if spec is None:  # a misspelt key would otherwise be ignored and its value lost
            raise ConfigError(f"table.{key}", "a table parameter: " + ", ".join(TABLE_FIELDS))
        items = value if spec.count > 1 and isinstance(value, list) else [value]
        if spec.count > 1 and len(items) != spec.count:
            raise ConfigError(f"table.{key}", f"a list of {spec.count} numbers in {spec.unit}", _shown(value))
        for item in items:
            if isinstance(item, bool) or not isinstance(item, (int, float)):
                raise ConfigError(f"table.{key}", f"a number in {spec.unit}", _shown(item))
            quantity(f"table.{key}", item, spec.unit, spec.check)
    check_table(table, where="table.")
