"""Render the discrete MIL controller (and optionally its VS) as portable C99.

The generated code performs exactly the operations of
:mod:`impedance_mil.implement.kernels` (and, for ``P_mil_step``, of the
virtual package's RK3 kernel) in the same order and precision, so the
shared library built from it reproduces :class:`MILRuntime` bit for bit in
the controller (``tests/implement/test_codegen_c.py``).

API of the generated code, for prefix ``P``::

    typedef struct {...} P_state_t;
    void      P_init(P_state_t *s);
    P_real_t  P_step(P_state_t *s, P_real_t z_vs, P_real_t w);      u [in]
    P_real_t  P_mil_step(P_state_t *s, P_real_t a_g, P_real_t w, P_real_t *z_vs);  (with a VS)
    void      P_run / P_mil_run (whole records), size_t P_state_size(void)
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from string import Template

import numpy as np

from ... import __version__ as _pkg_version
from ...errors import ConfigError
from ..discretize import DiscreteController
from ..identifiers import check_c_identifier
from ..runtime import precision_dtype
from ..vs_equations import RK3, equations_for, render


@dataclass(frozen=True)
class GeneratedFiles:
    """Generated source files: ``{file name: text}``."""

    files: dict

    def write(self, directory) -> None:
        """Write every file into ``directory`` (which must exist)."""
        for name, text in self.files.items():
            (directory / name).write_text(text)


def _template(name: str) -> Template:
    return Template(resources.files(__package__).joinpath("templates", name).read_text())


def c_literal(value: float, precision: str) -> str:
    """C literal that parses to exactly ``value`` rounded to the precision."""
    if precision == "single":
        text = repr(float(np.float32(value)))
        return text + ("f" if any(ch in text for ch in ".e") else ".0f")
    text = repr(float(value))
    return text if any(ch in text for ch in ".e") else text + ".0"


def _matrix(m: np.ndarray, precision: str) -> str:
    rows = []
    for row in m:
        rows.append("    {" + ", ".join(c_literal(v, precision) for v in row) + "}")
    return ",\n".join(rows)


def _vs_code(vs, prefix: str, precision: str, loop_time: str) -> dict:
    eq = equations_for(vs)
    if np.any(np.asarray(vs.initial_state(), float) != 0.0):
        raise ConfigError(
            "vs", "a virtual system starting at rest (generated init zeroes it)", list(vs.initial_state())
        )
    suffix = "f" if precision == "single" else ""
    funcs = {"abs": f"fabs{suffix}", "exp": f"exp{suffix}", "pow": f"pow{suffix}", "sign": f"{prefix}_sign"}
    pnames = set(eq.params)

    def name(n):
        return f"{prefix}_vs_{n}" if n in pnames else n

    def expr(e):
        return render(
            e, name, lambda v: c_literal(v, precision), lambda f, args: f"{funcs[f]}({', '.join(args)})"
        )

    values = vs.parameter_array()
    rt = f"{prefix}_real_t"
    params = "\n".join(
        f"static const {rt} {prefix}_vs_{n} = {c_literal(v, precision)};" for n, v in zip(eq.params, values)
    )
    locals_ = "\n".join(f"    const {rt} {s} = s_x[{i}];" for i, s in enumerate(eq.states))
    locals_ += "\n" + "\n".join(f"    (void){s};" for s in eq.states)
    temps = "\n".join(f"    const {rt} {n} = {expr(e)};" for n, e in eq.temps)
    temps += "\n" + "\n".join(f"    (void){n};" for n, _ in eq.temps)
    derivs = "\n".join(f"    dx[{i}] = {expr(e)};" for i, e in enumerate(eq.derivatives))
    fields = dict(
        vs_kind=eq.kind,
        vs_name=getattr(vs, "name", "") or "",
        vs_params=params,
        vs_state_locals=locals_,
        vs_temps=temps,
        vs_force=expr(eq.force),
        vs_derivs=derivs,
        n_vs=len(eq.states),
        loop_time_literal=loop_time,
        prefix=prefix,
        **{k: c_literal(v, precision) for k, v in RK3.items()},
    )
    return fields


def render_c(
    controller: DiscreteController,
    precision: str = "single",
    prefix: str = "imil",
    vs=None,
    design_summary: str = "",
) -> GeneratedFiles:
    """Generate ``<prefix>.h`` and ``<prefix>.c``.

    Parameters
    ----------
    controller : DiscreteController
        The discrete controller (Section 6.5, Step 5).
    precision : {"single", "double"}
        ``float`` or ``double`` arithmetic.
    prefix : str
        C identifier prefixed to every exported name.
    vs : VirtualSystem, optional
        Built-in SD/LR/FP VS; adds ``<prefix>_mil_step`` (Figure 7.9, corrected).
    design_summary : str
        One line describing the design, copied into the header comment.
    """
    check_c_identifier(prefix)
    precision_dtype(precision)
    ctype = "float" if precision == "single" else "double"
    m_z = controller.z.system_matrix()
    m_w = controller.w.system_matrix()
    n_z, n_w = controller.z.n_states, controller.w.n_states
    n_vs = len(equations_for(vs).states) if vs is not None else 0
    loop_time = c_literal(controller.loop_time_s, precision)
    fields = dict(
        prefix=prefix,
        PREFIX=prefix.upper(),
        guard=f"{prefix.upper()}_H_INCLUDED",
        software_version=_pkg_version,
        loop_time_s=repr(controller.loop_time_s),
        loop_time_literal=loop_time,
        method=controller.method,
        precision=precision,
        design_summary=design_summary or "(not recorded)",
        ctype=ctype,
        n_z=n_z,
        n_w=n_w,
        n_vs=n_vs,
        n_z1=n_z + 1,
        n_w1=n_w + 1,
        dim_z=max(n_z, 1),
        dim_w=max(n_w, 1),
        dim_vs=max(n_vs, 1),
        dim_max=max(n_z, n_w, 1),
        n_int=controller.z.n_integrators,
        mz=_matrix(m_z, precision),
        mw=_matrix(m_w, precision),
        vs_states=(" [" + ", ".join(equations_for(vs).states) + "]") if vs is not None else "(unused)",
        math_include="#include <math.h>" if vs is not None else "",
        mil_decl="",
        vs_code="",
    )
    if vs is not None:
        rt = f"{prefix}_real_t"
        fields["mil_decl"] = (
            f"\n/* One MIL loop (Figure 7.9, corrected): z_vs from the VS state, one RK3 step,\n"
            f" * then {prefix}_step(z_vs, w).  Returns u [in]; writes z_vs [in/s^2] if non-NULL. */\n"
            f"{rt} {prefix}_mil_step({prefix}_state_t *s, {rt} a_g, {rt} w, {rt} *z_vs_out);\n"
            f"void {prefix}_mil_run({prefix}_state_t *s, const {rt} *a_g, const {rt} *w,\n"
            f"                   {rt} *u, {rt} *z_vs, long n);\n"
        )
        fields["vs_code"] = _template("vs.c.tmpl").substitute(_vs_code(vs, prefix, precision, loop_time))
    header = _template("header.h.tmpl").substitute(fields)
    source = _template("source.c.tmpl").substitute(fields)
    return GeneratedFiles({f"{prefix}.h": header, f"{prefix}.c": source})
