"""Exact sampled-data model of the digitally controlled table (report Section 4.3.4).

The RMC75E computes, once per loop time T = tau_s,

    u_v(k) = K_e (u(k) - x(k-1)) - K_p dP(k-1)

from the measurements saved in the previous loop, and holds u_v until the
next loop (zero-order hold).  The continuous plant of Eq 4-11 is discretized
exactly (ZOH, matrix exponential) and augmented with one memory state
``m(k) = K_e x(k-1) + K_p dP(k-1)``.  This is the reference against which
the report's first-order approximation ``e^{-s tau} ~ 1 - s tau`` is judged
(:mod:`impedance_mil.plant.tuning`).

A controller with an output delay of N loops
(:attr:`~impedance_mil.plant.parameters.TableParameters.output_delay_loops`)
applies the command computed at loop k over loop k + N - 1, as the virtual
lab's ring buffer does (:func:`impedance_mil.lab.kernels.delayed_output`):
the valve receives ``u_v(k - N + 1)``, the command N - 1 loops and the
feedback N loops late.  The model carries the N - 1 commands computed and
not yet applied as N - 1 more states ``pending_j(k) = u_v(k - j)`` [V]; for
N = 1 it is the one-memory model above.

The force w is treated as held over each loop (the model describes the
response at the sampling instants).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..lti import StateSpace
from ..ss2tf import ss_to_tf
from .parameters import TableParameters
from .statespace import INPUTS, TableChannels, feedback_row, plant_state_space


@dataclass(frozen=True)
class DiscreteTransferFunction:
    """``num(z)/den(z)`` in descending powers of z, sample time ``dt`` [s], monic ``den``."""

    num: np.ndarray
    den: np.ndarray
    dt: float

    def frequency_response(self, f_hz) -> np.ndarray:
        """Complex response at ``f_hz`` [Hz] (``z = exp(j 2 pi f dt)``)."""
        z = np.exp(2j * np.pi * np.asarray(f_hz, dtype=float) * self.dt)
        return np.polyval(self.num, z) / np.polyval(self.den, z)

    def to_dict(self) -> dict:
        """``{"num": [...], "den": [...], "dt": ..., "variable": "z"}``."""
        return {
            "num": [float(c) for c in self.num],
            "den": [float(c) for c in self.den],
            "dt": float(self.dt),
            "variable": "z",
        }


@dataclass(frozen=True, eq=False)
class SampledTable(TableChannels):
    """The table under digital control, at the sampling instants.

    Attributes
    ----------
    system : StateSpace
        Discrete, sample time the loop time T [s]; states ``[x, v, dp,
        spool, spool_rate, memory, pending_1 ... pending_{N-1}]`` (no
        ``spool_rate`` with a first-order valve; ``memory``:
        the feedback saved in the previous loop [V]; ``pending_j``: the valve
        command computed j loops earlier [V], N the output delay); inputs the command u [in] and the force w [lbf];
        outputs ``"z"``, ``"x"``, ``"v"``, ``"dp"``.
    """

    @classmethod
    def from_params(cls, p: TableParameters) -> SampledTable:
        """Discretize Eq 4-11 with ZOH over ``p.loop_time`` and close the delayed hydraulic loop.

        The loop is delayed as the virtual lab delays it: the feedback by one
        loop (the ``memory`` state), the whole valve command by
        ``p.output_delay_loops - 1`` more (the ``pending_j`` states).
        """
        if not p.loop_time > 0:
            raise ConfigError("loop_time", "a positive loop time for the sampled-data model", p.loop_time)
        plant = plant_state_space(p)
        ol = plant.system.zoh(p.loop_time)
        phi, g_i, g_w = ol.A, ol.B[:, 0], ol.B[:, 1]
        n, extra = phi.shape[0], p.output_delay_loops - 1
        memory = n
        A = np.zeros((n + 1 + extra, n + 1 + extra))
        B = np.zeros((n + 1 + extra, 2))
        A[:n, :n] = phi
        A[memory, :n] = feedback_row(p)
        B[:n, 1] = g_w
        if extra == 0:
            # u_v(k) = K_e u(k) - m(k), applied at once
            A[:n, memory] = -p.Kv * g_i
            B[:n, 0] = p.Kv * p.Ke * g_i
        else:
            # pending_1(k+1) = u_v(k) = K_e u(k) - m(k); pending_j(k+1) = pending_{j-1}(k);
            # the valve receives pending_{N-1}(k)
            first, last = n + 1, n + extra
            A[first, memory] = -1.0
            B[first, 0] = p.Ke
            for j in range(first + 1, last + 1):
                A[j, j - 1] = 1.0
            A[:n, last] = p.Kv * g_i
        C = np.column_stack([ol.C, np.zeros((ol.n_outputs, 1 + extra))])
        states = plant.states + ("memory",) + tuple(f"pending_{j + 1}" for j in range(extra))
        return cls(StateSpace(A, B, C, ol.D, p.loop_time, INPUTS, ol.outputs, states))

    @property
    def dt(self) -> float:
        """Loop time T [s]."""
        return self.system.dt

    def poles_z(self) -> np.ndarray:
        """Eigenvalues of the discrete loop (z-plane)."""
        return self.system.poles()

    def poles_s(self) -> np.ndarray:
        """Discrete poles mapped to the s-plane, ``ln(z)/T`` [rad/s].

        Poles at z = 0 (a pure one-loop delay) have no s-plane image and are
        omitted.
        """
        z = self.poles_z()
        z = z[np.abs(z) > 1e-12]
        return np.log(z.astype(complex)) / self.dt

    def is_stable(self) -> bool:
        """True when every discrete pole is inside the unit circle."""
        return self.system.is_stable()

    def tf(self, output: str, input: str) -> DiscreteTransferFunction:
        """Discrete transfer function ``output(z)/input(z)`` at the sampling instants."""
        num, den = ss_to_tf(self.channel(output, input))  # round-off leading coefficients are exact zeros
        lead = np.flatnonzero(num)
        return DiscreteTransferFunction(num[lead[0] :] if lead.size else np.zeros(1), den, self.dt)
