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

from importlib import resources
from string import Template

import numpy as np

from ... import __version__ as _pkg_version
from ...virtual.expressions import CONSTANTS, st_dialect
from ...virtual.listing import Language, tick_statements
from ...virtual.stepping import RK3
from ..c.generator import definition_of
from ..discretize import DiscreteController
from ..identifiers import check_st_identifier
from ..runtime import precision_dtype


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


def _controller(controller: DiscreteController, precision: str, real: str, constants=(), variables=()):
    """Declarations and body of the controller; ``constants`` and ``variables`` are extra
    declaration lines for its VAR CONSTANT and VAR sections (the MIL block's VS)."""
    dz, az, oz, uz = _channel("Az", "X", "z_vs", controller.z.system_matrix(), precision, real)
    dw, aw, ow, uw = _channel("Aw", "Y", "w", controller.w.system_matrix(), precision, real)
    nmax = max(controller.z.n_states, controller.w.n_states, 1)
    decls = (
        "VAR CONSTANT\n"
        + "".join(line + "\n" for line in constants)
        + "    (* [[A - I, B], [C, D]] of H_uz (Az) and H_uw (Aw) *)\n"
        + "\n".join(dz + dw)
        + "\nEND_VAR\nVAR\n"
        + "\n".join(az + aw)
        + f"\n    t : ARRAY[0..{nmax - 1}] OF {real};\n    r : {real};\n    s : {real};"
        + "".join("\n" + line for line in variables)
        + "\nEND_VAR"
    )
    body = [
        "(* control input (position command) *)",
        f"u_z := {oz};",
        f"u_w := {ow};",
        "u := u_z + u_w;",
        "(* update of the controller states: H_uz with z_vs, H_uw with w *)",
        *uz,
        *uw,
    ]
    return decls, "\n".join(body)


def _mil_block(controller, vs, prefix, precision, real) -> str:
    d = definition_of(vs)
    n = d.n_states
    lit = lambda v: st_literal(v, precision)  # noqa: E731
    consts, inter = set(d.kernel_constants), {t for t, _ in d.intermediates}

    def name(x: str) -> str:
        if x in CONSTANTS:
            return lit(CONSTANTS[x])
        if x in consts:
            return f"p_{x}"
        if x in inter:
            return f"t_{x}"
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
    body = [
        "(* target acceleration from the VS state at the start of the loop, then the third-order",
        "   Runge-Kutta step of the VS (Figure 7.9), generated from its definition *)",
        *tick_statements(d, lang, "z_vs"),
    ]
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
    ]
    cdecls, cbody = _controller(
        controller,
        precision,
        real,
        constants=[f"    dt : {real} := {lit(controller.loop_time_s)};", *params, *rk],
        variables=local,
    )
    return (
        f"\n(* Figures 7.9-7.11 (corrected): {d.kind} virtual system ({d.title}; {d.source}) "
        f"and the controller in one loop.  States: {', '.join(d.states)}. *)\n"
        f"FUNCTION_BLOCK {prefix}_mil\nVAR_INPUT\n    a_g : {real};\n    w : {real};\nEND_VAR\n"
        f"VAR_OUTPUT\n    u : {real};\n    z_vs : {real};\nEND_VAR\n{cdecls}\n"
        + "\n".join(body)
        + "\n"
        + cbody
        + "\nEND_FUNCTION_BLOCK\n"
    )


def render_st(
    controller: DiscreteController,
    precision: str = "single",
    prefix: str = "imil",
    vs=None,
    design_summary: str = "",
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
    """
    check_st_identifier(prefix)
    precision_dtype(precision)
    real = "REAL" if precision == "single" else "LREAL"
    decls, body = _controller(controller, precision, real)
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
        controller_decls=decls,
        controller_body=body,
        mil_block=_mil_block(controller, vs, prefix, precision, real) if vs is not None else "",
    )
    return {f"{prefix}.st": text}
