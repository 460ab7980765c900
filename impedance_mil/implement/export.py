"""Export a design: discretize it and write C, ST, JSON or CSV into a directory, atomically.

Files for prefix ``P``: ``c`` -> ``P.h``, ``P.c``; ``st`` -> ``P.st``; ``json`` ->
``P_coefficients.json``; ``csv`` -> ``P_coefficients.csv``.  Everything is
written into a temporary directory beside the target and renamed into place,
so a failure leaves no partial output directory behind.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__ as _pkg_version
from ..errors import ConfigError
from ..fileio import atomic_directory
from ..virtual.definition import VSDefinition
from ..virtual.files import from_parameters
from ..virtual.vstype import VSType
from .c import render_c
from .discretization import DiscreteController, discretize
from .identifiers import check_c_identifier, check_st_identifier
from .io_units import IOUnits
from .runtime import precision_dtype
from .safety import COEFFICIENTS, CommandLimits, check_renderable
from .st import render_st

#: Export formats.
FORMATS = ("c", "st", "json", "csv")
#: Value of the "format" key of the coefficient file.
COEFF_FORMAT = "impedance-mil/coefficients"
#: Relative tolerance when comparing a requested loop time with the design's.
LOOP_TIME_RTOL = 1e-9


def controller_from_design(
    design,
    *,
    loop_time_s: float | None = None,
    method: str = "tustin",
    prewarp_hz: float | None = None,
    leak_hz: float | None = None,
) -> DiscreteController:
    """Discretize a :class:`~impedance_mil.design.ControllerDesign` at its loop time.

    Parameters
    ----------
    design : ControllerDesign
        From :func:`impedance_mil.design.load_design` or ``design_controller``.
    loop_time_s : float, optional
        Must equal the design's loop time [s] (the table model depends on it).
    method, prewarp_hz, leak_hz
        See :func:`~impedance_mil.implement.discretize`.
    """
    if design.H_ufh is not None:
        raise ConfigError(
            "H_ufh",
            "a two-input controller (standardized or tracking form); "
            "the f_h path of the vs-specific form is not implemented",
            "present",
        )
    if loop_time_s is not None and not math.isclose(loop_time_s, design.loop_time_s, rel_tol=LOOP_TIME_RTOL):
        raise ConfigError(
            "loop_time_s",
            f"the design's loop time {design.loop_time_s} s (the table model was built for it)",
            loop_time_s,
        )
    source = {
        "form": design.form,
        "reference": design.reference,
        "fc_hz": design.fc_hz,
        "filter": design.filter.to_dict(),
        "software_version": design.software_version,
        "table": dict(design.table),
        "vs": design.vs,
    }
    return discretize(
        design.H_uz,
        design.H_uw,
        design.loop_time_s,
        method=method,
        prewarp_hz=prewarp_hz,
        fc_hz=design.fc_hz,
        leak_hz=leak_hz,
        source=source,
    )


#: Relative tolerance when comparing a requested VS with the designed one.
VS_RTOL = 1e-12


@dataclass(frozen=True)
class ExportVS:
    """The virtual system rendered into the generated MIL step, and where it came from.

    Attributes
    ----------
    vs : VirtualSystem or None
        The system; ``None`` exports the controller alone (no MIL step).
    name : str
        Preset name or file stem of the design (or of ``--vs``).
    source : str
        ``"design"`` (rebuilt from the design file's parameters), ``"requested"``
        (given for a design made without a VS) or ``"none"``.
    note : str
        A sentence for the user when the export is not simply the designed VS.
    """

    vs: Any
    name: str
    source: str
    note: str = ""


def designed_vs(design, requested=None, requested_name: str = "") -> ExportVS:
    """The VS to render for ``design``: exactly the designed one, parameters included.

    Parameters
    ----------
    design : ControllerDesign
        Its ``vs`` entry (``{"kind", "name", "parameters"}``, internal units) is
        rebuilt parameter by parameter; the preset name is only a label.
    requested : VirtualSystem, optional
        A VS asked for explicitly (``imil export --vs``).  With a design that
        names a VS it must be that VS; with a design made without one (the
        standardized form does not depend on the VS) it is rendered, with a note
        that constraints I and III were not checked for it.

    Raises
    ------
    ConfigError
        The design's VS entry is malformed or of an unknown kind, or
        ``requested`` differs from the designed VS.
    """
    entry = design.vs
    if entry is None:
        if requested is None:
            return ExportVS(None, "", "none")
        return ExportVS(
            requested,
            requested_name,
            "requested",
            f"the design was made without a VS: constraints I and III were not checked "
            f"for {requested_name or requested.kind}",
        )
    if not isinstance(entry, dict):
        raise ConfigError("design vs", "a table with kind and parameters", type(entry).__name__)
    vstype = None
    if entry.get("definition") is not None:  # a user's type, kept whole in the design file
        try:
            vstype = VSType(VSDefinition.from_dict(entry["definition"]))
        except ConfigError as exc:
            raise ConfigError(f"design vs.{exc.key}", exc.expected, exc.got) from None
        if vstype.kind != entry.get("kind"):
            raise ConfigError(
                "design vs.kind", f"the kind of its definition, {vstype.kind!r}", entry.get("kind")
            )
    parameters = entry.get("parameters")
    if isinstance(parameters, dict) and parameters.get("kind", entry.get("kind")) != entry.get("kind"):
        raise ConfigError(
            "design vs.parameters.kind", f"the entry's kind, {entry.get('kind')!r}", parameters["kind"]
        )
    vs = from_parameters(entry.get("kind"), parameters, where="design vs.", vstype=vstype)
    name = str(entry.get("name") or vs.kind)
    if requested is not None and not _same_vs(vs, requested):
        raise ConfigError(
            "--vs",
            f"the designed VS {name} (omit --vs to export it; design again to export another VS)",
            requested_name or requested.kind,
        )
    return ExportVS(vs, name, "design")


def _same_vs(a, b) -> bool:
    if a.kind != b.kind:
        return False
    pa, pb = a.parameter_array(), b.parameter_array()
    return pa.shape == pb.shape and bool(np.allclose(pa, pb, rtol=VS_RTOL, atol=0.0))


def _mat(a: np.ndarray, dtype) -> dict:
    arr = np.atleast_1d(np.asarray(a, float)).astype(dtype).astype(float)
    return {"shape": list(np.shape(a)) or [], "data": arr.tolist() if np.ndim(a) else float(arr[0])}


def coefficients_document(
    controller: DiscreteController, precision: str, io_units: IOUnits | None = None
) -> dict[str, Any]:
    """The coefficient file: matrices with shapes, loop time, precision, units, provenance.

    The coefficients are in the internal units (``units``); with I/O units other
    than those, an ``io_units`` block (:meth:`IOUnits.to_dict`) gives the unit
    of each input and output and its factor.
    """
    dtype = precision_dtype(precision)
    units = {"H_uz": ("z_vs", "in/s^2"), "H_uw": ("w", "lbf")}
    channels = {}
    for ch in controller.channels:
        inp, unit = units[ch.name]
        channels[ch.name] = {
            "input": inp,
            "input_unit": unit,
            "output_unit": "in",
            "n_states": ch.n_states,
            "n_integrators": ch.n_integrators,
            "A": _mat(ch.A, dtype),
            "B": _mat(ch.B, dtype),
            "C": _mat(ch.C, dtype),
            "D": _mat(ch.D, dtype),
            "A_minus_I": _mat(ch.A - np.eye(ch.n_states), dtype),
            "sections": [s.form for s in ch.sections],
            "continuous": ch.continuous.to_dict(),
        }
    doc = {
        "format": COEFF_FORMAT,
        "version": 1,
        "software_version": _pkg_version,
        "loop_time_s": controller.loop_time_s,
        "precision": precision,
        "method": controller.method,
        "prewarp_hz": controller.prewarp_hz,
        "fc_hz": controller.fc_hz,
        "leak_hz": controller.leak_hz,
        "realization": controller.realization,
        "sign_convention": "u = H_uz*z_vs + H_uw*w",
        "state_update": "x[k+1] = x[k] + ((A - I) x[k] + B v[k]) (compensated summation); "
        "y[k] = C x[k] + D v[k]",
        "units": {"z_vs": "in/s^2", "w": "lbf", "u": "in", "loop_time_s": "s", "frequencies": "Hz"},
        "channels": channels,
        "design": controller.source,
    }
    if io_units is not None and not io_units.is_internal:
        doc["io_units"] = io_units.to_dict()
    return doc


def coefficients_csv(controller: DiscreteController, precision: str, io_units: IOUnits | None = None) -> str:
    """CSV ``channel,matrix,row,col,value`` after ``#`` header lines (loop time, units, I/O units ...)."""
    doc = coefficients_document(controller, precision, io_units)
    buf = io.StringIO()
    for key in (
        "format",
        "software_version",
        "loop_time_s",
        "precision",
        "method",
        "fc_hz",
        "leak_hz",
        "sign_convention",
        "state_update",
    ):
        buf.write(f"# {key}: {doc[key]}\n")
    buf.write("# units: z_vs in/s^2, w lbf, u in\n")
    if "io_units" in doc:
        z, w, u = (doc["io_units"][k] for k in ("z_vs", "w", "u"))
        buf.write(
            f"# io_units: {doc['io_units']['spec']}: z_vs {z['unit']} (x {z['to_internal']!r} -> in/s^2), "
            f"w {w['unit']} (x {w['to_internal']!r} -> lbf), u {u['unit']} (= in x {u['from_internal']!r}); "
            "the coefficients are in the internal units\n"
        )
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(["channel", "matrix", "row", "col", "value"])
    for name, ch in doc["channels"].items():
        for mname in ("A", "B", "C", "D"):
            data = np.atleast_2d(np.asarray(ch[mname]["data"], float))
            if mname == "B":
                data = data.T
            for (i, j), v in np.ndenumerate(data):
                writer.writerow([name, mname, i, j, repr(float(v))])
    return buf.getvalue()


def render(
    controller: DiscreteController,
    fmt: str,
    precision: str = "single",
    prefix: str = "imil",
    vs=None,
    design_summary: str = "",
    *,
    limits: CommandLimits | None = None,
    io_units: IOUnits | None = None,
) -> dict[str, str]:
    """``{file name: text}`` of one export format (no file is written).

    Parameters
    ----------
    limits : CommandLimits
        The safety layer's limits (:func:`~impedance_mil.implement.safety.command_limits`);
        required for ``c`` and ``st``.
    io_units : IOUnits, optional
        The units the generated code reads and writes (default the internal units:
        the output is what it was without them); recorded by ``json`` and ``csv``.

    Raises
    ------
    ConfigError
        An unknown format or precision, a prefix that is not an identifier,
        C/ST without ``limits``, or a number (I/O unit factors included) the precision cannot hold
        (:func:`~impedance_mil.implement.safety.check_renderable`), for every
        format: the coefficient files hold the values rounded to the precision.
    """
    if fmt not in FORMATS:
        raise ConfigError("--format", "one of " + ", ".join(FORMATS), fmt)
    precision_dtype(precision)
    for ch in controller.channels:
        check_renderable(ch.name, ch.system_matrix(), precision, COEFFICIENTS)
    check_renderable("loop_time_s", controller.loop_time_s, precision, "a loop time")
    io = io_units or IOUnits.internal()
    io.check(precision)
    if fmt in ("c", "st"):
        if limits is None:
            raise ConfigError("limits", "the safety layer's command limits for generated code")
        if fmt == "c":
            return render_c(
                controller,
                precision,
                prefix,
                vs=vs,
                design_summary=design_summary,
                limits=limits,
                io_units=io,
            ).files
        return render_st(
            controller, precision, prefix, vs=vs, design_summary=design_summary, limits=limits, io_units=io
        )
    check_c_identifier(prefix)
    check_st_identifier(prefix)
    if fmt == "json":
        return {
            f"{prefix}_coefficients.json": json.dumps(
                coefficients_document(controller, precision, io), indent=2
            )
            + "\n"
        }
    return {f"{prefix}_coefficients.csv": coefficients_csv(controller, precision, io)}


def write_directory(files: dict[str, str], out_dir: str | os.PathLike, force: bool = False) -> Path:
    """Write ``files`` into ``out_dir`` atomically (temp dir beside it, then rename).

    ``out_dir`` must not exist, unless it is empty or ``force`` is set (then
    it is replaced only after the new directory is complete).
    """
    target = Path(out_dir)
    if not target.parent.is_dir():
        raise ConfigError("-o", "a directory path inside an existing folder", str(target))
    exists = target.exists()
    if exists and not target.is_dir():
        raise ConfigError("-o", "a directory path (a file of that name exists)", str(target))
    if exists and any(target.iterdir()) and not force:
        raise ConfigError("-o", "a new or empty directory (use --force to replace)", str(target))
    with atomic_directory(target) as tmp:
        for name, text in files.items():
            (tmp / name).write_text(text, encoding="utf-8")
    return target
