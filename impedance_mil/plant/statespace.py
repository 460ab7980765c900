"""State-space building blocks of the shake-table model (report Eq 4-9, 4-3, 4-11).

States of the open-loop model (Eq 4-11): ``x`` table displacement [in], ``v``
velocity [in/s], ``dp`` differential pressure [psi], ``spool`` servovalve
state in equivalent current [mA] (unit DC gain from u_i), ``spool_rate``
[mA/s] (a second-order valve; a first-order valve has no ``spool_rate``,
:func:`plant_states`).  Sign convention (Eq 4-7b): ``m_st z = A_p dP + w``,
with the general model's platen damping c_p and grounded stiffness k_g
``m_st z = A_p dP + w - k_g x - c_p v`` (both 0 in the report's table).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..errors import ConfigError
from ..lti import StateSpace
from ..systems import TransferFunction
from .parameters import TableParameters

#: Outputs: acceleration z [in/s^2], displacement x [in], velocity v [in/s], dP [psi].
OUTPUTS = ("z", "x", "v", "dp")
#: Inputs: position command u [in], test-article force w [lbf].
INPUTS = ("u", "w")
#: Names of the states of Eq 4-11 (a second-order valve: the report's).
PLANT_STATES = ("x", "v", "dp", "spool", "spool_rate")
#: Names of the states with a first-order valve.
FIRST_ORDER_PLANT_STATES = PLANT_STATES[:4]


def plant_states(p: TableParameters) -> tuple[str, ...]:
    """The open-loop states of ``p``'s model: :data:`PLANT_STATES`, without ``spool_rate`` for a first-order valve."""
    return PLANT_STATES if p.valve_dynamics.order == 2 else FIRST_ORDER_PLANT_STATES


@dataclass(frozen=True, eq=False)
class TableChannels:
    """A table model by name: one :class:`~impedance_mil.lti.StateSpace` and its named rows.

    Every evaluation (transfer functions, frequency responses, poles) is that
    of ``system``; the properties give its matrices by name, as the report
    writes them (``B_u``, ``B_w``, the output rows ``C["z"]`` ...).

    Attributes
    ----------
    system : StateSpace
        Inputs ``(input_name, "w")``, outputs a subset of :data:`OUTPUTS`.
    input_name : str
        Name of the command input: ``"u"`` [in] (closed loop) or ``"u_i"``
        [mA] (open loop, Eq 4-11); ``"u"`` is accepted for either.
    """

    system: StateSpace
    input_name: str = "u"

    @property
    def A(self) -> np.ndarray:
        """State matrix ([1/s] continuous, dimensionless discrete)."""
        return self.system.A

    @property
    def B_u(self) -> np.ndarray:
        """Input vector of the command."""
        return self.system.B[:, 0]

    @property
    def B_w(self) -> np.ndarray:
        """Input vector of the test-article force w [lbf]."""
        return self.system.B[:, 1]

    @cached_property
    def C(self) -> dict[str, np.ndarray]:
        """Output rows by name."""
        return dict(zip(self.system.outputs, self.system.C))

    @cached_property
    def D(self) -> dict[str, tuple[float, float]]:
        """Feedthrough (from the command, from w) by output name."""
        return {k: (float(row[0]), float(row[1])) for k, row in zip(self.system.outputs, self.system.D)}

    @property
    def states(self) -> tuple[str, ...]:
        """State names."""
        return self.system.states

    def channel(self, output: str, input: str) -> StateSpace:
        """The SISO system ``output/input``."""
        if output not in self.system.outputs:
            raise ConfigError("output", "one of " + ", ".join(self.system.outputs), output)
        if input not in ("w", self.input_name, "u"):
            raise ConfigError("input", f"one of {self.input_name}, w", input)
        return self.system.channel(output, "w" if input == "w" else self.input_name)

    def input_vector(self, input: str) -> np.ndarray:
        """``B_u`` for the command input, ``B_w`` for ``"w"``."""
        return self.channel(self.system.outputs[0], input).B[:, 0]

    def poles(self) -> np.ndarray:
        """Eigenvalues of A ([rad/s] continuous, z-plane discrete)."""
        return self.system.poles()

    def frequency_response(self, output: str, input: str, f_hz) -> np.ndarray:
        """Complex response at ``f_hz`` [Hz] by solving ``(pI - A) X = b`` (no polynomials)."""
        return self.channel(output, input).frequency_response(np.atleast_1d(np.asarray(f_hz, dtype=float)))


@dataclass(frozen=True, eq=False)
class TableStateSpace(TableChannels):
    """Continuous table model ``x' = A x + B_u u + B_w w``, ``y = C[y] x + D[y] (u, w)``.

    Attributes
    ----------
    system : StateSpace
        A [1/s]; inputs the command (``u`` [in] closed loop, ``u_i`` [mA]
        open loop) and the test-article force w [lbf]; outputs ``"z"``,
        ``"x"``, ``"v"``, ``"dp"``.
    input_name : str
        ``"u"`` (closed loop) or ``"u_i"`` (open loop, Eq 4-11).
    """

    @classmethod
    def build(cls, A, B_u, B_w, C, D, states, input_name: str = "u") -> TableStateSpace:
        """From the state matrix, the two input vectors and the output rows and feedthroughs by name.

        Parameters
        ----------
        A : ndarray, shape (n, n)
            State matrix [1/s].
        B_u, B_w : ndarray, shape (n,)
            Input vectors of the command and of w [lbf].
        C : mapping of str to ndarray, shape (n,)
            Output rows by name (``"z"``, ``"x"``, ``"v"``, ``"dp"``).
        D : mapping of str to (float, float)
            Feedthrough (from the command, from w) of each output.
        states : tuple of str
        input_name : str
        """
        names = tuple(C)
        system = StateSpace(
            A,
            np.column_stack([B_u, B_w]),
            np.vstack([C[k] for k in names]),
            np.array([D[k] for k in names], dtype=float),
            0.0,
            (input_name, "w"),
            names,
            states,
        )
        return cls(system, input_name)

    def tf(self, output: str, input: str) -> TransferFunction:
        """Transfer function ``output/input`` (round-off safe, :meth:`TransferFunction.from_lti`)."""
        return TransferFunction.from_lti(self.channel(output, input))


def plant_state_space(p: TableParameters) -> TableStateSpace:
    """Open-loop model Eq 4-11: inputs valve current u_i [mA] and force w [lbf].

    Built from the servovalve (Eq 4-3, scaled to unit DC gain from u_i; or the
    first- or second-order valve of ``p.valve``) and the actuator-table model
    (Eq 4-9 with Eq 4-10a/b, plus the platen damping c_p and the grounded
    stiffness k_g of the general model: ``m_st v' = A_p dP + w - k_g x - c_p v``).
    """
    valve = p.valve_dynamics
    w2, eps = p.omega_oil**2, 2.0 * p.zeta_oil * p.omega_oil
    m, ap = p.mass, p.piston_area
    states = plant_states(p)
    n = len(states)
    A = np.zeros((n, n))
    A[0, 1] = 1.0
    # 0.0 - c: an exact +0.0 when c = 0 (the report's table, bit for bit)
    A[1, 0] = 0.0 - p.grounded_stiffness / m
    A[1, 1] = 0.0 - (p.platen_damping or 0.0) / m
    A[1, 2] = ap / m
    A[2, 1] = -w2 * m / ap
    A[2, 2] = -eps
    A[2, 3] = p.d
    B_i = np.zeros(n)
    if valve.order == 2:
        A[3, 4] = 1.0
        A[4, 3] = -valve.gamma
        A[4, 4] = -valve.delta
    else:
        A[3, 3] = -valve.gamma
    B_i[n - 1] = valve.gamma
    B_w = np.zeros(n)
    B_w[1] = 1.0 / m
    eye = np.eye(n)
    C = {"z": A[1].copy(), "x": eye[0], "v": eye[1], "dp": eye[2]}
    D = {"z": (0.0, 1.0 / m), "x": (0.0, 0.0), "v": (0.0, 0.0), "dp": (0.0, 0.0)}
    return TableStateSpace.build(A, B_i, B_w, C, D, states, input_name="u_i")


def feedback_row(p: TableParameters) -> np.ndarray:
    """Row ``k`` with ``k x = K_e g x_st + K_p dP`` [V], the delayed feedback of Section 4.3.4.

    ``g`` is the displacement sensor's gain (``p.output_gain``, 1 in the report).
    """
    k = np.zeros(len(plant_states(p)))
    k[0] = p.Ke * p.output_gain
    k[2] = p.Kp
    return k
