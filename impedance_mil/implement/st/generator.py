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
from ..discretize import DiscreteController
from ..identifiers import check_st_identifier
from ..runtime import precision_dtype
from ..vs_equations import RK3, equations_for, render


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
    eq = equations_for(vs)
    n = len(eq.states)
    lit = lambda v: st_literal(v, precision)  # noqa: E731
    pnames, snames, tnames = set(eq.params), set(eq.states), {t for t, _ in eq.temps}

    def name(x):
        if x in pnames:
            return f"p_{x}"
        if x in snames:
            return f"s_{x}"
        if x in tnames:
            return f"t_{x}"
        return x

    fn = {"abs": "ABS", "exp": "EXP", "pow": "EXPT", "sign": f"{prefix}_sign"}
    ex = lambda e: render(e, name, lit, lambda f, a: f"{fn[f]}({', '.join(a)})")  # noqa: E731
    params = [f"    p_{p} : {real} := {lit(v)};" for p, v in zip(eq.params, vs.parameter_array())]
    rk = [f"    rk_{k} : {real} := {lit(v)};" for k, v in RK3.items()]

    def load(src):
        """State and intermediate values at the state ``src``."""
        return [f"s_{s} := {src}[{i}];" for i, s in enumerate(eq.states)] + [
            f"t_{t} := {ex(e)};" for t, e in eq.temps
        ]

    def derivatives(dst):
        return [f"{dst}[{i}] := {ex(e)};" for i, e in enumerate(eq.derivatives)]

    def stage(src, dst):
        return load(src) + derivatives(dst)

    body = [
        "(* target acceleration from the VS state at the start of the loop *)",
        *load("x_vs"),
        f"z_vs := (w - ({ex(eq.force)})) / p_m_vs;",
        "(* third-order Runge-Kutta step of the VS (Figure 7.9); first stage at x_vs *)",
        *derivatives("k1"),
    ]
    body += [f"xs[{i}] := x_vs[{i}] + rk_a21 * dt * k1[{i}];" for i in range(n)]
    body += stage("xs", "k2")
    body += [f"xs[{i}] := x_vs[{i}] + rk_a32 * dt * k2[{i}];" for i in range(n)]
    body += stage("xs", "k3")
    body += [
        f"x_vs[{i}] := x_vs[{i}] + dt * (rk_b1 * k1[{i}] + rk_b2 * k2[{i}] + rk_b3 * k3[{i}]);"
        for i in range(n)
    ]
    local = [
        *[f"    {k} : ARRAY[0..{n - 1}] OF {real};" for k in ("x_vs", "xs", "k1", "k2", "k3")],
        *[f"    s_{s} : {real};" for s in eq.states],
        *[f"    t_{t} : {real};" for t in tnames],
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
        f"\n(* Figures 7.9-7.11 (corrected): {eq.kind} virtual system "
        f"{getattr(vs, 'name', '') or ''} and the controller in one loop. *)\n"
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
    vs : VirtualSystem, optional
        Built-in SD/LR/FP VS; adds the function block ``<prefix>_mil``.
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
