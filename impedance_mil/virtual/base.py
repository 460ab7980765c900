"""The virtual-system contract: :class:`VirtualSystem`, its named results, and Python-written systems.

A virtual system (VS, report Section 5) is the simulated environment under
the test article, e.g. a basemat of mass ``m_vs`` on isolators.  Its inputs
are the ground acceleration ``a_g`` [in/s**2] and the force ``w`` [lbf] the
test article applies on it (the sign convention of Eq 4-7b:
``m_vs * z_vs = -F + w`` with ``F`` the isolator shear force); its output is
the absolute acceleration ``z_vs`` [in/s**2] the table must imitate.

Two kinds of VS meet this contract:

- :class:`~impedance_mil.virtual.system.DefinedVS`, a system of a type
  written once as a :class:`~impedance_mil.virtual.definition.VSDefinition`
  (SD, LR, FP, TFP and any user type): compiled kernels, code generation,
  linear part and describing function are derived from the definition.
- :class:`PythonVS`, a frozen dataclass whose dynamics are Python methods
  (``derivative``, ``outputs``, ``linear_part``): for a model that cannot be
  written as expressions (e.g. one stepped by another program).  It runs in
  the virtual lab through the plant interface, about 100x slower, and the
  code generators cannot render it.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from ..errors import ConfigError, IncompleteModelError
from .stepping import run_program

if TYPE_CHECKING:  # the linear part's type: a system is built and listed without the LTI core
    from ..systems import TransferFunction


@dataclass(frozen=True)
class VSOutput:
    """Outputs of a VS at one instant.

    Attributes
    ----------
    z_vs : float
        Absolute basemat acceleration [in/s**2] (the table's target).
    displacement : float
        Basemat displacement relative to the ground [in].
    velocity : float
        Basemat velocity relative to the ground [in/s].
    force : float
        Isolator shear force F [lbf], restoring (positive with the
        displacement, Eq 5-3); the force on the basemat is ``-force``, so
        ``m_vs * z_vs = w - force``.
    """

    z_vs: float
    displacement: float
    velocity: float
    force: float


@dataclass(frozen=True)
class LinearPart:
    """Linear part of a VS (Figures 5.3, 5.5): ``z = H_zag a_g + H_zw w + H_zfh f_h``.

    Attributes
    ----------
    H_zag : TransferFunction
        From ground acceleration [in/s**2] to z_vs [in/s**2].
    H_zw : TransferFunction
        From test-article force [lbf] to z_vs [in/s**2].
    H_zfh : TransferFunction or None
        From the nonlinear input f_h to z_vs; ``None`` for a linear VS.
    """

    H_zag: TransferFunction
    H_zw: TransferFunction
    H_zfh: TransferFunction | None = None


@dataclass(frozen=True)
class VSResponse:
    """Time histories of a VS run (one RK3 step per sample).

    Attributes
    ----------
    time : ndarray
        Sample times [s]; outputs at ``time[k]`` use the state at the start of step k.
    a_g, w : ndarray
        Inputs: ground acceleration [in/s**2], test-article force [lbf].
    z_vs : ndarray
        Absolute basemat acceleration [in/s**2].
    displacement, velocity : ndarray
        Relative basemat displacement [in] and velocity [in/s].
    force : ndarray
        Isolator shear force [lbf] (see :class:`VSOutput`).
    f_h : ndarray
        Nonlinear input of the linear part (zeros for a linear VS).
    final_state : ndarray
        State after the last step.
    """

    time: np.ndarray
    a_g: np.ndarray
    w: np.ndarray
    z_vs: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    f_h: np.ndarray
    final_state: np.ndarray


def inputs_of(a_g, w) -> tuple[np.ndarray, np.ndarray]:
    """Input histories as contiguous float64 arrays (w broadcast, zeros when None).

    Raises
    ------
    ConfigError
        A NaN or infinite sample.
    """
    a = np.ascontiguousarray(a_g, dtype=float).reshape(-1)
    if w is None:
        ww = np.zeros_like(a)
    else:
        ww = np.ascontiguousarray(np.broadcast_to(np.asarray(w, dtype=float), a.shape), dtype=float)
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(ww))):
        raise ConfigError("a_g/w", "finite input histories")
    return a, ww


def state_of(x) -> np.ndarray:
    """A state as a contiguous float64 array."""
    return np.ascontiguousarray(x, dtype=float)


class VirtualSystem:
    """What every VS offers (see the module docstring); subclasses implement the dynamics.

    Attributes
    ----------
    kind : str
        Short name of the type ("SD", "LR", "FP", "TFP", or a user name).
    """

    kind: ClassVar[str] = "user"
    #: Mass on which the test article stands [lbf*s**2/in] (a parameter of every VS).
    m_vs: float

    # ------------------------------------------------------------ contract
    @property
    def n_states(self) -> int:
        """Number of states."""
        raise IncompleteModelError(f"{type(self).__name__} must define this method of the VS contract")

    @property
    def state_names(self) -> tuple[str, ...]:
        """Names of the states."""
        return tuple(f"s{i}" for i in range(self.n_states))

    def parameter_array(self) -> np.ndarray:
        """The parameter vector of the kernels (float64, internal units)."""
        raise IncompleteModelError(f"{type(self).__name__} must define this method of the VS contract")

    def initial_state(self) -> np.ndarray:
        """State at rest: all zeros."""
        return np.zeros(self.n_states)

    def derivative(self, x, a_g: float, w: float) -> np.ndarray:
        """State derivative dx/dt at state ``x`` for ``a_g`` [in/s**2] and ``w`` [lbf]."""
        raise IncompleteModelError(f"{type(self).__name__} must define this method of the VS contract")

    def outputs(self, x, a_g: float, w: float) -> VSOutput:
        """Outputs at state ``x`` for inputs ``a_g`` [in/s**2] and ``w`` [lbf]."""
        raise IncompleteModelError(f"{type(self).__name__} must define this method of the VS contract")

    def nonlinear_input(self, x) -> float:
        """Nonlinear input f_h of :meth:`linear_part` at state ``x`` (zero for a linear VS)."""
        return 0.0

    def linear_part(self) -> LinearPart:
        """Transfer functions of the linear part (Figures 5.3, 5.5)."""
        raise IncompleteModelError(f"{type(self).__name__} must define this method of the VS contract")

    def step_rk3(self, x, a_g: float, w: float, dt: float) -> np.ndarray:
        """State after one step ``dt`` [s] of the report's RK3 (inputs held; ``x`` not modified)."""
        return run_program(lambda s: self.derivative(s, a_g, w), state_of(x), float(dt))

    def simulate(self, a_g, w=None, dt: float = 0.0005, x0=None) -> VSResponse:
        """Run the VS over sampled inputs, one RK3 step per sample.

        Parameters
        ----------
        a_g : array_like
            Ground acceleration per sample [in/s**2].
        w : array_like or float, optional
            Test-article force per sample [lbf]; zero when omitted.
        dt : float
            Sample period [s] (the report's loop time is 0.0005 s).
        x0 : array_like, optional
            Initial state; at rest when omitted.
        """
        if not dt > 0:
            raise ConfigError("dt", "a positive time step in s", dt)
        a, ww = inputs_of(a_g, w)
        x = self.initial_state() if x0 is None else state_of(x0).copy()
        n = a.size
        z, disp, vel, force, fh = (np.empty(n) for _ in range(5))
        for k in range(n):
            out = self.outputs(x, a[k], ww[k])
            z[k], disp[k], vel[k], force[k] = out.z_vs, out.displacement, out.velocity, out.force
            fh[k] = self.nonlinear_input(x)
            x = self.step_rk3(x, a[k], ww[k], dt)
        return VSResponse(np.arange(n) * dt, a, ww, z, disp, vel, force, fh, x)

    def force_along(self, states) -> np.ndarray:
        """Isolator force [lbf] at each row of ``states`` (shape (n, n_states))."""
        return np.array([self.outputs(x, 0.0, 0.0).force for x in np.asarray(states, dtype=float)])

    def with_rigid_article(self, m_article: float) -> VirtualSystem:
        """Equivalent VS with a rigid test article of mass ``m_article`` [lbf*s**2/in] on it.

        With a rigid article, ``w = -m_article * z_vs``; lumping the mass solves
        that algebraic loop exactly.
        """
        raise IncompleteModelError(f"{type(self).__name__} must define this method of the VS contract")

    # ---------------------------------------------------------- description
    def derived(self) -> dict[str, float]:
        """Derived properties (name -> value in internal units); none by default."""
        return {}

    def to_dict(self) -> dict[str, Any]:
        """``kind``, the parameters and the derived properties (internal units)."""
        raise IncompleteModelError(f"{type(self).__name__} must define this method of the VS contract")


@dataclass(frozen=True)
class PythonVS(VirtualSystem):
    """Base of a VS written as Python methods (a frozen dataclass); see the module docstring.

    Set the class attributes ``kind`` and ``user_n_states``, and define
    :meth:`derivative`, :meth:`outputs` and :meth:`linear_part` (and
    :meth:`nonlinear_input` if the linear part has one).

    Parameters
    ----------
    m_vs : float
        Mass on which the test article stands [lbf*s**2/in].
    """

    m_vs: float

    #: Number of states (set by the subclass).
    user_n_states: ClassVar[int] = 0

    def __post_init__(self):
        positive("m_vs", self.m_vs)

    @property
    def n_states(self) -> int:
        """Number of states (``user_n_states``)."""
        return self.user_n_states

    def parameter_array(self) -> np.ndarray:
        """The dataclass fields in declaration order (float64)."""
        return np.array([float(getattr(self, f.name)) for f in dataclasses.fields(self)])

    def with_rigid_article(self, m_article: float) -> VirtualSystem:
        nonnegative("m_article", m_article)
        return dataclasses.replace(self, m_vs=self.m_vs + m_article)

    def to_dict(self) -> dict[str, Any]:
        data: dict[str, Any] = {"kind": self.kind}
        data.update({f.name: getattr(self, f.name) for f in dataclasses.fields(self)})
        data.update(self.derived())
        return data


def positive(key: str, value: float) -> None:
    """Raise ConfigError unless ``value`` is finite and > 0."""
    if not (np.isfinite(value) and value > 0):
        raise ConfigError(key, "a positive value", value)


def nonnegative(key: str, value: float) -> None:
    """Raise ConfigError unless ``value`` is finite and >= 0."""
    if not (np.isfinite(value) and value >= 0):
        raise ConfigError(key, "a non-negative value", value)
