"""The report's RK3 step of a virtual system, written once as a program that every target renders.

The report's RMC programs (Figure 7.9) advance the VS with an explicit
third-order Runge-Kutta scheme, inputs ``a_g`` and ``w`` held over the step:
stages at ``x``, ``x + a21*dt*k1`` and ``x + a32*dt*k2``, update
``x + dt*(b1*k1 + b2*k2 + b3*k3)``, with Ralston's tableau
``a21 = 1/2, a32 = 3/4, b = (2/9, 3/9, 4/9)`` (:data:`RK3`).

:func:`rk_program` turns a tableau into a short straight-line *program* of
two kinds of statement, :class:`Evaluate` (the rates at a stage state) and
:class:`Combine` (a stage state or the update, written as
``base + coef*dt*k`` or ``base + dt*(c1*k1 + c2*k2 + ...)``).  The numba
kernel, the generated C and the generated Structured Text render this same
program (:mod:`impedance_mil.virtual.codegen`,
:mod:`impedance_mil.implement.c`, :mod:`impedance_mil.implement.st`), and
:func:`run_program` executes it directly on numpy arrays for a VS written as
Python methods.  So the scheme, its stage order and the grouping of its
arithmetic exist once.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Tableau:
    """An explicit Runge-Kutta tableau (strictly lower-triangular ``a``).

    Attributes
    ----------
    a : tuple of tuple of float
        ``a[s]`` holds the coefficients of stages ``0..s-1`` in stage ``s``.
    b : tuple of float
        Weights of the update.
    """

    a: tuple[tuple[float, ...], ...]
    b: tuple[float, ...]


#: Ralston's third-order scheme of the report's programs (Figure 7.9).
RK3 = Tableau(a=((), (0.5,), (0.0, 0.75)), b=(2.0 / 9.0, 3.0 / 9.0, 4.0 / 9.0))


@dataclass(frozen=True)
class Evaluate:
    """``rates[target] = f(stage state source)``; ``source`` is ``"x"`` or ``"xs"``."""

    source: str
    target: str


@dataclass(frozen=True)
class Combine:
    """``target[i] = x[i] + ...`` for every state ``i``.

    ``terms`` pairs each rates array (``"k1"`` ...) with its coefficient; one
    term is written ``x + c*dt*k`` (as the report's program writes a stage),
    several ``x + dt*(c1*k1 + c2*k2 + ...)`` (the update).  ``target`` is
    ``"xs"`` (the stage state) or ``"x"`` (the state, updated in place).
    """

    target: str
    terms: tuple[tuple[str, float], ...]


Statement = Evaluate | Combine


def rk_program(tableau: Tableau = RK3) -> tuple[Statement, ...]:
    """The straight-line program of one step of ``tableau`` (see the module docstring)."""
    program: list[Statement] = []
    for s, row in enumerate(tableau.a):
        terms = tuple((f"k{j + 1}", c) for j, c in enumerate(row) if c != 0.0)
        if s > 0:
            program.append(Combine("xs", terms))
        program.append(Evaluate("x" if s == 0 else "xs", f"k{s + 1}"))
    program.append(Combine("x", tuple((f"k{j + 1}", c) for j, c in enumerate(tableau.b))))
    return tuple(program)


def rates_arrays(tableau: Tableau = RK3) -> tuple[str, ...]:
    """Names of the rates arrays the program uses (``k1``, ``k2``, ...)."""
    return tuple(f"k{s + 1}" for s in range(len(tableau.a)))


def combine_text(
    statement: Combine,
    i: str,
    x: str,
    dt: str,
    number: Callable[[float], str],
    ref: Callable[[str, str], str],
) -> str:
    """Right-hand side of a :class:`Combine` for state index ``i``, in a C-like syntax.

    ``ref(array, i)`` renders an element, ``number`` a coefficient; the
    grouping is the one of the module docstring, so that every target rounds
    the same way.
    """
    base = ref(x, i)
    if len(statement.terms) == 1:
        ((k, c),) = statement.terms
        return f"{base} + {number(c)} * {dt} * {ref(k, i)}"
    inner = " + ".join(f"{number(c)} * {ref(k, i)}" for k, c in statement.terms)
    return f"{base} + {dt} * ({inner})"


def run_program(
    rates: Callable[[np.ndarray], np.ndarray], x: np.ndarray, dt: float, tableau: Tableau = RK3
) -> np.ndarray:
    """Execute one step on float64 arrays for a rates function ``f(state)``; returns the new state.

    Used for a virtual system written as Python methods (no kernel); the
    statements and their grouping are those that the compiled and generated
    code render.
    """
    arrays: dict[str, np.ndarray] = {"x": np.array(x, dtype=float), "xs": np.empty(len(x))}
    for st in rk_program(tableau):
        if isinstance(st, Evaluate):
            arrays[st.target] = np.asarray(rates(arrays[st.source].copy()), dtype=float)
            continue
        base = arrays["x"]
        if len(st.terms) == 1:
            ((k, c),) = st.terms
            value = base + c * dt * arrays[k]
        else:
            acc = st.terms[0][1] * arrays[st.terms[0][0]]
            for k, c in st.terms[1:]:
                acc = acc + c * arrays[k]
            value = base + dt * acc
        arrays[st.target] = value
    return arrays["x"]
