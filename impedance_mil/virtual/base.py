"""The virtual-system contract: :class:`VirtualSystem` and its named results.

A virtual system (VS, report Section 5) is the simulated environment under
the test article: a basemat of mass ``m_vs`` on isolators.  Its inputs are
the ground acceleration ``a_g`` [in/s**2] and the force ``w`` [lbf] the test
article applies on the basemat (the sign convention of Eq 4-7b:
``m_vs * z_vs = -F + w`` with ``F`` the isolator shear force); its output is
the absolute basemat acceleration ``z_vs`` [in/s**2] the table must imitate.

Adding a VS of your own
-----------------------
Subclass :class:`VirtualSystem` as a frozen dataclass, set the class
attributes ``kind`` and ``user_n_states``, and define :meth:`derivative`,
:meth:`outputs` and :meth:`linear_part` (and :meth:`nonlinear_input` if the
linear part has one).  :meth:`step_rk3` and :meth:`simulate` then work
through a Python path with the same RK3 tableau as the compiled kernel.
``MILRuntime`` steps such a VS through these methods, and
:func:`impedance_mil.lab.loop.simulate` runs its MIL tests through the plant
interface instead of the compiled loop (same ticks and plant kernels; about
8x faster than real time instead of ~750x; tested to give the compiled
loop's numbers, measured bit for bit, for a Python transcription of SD2).  The code
generators render only the built-in kinds.  See
:mod:`impedance_mil.virtual.two_storey` for a complete example.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..errors import ConfigError, IncompleteModelError
from ..systems import TransferFunction
from . import kernels
from .kernels import KIND_PYTHON, RK3_A21, RK3_A32, RK3_B1, RK3_B2, RK3_B3


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


def rk3_step_python(derivative, x: np.ndarray, dt: float) -> np.ndarray:
    """One step of the report's RK3 (Figure 7.9) for a Python derivative ``f(x)``.

    Same tableau as :func:`impedance_mil.virtual.kernels.vs_step_rk3` (shared
    constants); used for user-defined VS classes.
    """
    k1 = derivative(x)
    k2 = derivative(x + RK3_A21 * dt * k1)
    k3 = derivative(x + RK3_A32 * dt * k2)
    return x + dt * (RK3_B1 * k1 + RK3_B2 * k2 + RK3_B3 * k3)


def _inputs(a_g, w) -> tuple[np.ndarray, np.ndarray]:
    """Input histories as contiguous float64 arrays (w broadcast, zeros when None)."""
    a = np.ascontiguousarray(a_g, dtype=float).reshape(-1)
    if w is None:
        ww = np.zeros_like(a)
    else:
        ww = np.ascontiguousarray(np.broadcast_to(np.asarray(w, dtype=float), a.shape), dtype=float)
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(ww))):
        raise ConfigError("a_g/w", "finite input histories")
    return a, ww


@dataclass(frozen=True)
class VirtualSystem:
    """Base of every virtual system: a rigid basemat of mass ``m_vs`` on isolators.

    Parameters
    ----------
    m_vs : float
        Basemat mass [lbf*s**2/in].

    Notes
    -----
    Built-in kinds (``kind_code >= 1``) evaluate their dynamics in the
    compiled kernels of :mod:`impedance_mil.virtual.kernels`; a subclass with
    ``kind_code == KIND_PYTHON`` overrides :meth:`derivative`,
    :meth:`outputs` and :meth:`linear_part` instead.
    """

    m_vs: float

    #: Short name of the kind ("SD", "LR", "FP", or a user name).
    kind: ClassVar[str] = "user"
    #: Kernel selector; KIND_PYTHON for a user-defined VS.
    kind_code: ClassVar[int] = KIND_PYTHON
    #: Number of states of a user-defined VS (built-ins take it from the kernel).
    user_n_states: ClassVar[int] = 0

    def __post_init__(self):
        _positive("m_vs", self.m_vs)

    # ------------------------------------------------------------ contract
    @property
    def n_states(self) -> int:
        """Number of states."""
        if self.kind_code == KIND_PYTHON:
            return self.user_n_states
        return int(kernels.vs_n_states(self.kind_code))

    def parameter_array(self) -> np.ndarray:
        """Parameters as float64 in the kernel layout of :mod:`~impedance_mil.virtual.kernels`.

        For a user-defined VS: its dataclass fields in declaration order.
        """
        names = kernels.PARAM_NAMES.get(self.kind_code)
        if names is None:
            names = tuple(f.name for f in dataclasses.fields(self))
        return np.array([float(getattr(self, name)) for name in names])

    def initial_state(self) -> np.ndarray:
        """State at rest [in, in/s, ...]: all zeros."""
        return np.zeros(self.n_states)

    def derivative(self, x, a_g: float, w: float) -> np.ndarray:
        """State derivative dx/dt.

        Parameters
        ----------
        x : array_like
            State (layout per kind, see kernels).
        a_g : float
            Ground acceleration [in/s**2].
        w : float
            Force from the test article on the basemat [lbf].
        """
        self._require_kernel("derivative")
        out = np.empty(self.n_states)
        kernels.vs_derivative(self.kind_code, self.parameter_array(), _state(x), float(a_g), float(w), out)
        return out

    def outputs(self, x, a_g: float, w: float) -> VSOutput:
        """Outputs at state ``x`` for inputs ``a_g`` [in/s**2] and ``w`` [lbf]."""
        self._require_kernel("outputs")
        p = self.parameter_array()
        xs = _state(x)
        return VSOutput(
            z_vs=float(kernels.vs_output_z(self.kind_code, p, xs, float(a_g), float(w))),
            displacement=float(xs[0]),
            velocity=float(xs[1]),
            force=float(kernels.vs_force(self.kind_code, p, xs)),
        )

    def nonlinear_input(self, x) -> float:
        """Nonlinear input f_h of :meth:`linear_part` at state ``x``.

        Zero for a linear VS; a user-defined nonlinear VS overrides this.
        """
        if self.kind_code == KIND_PYTHON:
            return 0.0
        return float(kernels.vs_nonlinear_input(self.kind_code, self.parameter_array(), _state(x)))

    def linear_part(self) -> LinearPart:
        """Transfer functions of the linear part (Figures 5.3, 5.5).

        For built-in kinds they are derived from the compiled kernel
        :func:`~impedance_mil.virtual.kernels.vs_linear_derivative` (exact,
        the part is linear), then reduced with relative-tolerance
        cancellation; they equal Eq 5-2, 5-8 and 5-13 (corrected, see
        docs/errata.md).
        """
        self._require_kernel("linear_part")
        return _kernel_linear_part(self.kind_code, self.parameter_array())

    def step_rk3(self, x, a_g: float, w: float, dt: float) -> np.ndarray:
        """State after one step ``dt`` [s] of the report's RK3, inputs held.

        Parameters
        ----------
        x : array_like
            State at the start of the step (not modified).
        a_g : float
            Ground acceleration [in/s**2], held over the step.
        w : float
            Test-article force [lbf], held over the step.
        dt : float
            Step [s].
        """
        xs = _state(x).copy()
        if self.kind_code == KIND_PYTHON:
            return rk3_step_python(lambda s: self.derivative(s, a_g, w), xs, float(dt))
        work = np.empty(4 * self.n_states)
        kernels.vs_step_rk3(self.kind_code, self.parameter_array(), xs, float(a_g), float(w), float(dt), work)
        return xs

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

        Returns
        -------
        VSResponse
        """
        if not dt > 0:
            raise ConfigError("dt", "a positive time step in s", dt)
        a, ww = _inputs(a_g, w)
        x = self.initial_state() if x0 is None else _state(x0).copy()
        n = a.size
        z, disp, vel, force, fh = (np.empty(n) for _ in range(5))
        if self.kind_code == KIND_PYTHON:
            for k in range(n):
                out = self.outputs(x, a[k], ww[k])
                z[k], disp[k], vel[k], force[k] = out.z_vs, out.displacement, out.velocity, out.force
                fh[k] = self.nonlinear_input(x)
                x = self.step_rk3(x, a[k], ww[k], dt)
        else:
            kernels.vs_simulate(
                self.kind_code, self.parameter_array(), x, a, ww, float(dt), z, disp, vel, force, fh
            )
        return VSResponse(
            time=np.arange(n) * dt,
            a_g=a,
            w=ww,
            z_vs=z,
            displacement=disp,
            velocity=vel,
            force=force,
            f_h=fh,
            final_state=x,
        )

    def with_rigid_article(self, m_article: float) -> VirtualSystem:
        """Equivalent VS with a rigid test article of mass ``m_article`` lumped on the basemat.

        With a rigid article, ``w = -m_article * z_vs``; lumping the mass
        solves that algebraic loop exactly.  Subclasses whose parameters
        depend on the article (FP axial load) override this.
        """
        _nonnegative("m_article", m_article)
        return dataclasses.replace(self, m_vs=self.m_vs + m_article)

    # ---------------------------------------------------------- description
    def derived(self) -> dict[str, float]:
        """Derived properties (name -> value in internal units); none by default."""
        return {}

    def to_dict(self) -> dict[str, Any]:
        """``kind``, the parameters and the derived properties (internal units)."""
        data: dict[str, Any] = {"kind": self.kind}
        data.update({f.name: getattr(self, f.name) for f in dataclasses.fields(self)})
        data.update(self.derived())
        return data

    def _require_kernel(self, what: str) -> None:
        if self.kind_code == KIND_PYTHON:
            raise IncompleteModelError(f"{type(self).__name__} must define {what}()")


def _kernel_linear_part(kind_code: int, params: np.ndarray) -> LinearPart:
    """Read (A, B, C, D) of the linear part off the kernel with unit states and inputs."""
    n = kernels.N_LINEAR_STATES[kind_code]
    n_full = int(kernels.vs_n_states(kind_code))

    def column(x, a_g, w, f_h):
        out = np.zeros(n_full)
        kernels.vs_linear_derivative(kind_code, params, x, a_g, w, f_h, out)
        return out[:n]

    zero = np.zeros(n_full)
    A = np.column_stack([column(np.eye(n_full)[j], 0.0, 0.0, 0.0) for j in range(n)])
    B = np.column_stack([column(zero, *np.eye(3)[j]) for j in range(3)])
    # z_vs = dv/dt + a_g: the second row of (A, B), plus 1 on a_g.
    C = A[1, :]
    D = B[1, :] + np.array([1.0, 0.0, 0.0])
    omega = max(float(np.max(np.abs(np.linalg.eigvals(A)))), 1e-12)
    tfs = [_drop_residue(TransferFunction.from_ss(A, B[:, j], C, D[j]), omega).minreal() for j in range(3)]
    has_fh = kind_code != kernels.KIND_SD
    return LinearPart(H_zag=tfs[0], H_zw=tfs[1], H_zfh=tfs[2] if has_fh else None)


def _drop_residue(tf: TransferFunction, omega: float, rtol: float = 1e-9) -> TransferFunction:
    """Zero numerator coefficients that are rounding residue on the system's frequency scale.

    A coefficient of s**p counts as residue when ``|c_p|*omega**p`` is below
    ``rtol`` times the largest such term (``omega`` [rad/s]: spectral radius of A).
    """
    num = np.array(tf.num, dtype=float)
    powers = np.arange(num.size - 1, -1, -1)
    terms = np.abs(num) * omega**powers
    num[terms < rtol * terms.max()] = 0.0
    return TransferFunction(num, tf.den)


def _state(x) -> np.ndarray:
    return np.ascontiguousarray(x, dtype=float)


def _positive(key: str, value: float) -> None:
    if not (np.isfinite(value) and value > 0):
        raise ConfigError(key, "a positive value", value)


def _nonnegative(key: str, value: float) -> None:
    if not (np.isfinite(value) and value >= 0):
        raise ConfigError(key, "a non-negative value", value)
