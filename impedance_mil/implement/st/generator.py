"""Render the discrete MIL controller as IEC 61131-3 Structured Text (report Figures 7.6-7.12).

The generated file holds ``P_sign``, ``P_custom_feedback`` (Figure 7.6),
the function block ``P_controller`` (Figure 7.8 and Step 6, corrected) and,
with a virtual system, ``P_mil`` (Figures 7.9-7.11, corrected: the RK3
block of the VS followed by the controller in the same loop).  Statements
are unrolled, coefficients are named constants (``Az_i_j`` is ``(A - I)``),
and every sum is written in the order of
:mod:`impedance_mil.implement.kernels`, so an IEEE-754 implementation that
evaluates left to right reproduces the runtime.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from importlib import resources
from string import Template

import numpy as np

from ... import __version__ as _pkg_version
from ...virtual.expressions import CONSTANTS, st_dialect
from ...virtual.listing import Language, tick_statements
from ...virtual.stepping import RK3
from ..c.generator import definition_of
from ..discretization import DiscreteController
from ..identifiers import check_st_identifier
from ..io_units import IOUnits
from ..runtime import precision_dtype
from ..safety import COEFFICIENTS, CommandLimits, Fault, check_renderable
from . import guards


def st_literal(value: float, precision: str) -> str:
    """ST real literal equal to ``value`` rounded to the precision (always has a point)."""
    v = float(np.float32(value)) if precision == "single" else float(value)
    text = repr(v)
    if "e" in text and "." not in text.split("e")[0]:
        mant, exp = text.split("e")
        text = f"{mant}.0e{exp}"
    elif "." not in text and "e" not in text:
        text += ".0"
    return text.upper().replace("E+", "E")


@dataclass(frozen=True)
class _Names:
    """The ST names of the values the body computes with, in the internal units.

    Without I/O units they are the block's inputs and outputs; with them, locals
    ``*_int`` that the scan fills from the inputs and converts into the outputs.
    """

    z_vs: str = "z_vs"
    w: str = "w"
    a_g: str = "a_g"
    u: str = "u"
    u_z: str = "u_z"
    u_w: str = "u_w"

    @classmethod
    def of(cls, io: IOUnits) -> _Names:
        if io.is_internal:
            return cls()
        return cls(**{f.name: f"{f.name}_int" for f in fields(cls)})


@dataclass(frozen=True)
class _IOCode:
    """What I/O units add to a block: constants, locals, the scan's first and last statements."""

    constants: list[str]
    variables: list[str]
    inputs: list[str]
    outputs: list[str]


#: Factor constants of the I/O units: (ST name, unit attribute, factor attribute, meaning).
_FACTORS = (
    ("accel_to_internal", "accel", "to_internal", "z_vs, a_g as read"),
    ("force_to_internal", "force", "to_internal", "w as read"),
    ("disp_from_internal", "disp", "from_internal", "u as written"),
    ("accel_from_internal", "accel", "from_internal", "z_vs of the MIL block as written"),
)


def _io_code(io: IOUnits, names: _Names, inputs, outputs, real: str, lit) -> _IOCode:
    """Conversions of ``inputs`` and ``outputs`` (ST names) between the I/O and the internal units."""
    if io.is_internal:
        return _IOCode([], [], [], [])
    factor = {"z_vs": "accel", "a_g": "accel", "w": "force", "u": "disp", "u_z": "disp", "u_w": "disp"}
    constants = ["    (* I/O units: factors between the lab's units and the internal ones *)"]
    for name, key, attr, meaning in _FACTORS:
        unit = getattr(io, key)
        per = (
            f"{unit.internal} per {unit.unit}"
            if attr == "to_internal"
            else f"{unit.unit} per {unit.internal}"
        )
        constants.append(f"    {name} : {real} := {lit(getattr(unit, attr))};  (* {per}: {meaning} *)")
    local = [
        f"    {getattr(names, n)} : {real};  (* {n} [{getattr(io, factor[n]).internal}] *)" for n in inputs
    ]
    local += [
        f"    {getattr(names, n)} : {real};  (* {n} [{getattr(io, factor[n]).internal}] *)" for n in outputs
    ]
    return _IOCode(
        constants,
        local,
        ["(* inputs in the I/O units to the internal units *)"]
        + [f"{getattr(names, n)} := {n} * {factor[n]}_to_internal;" for n in inputs],
        ["(* outputs from the internal units to the I/O units *)"]
        + [f"{n} := {getattr(names, n)} * {factor[n]}_from_internal;" for n in outputs],
    )


def _unit_note(io: IOUnits, key: str) -> str:
    """`` (* [unit] *)`` after an input or output declared in the I/O units (nothing without them)."""
    return "" if io.is_internal else f"  (* [{getattr(io, key).unit}] *)"


def _channel(tag: str, state: str, inp: str, m: np.ndarray, precision: str, real: str):
    """Declarations and statements of one channel (output, then delta-form update)."""
    n = m.shape[0] - 1
    lit = lambda v: st_literal(v, precision)  # noqa: E731
    decls = [f"    {tag}_{i}_{j} : {real} := {lit(m[i, j])};" for i in range(n + 1) for j in range(n + 1)]
    out = " + ".join([f"{tag}_{n}_{n} * {inp}"] + [f"{tag}_{n}_{j} * {state}[{j}]" for j in range(n)])
    upd = []
    for i in range(n):
        terms = [f"{tag}_{i}_{n} * {inp}"] + [f"{tag}_{i}_{j} * {state}[{j}]" for j in range(n)]
        upd.append(f"t[{i}] := {' + '.join(terms)};")
    for i in range(n):
        upd.append(
            f"r := t[{i}] - {state}c[{i}]; s := {state}[{i}] + r; "
            f"{state}c[{i}] := (s - {state}[{i}]) - r; {state}[{i}] := s;"
        )
    arrays = (
        [f"    {state} : ARRAY[0..{n - 1}] OF {real};", f"    {state}c : ARRAY[0..{n - 1}] OF {real};"]
        if n
        else []
    )
    return decls, arrays, out, upd


def _controller(
    controller: DiscreteController, precision: str, real: str, constants=(), variables=(), names=_Names()
):
    """Declarations, state names and the guarded body of the controller.

    ``constants`` and ``variables`` are declaration lines for its VAR CONSTANT
    and VAR sections (the safety layer's, the MIL block's VS).  The body
    computes ``u_raw`` (``u_z + u_w``), updates the states and latches an
    overflow; :func:`guards.command` turns ``u_raw`` into the safe ``u``.
    """
    dz, az, oz, uz = _channel("Az", "X", names.z_vs, controller.z.system_matrix(), precision, real)
    dw, aw, ow, uw = _channel("Aw", "Y", names.w, controller.w.system_matrix(), precision, real)
    nmax = max(controller.z.n_states, controller.w.n_states, 1)
    decls = (
        "VAR CONSTANT\n"
        + "".join(line + "\n" for line in constants)
        + "    (* [[A - I, B], [C, D]] of H_uz (Az) and H_uw (Aw) *)\n"
        + "\n".join(dz + dw)
        + "\nEND_VAR\nVAR\n"
        + "\n".join(az + aw)
        + f"\n    t : ARRAY[0..{nmax - 1}] OF {real};\n    r : {real};\n    s : {real};"
        + f"\n    u_raw : {real};\n    u_safe : {real};"
        + "".join("\n" + line for line in variables)
        + "\nEND_VAR"
    )
    states = [
        f"{a}[{i}]" for a, n in (("X", controller.z.n_states), ("Y", controller.w.n_states)) for i in range(n)
    ]
    body = [
        "    (* control input (position command), before the clamp and the rate limit *)",
        f"    {names.u_z} := {oz};",
        f"    {names.u_w} := {ow};",
        f"    u_raw := {names.u_z} + {names.u_w};",
        "    (* update of the controller states: H_uz with z_vs, H_uw with w *)",
        *[f"    {line}" for line in uz + uw],
        *guards.overflow(["u_raw", *states]),
    ]
    compensation = [
        f"{a}c[{i}]"
        for a, n in (("X", controller.z.n_states), ("Y", controller.w.n_states))
        for i in range(n)
    ]
    return decls, states + compensation, body


def _guarded(prefix_lines: list[str], body: list[str], extra_hold=(), u="u", outputs=()) -> str:
    """The scan: reset, loop-time and input checks, the body when no fault holds, the command."""
    return "\n".join(
        [
            *prefix_lines,
            f"IF (fault AND F_HOLD) = {guards.word(0)} THEN",
            *body,
            "END_IF;",
            *guards.command(extra_hold, u),
            *outputs,
        ]
    )


def _mil_block(controller, vs, prefix, precision, real, limits, io: IOUnits) -> str:
    d = definition_of(vs)
    n = d.n_states
    lit = lambda v: st_literal(v, precision)  # noqa: E731
    names = replace(_Names.of(io), u_z="u_z", u_w="u_w")  # u_z, u_w are locals here
    io_code = _io_code(io, names, ("a_g", "w"), ("u", "z_vs"), real, lit)
    consts, inter = set(d.kernel_constants), {t for t, _ in d.intermediates}

    def name(x: str) -> str:
        if x in CONSTANTS:
            return lit(CONSTANTS[x])
        if x in consts:
            return f"p_{x}"
        if x in inter:
            return f"t_{x}"
        if x in ("a_g", "w"):
            return getattr(names, x)
        return f"s_{x}" if x in d.states else x

    # the RK3 coefficients are named constants (rk_a21 ... rk_b3), as in the report's program
    coefficients = {f"rk_a{s + 1}{j + 1}": c for s, row in enumerate(RK3.a) for j, c in enumerate(row) if c}
    coefficients.update({f"rk_b{j + 1}": c for j, c in enumerate(RK3.b)})
    by_value = {c: k for k, c in reversed(coefficients.items())}

    def number(v: float) -> str:
        return by_value[v]

    lang = Language(
        dialect=st_dialect(name, lit, f"{prefix}_sign"),
        element=lambda a, i: f"{a if a != 'x' else 'x_vs'}[{i}]",
        assign=lambda t, v: f"{t} := {v};",
        number=number,
    )
    for p, v in zip(d.kernel_constants, vs.parameter_array(), strict=True):
        check_renderable(f"vs.{p}", v, precision, "a VS parameter")
    params = [
        f"    p_{p} : {real} := {lit(v)};"
        for p, v in zip(d.kernel_constants, vs.parameter_array(), strict=True)
    ]
    rk = [f"    {k} : {real} := {lit(v)};" for k, v in coefficients.items()]
    local = [
        *[f"    {k} : ARRAY[0..{n - 1}] OF {real};" for k in ("x_vs", "xs", "k1", "k2", "k3")],
        *[f"    s_{s} : {real};" for s in d.states],
        *[f"    t_{t} : {real};" for t, _ in d.intermediates],
        f"    u_z : {real};",
        f"    u_w : {real};",
        f"    z_safe : {real};",
    ]
    cdecls, cstates, cbody = _controller(
        controller,
        precision,
        real,
        constants=[
            f"    dt : {real} := {lit(controller.loop_time_s)};",
            *params,
            *rk,
            *guards.constants(limits, controller.loop_time_s, precision, real, lit),
            *io_code.constants,
        ],
        variables=local + io_code.variables,
        names=names,
    )
    x_vs = [f"x_vs[{i}]" for i in range(n)]
    vs_range = (
        f"({guards.out_of_range([names.z_vs], 'accel_limit')}) OR "
        f"({guards.out_of_range(x_vs, 'value_limit')})"
    )
    body = [
        "    (* target acceleration from the VS state at the start of the loop, then the third-order",
        "       Runge-Kutta step of the VS (Figure 7.9), generated from its definition *)",
        *[f"    {line}" for line in tick_statements(d, lang, names.z_vs)],
        "    (* the VS target and states are internal values: out of range, they hold *)",
        f"    IF {vs_range} THEN",
        f"        active := active OR {guards.BIT_NAMES[Fault.OVERFLOW]};",
        "        fault := fault OR active;",
        "    ELSE",
        f"        z_safe := {names.z_vs};",
        *[f"    {line}" for line in cbody],
        "    END_IF;",
    ]
    scan = _guarded(
        [
            *guards.reset_block([*cstates, *x_vs]),
            *io_code.inputs,
            *guards.input_checks([(names.a_g, "accel_limit"), (names.w, "force_limit")]),
        ],
        body,
        extra_hold=[f"{names.z_vs} := z_safe;"],
        u=names.u,
        outputs=io_code.outputs,
    )
    return (
        f"\n(* Figures 7.9-7.11 (corrected): {d.kind} virtual system ({d.title}; {d.source}) "
        f"and the controller in one loop.  States: {', '.join(d.states)}. *)\n"
        f"FUNCTION_BLOCK {prefix}_mil\n{_mil_interface(real, io)}{cdecls}\n" + scan + "\nEND_FUNCTION_BLOCK\n"
    )


def _mil_interface(real: str, io: IOUnits) -> str:
    """VAR_INPUT and VAR_OUTPUT of the MIL block, each in its I/O unit."""
    return (
        f"VAR_INPUT\n    a_g : {real};{_unit_note(io, 'accel')}\n"
        f"    w : {real};{_unit_note(io, 'force')}\n{_SAFETY_INPUTS.format(real=real)}END_VAR\n"
        f"VAR_OUTPUT\n    u : {real};{_unit_note(io, 'disp')}\n    z_vs : {real};{_unit_note(io, 'accel')}\n"
        f"{_SAFETY_OUTPUTS}END_VAR\n"
    )


#: Inputs and outputs of the safety layer, in both function blocks.
_SAFETY_INPUTS = (
    "    loop_time_s : {real} := 0.0;  (* measured loop time [s]; 0.0: not checked *)\n"
    "    reset : BOOL := FALSE;  (* TRUE for one scan: clear the faults, controller at rest *)\n"
)
_SAFETY_OUTPUTS = (
    "    fault : WORD;  (* latched and sticky bits (F_...) *)\n    active : WORD;  (* this scan's bits *)\n"
)


def render_st(
    controller: DiscreteController,
    precision: str = "single",
    prefix: str = "imil",
    vs=None,
    design_summary: str = "",
    *,
    limits: CommandLimits,
    io_units: IOUnits | None = None,
) -> dict:
    """Generate ``{"<prefix>.st": text}``.

    Parameters
    ----------
    controller : DiscreteController
        The discrete controller.
    precision : {"single", "double"}
        ``REAL`` (32-bit, as the RMC75E) or ``LREAL``.
    prefix : str
        IEC 61131-3 identifier prefixed to every POU name.
    vs : DefinedVS, optional
        A VS of a defined type; adds the function block ``<prefix>_mil``, rendered
        from the type's definition.
    design_summary : str
        One line describing the design (copied into the header comment).
    limits : CommandLimits
        The stroke clamp, rate limit and input ranges of the safety layer
        (:mod:`impedance_mil.implement.st.guards`).
    io_units : IOUnits, optional
        The units the blocks read and write (:mod:`impedance_mil.implement.io_units`);
        default the internal units (no scaling).

    Raises
    ------
    ConfigError
        A prefix that is not an ST identifier, or a coefficient, VS parameter,
        limit or I/O unit factor the precision cannot hold.
    """
    check_st_identifier(prefix)
    precision_dtype(precision)
    real = "REAL" if precision == "single" else "LREAL"
    check_renderable("H_uz", controller.z.system_matrix(), precision, COEFFICIENTS)
    check_renderable("H_uw", controller.w.system_matrix(), precision, COEFFICIENTS)
    lit = lambda v: st_literal(v, precision)  # noqa: E731
    io = io_units or IOUnits.internal()
    io.check(precision)
    names = _Names.of(io)
    io_code = _io_code(io, names, ("z_vs", "w"), ("u", "u_z", "u_w"), real, lit)
    safety = guards.constants(limits, controller.loop_time_s, precision, real, lit) + io_code.constants
    decls, states, body = _controller(
        controller, precision, real, constants=safety, variables=io_code.variables, names=names
    )
    scan = _guarded(
        [
            *guards.reset_block(states),
            *io_code.inputs,
            *guards.input_checks([(names.z_vs, "accel_limit"), (names.w, "force_limit")]),
        ],
        body,
        u=names.u,
        outputs=io_code.outputs,
    )
    text = Template(
        resources.files(__package__).joinpath("templates", "program.st.tmpl").read_text()
    ).substitute(
        prefix=prefix,
        software_version=_pkg_version,
        loop_time_s=repr(controller.loop_time_s),
        method=controller.method,
        precision=precision,
        real=real,
        design_summary=design_summary or "(not recorded)",
        io_units=_io_paragraph(io, prefix),
        z_note=_unit_note(io, "accel"),
        w_note=_unit_note(io, "force"),
        u_note=_unit_note(io, "disp"),
        safety_header=guards.header(limits, controller.loop_time_s, io),
        safety_inputs=_SAFETY_INPUTS.format(real=real),
        safety_outputs=_SAFETY_OUTPUTS,
        controller_decls=decls,
        controller_body=scan,
        mil_block=_mil_block(controller, vs, prefix, precision, real, limits, io) if vs is not None else "",
    )
    return {f"{prefix}.st": text}


def _io_paragraph(io: IOUnits, prefix: str) -> str:
    """The program comment's line on units (the I/O units and the internal ones, when they differ)."""
    internal = "z_vs, a_g [in/s^2]; w [lbf]; u [in]"
    if io.is_internal:
        return f"Units: {internal}."
    a, f, d = io.units
    return (
        f"I/O units ({io.spec}): z_vs, a_g [{a.unit}]; w [{f.unit}]; u, u_z, u_w [{d.unit}]\n"
        f"   (z_vs of {prefix}_mil [{a.unit}]).  Each input times its *_to_internal constant is in\n"
        f"   the internal units before the guards and the controller: {internal};\n"
        "   each output is converted back by its *_from_internal constant.  The limits are internal.\n "
    )
