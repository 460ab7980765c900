"""The statements of one VS loop, for any target language (numba, C, Structured Text).

:func:`tick_statements` lists one loop of the report's MIL programs (Figure
7.9): the state loaded into named locals, the intermediates, ``z_vs`` from
the state at the start of the loop, then the RK3 program of
:mod:`impedance_mil.virtual.stepping` (stage states, rates, update), every
expression rendered from the type's definition with the target's
:class:`~impedance_mil.virtual.expressions.Dialect`.  The numba kernel
(:mod:`impedance_mil.virtual.codegen`), the generated C and the generated ST
(:mod:`impedance_mil.implement`) are this one listing in three syntaxes.

:func:`value_types` gives the precision in which each intermediate is
evaluated by the numba kernel when its arrays are float32 (a float64 literal
promotes what it enters), so that a C target can declare its locals alike
and reproduce the kernel bit for bit.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from dataclasses import dataclass

from .definition import VSDefinition
from .expressions import Dialect, parse, render
from .stepping import Combine, Evaluate, combine_text, rk_program


@dataclass(frozen=True)
class Language:
    """How a target writes the listing.

    Attributes
    ----------
    dialect : Dialect
        Expressions; its ``name`` maps parameters, states, intermediates and
        the inputs ``a_g``, ``w`` to the target's variables.
    element : callable
        ``(array, i) -> text`` for the arrays ``x`` (the state), ``xs`` (the
        stage state) and ``k1``, ``k2``, ``k3`` (the stage rates).
    assign : callable
        ``(target, value) -> statement``.
    number : callable
        The RK3 coefficients as literals.
    dt : str
        The loop time's name.
    """

    dialect: Dialect
    element: Callable[[str, int], str]
    assign: Callable[[str, str], str]
    number: Callable[[float], str]
    dt: str = "dt"


def _expr(d: VSDefinition, lang: Language, text: str, where: str) -> str:
    return render(text, lang.dialect, f"VS definition {d.kind}: {where}")


def load_statements(d: VSDefinition, lang: Language, source: str) -> list[str]:
    """The states from the array ``source`` into their locals, then the intermediates."""
    out = [lang.assign(lang.dialect.name(s), lang.element(source, i)) for i, s in enumerate(d.states)]
    return out + [
        lang.assign(lang.dialect.name(n), _expr(d, lang, e, f"intermediates.{n}")) for n, e in d.intermediates
    ]


def rate_statements(d: VSDefinition, lang: Language, target: str) -> list[str]:
    """The rates at the loaded state into the array ``target``."""
    return [
        lang.assign(lang.element(target, i), _expr(d, lang, d.rates[s], f"rates.{s}"))
        for i, s in enumerate(d.states)
    ]


def output_expression(d: VSDefinition, lang: Language, output: str) -> str:
    """An output (``z_vs``, ``force`` ...) at the loaded state, rendered."""
    return _expr(d, lang, d.output_expressions[output], f"outputs.{output}")


def tick_statements(d: VSDefinition, lang: Language, z_target: str) -> list[str]:
    """One loop: ``z_target`` receives z_vs at the state ``x``, then one RK3 step of ``x``."""
    body = load_statements(d, lang, "x")
    body.append(lang.assign(z_target, output_expression(d, lang, "z_vs")))
    at_x = True
    for st in rk_program():
        if isinstance(st, Evaluate):
            if not (st.source == "x" and at_x):
                body += load_statements(d, lang, st.source)
            body += rate_statements(d, lang, st.target)
        elif isinstance(st, Combine):
            at_x = False
            for i in range(d.n_states):
                rhs = combine_text(
                    st, str(i), "x", lang.dt, lang.number, lambda array, j: lang.element(array, int(j))
                )
                body.append(lang.assign(lang.element(st.target, i), rhs))
    return body


# ------------------------------------------------------------ precision
def _type(node: ast.AST, known: dict[str, str]) -> str:
    """numba's result type of an expression whose names are float32 (``"T"``) or as ``known``."""
    if isinstance(node, ast.Constant):
        return "f64"
    if isinstance(node, ast.Name):
        return known.get(node.id, "T")
    if isinstance(node, ast.BinOp):
        return _wider(_type(node.left, known), _type(node.right, known))
    if isinstance(node, ast.UnaryOp):
        return _type(node.operand, known)
    if isinstance(node, ast.Compare):
        return "bool"
    fn = node.func.id  # type: ignore[attr-defined]
    args = [_type(a, known) for a in node.args]  # type: ignore[attr-defined]
    if fn == "sign":
        return "f64"  # the helper returns float64 literals
    if fn == "where":
        return _wider(args[1], args[2])
    return _wider(*args) if len(args) > 1 else args[0]


def _wider(*types: str) -> str:
    return "f64" if "f64" in types else "T"


def expression_type(node: ast.AST, known: dict[str, str]) -> str:
    """``"T"`` or ``"f64"``: the type numba gives ``node`` for float32 arrays (see :func:`value_types`)."""
    return _type(node, known)


def value_types(d: VSDefinition) -> dict[str, str]:
    """``"T"`` (the arrays' precision) or ``"f64"`` for every intermediate and output.

    For float32 arrays these are the types numba gives: a float64 literal or
    the ``sign`` helper promotes the operation it enters; ``exp``, ``sqrt``,
    ``abs``, ``pow``, ``min``, ``max`` keep float32 arguments float32.
    """
    known: dict[str, str] = {}
    for n, e in d.intermediates:
        known[n] = _type(parse(e), known)
    for o, e in d.output_expressions.items():
        known[f"outputs.{o}"] = _type(parse(e), known)
    return known
