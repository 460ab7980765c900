"""The built-in virtual systems' equations as expressions, for the code generators.

The numba kernels of :mod:`impedance_mil.virtual.kernels` are the single
definition of the VS dynamics; this module transcribes their documented
equations (same parameter and state layout, same order of operations) into
small Python-syntax expressions that the C and ST generators render.  The
tests compile the rendered C and compare it with the kernels (bit for bit in
double precision), so a change on either side that is not mirrored fails.

Names: parameters as in ``kernels.PARAM_NAMES``, states as in
``kernels.STATE_NAMES``, inputs ``a_g`` [in/s**2] and ``w`` [lbf];
functions ``abs``, ``exp``, ``pow``, ``sign``.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from dataclasses import dataclass

from ..errors import ConfigError
from ..virtual import kernels as vk

#: RK3 tableau of the report's programs (Figure 7.9), as the kernels use it.
RK3 = {"a21": vk.RK3_A21, "a32": vk.RK3_A32, "b1": vk.RK3_B1, "b2": vk.RK3_B2, "b3": vk.RK3_B3}


@dataclass(frozen=True)
class VSEquations:
    """Equations of one built-in VS kind.

    Attributes
    ----------
    kind : str
        ``"SD"``, ``"LR"`` or ``"FP"``.
    kind_code : int
        Kernel kind code.
    params, states : tuple of str
        Parameter and state names (kernel layouts).
    temps : tuple of (str, str)
        Intermediate values (name, expression) computed from params and state.
    force : str
        Isolator shear force F [lbf]; ``z_vs = (w - F)/m_vs``.
    derivatives : tuple of str
        dx/dt per state.
    """

    kind: str
    kind_code: int
    params: tuple
    states: tuple
    temps: tuple
    force: str
    derivatives: tuple


_BW = "inv_uy*0.5*pow(abs(h), n)*(1.0 + sign(v*h))*v"

EQUATIONS = {
    vk.KIND_SD: VSEquations(
        "SD",
        vk.KIND_SD,
        vk.PARAM_NAMES[vk.KIND_SD],
        vk.STATE_NAMES[vk.KIND_SD],
        (),
        "k_s*x + c*v",
        ("v", "(w - k_s*x - c*v)/m_vs - a_g"),
    ),
    vk.KIND_LR: VSEquations(
        "LR",
        vk.KIND_LR,
        vk.PARAM_NAMES[vk.KIND_LR],
        vk.STATE_NAMES[vk.KIND_LR],
        (("inv_uy", "(1.0 - alpha)*k_i/q_d"),),
        "alpha*k_i*x + c*v + q_d*h",
        ("v", "(w - alpha*k_i*x - c*v - q_d*h)/m_vs - a_g", "inv_uy*v - " + _BW),
    ),
    vk.KIND_FP: VSEquations(
        "FP",
        vk.KIND_FP,
        vk.PARAM_NAMES[vk.KIND_FP],
        vk.STATE_NAMES[vk.KIND_FP],
        (("mu", "mu_max - (mu_max - mu_min)*exp(-a*abs(v))"), ("inv_uy", "1.0/u_y")),
        "k_s*x + mu*W*h",
        ("v", "(w - k_s*x - mu*W*h)/m_vs - a_g", "inv_uy*v - " + _BW),
    ),
}


def equations_for(vs) -> VSEquations:
    """The :class:`VSEquations` of a built-in virtual system object."""
    eq = EQUATIONS.get(int(getattr(vs, "kind_code", -1)))
    if eq is None:
        raise ConfigError(
            "vs", "a built-in virtual system (SD, LR or FP) for code generation", type(vs).__name__
        )
    return eq


_PREC = {ast.Add: 1, ast.Sub: 1, ast.Mult: 2, ast.Div: 2}
_OPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}


def render(
    expr: str, name: Callable[[str], str], number: Callable[[float], str], call: Callable[[str, list], str]
) -> str:
    """Render a Python-syntax expression, keeping its evaluation order exactly.

    Parameters
    ----------
    expr : str
        Expression over names, numbers, + - * / and calls.
    name, number, call : callable
        Renderers for a variable name, a numeric literal, and a function call
        (function name, rendered arguments).
    """

    def go(node, parent_prec=0, right=False):
        if isinstance(node, ast.BinOp):
            p = _PREC[type(node.op)]
            text = f"{go(node.left, p)} {_OPS[type(node.op)]} {go(node.right, p, True)}"
            return f"({text})" if p < parent_prec or (right and p == parent_prec) else text
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            return f"(-{go(node.operand, 3)})"
        if isinstance(node, ast.Name):
            return name(node.id)
        if isinstance(node, ast.Constant):
            return number(float(node.value))
        if isinstance(node, ast.Call):
            return call(node.func.id, [go(a) for a in node.args])
        raise ConfigError("expression", "arithmetic on names and numbers", ast.dump(node))

    return go(ast.parse(expr, mode="eval").body)
