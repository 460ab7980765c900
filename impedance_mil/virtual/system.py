"""A virtual system of a defined type: :class:`DefinedVS` (a definition and its parameter values).

Every method evaluates the type's one definition: the dynamics through the
kernels generated from it (:mod:`impedance_mil.virtual.codegen`), the linear
part through :mod:`impedance_mil.virtual.structure`.  Parameters and derived
values read as attributes (``vs.k_s``, ``vs.W``); the object is immutable
(:meth:`DefinedVS.replace` makes a changed copy).

>>> from impedance_mil.virtual import presets
>>> sd = presets.get("SD2")
>>> sd.kind, sd.state_names
('SD', ('x', 'v'))
>>> round(sd.linear_part().H_zag.dcgain(), 6)
1.0
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ConfigError
from ..lazy import LazyModule
from ..units import G0
from .base import LinearPart, VirtualSystem, VSOutput, VSResponse, inputs_of, nonnegative, state_of
from .definition import VSDefinition, python_eval
from .expressions import CONSTANTS
from .structure import linear_matrices, linear_structure

if TYPE_CHECKING:
    from ..systems import TransferFunction

#: The transfer functions of the linear part (and through them the LTI core), imported on first
#: use: listing and describing the presets does not need them (issue 16, start-up).
systems = LazyModule("impedance_mil.systems")
#: The generated kernels and the loops over a history (numba), imported on first use: building,
#: listing and describing a system does not compile or load them (issue 16, start-up).
codegen = LazyModule("impedance_mil.virtual.codegen")
kernels = LazyModule("impedance_mil.virtual.kernels")

#: Residue threshold of the linear part's numerators (relative, on the system's frequency scale).
RESIDUE_RTOL = 1e-9


class DefinedVS(VirtualSystem):
    """A VS of the type ``definition`` with parameter ``values`` (internal units).

    Parameters
    ----------
    definition : VSDefinition
    values : Mapping[str, float]
        Every parameter without a default; checked against the definition's
        ranges and rules.
    where : str
        Prefix of the key in error messages (e.g. a file name).

    Raises
    ------
    ConfigError
        A missing, unknown or out-of-range parameter.
    """

    __slots__ = ("definition", "_values", "_derived", "_params")
    definition: VSDefinition
    _values: dict[str, float]
    _derived: dict[str, float]
    _params: np.ndarray

    def __init__(self, definition: VSDefinition, values: Mapping[str, Any], where: str = ""):
        vals = definition.check_values(values, where)
        derived = definition.derived_values(vals)
        scope = {**vals, **derived}
        object.__setattr__(self, "definition", definition)
        object.__setattr__(self, "_values", vals)
        object.__setattr__(self, "_derived", derived)
        object.__setattr__(self, "_params", np.array([scope[n] for n in definition.kernel_constants], float))

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f"{self.kind} virtual systems are immutable: use .replace({name}=...)")

    def __getattr__(self, name: str) -> float:
        # only reached when normal lookup fails: parameters and derived values
        for table in (object.__getattribute__(self, "_values"), object.__getattribute__(self, "_derived")):
            if name in table:
                return table[name]
        raise AttributeError(
            f"{object.__getattribute__(self, 'definition').kind} virtual system has no "
            f"parameter or derived value {name!r}"
        )

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, DefinedVS)
            and other.definition.fingerprint == self.definition.fingerprint
            and other._values == self._values
        )

    def __hash__(self) -> int:
        return hash((self.definition.kind, tuple(sorted(self._values.items()))))

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self._values.items())
        return f"{self.kind}({args})"

    def __reduce__(self):
        return (DefinedVS, (self.definition, dict(self._values)))

    # ------------------------------------------------------------ contract
    @property
    def kind(self) -> str:  # type: ignore[override]
        """The type's short name."""
        return self.definition.kind

    @property
    def parameters(self) -> dict[str, float]:
        """Parameter values (internal units), in declaration order."""
        return dict(self._values)

    @property
    def n_states(self) -> int:
        return self.definition.n_states

    @property
    def state_names(self) -> tuple[str, ...]:
        return self.definition.states

    def replace(self, **changes: float) -> DefinedVS:
        """A copy with some parameters changed (internal units)."""
        return DefinedVS(self.definition, {**self._values, **changes})

    def parameter_array(self) -> np.ndarray:
        """Kernel parameter vector: :attr:`VSDefinition.kernel_constants` (float64)."""
        return self._params.copy()

    def derivative(self, x, a_g: float, w: float) -> np.ndarray:
        out = np.empty(self.n_states)
        codegen.compiled(self.definition).derivative(self._params, state_of(x), float(a_g), float(w), out)
        return out

    def _outputs(self, x, a_g: float, w: float) -> np.ndarray:
        kern = codegen.compiled(self.definition)
        out = np.empty(kern.n_outputs)
        kern.outputs(self._params, state_of(x), float(a_g), float(w), out)
        return out

    def outputs(self, x, a_g: float, w: float) -> VSOutput:
        o = self._outputs(x, a_g, w)
        return VSOutput(
            float(o[kernels.OUT_Z]),
            float(o[kernels.OUT_DISP]),
            float(o[kernels.OUT_VEL]),
            float(o[kernels.OUT_FORCE]),
        )

    def nonlinear_input(self, x) -> float:
        if not self.definition.nonlinear_inputs:
            return 0.0
        return float(self._outputs(x, 0.0, 0.0)[kernels.OUT_FORCE + 1])

    def step_rk3(self, x, a_g: float, w: float, dt: float) -> np.ndarray:
        xs = state_of(x).copy()
        work = np.empty(4 * max(self.n_states, 1))
        codegen.compiled(self.definition).tick64(self._params, xs, float(a_g), float(w), float(dt), work)
        return xs

    def simulate(self, a_g, w=None, dt: float = 0.0005, x0=None) -> VSResponse:
        if not dt > 0:
            raise ConfigError("dt", "a positive time step in s", dt)
        a, ww = inputs_of(a_g, w)
        x = self.initial_state() if x0 is None else state_of(x0).copy()
        kern = codegen.compiled(self.definition)
        rec = np.empty((kern.n_outputs, a.size))  # output-major: each history a contiguous row, no copies
        work = np.empty(4 * max(self.n_states, 1))
        kern.simulate_records(
            self._params,
            x,
            a,
            ww,
            float(dt),
            work,
            np.empty(kern.n_outputs),
            rec,
        )
        fh = rec[kernels.OUT_FORCE + 1] if self.definition.nonlinear_inputs else np.zeros(a.size)
        return VSResponse(
            np.arange(a.size) * dt,
            a,
            ww,
            rec[kernels.OUT_Z],
            rec[kernels.OUT_DISP],
            rec[kernels.OUT_VEL],
            rec[kernels.OUT_FORCE],
            fh,
            x,
        )

    def force_along(self, states) -> np.ndarray:
        """Isolator force [lbf] at each row of ``states`` (compiled: one call for the whole record)."""
        x = np.ascontiguousarray(states, dtype=float).reshape(-1, self.n_states)
        kern = codegen.compiled(self.definition)
        rec = np.empty((kern.n_outputs, x.shape[0]))
        kern.outputs_along(self._params, x, np.empty(kern.n_outputs), rec)
        return rec[kernels.OUT_FORCE]

    def linear_part(self) -> LinearPart:
        """Transfer functions of the linear part (Figures 5.3, 5.5), from the definition.

        See :mod:`impedance_mil.virtual.structure`; each path is reduced with
        relative-tolerance cancellation.  For SD, LR and FP they equal Eq 5-2,
        5-8 and 5-13 (corrected, see docs/errata.md).
        """
        A, B, C, D = linear_matrices(self.definition, {**self._values, **self._derived})
        omega = max(float(np.max(np.abs(np.linalg.eigvals(A)))), 1e-12) if A.size else 1e-12
        tfs = [
            _drop_residue(systems.TransferFunction.from_ss(A, B[:, j], C, D[j]), omega).minreal()
            for j in range(B.shape[1])
        ]
        has_fh = len(linear_structure(self.definition).inputs) > 2
        return LinearPart(H_zag=tfs[0], H_zw=tfs[1], H_zfh=tfs[2] if has_fh else None)

    def with_rigid_article(self, m_article: float) -> DefinedVS:
        """Lump a rigid article of mass ``m_article`` [lbf*s**2/in] on the basemat.

        For a type whose ``article_weight`` parameter already carries the
        article (sliding bearings: it sets the friction force), the article's
        weight moves from that parameter into the mass, keeping the axial load;
        it must not exceed that parameter.
        """
        nonnegative("m_article", m_article)
        d = self.definition
        changes = {"m_vs": self._values["m_vs"] + m_article}
        if d.article_weight is not None:
            carried = self._values[d.article_weight]
            rest = carried - m_article * G0
            if rest < -1e-9 * max(carried, 1.0):
                raise ConfigError(
                    "m_article", f"a weight of at most {d.article_weight} = {carried:g} lbf", m_article * G0
                )
            changes[d.article_weight] = max(rest, 0.0)
        return self.replace(**changes)

    @property
    def transition_length(self) -> float | None:
        """Displacement over which the hysteresis turns [in] (the definition's expression), or None."""
        expr = self.definition.transition_length
        return (
            None if expr is None else float(python_eval(expr, {**CONSTANTS, **self._values, **self._derived}))
        )

    # ---------------------------------------------------------- description
    def derived(self) -> dict[str, float]:
        return dict(self._derived)

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, **self._values, **self._derived}


def _drop_residue(tf: TransferFunction, omega: float, rtol: float = RESIDUE_RTOL) -> TransferFunction:
    """Zero numerator coefficients that are rounding residue on the system's frequency scale.

    A coefficient of s**p counts as residue when ``|c_p|*omega**p`` is below
    ``rtol`` times the largest such term (``omega`` [rad/s]: spectral radius of A).
    """
    num = np.array(tf.num, dtype=float)
    powers = np.arange(num.size - 1, -1, -1)
    terms = np.abs(num) * omega**powers
    num[terms < rtol * terms.max()] = 0.0
    return systems.TransferFunction(num, tf.den)
