"""The small expression language of virtual-system definitions, and its renderers.

A VS definition (:mod:`impedance_mil.virtual.definition`) writes its equations
as strings in a restricted Python syntax::

    "(w - k_s*x - c*v)/m_vs - a_g"
    "inv_uy*0.5*pow(abs(h), n)*(1.0 + sign(v*h))*v"
    "where(abs(u) > d, k_gap*(abs(u) - d)*sign(u), 0.0)"

Allowed: names, numbers, ``+ - * /``, unary minus, parentheses, and the
functions ``abs``, ``exp``, ``sqrt``, ``pow``, ``sign``, ``min``, ``max`` and
``where(condition, if_true, if_false)``, whose condition is one comparison
(``< <= > >=``).  Nothing else parses (no ``**``: write ``pow``; no
attribute access, subscripts, lambdas or calls of other functions).

Each expression is rendered, with its evaluation order kept exactly (the same
operations in the same order, so that the numba kernel, the generated C and
the generated Structured Text compute the same IEEE-754 results), by
:func:`render` with a :class:`Dialect`: :data:`PYTHON` (also compiled by
numba), :func:`c_dialect` and :func:`st_dialect`.
"""

from __future__ import annotations

import ast
import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

from ..errors import ConfigError
from ..units import G0, TWO_PI

#: Functions of the language and their number of arguments.
FUNCTIONS: dict[str, int] = {
    "abs": 1,
    "exp": 1,
    "sqrt": 1,
    "pow": 2,
    "sign": 1,
    "min": 2,
    "max": 2,
    "where": 3,
}
#: Named constants every expression may use (values in internal units).
CONSTANTS: dict[str, float] = {"pi": math.pi, "two_pi": TWO_PI, "g0": G0}

_PREC = {ast.Add: 1, ast.Sub: 1, ast.Mult: 2, ast.Div: 2}
_OPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}
_CMP = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">="}


class ExpressionError(ConfigError):
    """An expression of a VS definition that is not in the language (names the symbol)."""


@dataclass(frozen=True)
class Dialect:
    """How one target language writes names, numbers, operators and functions.

    Attributes
    ----------
    name : callable
        Variable name -> target text.
    number : callable
        Float literal -> target text (must parse back to exactly that value).
    call : callable
        (function name, rendered arguments, argument nodes) -> target text
        (the nodes let a typed target choose a function by argument type).
    compare : callable
        (left, operator, right) -> text of a comparison (the condition of ``where``).
    """

    name: Callable[[str], str]
    number: Callable[[float], str]
    call: Callable[[str, list[str], list[ast.expr]], str]
    compare: Callable[[str, str, str], str]


@lru_cache(maxsize=4096)
def parse(text: str, where: str = "expression", condition: bool = False) -> ast.expr:
    """Parse and check one expression (cached; the tree is never modified).

    ``condition``: the expression is one comparison (a rule on parameters).

    Raises
    ------
    ExpressionError
        Syntax outside the language, an unknown function, a wrong number of
        arguments, or a non-finite literal (``where`` names the expression).
    """
    if not isinstance(text, str) or not text.strip():
        raise ExpressionError(where, "an expression (a non-empty string)", text)
    try:
        tree = ast.parse(text.strip(), mode="eval").body
    except SyntaxError as exc:
        raise ExpressionError(where, f"an arithmetic expression ({exc.msg})", text) from None
    if condition and not isinstance(tree, ast.Compare):
        raise ExpressionError(where, "one comparison (<, <=, >, >=)", text)
    _check(tree, where, in_condition=condition)
    return tree


def _check(node: ast.AST, where: str, in_condition: bool) -> None:
    if isinstance(node, ast.BinOp) and type(node.op) in _PREC:
        _check(node.left, where, False)
        _check(node.right, where, False)
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
        _check(node.operand, where, False)
    elif isinstance(node, ast.Name):
        if node.id.startswith("_"):
            raise ExpressionError(where, "names that do not start with an underscore", node.id)
    elif isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, int | float):
            raise ExpressionError(where, "numbers and names only", node.value)
        if not math.isfinite(float(node.value)):
            raise ExpressionError(where, "finite numbers (a literal is not finite)", node.value)
    elif isinstance(node, ast.Call):
        fname = node.func.id if isinstance(node.func, ast.Name) else None
        if fname not in FUNCTIONS or node.keywords:
            raise ExpressionError(where, "functions " + ", ".join(FUNCTIONS), ast.unparse(node.func))
        if len(node.args) != FUNCTIONS[fname]:
            raise ExpressionError(where, f"{FUNCTIONS[fname]} argument(s) to {fname}()", len(node.args))
        for i, arg in enumerate(node.args):
            _check(arg, where, fname == "where" and i == 0)
    elif isinstance(node, ast.Compare) and in_condition:
        if len(node.ops) != 1 or type(node.ops[0]) not in _CMP:
            raise ExpressionError(where, "one comparison (<, <=, >, >=) as the condition of where()")
        _check(node.left, where, False)
        _check(node.comparators[0], where, False)
    else:
        raise ExpressionError(
            where, "arithmetic on names and numbers (+ - * /, functions)", ast.unparse(node)
        )
    if (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Name)
        and node.func.id == "where"
        and not isinstance(node.args[0], ast.Compare)
    ):
        raise ExpressionError(
            where, "a comparison as the first argument of where()", ast.unparse(node.args[0])
        )


def names(text: str, where: str = "expression", condition: bool = False) -> frozenset[str]:
    """The variable names an expression uses (functions excluded)."""
    tree = parse(text, where, condition)
    return frozenset(n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and n.id not in FUNCTIONS)


def render(text: str, dialect: Dialect, where: str = "expression", condition: bool = False) -> str:
    """Render an expression in a target language, keeping its evaluation order exactly.

    Parentheses are written where the target needs them to evaluate the tree
    as Python does (left to right within a precedence level), and nowhere else.
    """

    def go(node, parent_prec=0, right=False):
        if isinstance(node, ast.BinOp):
            p = _PREC[type(node.op)]
            text = f"{go(node.left, p)} {_OPS[type(node.op)]} {go(node.right, p, True)}"
            return f"({text})" if p < parent_prec or (right and p == parent_prec) else text
        if isinstance(node, ast.UnaryOp):
            inner = go(node.operand, 3)
            return f"(-{inner})" if isinstance(node.op, ast.USub) else inner
        if isinstance(node, ast.Name):
            return dialect.name(node.id)
        if isinstance(node, ast.Constant):
            return dialect.number(float(node.value))
        if isinstance(node, ast.Compare):
            return dialect.compare(go(node.left), _CMP[type(node.ops[0])], go(node.comparators[0]))
        return dialect.call(node.func.id, [go(a) for a in node.args], node.args)

    return go(parse(text, where, condition))


def _python_call(fn: str, args: list[str], nodes: list[ast.expr]) -> str:
    if fn == "pow":
        # ``a ** b`` as the hand-written kernels wrote it (numba lowers both to pow)
        return f"({args[0]}) ** ({args[1]})"
    if fn == "where":
        return f"(({args[1]}) if {args[0]} else ({args[2]}))"
    return {"exp": "math.exp", "sqrt": "math.sqrt", "sign": "_sign"}.get(fn, fn) + f"({', '.join(args)})"


def python_dialect(name: Callable[[str], str]) -> Dialect:
    """Python source (also compiled by numba); needs ``math`` and a ``_sign`` helper in scope."""
    return Dialect(name, lambda v: repr(float(v)), _python_call, lambda a, op, b: f"{a} {op} {b}")


def c_dialect(
    name: Callable[[str], str],
    number: Callable[[float], str],
    sign: str,
    is_float: Callable[[ast.expr], bool],
) -> Dialect:
    """C99 (``<math.h>``); ``sign`` is the sign helper.

    ``is_float(node)`` tells whether an argument is evaluated in ``float``: a
    call whose arguments all are uses the ``float`` function (``expf`` ...),
    as numba does for float32 arguments; otherwise the ``double`` one.
    """
    base = {"abs": "fabs", "exp": "exp", "sqrt": "sqrt", "pow": "pow", "min": "fmin", "max": "fmax"}

    def call(fn: str, args: list[str], nodes: list[ast.expr]) -> str:
        if fn == "where":
            return f"(({args[0]}) ? ({args[1]}) : ({args[2]}))"
        if fn == "sign":
            return f"{sign}({args[0]})"
        suffix = "f" if all(is_float(n) for n in nodes) else ""
        return f"{base[fn]}{suffix}({', '.join(args)})"

    return Dialect(name, number, call, lambda a, op, b: f"{a} {op} {b}")


def st_dialect(name: Callable[[str], str], number: Callable[[float], str], sign: str) -> Dialect:
    """IEC 61131-3 Structured Text; ``where`` becomes ``SEL(G, IN0, IN1)`` (IN1 when G is TRUE)."""
    fns = {
        "abs": "ABS",
        "exp": "EXP",
        "sqrt": "SQRT",
        "pow": "EXPT",
        "sign": sign,
        "min": "MIN",
        "max": "MAX",
    }

    def call(fn: str, args: list[str], nodes: list[ast.expr]) -> str:
        if fn == "where":
            return f"SEL({args[0]}, {args[2]}, {args[1]})"
        return f"{fns[fn]}({', '.join(args)})"

    return Dialect(name, number, call, lambda a, op, b: f"({a} {op} {b})")
