"""The linear part of a VS type and its nonlinear input f_h, derived from the definition.

The report splits a hysteretic VS into a linear part in feedback with a
nonlinear block (Figures 5.3, 5.5): the linear part sees the nonlinear
input ``f_h`` as an input.  Here the split follows from the definition: the
intermediates listed in ``nonlinear_inputs`` are cut (their values become
inputs), and the linear part keeps the states that ``z_vs`` depends on,
directly or through their rates, with the cut in place.  Those rates and
``z_vs`` must then be linear in the kept states, ``a_g``, ``w`` and ``f_h``;
this is checked on the definition's reference parameters when the structure
is first needed (a nonlinear term outside ``nonlinear_inputs`` is refused,
naming the state).  The matrices are read off the equations with unit
states and inputs, which is exact for linear expressions.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .definition import INPUTS, VSDefinition, VSDefinitionError, python_eval
from .expressions import CONSTANTS, names

#: Relative tolerance of the superposition test of linearity.
LINEARITY_RTOL = 1e-9


@dataclass(frozen=True)
class LinearStructure:
    """Which states and inputs form the linear part of a type.

    Attributes
    ----------
    states : tuple of str
        States of the linear part, in the definition's order.
    inputs : tuple of str
        ``a_g``, ``w``, then the nonlinear inputs.
    """

    states: tuple[str, ...]
    inputs: tuple[str, ...]


def linear_structure(d: VSDefinition) -> LinearStructure:
    """The linear part's states and inputs (cached per definition; checked once)."""
    return d.cached("linear-structure", lambda: _structure(d))


def _structure(d: VSDefinition) -> LinearStructure:
    inter = dict(d.intermediates)
    cut = set(d.nonlinear_inputs)

    def state_deps(expr: str) -> set[str]:
        out: set[str] = set()
        stack = list(names(expr))
        seen: set[str] = set()
        while stack:
            n = stack.pop()
            if n in seen:
                continue
            seen.add(n)
            if n in d.states:
                out.add(n)
            elif n in inter and n not in cut:
                stack.extend(names(inter[n]))
        return out

    kept = state_deps(d.output_expressions["z_vs"])
    frontier = list(kept)
    while frontier:
        for s in state_deps(d.rates[frontier.pop()]):
            if s not in kept:
                kept.add(s)
                frontier.append(s)
    structure = LinearStructure(tuple(s for s in d.states if s in kept), INPUTS + tuple(d.nonlinear_inputs))
    values = {p.name: float(d.reference.get(p.name, p.default or 0.0)) for p in d.parameters}
    _check_linear(d, structure, {**values, **d.derived_values(values)})
    return structure


def evaluate_linear(
    d: VSDefinition,
    structure: LinearStructure,
    constants: Mapping[str, float],
    state: Mapping[str, float],
    inputs: Mapping[str, float],
) -> np.ndarray:
    """``[rates of the linear part's states..., z_vs]`` with the nonlinear inputs given.

    States outside the linear part are zero (they cannot matter, by construction).
    """
    scope: dict[str, float] = {**CONSTANTS, **constants}
    scope.update({s: float(state.get(s, 0.0)) for s in d.states})
    scope.update({k: float(inputs.get(k, 0.0)) for k in INPUTS})
    for n, e in d.intermediates:
        scope[n] = float(inputs.get(n, 0.0)) if n in d.nonlinear_inputs else python_eval(e, scope)
    rates = [python_eval(d.rates[s], scope) for s in structure.states]
    return np.array(rates + [python_eval(d.output_expressions["z_vs"], scope)], dtype=float)


def linear_matrices(d: VSDefinition, constants: Mapping[str, float]) -> tuple[np.ndarray, ...]:
    """``(A, B, C, D)`` of the linear part: ``dx/dt = A x + B u``, ``z_vs = C x + D u``.

    ``u = [a_g, w, f_h...]`` (:attr:`LinearStructure.inputs`); read off the
    equations with unit vectors (exact: the part is linear).
    """
    st = linear_structure(d)
    cols_x = [evaluate_linear(d, st, constants, {s: 1.0}, {}) for s in st.states]
    cols_u = [evaluate_linear(d, st, constants, {}, {u: 1.0}) for u in st.inputs]
    n = len(st.states)
    X = np.column_stack(cols_x) if cols_x else np.zeros((n + 1, 0))
    U = np.column_stack(cols_u)
    return X[:n, :], U[:n, :], X[n, :], U[n, :]


def _check_linear(d: VSDefinition, st: LinearStructure, constants: Mapping[str, float]) -> None:
    """Superposition at random points: f(a + b) = f(a) + f(b) - f(0) for every kept equation."""
    rng = np.random.default_rng(0)
    variables = list(st.states) + list(st.inputs)

    def at(vec: np.ndarray) -> np.ndarray:
        point = dict(zip(variables, vec))
        return evaluate_linear(d, st, constants, point, point)

    zero = at(np.zeros(len(variables)))
    for _ in range(3):
        a, b = rng.standard_normal(len(variables)), rng.standard_normal(len(variables))
        fa, fb, fab = at(a), at(b), at(a + b)
        scale = np.maximum(np.abs(fa) + np.abs(fb) + np.abs(fab), 1e-300)
        bad = np.abs(fab - fa - fb + zero) > LINEARITY_RTOL * scale
        if np.any(bad):
            labels = [f"rates.{s}" for s in st.states] + ["outputs.z_vs"]
            where = labels[int(np.argmax(bad))]
            raise VSDefinitionError(
                d.kind,
                where,
                "an equation linear in the linear part's states and inputs (declare the "
                "nonlinear term as an intermediate listed in nonlinear_inputs)",
            )
