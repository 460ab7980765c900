"""Linear model of the servo-hydraulic shake table, built from state space (report Section 4.3).

The open-loop model is Eq 4-11 (servovalve Eq 4-3 in series with the
actuator-table Eq 4-9), with inputs valve current u_i [mA] and test-article
force w [lbf].  The hydraulic loop ``u_i = K_v (K_e (u - x) - K_p dP)`` is
closed with the feedback delayed by one loop time tau_s, treated as

* ``"none"``: analog controller, Eq 4-14b;
* ``"first-order"``: ``e^{-s tau} ~ 1 - s tau``, Eq 4-13/4-14a (the report's model);
* ``"pade"``: a Pade approximation of order n of ``e^{-s tau}`` on the feedback signal;
* ``"sampled"``: the exact sampled-data loop (see :mod:`impedance_mil.plant.sampled`).

A controller with an output delay of N loops (``TableParameters.output_delay_loops``,
a lab's ``[controller] output_delay``; 1 for the report's) applies the command it
computes at loop k over loop k + N - 1, so that
``u_v(t) = K_e u(t - (N-1) tau_s) - [K_e x + K_p dP](t - N tau_s)``: the feedback is
delayed by N tau_s and the command by (N-1) tau_s.  The continuous treatments
approximate both delays:

* ``"first-order"``: the feedback ``e^{-s N tau} ~ 1 - s N tau`` (the report's
  treatment with N tau for tau), and the command ``e^{-s (N-1) tau} ~ 1 / (1 + s (N-1) tau)``,
  a first-order lag (``1 - s (N-1) tau`` would differentiate the command), one more state;
* ``"pade"``: Pade approximations of order n of ``e^{-s N tau}`` on the feedback and of
  ``e^{-s (N-1) tau}`` on the command (n more states);
* ``"none"``: the analog controller has no loop time and no delay, whatever N;
* ``"sampled"``: the N - 1 commands not yet applied are states of the discrete model.

N = 1 is the model above, to the last bit.

The six transfer functions of Eq 4-15 follow from the state space; they are
never typed in by hand (the tests compare them with Eq 4-15 coefficient by
coefficient).

States: ``x`` table displacement [in], ``v`` velocity [in/s], ``dp``
differential pressure [psi], ``spool`` servovalve state in equivalent
current [mA] (Eq 4-11 scaling: unit DC gain from u_i), ``spool_rate`` [mA/s].
Sign convention (Eq 4-7b): ``m_st z = A_p dP + w``, w being the force the
test article applies on the table.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ConfigError, UnstableSystemError
from ..lazy import LazyModule
from ..lti import StateSpace
from ..systems import TransferFunction
from .parameters import TableParameters
from .sampled import SampledTable
from .statespace import INPUTS, OUTPUTS, TableStateSpace, feedback_row, plant_state_space

#: python-control and scipy.linalg, imported on first use (:class:`~impedance_mil.lazy.LazyModule`):
#: a command that only reads a configuration does not need them (issue 16, start-up).
control = LazyModule("control")
scipy_linalg = LazyModule("scipy.linalg")

#: Delay treatments of the loop time.
DELAYS = ("none", "first-order", "pade", "sampled")
#: Default order of the Pade approximation.
DEFAULT_PADE_ORDER = 6
#: Highest order accepted: the coefficients of the order-10 Pade polynomials already span
#: 12 decades (6.7e11), beyond which a double cannot hold the approximation; the one-loop
#: delay is resolved to 1e-6 well before (``--pade-order 1000`` divided by zero in python-control).
MAX_PADE_ORDER = 10


@dataclass(frozen=True, eq=False)
class DelayApproximation:
    """A SISO rational approximation of a delay ``e^{-s tau}``: ``q' = A q + b y``, output ``c q + d y``.

    Attributes
    ----------
    A : ndarray, shape (n, n)
        State matrix [1/s].
    b, c : ndarray, shape (n,)
        Input and output vectors (``b`` [1/s]).
    d : float
        Feedthrough [-].
    """

    A: np.ndarray
    b: np.ndarray
    c: np.ndarray
    d: float


def pade_state_space(tau: float, order: int) -> DelayApproximation:
    """The Pade approximation of order ``order`` of ``e^{-s tau}``, tau [s].

    Realized for tau = 1 and balanced, then scaled by ``1/tau`` (``s tau`` is
    the natural variable), so that short delays do not give huge coefficients.
    """
    unit = StateSpace.from_polynomials(*control.pade(1.0, order))
    A1, T = scipy_linalg.matrix_balance(unit.A, permute=False)
    scaling = np.diag(T)
    return DelayApproximation(
        A1 / tau, unit.B[:, 0] / scaling / tau, unit.C[0] * scaling, float(unit.D[0, 0])
    )


def first_order_lag(tau: float) -> DelayApproximation:
    """``1 / (1 + s tau)``, the first-order approximation of ``e^{-s tau}`` that needs no derivative, tau [s]."""
    return DelayApproximation(np.array([[-1.0 / tau]]), np.array([1.0 / tau]), np.array([1.0]), 0.0)


def closed_loop_state_space(
    p: TableParameters,
    delay: str = "first-order",
    pade_order: int = DEFAULT_PADE_ORDER,
    open_loop: TableStateSpace | None = None,
) -> TableStateSpace:
    """Closed hydraulic loop ``u_i = K_v (K_e u(t - (N-1) tau_s) - [K_e x + K_p dP](t - N tau_s))``.

    Parameters
    ----------
    p : TableParameters
        Model parameters; N = ``p.output_delay_loops`` (1: the report's one-loop delay).
    delay : {"none", "first-order", "pade"}
        Treatment of the feedback delay N tau_s and the command delay (N-1) tau_s,
        tau_s = ``p.loop_time`` [s] (module docstring).
    pade_order : int
        Order of the Pade approximations (``delay="pade"``).
    open_loop : TableStateSpace, optional
        The open-loop plant to close (input u_i [mA], states ``x, v, dp, ...`` as
        :func:`plant_state_space`, whose ``x`` and ``dp`` the feedback reads); default
        Eq 4-11 of ``p``.  The richer linearized table of
        :func:`impedance_mil.plant.table_dynamics_model.linearized_plant` (issue 17).

    Returns
    -------
    TableStateSpace
        Eq 4-14b (``"none"``), Eq 4-14a (``"first-order"``) or the model
        augmented with the Pade states (``"pade"``); for N > 1 with the states
        of the command delay after them (``command_delay_i``).
    """
    ol = plant_state_space(p) if open_loop is None else open_loop
    A, b_i = ol.A, ol.B_u
    k = feedback_row(p)
    tau = p.loop_time
    loops = p.output_delay_loops
    b_u = p.Kv * p.Ke * b_i
    if delay == "none" or tau == 0.0:
        A_cl = A - p.Kv * np.outer(b_i, k)
        return TableStateSpace.build(A_cl, b_u, ol.B_w, ol.C, ol.D, ol.states)
    if delay == "first-order":
        # y(t - N tau) ~ y - N tau y' with y' = k A x (k B = 0: x and dP have no direct input)
        k_delayed = k - (loops * tau) * (k @ A)
        A_cl = A - p.Kv * np.outer(b_i, k_delayed)
        loop = TableStateSpace.build(A_cl, b_u, ol.B_w, ol.C, ol.D, ol.states)
        return loop if loops == 1 else command_delayed(loop, first_order_lag((loops - 1) * tau))
    if delay == "pade":
        if (
            isinstance(pade_order, bool)
            or not isinstance(pade_order, (int, np.integer))
            or not 1 <= pade_order <= MAX_PADE_ORDER
        ):
            raise ConfigError("pade_order", f"an integer from 1 to {MAX_PADE_ORDER}", pade_order)
        fb = pade_state_space(loops * tau, pade_order)
        Ad, bd, cd, dd = fb.A, fb.b, fb.c, fb.d
        q = Ad.shape[0]
        A_cl = np.block(
            [
                [A - p.Kv * dd * np.outer(b_i, k), -p.Kv * np.outer(b_i, cd)],
                [np.outer(bd, k), Ad],
            ]
        )
        pad = np.zeros(q)
        C = {name: np.concatenate([row, pad]) for name, row in ol.C.items()}
        states = ol.states + tuple(f"delay_{i + 1}" for i in range(q))
        loop = TableStateSpace.build(
            A_cl, np.concatenate([b_u, pad]), np.concatenate([ol.B_w, pad]), C, ol.D, states
        )
        if loops == 1:
            return loop
        return command_delayed(loop, pade_state_space((loops - 1) * tau, pade_order))
    raise ConfigError("delay", "one of none, first-order, pade", delay)


def command_delayed(loop: TableStateSpace, delay: DelayApproximation) -> TableStateSpace:
    """``loop`` with its command u [in] first passed through ``delay``.

    The delay's states follow the loop's, named ``command_delay_i``; the
    force w [lbf] does not pass through it.
    """
    Ad, bd, cd, dd = delay.A, delay.b, delay.c, delay.d
    n, q = loop.A.shape[0], Ad.shape[0]
    A = np.block([[loop.A, np.outer(loop.B_u, cd)], [np.zeros((q, n)), Ad]])
    C = {name: np.concatenate([row, loop.D[name][0] * cd]) for name, row in loop.C.items()}
    D = {name: (dd * d_u, d_w) for name, (d_u, d_w) in loop.D.items()}
    states = loop.states + tuple(f"command_delay_{i + 1}" for i in range(q))
    return TableStateSpace.build(
        A, np.concatenate([dd * loop.B_u, bd]), np.concatenate([loop.B_w, np.zeros(q)]), C, D, states
    )


@dataclass(frozen=True, eq=False)
class LinearTable:
    """Linear shake-table model for given parameters and delay treatment.

    Parameters
    ----------
    params : TableParameters
        Model parameters (report Table 4.1).
    delay : {"none", "first-order", "pade", "sampled"}
        Treatment of the controller loop time and of its output delay of
        ``params.output_delay_loops`` loops (see module docstring).
    pade_order : int
        Order of the Pade approximation for ``delay="pade"``.

    Notes
    -----
    For ``delay="sampled"`` the model is discrete: :meth:`tf` raises
    :class:`~impedance_mil.errors.ConfigError` (there is no continuous
    transfer function), :meth:`sampled` gives the discrete model (discrete
    transfer functions, frequency response), and :meth:`poles` returns its
    poles mapped to the s-plane by ``ln(z)/T``.

    Examples
    --------
    >>> tbl = LinearTable(TableParameters.report_default(), delay="none")
    >>> round(tbl.tf("x", "u").dcgain(), 12)
    1.0
    """

    params: TableParameters
    delay: str = "first-order"
    pade_order: int = DEFAULT_PADE_ORDER
    _ss: TableStateSpace | None = field(default=None, init=False, repr=False)

    def __post_init__(self):
        if self.delay not in DELAYS:
            raise ConfigError("delay", "one of " + ", ".join(DELAYS), self.delay)
        if self.delay == "sampled":
            if self.params.loop_time <= 0:
                raise ConfigError(
                    "loop_time", "a positive loop time for delay='sampled'", self.params.loop_time
                )
            return
        object.__setattr__(self, "_ss", closed_loop_state_space(self.params, self.delay, self.pade_order))

    def state_space(self) -> TableStateSpace:
        """The closed-loop state space (continuous delay treatments only)."""
        if self._ss is None:
            raise ConfigError(
                "delay",
                "none, first-order or pade for a continuous state space "
                "(use LinearTable.sampled() for 'sampled')",
                self.delay,
            )
        return self._ss

    def open_loop(self) -> TableStateSpace:
        """Eq 4-11: valve current u_i [mA] and force w [lbf] to the table outputs."""
        return plant_state_space(self.params)

    def tf(self, output: str, input: str) -> TransferFunction:
        """Transfer function ``output/input``.

        Parameters
        ----------
        output : {"z", "x", "v", "dp"}
            Acceleration [in/s^2], displacement [in], velocity [in/s] or dP [psi].
        input : {"u", "w"}
            Position command [in] or test-article force [lbf].
        """
        if output not in OUTPUTS:
            raise ConfigError("output", "one of " + ", ".join(OUTPUTS), output)
        if input not in INPUTS:
            raise ConfigError("input", "one of " + ", ".join(INPUTS), input)
        return self.state_space().tf(output, input)

    def sampled(self) -> SampledTable:
        """The exact sampled-data model (:class:`~impedance_mil.plant.sampled.SampledTable`)."""
        return SampledTable.from_params(self.params)

    def poles(self) -> np.ndarray:
        """Closed-loop poles [rad/s] (for ``"sampled"``: ``ln(z)/T`` of the discrete poles)."""
        if self.delay == "sampled":
            return self.sampled().poles_s()
        return self.state_space().poles()

    def is_stable(self) -> bool:
        """True when every closed-loop pole is in the open left half plane (|z| < 1 sampled)."""
        if self.delay == "sampled":
            return self.sampled().is_stable()
        return bool(np.all(self.poles().real < 0))

    def require_stable(self) -> LinearTable:
        """Return self, or raise :class:`UnstableSystemError` naming the unstable poles."""
        if not self.is_stable():
            bad = [p for p in self.poles() if p.real >= 0]
            text = (
                ", ".join(f"{abs(q) / (2 * np.pi):.1f} Hz (real part {q.real:+.2f} rad/s)" for q in bad)
                or "|z| >= 1"
            )
            loops = self.params.output_delay_loops
            output_delay = f", output_delay={loops} loops" if loops > 1 else ""
            raise UnstableSystemError(
                f"the table loop is unstable (Ke={self.params.Ke:g} V/in, Kp={self.params.Kp:g} "
                f"V/psi, loop_time={self.params.loop_time:g} s{output_delay}, delay={self.delay}): {text}"
            )
        return self
