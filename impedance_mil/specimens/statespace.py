"""The linear state-space form shared by every test article.

Every specimen is a linear system with one input and one output:

* input: the absolute acceleration of the table (the base of the specimen),
  ``z`` [in/s**2];
* output: the interface force ``w`` [lbf] that the specimen applies on the
  table, ``w = -sum_i m_i * a_i`` where ``a_i`` [in/s**2] are the absolute
  accelerations of the specimen's masses.

With this sign, force equilibrium of the table (report Eq 4-7b) reads
``m_st * z = A_p * dP + w``, and a rigid mass ``m`` on the table gives
``w = -m * z``.

The state space ``x' = A x + B z``, ``w = C x + D z`` is stored in plain,
contiguous float64 arrays (``B`` and ``C`` as vectors, ``D`` a float) so the
lab's compiled loop can integrate it directly (coupled with the table, in
:func:`impedance_mil.lab.kernels.plant_advance`, substeps chosen by
:func:`impedance_mil.lab.substeps.choose_substeps`).  :func:`rk4_step` and
:meth:`SpecimenStateSpace.rk4_substeps` integrate a specimen alone, driven by
a given ``z`` (the lab does not use them).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numba
import numpy as np

from ..errors import ConfigError
from ..lti import StateSpace
from ..systems import TransferFunction

#: Stability limit of classical RK4 on the imaginary axis, |lambda| h <= 2 sqrt(2).
RK4_STABILITY_LIMIT = 2.0 * np.sqrt(2.0)


@dataclass(frozen=True, eq=False)
class SpecimenStateSpace:
    """Continuous-time state space of a specimen, input ``z`` and output ``w``.

    Parameters
    ----------
    A : ndarray, shape (n, n)
        State matrix [1/s and 1/s**2 entries, depending on the state].
    B : ndarray, shape (n,)
        Input vector; the input is the table acceleration ``z`` [in/s**2].
    C : ndarray, shape (n,)
        Output vector; the output is the interface force ``w`` [lbf].
    D : float
        Feedthrough [lbf per in/s**2]; ``-m`` of the rigidly attached mass.

    Notes
    -----
    A specimen without internal dynamics (a rigid mass) has ``n = 0``:
    ``A`` is (0, 0), ``B`` and ``C`` are empty and ``w = D * z``.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: float

    def __post_init__(self):
        B = np.ascontiguousarray(np.asarray(self.B, dtype=float).ravel())
        C = np.ascontiguousarray(np.asarray(self.C, dtype=float).ravel())
        n = B.size
        A = np.asarray(self.A, dtype=float)
        A = np.zeros((0, 0)) if A.size == 0 else np.ascontiguousarray(np.atleast_2d(A))
        if A.shape != (n, n) or C.size != n:
            raise ConfigError(
                "state_space",
                f"A ({n}x{n}), B ({n}) and C ({n}) of matching sizes",
                f"A {A.shape}, B {B.shape}, C {C.shape}",
            )
        if not (
            np.all(np.isfinite(A))
            and np.all(np.isfinite(B))
            and np.all(np.isfinite(C))
            and np.isfinite(self.D)
        ):
            raise ConfigError("state_space", "finite matrices")
        for arr in (A, B, C):
            arr.setflags(write=False)
        object.__setattr__(self, "A", A)
        object.__setattr__(self, "B", B)
        object.__setattr__(self, "C", C)
        object.__setattr__(self, "D", float(self.D))

    @property
    def n_states(self) -> int:
        """Number of states."""
        return self.B.size

    def derivative(self, x: np.ndarray, z: float) -> np.ndarray:
        """State derivative ``A x + B z`` for table acceleration ``z`` [in/s**2]."""
        return self.A @ x + self.B * z

    def output(self, x: np.ndarray, z: float) -> float:
        """Interface force ``w`` [lbf] for state ``x`` and table acceleration ``z`` [in/s**2]."""
        return float(self.C @ x + self.D * z)

    @cached_property
    def system(self) -> StateSpace:
        """The same model as one :class:`~impedance_mil.lti.StateSpace`, input ``"z"``, output ``"w"``."""
        return StateSpace(self.A, self.B, self.C, self.D, 0.0, ("z",), ("w",))

    def frequency_response(self, f_hz) -> np.ndarray:
        """Complex ``w/z`` [lbf per in/s**2] at frequencies ``f_hz`` [Hz].

        Evaluated as ``C (j w I - A)^-1 B + D`` by a linear solve at each
        frequency (:meth:`StateSpace.frequency_response`), which stays
        accurate for lightly damped, widely spaced modes where polynomial
        coefficients would not.
        """
        return self.system.frequency_response(np.atleast_1d(np.asarray(f_hz, dtype=float)))

    def poles(self) -> np.ndarray:
        """Eigenvalues of ``A`` [rad/s]."""
        return self.system.poles()

    def is_stable(self) -> bool:
        """True when every pole has a negative real part."""
        return bool(np.all(self.poles().real < 0.0))

    def rk4_substeps(self, dt: float, margin: float = 0.5) -> int:
        """Number of RK4 substeps per step ``dt`` [s] that keeps :func:`rk4_step` stable.

        Classical RK4 is stable for ``|lambda| h <= 2.83`` on the imaginary axis
        (lightly damped modes); the substep ``h`` is chosen so that
        ``|lambda|_max h <= margin * 2.83``.
        """
        if self.n_states == 0:
            return 1
        fastest = float(np.max(np.abs(self.poles())))
        return max(1, int(np.ceil(fastest * dt / (margin * RK4_STABILITY_LIMIT))))

    def transfer_function(self) -> TransferFunction:
        """``w/z`` as a :class:`~impedance_mil.systems.TransferFunction` (s in rad/s)."""
        return TransferFunction.from_lti(self.system)

    def to_dict(self) -> dict:
        """Plain lists, for result files."""
        return {"A": self.A.tolist(), "B": self.B.tolist(), "C": self.C.tolist(), "D": self.D}


@numba.njit(cache=True)
def rk4_step(A, B, C, D, x, z_start, z_end, dt, x_out):
    """Advance a specimen one step with classical RK4; return ``w`` at the end.

    The table acceleration is taken linear in time over the step, from
    ``z_start`` to ``z_end`` [in/s**2] (first-order hold), which is what a
    compiled loop sees between two samples of a continuous plant.

    Parameters
    ----------
    A, B, C, D : ndarray, ndarray, ndarray, float
        Arrays of :class:`SpecimenStateSpace`.
    x : ndarray, shape (n,)
        State at the start of the step.
    z_start, z_end : float
        Table acceleration at the start and the end of the step [in/s**2].
    dt : float
        Step [s].
    x_out : ndarray, shape (n,)
        Receives the state at the end of the step (may be ``x`` itself).

    Returns
    -------
    float
        Interface force ``w`` [lbf] at the end of the step.
    """
    z_mid = 0.5 * (z_start + z_end)
    k1 = A @ x + B * z_start
    k2 = A @ (x + 0.5 * dt * k1) + B * z_mid
    k3 = A @ (x + 0.5 * dt * k2) + B * z_mid
    k4 = A @ (x + dt * k3) + B * z_end
    for i in range(x.size):
        x_out[i] = x[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
    w = D * z_end
    for i in range(x.size):
        w += C[i] * x_out[i]
    return w
