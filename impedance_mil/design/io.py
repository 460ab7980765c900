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

import json
import math
import os
from pathlib import Path
from typing import Any

from ..config import quantity
from ..errors import ConfigError, DataFileError
from ..fileio import atomic_write_text, json_safe, read_text
from ..plant.parameters import FIELDS as TABLE_FIELDS
from ..plausibility import check_table
from ..systems import TransferFunction
from .constraints import ConstraintResult
from .controller import ControllerDesign, FilterSpec
from .forms import FORMS, REFERENCE_INPUT

#: Value of the "format" key.
FORMAT = "impedance-mil/design"

#: Current schema version.
VERSION = 1

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
    doc = {"format": FORMAT, "version": VERSION, "software_version": design.software_version}
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
            "vs": design.vs,
            "H_uz": body["H_uz"],
            "H_uw": body["H_uw"],
            "H_ufh": body["H_ufh"],
            "constraints": body["constraints"],
            "feasible_fc_hz": body["feasible_fc_hz"],
            "warnings": body["warnings"],
        }
    )
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
        Missing or unreadable file, not JSON, wrong format or version, a
        missing field, a malformed transfer function (a coefficient that is
        not a finite number, e.g. a boolean), or table parameters that are
        not numbers, out of range or physically impossible
        (:mod:`impedance_mil.plausibility`).
    """
    p = Path(path)
    text = read_text(p, "a design file")
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise DataFileError(p, f"not valid JSON ({exc.msg} at line {exc.lineno})") from None
    return design_from_dict(doc, p)


def design_from_dict(doc: Any, where: str | os.PathLike = "<design>") -> ControllerDesign:
    """Validate a design document and build the :class:`ControllerDesign`.

    Raises
    ------
    DataFileError
        See :func:`load_design`.
    """
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise DataFileError(where, f"not an impedance-mil design file (expected format {FORMAT!r})")
    if doc.get("version") != VERSION:
        raise DataFileError(
            where, f"design file version {doc.get('version')!r} is not supported (expected {VERSION})"
        )
    missing = [k for k in _REQUIRED if k not in doc]
    if missing:
        raise DataFileError(where, f"missing field {missing[0]!r}")
    if doc["form"] not in FORMS:
        raise DataFileError(where, f"form {doc['form']!r} is not one of {', '.join(FORMS)}")
    for key in ("H_uz", "H_uw", "H_ufh"):
        _check_coefficients(doc[key], key, where)
    _check_table(doc["table"], where)
    try:
        H = {
            k: (None if doc[k] is None else TransferFunction.from_dict(doc[k]))
            for k in ("H_uz", "H_uw", "H_ufh")
        }
        flt = doc["filter"]
        spec = FilterSpec(
            str(flt["family"]),
            int(flt["order_z"]),
            int(flt["order_w"]),
            int(flt.get("order_fh", 0)),
            float(flt.get("ripple_db", 0.5)),
            None if flt.get("fc_w_hz") is None else float(flt["fc_w_hz"]),
        )
        constraints = tuple(
            ConstraintResult(**{k: (v if v is not None else math.nan) for k, v in c.items()})
            for c in doc["constraints"]
        )
        fc, loop = float(doc["fc_hz"]), float(doc["loop_time_s"])
        feas = doc["feasible_fc_hz"]
        feas = None if feas is None else (float(feas[0]), float(feas[1]))
    except (KeyError, TypeError, ValueError, IndexError, OverflowError) as exc:
        raise DataFileError(where, f"malformed design ({exc})") from None
    if H["H_uz"] is None or H["H_uw"] is None:
        raise DataFileError(where, "H_uz and H_uw must be transfer functions")
    for name, tf in H.items():
        if tf is not None and not tf.is_proper:
            raise DataFileError(
                where, f"{name} is improper: a design file holds filtered, proper controllers"
            )
    if not (fc > 0 and loop >= 0):
        raise DataFileError(where, "fc_hz must be positive and loop_time_s non-negative")
    return ControllerDesign(
        form=doc["form"],
        reference=doc.get("reference", REFERENCE_INPUT[doc["form"]]),
        fc_hz=fc,
        filter=spec,
        loop_time_s=loop,
        H_uz=H["H_uz"],
        H_uw=H["H_uw"],
        H_ufh=H["H_ufh"],
        constraints=constraints,
        feasible_fc_hz=feas,
        warnings=tuple(str(w) for w in doc["warnings"]),
        table=dict(doc["table"] or {}),
        vs=doc["vs"],
        software_version=str(doc["software_version"]),
    )


def _check_coefficients(tf: Any, key: str, where: str | os.PathLike) -> None:
    """Refuse coefficients that are not real numbers (a boolean is not a coefficient) or not finite."""
    if tf is None or not isinstance(tf, dict):
        return  # absent or malformed: design_from_dict says which
    for part in ("num", "den"):
        values = tf.get(part)
        if not isinstance(values, list):
            continue
        for value in values:
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise DataFileError(where, f"{key}.{part}: expected numbers, got {value!r}")
            try:
                finite = math.isfinite(float(value))
            except OverflowError:
                finite = False
            if not finite:
                raise DataFileError(where, f"{key}.{part}: expected finite numbers, got {str(value)[:40]}")


def _check_table(table: Any, where: str | os.PathLike) -> None:
    """Refuse table parameters that are not numbers, out of range or implausible (present keys only).

    A design file's table is ``TableParameters.to_dict()`` in internal units;
    a design built from closed forms may carry only some of the keys.
    """
    if table is None:
        return
    if not isinstance(table, dict):
        raise DataFileError(where, "table: expected the table parameters (TableParameters.to_dict())")
    try:
        for key, value in table.items():
            spec = TABLE_FIELDS.get(key)
            for item in value if spec is not None and spec.count > 1 and isinstance(value, list) else [value]:
                if spec is not None and (isinstance(item, bool) or not isinstance(item, (int, float))):
                    raise ConfigError(f"table.{key}", f"a number in {spec.unit}", item)
                if spec is not None:
                    quantity(f"table.{key}", item, spec.unit, spec.check)
        check_table(table, where="table.")
    except ConfigError as exc:
        raise DataFileError(where, str(exc)) from None
