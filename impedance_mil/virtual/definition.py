"""One definition per virtual-system type: parameters, states, equations, by name.

A :class:`VSDefinition` declares a VS type once: its parameters (with units),
its states, the intermediate values, the rate of every state and the named
outputs, as expressions of :mod:`impedance_mil.virtual.expressions`.  Inputs
are always ``a_g`` (ground acceleration [in/s**2]) and ``w`` (force of the test
article on the VS [lbf]); outputs are ``z_vs`` (the absolute acceleration the
table must imitate [in/s**2]), ``displacement`` [in], ``velocity`` [in/s] and
``force`` [lbf] (the isolator force, for force-displacement loops).

Everything else is derived from the definition: the compiled numba kernel
(:mod:`impedance_mil.virtual.codegen`), the linear part and its nonlinear
input ``f_h`` (:meth:`VSDefinition.linear_structure`, Figures 5.3, 5.5), the
describing-function and equivalent-viscous linearizations
(:mod:`impedance_mil.design.linearize`), the generated C and IEC 61131-3
code (:mod:`impedance_mil.implement`).  A definition is checked when it is
made: a name used but not declared, a state without a rate, an expression
that is not finite at the reference point, ... is refused in one line naming
the definition and the symbol (:class:`VSDefinitionError`).

Isolator types (a basemat of mass ``m_vs`` on isolators whose relative
displacement and velocity are the states ``kinematics``) additionally support
the describing function (the internal states are integrated with the
kinematics prescribed) and lumping a rigid article on the basemat.
"""

from __future__ import annotations

import dataclasses
import hashlib
import keyword
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

from ..errors import ConfigError
from ..plausibility import check_vs_value
from .expressions import CONSTANTS, FUNCTIONS, names, python_dialect, render

#: The inputs of every VS.
INPUTS = ("a_g", "w")
#: Outputs every VS defines (``displacement``/``velocity`` default to the kinematic states).
OUTPUTS = ("z_vs", "displacement", "velocity", "force")
#: Range checks a parameter may declare.
CHECKS = ("positive", "nonnegative", "fraction", "any")


class VSDefinitionError(ConfigError):
    """A VS definition that is inconsistent (the message names the definition and the symbol)."""

    def __init__(self, kind: str, symbol: str, problem: str):
        super().__init__(f"VS definition {kind}: {symbol}", problem)


@dataclass(frozen=True)
class Parameter:
    """One parameter of a VS type.

    Attributes
    ----------
    name : str
        Identifier used in the expressions.
    unit : str
        Internal unit (pint expression, e.g. ``"force_pound / inch"``).
    label : str
        Human-readable name (listings, generated-code comments).
    check : str
        ``positive`` (default), ``nonnegative``, ``fraction`` ([0, 1)) or ``any`` (finite).
    default : float, optional
        Value used when none is given (internal units).
    """

    name: str
    unit: str
    label: str
    check: str = "positive"
    default: float | None = None


@dataclass(frozen=True)
class Derived:
    """A value computed once from the parameters (and earlier derived values).

    Used by the equations (then it is part of the kernel's parameter vector,
    computed in float64 before any rounding to the runtime precision) or only
    listed (frequencies, damping ratios ...).
    """

    name: str
    expression: str
    unit: str
    label: str


@dataclass(frozen=True)
class Rule:
    """A condition on the parameters, e.g. ``Rule("mu_min", "mu_min <= mu_max", ...)``.

    ``condition`` is one comparison of two expressions; ``key`` is the
    parameter named when it fails, ``expected`` the sentence shown.
    """

    key: str
    condition: str
    expected: str


@dataclass(frozen=True, eq=False)
class VSDefinition:
    """A virtual-system type, written once (see the module docstring).

    Attributes
    ----------
    kind : str
        Short name (``"SD"``, ``"LR"``, ``"FP"``, ``"TFP"``, or a user's).
    title : str
        One line: what it is.
    source : str
        Where its equations come from (report equations, a paper).
    parameters : tuple of Parameter
    states : tuple of str
        State names, in the order of the state vector.
    state_units : tuple of str
        Internal unit of each state.
    intermediates : tuple of (str, str)
        ``(name, expression)`` evaluated in this order at every evaluation;
        each may use parameters, derived values, states, inputs and earlier
        intermediates.
    rates : Mapping[str, str]
        ``state -> d(state)/dt`` expression.
    outputs : Mapping[str, str]
        Expressions of ``z_vs`` and ``force`` (required) and of
        ``displacement`` and ``velocity`` (default: the kinematic states).
    derived : tuple of Derived
    nonlinear_inputs : tuple of str
        Intermediates that the linear part takes as inputs ``f_h`` (Figures
        5.3, 5.5); empty for a linear VS.
    kinematics : (str, str) or None
        Relative displacement and velocity states of the isolator (None: not an
        isolator type; no describing function).  Every type has the parameter
        ``m_vs``, the mass on which the test article stands (the basemat).
    article_weight : str or None
        Parameter that includes the test article's weight (it sets the
        friction of sliding bearings); lumping a rigid article on the basemat
        moves the article's weight out of it into ``m_vs``.
    transition_length : str or None
        Expression of the displacement over which the hysteresis turns (the
        yield displacement); sets the steps of the describing function.
    rules : tuple of Rule
        Conditions on the parameters beyond their range checks.
    reference : Mapping[str, float]
        Parameter values at which every expression is checked to be finite
        when the definition is made (a typical system of the type).
    """

    kind: str
    title: str
    source: str
    parameters: tuple[Parameter, ...]
    states: tuple[str, ...]
    state_units: tuple[str, ...]
    rates: Mapping[str, str]
    outputs: Mapping[str, str]
    reference: Mapping[str, float]
    intermediates: tuple[tuple[str, str], ...] = ()
    derived: tuple[Derived, ...] = ()
    nonlinear_inputs: tuple[str, ...] = ()
    kinematics: tuple[str, str] | None = None
    article_weight: str | None = None
    transition_length: str | None = None
    rules: tuple[Rule, ...] = ()
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self):
        validate(self)

    # ----------------------------------------------------------------- names
    @property
    def parameter_names(self) -> tuple[str, ...]:
        """Parameter names, in declaration order."""
        return tuple(p.name for p in self.parameters)

    @property
    def n_states(self) -> int:
        """Number of states."""
        return len(self.states)

    @property
    def output_expressions(self) -> dict[str, str]:
        """Every output's expression (``displacement``/``velocity`` filled from the kinematics)."""
        out = dict(self.outputs)
        if self.kinematics is not None:
            out.setdefault("displacement", self.kinematics[0])
            out.setdefault("velocity", self.kinematics[1])
        return out

    @property
    def kernel_constants(self) -> tuple[str, ...]:
        """Parameters and derived values the equations use: the kernel's parameter vector, in order."""
        used = self._used_names()
        params = [p for p in self.parameter_names if p in used]
        return tuple(params + [d.name for d in self.derived if d.name in used])

    @property
    def internal_states(self) -> tuple[str, ...]:
        """States other than the kinematic ones (integrated by the describing function)."""
        kin = self.kinematics or ()
        return tuple(s for s in self.states if s not in kin)

    def _used_names(self) -> frozenset[str]:
        """Names the runtime equations (intermediates, rates, outputs) use directly; derived
        values needed only to compute other derived values stay out of the kernel."""
        exprs = [e for _, e in self.intermediates] + list(self.rates.values())
        exprs += list(self.output_expressions.values())
        used: set[str] = set()
        for e in exprs:
            used |= names(e)
        return frozenset(used)

    # ------------------------------------------------------------ evaluation
    def derived_values(self, values: Mapping[str, float]) -> dict[str, float]:
        """Derived values (float64, internal units) for the parameter ``values``."""
        scope: dict[str, float] = dict(CONSTANTS)
        scope.update(values)
        out: dict[str, float] = {}
        for d in self.derived:
            out[d.name] = scope[d.name] = python_eval(d.expression, scope)
        return out

    def check_values(self, values: Mapping[str, Any], where: str = "") -> dict[str, float]:
        """Parameter values checked against their ranges and the rules; returns floats.

        Raises
        ------
        ConfigError
            A missing, unknown, non-numeric or out-of-range value, or one outside the
            broad bounds of its dimension (:func:`impedance_mil.plausibility.check_vs_value`;
            the key is named).
        """
        known = set(self.parameter_names)
        for key in values:
            if key not in known:
                raise ConfigError(
                    f"{where}{key}", f"a {self.kind} parameter: " + ", ".join(self.parameter_names)
                )
        out: dict[str, float] = {}
        for p in self.parameters:
            value = values.get(p.name, p.default)
            if value is None:
                raise ConfigError(f"{where}{p.name}", f"a value for {p.label} [{p.unit}]")
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ConfigError(f"{where}{p.name}", f"a number [{p.unit}]", value)
            out[p.name] = check_vs_value(
                f"{where}{p.name}", _checked(f"{where}{p.name}", float(value), p.check), p.unit
            )
        scope = {**CONSTANTS, **out, **self.derived_values(out)}
        for rule in self.rules:
            if not python_eval(rule.condition, scope, condition=True):
                raise ConfigError(f"{where}{rule.key}", rule.expected, out.get(rule.key))
        return out

    @property
    def fingerprint(self) -> str:
        """A digest of everything the definition says (two loads of one file compare equal)."""
        return self.cached("fingerprint", lambda: hashlib.sha256(repr(self).encode()).hexdigest())

    def to_dict(self) -> dict[str, Any]:
        """The definition as plain data (JSON-ready), e.g. to keep a user's type in a design file."""
        out: dict[str, Any] = {}
        for f in dataclasses.fields(self):
            if f.name.startswith("_"):
                continue
            value = getattr(self, f.name)
            if f.name in ("parameters", "derived", "rules"):
                value = [dataclasses.asdict(x) for x in value]
            elif isinstance(value, Mapping):
                value = dict(value)
            elif isinstance(value, tuple):
                value = [list(x) if isinstance(x, tuple) else x for x in value]
            out[f.name] = value
        return out

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> VSDefinition:
        """The inverse of :meth:`to_dict` (checked as any definition).

        Raises
        ------
        ConfigError
            Missing or unknown fields, or an inconsistent definition.
        """
        if not isinstance(data, Mapping):
            raise ConfigError("definition", "a table of the VS definition's fields", type(data).__name__)
        known = {f.name for f in dataclasses.fields(cls) if not f.name.startswith("_")}
        for key in data:
            if key not in known:
                raise ConfigError(
                    f"definition.{key}", "a field of a VS definition: " + ", ".join(sorted(known))
                )
        try:
            kw = dict(data)
            kw["parameters"] = tuple(Parameter(**p) for p in kw.get("parameters", ()))
            kw["derived"] = tuple(Derived(**x) for x in kw.get("derived", ()))
            kw["rules"] = tuple(Rule(**x) for x in kw.get("rules", ()))
            kw["intermediates"] = tuple(tuple(x) for x in kw.get("intermediates", ()))
            for key in ("states", "state_units", "nonlinear_inputs"):
                kw[key] = tuple(kw.get(key, ()))
            if kw.get("kinematics") is not None:
                kw["kinematics"] = tuple(kw["kinematics"])
            return cls(**kw)
        except TypeError as exc:
            raise ConfigError("definition", f"the fields of a VS definition ({exc})") from None

    def __getstate__(self) -> dict[str, Any]:
        # compiled kernels are per process: a pickled definition starts without them
        return {**self.__dict__, "_cache": {}}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)

    def cached(self, key: str, build: Callable[[], Any]) -> Any:
        """Per-definition memo of derived artefacts (compiled kernels, structure)."""
        if key not in self._cache:
            self._cache[key] = build()
        return self._cache[key]


def _checked(key: str, value: float, check: str) -> float:
    ok = (
        math.isfinite(value)
        and {
            "positive": value > 0,
            "nonnegative": value >= 0,
            "fraction": 0.0 <= value < 1.0,
            "any": True,
        }[check]
    )
    if not ok:
        expected = {
            "positive": "a positive value",
            "nonnegative": "a non-negative value",
            "fraction": "a fraction in [0, 1)",
            "any": "a finite value",
        }[check]
        raise ConfigError(key, expected, value)
    return value


# --------------------------------------------------------------- checking
def validate(d: VSDefinition) -> None:
    """Check a definition; raise :class:`VSDefinitionError` naming the first problem."""
    kind = d.kind
    ident = [p.name for p in d.parameters] + [x.name for x in d.derived] + list(d.states)
    ident += [n for n, _ in d.intermediates]
    for n in ident:
        if (
            not n.isidentifier()
            or keyword.iskeyword(n)
            or n.startswith("_")
            or n == "math"
            or n in CONSTANTS
            or n in INPUTS
            or n in OUTPUTS
            or n in FUNCTIONS
        ):
            raise VSDefinitionError(
                kind,
                n,
                "an identifier that is not reserved (a_g, w, pi, two_pi, g0, "
                "outputs, functions, Python keywords)",
            )
    seen: set[str] = set()
    for n in ident:
        if n in seen:
            raise VSDefinitionError(kind, n, "a name declared once")
        seen.add(n)
    for p in d.parameters:
        if p.check not in CHECKS:
            raise VSDefinitionError(kind, p.name, "a check among " + ", ".join(CHECKS))
    if len(d.state_units) != len(d.states):
        raise VSDefinitionError(kind, "state_units", f"one unit per state ({len(d.states)})")
    for s in d.states:
        if s not in d.rates:
            raise VSDefinitionError(kind, s, "a rate for every declared state")
    for s in d.rates:
        if s not in d.states:
            raise VSDefinitionError(kind, f"rates.{s}", "a rate of a declared state")
    for o in ("z_vs", "force"):
        if o not in d.outputs:
            raise VSDefinitionError(kind, f"outputs.{o}", "an expression (required output)")
    for o in d.outputs:
        if o not in OUTPUTS:
            raise VSDefinitionError(kind, f"outputs.{o}", "one of the outputs " + ", ".join(OUTPUTS))
    if d.kinematics is None and not {"displacement", "velocity"} <= set(d.outputs):
        raise VSDefinitionError(kind, "outputs", "displacement and velocity (or kinematics)")
    params = set(d.parameter_names)
    if "m_vs" not in params:
        raise VSDefinitionError(kind, "m_vs", "a parameter m_vs (the mass the test article stands on)")
    constants = params | set(CONSTANTS) | {x.name for x in d.derived}
    # derived values: over parameters and earlier derived values
    known = set(params) | set(CONSTANTS)
    for x in d.derived:
        _names_within(kind, f"derived.{x.name}", x.expression, known)
        known.add(x.name)
    for r in d.rules:
        _names_within(kind, f"rules.{r.key}", r.condition, constants, condition=True)
    runtime = constants | set(d.states) | set(INPUTS)
    for n, e in d.intermediates:
        _names_within(kind, f"intermediates.{n}", e, runtime)
        runtime.add(n)
    for s, e in d.rates.items():
        _names_within(kind, f"rates.{s}", e, runtime)
    for o, e in d.outputs.items():
        _names_within(kind, f"outputs.{o}", e, runtime)
    for n in d.nonlinear_inputs:
        if n not in dict(d.intermediates):
            raise VSDefinitionError(kind, n, "a nonlinear input that is a declared intermediate")
    if d.kinematics is not None:
        for n in d.kinematics:
            if n not in d.states:
                raise VSDefinitionError(kind, n, "a kinematic state that is declared")
    if d.article_weight is not None and d.article_weight not in params:
        raise VSDefinitionError(kind, "article_weight", "a declared parameter")
    if d.transition_length is not None:
        _names_within(kind, "transition_length", d.transition_length, constants)
    for p in d.parameters:
        if p.name not in d.reference and p.default is None:
            raise VSDefinitionError(
                kind, p.name, "a reference value (the parameter is missing from reference)"
            )
    for k in d.reference:
        if k not in params:
            raise VSDefinitionError(kind, f"reference.{k}", "a declared parameter")
    _check_finite(d)


def _names_within(kind: str, where: str, expr: str, allowed: set[str], condition: bool = False) -> None:
    try:
        used = _condition_names(expr, where) if condition else names(expr, where)
    except ConfigError as exc:
        raise VSDefinitionError(kind, where, f"{exc.expected} ({exc.got!r})") from None
    for n in sorted(used - allowed):
        raise VSDefinitionError(kind, n, f"a declared name (used in {where} but not declared)")


def _condition_names(expr: str, where: str) -> frozenset[str]:
    """Names of a rule's condition ``lhs OP rhs``."""
    return names(expr, where, condition=True)


def _check_finite(d: VSDefinition) -> None:
    """Every expression is finite at the reference parameters, with states and inputs at
    rest and at a small excursion (catches a division by a parameter that is zero there,
    a log of a negative, a literal overflow)."""
    values = {p.name: float(d.reference.get(p.name, p.default or 0.0)) for p in d.parameters}
    scope: dict[str, float] = {**CONSTANTS, **values}
    for x in d.derived:
        scope[x.name] = _finite(d.kind, f"derived.{x.name}", x.expression, scope)
    for point in (0.0, 0.01):
        s = dict(scope)
        s.update({n: point for n in d.states})
        s.update({"a_g": 10.0 * point, "w": 100.0 * point})
        for n, e in d.intermediates:
            s[n] = _finite(d.kind, f"intermediates.{n}", e, s)
        for k, e in list(d.rates.items()) + list(d.outputs.items()):
            _finite(d.kind, k, e, s)


def _finite(kind: str, where: str, expr: str, scope: Mapping[str, float]) -> float:
    try:
        value = python_eval(expr, scope)
    except (ZeroDivisionError, OverflowError, ValueError) as exc:
        raise VSDefinitionError(kind, where, f"a finite expression at the reference point ({exc})") from None
    if not math.isfinite(value):
        raise VSDefinitionError(kind, where, "a finite expression at the reference point")
    return value


# -------------------------------------------------------- Python evaluation
def _sign(v: float) -> float:
    return 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)


_GLOBALS = {"__builtins__": {"abs": abs, "min": min, "max": max}, "math": math, "_sign": _sign}


def python_eval(expr: str, scope: Mapping[str, float], condition: bool = False) -> Any:
    """Evaluate an expression in float64 Python arithmetic (the kernels' operation order).

    A complex result (a negative number to a fractional power) is returned as NaN,
    as the compiled kernels give.  ``condition``: a rule's comparison (returns a bool).
    """
    value = eval(_compiled(expr, condition), _GLOBALS, dict(scope))  # noqa: S307 (the language admits no calls but its own)
    return math.nan if isinstance(value, complex) else value


@lru_cache(maxsize=4096)
def _compiled(expr: str, condition: bool = False):
    return compile(render(expr, python_dialect(lambda n: n), condition=condition), f"<{expr}>", "eval")
