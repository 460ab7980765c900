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
    unsigned  P_fault(s), P_active(s); void P_reset(s); int P_check_loop_time(s, measured_s)

Every step runs through the safety layer of :mod:`impedance_mil.implement.safety`
(input and overflow guards that latch and hold the last safe command, the
stroke clamp, the rate limit, the fault word); the guards only compare, so
when none acts the step computes exactly what the runtime computes.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from string import Template

import numpy as np

from ... import __version__ as _pkg_version
from ...errors import ConfigError
from ...virtual.expressions import CONSTANTS, c_dialect
from ...virtual.listing import Language, expression_type, tick_statements, value_types
from ...virtual.system import DefinedVS
from ..discretization import DiscreteController
from ..identifiers import check_c_identifier
from ..io_units import IOUnits
from ..runtime import precision_dtype
from ..safety import (
    COEFFICIENTS,
    FAULT_TEXT,
    HOLD,
    VALUE_LIMIT,
    CommandLimits,
    Fault,
    check_renderable,
    rendered_limits,
)


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


def safety_fields(limits: CommandLimits, loop_time_s: float, precision: str, prefix: str) -> dict[str, str]:
    """Template fields of the safety layer: the limits as C literals and their sources.

    Raises
    ------
    ConfigError
        A limit the precision cannot hold.
    """
    values = rendered_limits(limits, loop_time_s, precision)
    bits = [(f.name, f"0x{int(f):04X}u", FAULT_TEXT[f]) for f in Fault]
    bits.append(("HOLD", f"0x{int(HOLD):04X}u", "the bits that latch and hold the command"))
    return {
        "fault_defines": "\n".join(
            f"#define {prefix.upper()}_FAULT_{n:<12s}{v}  /* {t} */" for n, v, t in bits
        ),
        "stroke_in": f"{limits.stroke_in:.6g}",
        "max_rate": f"{limits.max_rate_in_s:.6g}",
        "du_max": f"{values['du_max']:.6g}",
        "accel_limit": f"{limits.accel_limit_in_s2:.6g}",
        "force_limit": f"{limits.force_limit_lbf:.6g}",
        "value_limit": f"{VALUE_LIMIT[precision]:g}",
        "stroke_source": limits.source("stroke"),
        "rate_source": limits.source("rate"),
        "inputs_source": limits.source("inputs"),
        **{f"{key}_literal": c_literal(value, precision) for key, value in values.items()},
        "loop_time_rtol": repr(limits.loop_time_rtol),
    }


def io_fields(io: IOUnits, limits: CommandLimits, precision: str, prefix: str, rt: str) -> dict[str, str]:
    """Template fields of the I/O units: empty (the code without them) for the internal units.

    Otherwise the step functions become ``static ..._internal`` and public wrappers
    scale at the edges: each input times its ``P_*_TO_INTERNAL`` factor before the
    guards and the controller, the safe command (and the MIL step's ``z_vs``) times
    its ``P_*_FROM_INTERNAL`` factor on output.

    Raises
    ------
    ConfigError
        A factor the precision cannot hold.
    """
    a, f, d = io.units
    fields = dict(
        z_unit=a.unit, w_unit=f.unit, u_unit=d.unit, io_header="", io_ranges="", io_defines="",
        step_static="", step_internal="", io_step="", io_mil_step="",
    )  # fmt: skip
    if io.is_internal:
        return fields
    io.check(precision)
    P = prefix.upper()
    factors = [
        ("ACCEL_TO_INTERNAL", a.to_internal, f"{a.internal} per {a.unit}: z_vs, a_g as read"),
        ("FORCE_TO_INTERNAL", f.to_internal, f"{f.internal} per {f.unit}: w as read"),
        ("DISP_FROM_INTERNAL", d.from_internal, f"{d.unit} per {d.internal}: u as returned"),
        (
            "ACCEL_FROM_INTERNAL",
            a.from_internal,
            f"{a.unit} per {a.internal}: z_vs as the MIL step writes it",
        ),
    ]
    fields.update(
        io_header=(
            f"\n *\n * I/O units ({io.spec}): {io.describe()}, with z_vs of the MIL step in {a.unit}.\n"
            f" * Each input times its {P}_*_TO_INTERNAL factor is in the internal unit above before the\n"
            f" * guards and the controller; the safe command [in] times {P}_DISP_FROM_INTERNAL is in\n"
            f" * {d.unit} on output.  The limits below are in the internal units."
        ),
        io_ranges=f"\n *                   (in the I/O units: {io.input_ranges(limits)})",
        io_defines="\n\n/* I/O units: factors between the lab's units and the internal ones (see above). */\n"
        + "\n".join(f"#define {P}_{n} {c_literal(v, precision)}  /* {t} */" for n, v, t in factors),
        step_static="static ",
        step_internal="_internal",
        io_step=_template("io_step.c.tmpl").substitute(rt=rt, prefix=prefix, PREFIX=P),
        io_mil_step=_template("io_mil_step.c.tmpl").substitute(rt=rt, prefix=prefix, PREFIX=P),
    )
    return fields


def _matrix(m: np.ndarray, precision: str) -> str:
    rows = []
    for row in m:
        rows.append("    {" + ", ".join(c_literal(v, precision) for v in row) + "}")
    return ",\n".join(rows)


def _vs_code(vs, prefix: str, precision: str, loop_time: str) -> dict:
    """Template fields of the VS: its constants and the loop listing of its definition."""
    d = definition_of(vs)
    rt = f"{prefix}_real_t"
    single = precision == "single"
    types = value_types(d)
    consts, inter = set(d.kernel_constants), {n for n, _ in d.intermediates}

    def name(n: str) -> str:
        if n in CONSTANTS:
            return c_literal(CONSTANTS[n], "double")
        if n in consts:
            return f"{prefix}_vs_{n}"
        if n in inter:
            return f"t_{n}"
        return f"s_{n}" if n in d.states else n

    def is_float(node) -> bool:
        return single and expression_type(node, types) == "T"

    arrays = {"x": "s->x_vs", "xs": "xs", "k1": "k1", "k2": "k2", "k3": "k3"}
    lang = Language(
        dialect=c_dialect(name, lambda v: c_literal(v, "double"), f"{prefix}_sign", is_float),
        element=lambda a, i: f"{arrays[a]}[{i}]",
        assign=lambda t, v: f"    {t} = {v};",
        number=lambda v: c_literal(v, "double"),
    )
    values = vs.parameter_array()
    for n, v in zip(d.kernel_constants, values, strict=True):
        check_renderable(f"vs.{n}", v, precision, "a VS parameter")
    params = "\n".join(
        f"static const {rt} {prefix}_vs_{n} = {c_literal(v, precision)};  /* {_label(d, n)} */"
        for n, v in zip(d.kernel_constants, values, strict=True)
    )
    locals_ = [f"    {rt} s_{s};" for s in d.states]
    locals_ += [f"    {'double' if types[n] == 'f64' else rt} t_{n};" for n, _ in d.intermediates]
    unused = [f"    (void)t_{n};" for n, _ in d.intermediates]
    return dict(
        vs_kind=d.kind,
        vs_name=getattr(vs, "name", "") or "",
        vs_title=d.title,
        vs_source=d.source,
        vs_states=" [" + ", ".join(f"{s} [{u}]" for s, u in zip(d.states, d.state_units, strict=True)) + "]",
        vs_params=params,
        vs_locals="\n".join(locals_),
        vs_unused="\n".join(unused),
        vs_body="\n".join(tick_statements(d, lang, "z_vs")),
        n_vs=d.n_states,
        loop_time_literal=loop_time,
        prefix=prefix,
        PREFIX=prefix.upper(),
    )


def _label(d, name: str) -> str:
    for p in d.parameters:
        if p.name == name:
            return f"{p.label} [{p.unit}]"
    for x in d.derived:
        if x.name == name:
            return f"{x.label} [{x.unit}] = {x.expression}"
    return name


def definition_of(vs):
    """The definition of a VS the generators can render (a :class:`~impedance_mil.virtual.DefinedVS`).

    Raises
    ------
    ConfigError
        A VS written as Python methods (no definition to render).
    """
    if not isinstance(vs, DefinedVS):
        raise ConfigError(
            "vs",
            "a virtual system of a defined type (SD, LR, FP, TFP or a user's "
            "VSDefinition) for code generation",
            type(vs).__name__,
        )
    if np.any(np.asarray(vs.initial_state(), float) != 0.0):
        raise ConfigError(
            "vs", "a virtual system starting at rest (generated init zeroes it)", list(vs.initial_state())
        )
    return vs.definition


def render_c(
    controller: DiscreteController,
    precision: str = "single",
    prefix: str = "imil",
    vs=None,
    design_summary: str = "",
    *,
    limits: CommandLimits,
    io_units: IOUnits | None = None,
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
    vs : DefinedVS, optional
        A VS of a defined type (built-in or a user's); adds ``<prefix>_mil_step``
        (Figure 7.9, corrected), rendered from the type's definition.
    design_summary : str
        One line describing the design, copied into the header comment.
    limits : CommandLimits
        The stroke clamp, rate limit and input ranges of the safety layer
        (:func:`impedance_mil.implement.safety.command_limits` derives them
        from a design's table).
    io_units : IOUnits, optional
        The units the step reads and writes (:mod:`impedance_mil.implement.io_units`);
        default the internal units (no scaling).

    Raises
    ------
    ConfigError
        A prefix that is not a C identifier, or a coefficient, VS parameter,
        limit or I/O unit factor the precision cannot hold (:func:`~impedance_mil.implement.safety.check_renderable`).
    """
    check_c_identifier(prefix)
    precision_dtype(precision)
    ctype = "float" if precision == "single" else "double"
    m_z = controller.z.system_matrix()
    m_w = controller.w.system_matrix()
    check_renderable("H_uz", m_z, precision, COEFFICIENTS)
    check_renderable("H_uw", m_w, precision, COEFFICIENTS)
    safety = safety_fields(limits, controller.loop_time_s, precision, prefix)
    n_z, n_w = controller.z.n_states, controller.w.n_states
    n_vs = definition_of(vs).n_states if vs is not None else 0
    loop_time = c_literal(controller.loop_time_s, precision)
    rt = f"{prefix}_real_t"
    io = io_fields(io_units or IOUnits.internal(), limits, precision, prefix, rt)
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
        vs_states=(" [" + ", ".join(definition_of(vs).states) + "]") if vs is not None else "(unused)",
        mil_decl="",
        vs_code="",
        **safety,
        **io,
    )
    if vs is not None:
        fields["mil_decl"] = (
            f"\n/* One MIL loop (Figure 7.9, corrected): z_vs from the VS state, one RK3 step,\n"
            f" * then {prefix}_step(z_vs, w).  Returns u [{io['u_unit']}]; writes z_vs [{io['z_unit']}] "
            "if non-NULL. */\n"
            f"{rt} {prefix}_mil_step({prefix}_state_t *s, {rt} a_g, {rt} w, {rt} *z_vs_out);\n"
            f"void {prefix}_mil_run({prefix}_state_t *s, const {rt} *a_g, const {rt} *w,\n"
            f"                   {rt} *u, {rt} *z_vs, long n);\n"
        )
        fields["vs_code"] = _template("vs.c.tmpl").substitute(
            {**_vs_code(vs, prefix, precision, loop_time), **io}
        )
    header = _template("header.h.tmpl").substitute(fields)
    source = _template("source.c.tmpl").substitute(fields)
    return GeneratedFiles({f"{prefix}.h": header, f"{prefix}.c": source})
