"""Exact sampled-data model of the digitally controlled table (report Section 4.3.4).

The RMC75E computes, once per loop time T = tau_s,

    u_v(k) = K_e (u(k) - x(k-1)) - K_p dP(k-1)

from the measurements saved in the previous loop, and holds u_v until the
next loop (zero-order hold).  The continuous plant of Eq 4-11 is discretized
exactly (ZOH, matrix exponential) and augmented with one memory state
``m(k) = K_e x(k-1) + K_p dP(k-1)``.  This is the reference against which
the report's first-order approximation ``e^{-s tau} ~ 1 - s tau`` is judged
(:mod:`impedance_mil.plant.tuning`).

The force w is treated as held over each loop (the model describes the
response at the sampling instants).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ..errors import ConfigError
from .parameters import TableParameters
from .statespace import (
    INPUTS,
    OUTPUTS,
    PLANT_STATES,
    feedback_row,
    plant_state_space,
    resolvent_response,
    ss_to_tf,
)


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


def zoh_discretize(A: np.ndarray, B: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact ZOH discretization ``(Phi, Gamma)`` of ``x' = A x + B u`` over ``dt`` [s]."""
    n, m = A.shape[0], B.shape[1]
    block = np.zeros((n + m, n + m))
    block[:n, :n] = A * dt
    block[:n, n:] = B * dt
    E = scipy.linalg.expm(block)
    return E[:n, :n], E[:n, n:]


@dataclass(frozen=True, eq=False)
class SampledTable:
    """The table under digital control, at the sampling instants.

    Attributes
    ----------
    A : ndarray, shape (6, 6)
        Discrete state matrix of ``[x, v, dp, spool, spool_rate, m]``.
    B_u, B_w : ndarray, shape (6,)
        Input vectors of the command u [in] and the force w [lbf].
    C : dict of str to ndarray
        Output rows (``"z"``, ``"x"``, ``"v"``, ``"dp"``).
    D : dict of str to tuple of float
        Feedthrough (from u, from w).
    dt : float
        Loop time T [s].
    """

    A: np.ndarray
    B_u: np.ndarray
    B_w: np.ndarray
    C: dict
    D: dict
    dt: float

    @classmethod
    def from_params(cls, p: TableParameters) -> SampledTable:
        """Discretize Eq 4-11 with ZOH over ``p.loop_time`` and close the one-loop-delayed feedback."""
        if not p.loop_time > 0:
            raise ConfigError("loop_time", "a positive loop time for the sampled-data model", p.loop_time)
        ol = plant_state_space(p)
        phi, gam = zoh_discretize(ol.A, np.column_stack([ol.B_u, ol.B_w]), p.loop_time)
        g_i, g_w = gam[:, 0], gam[:, 1]
        n = phi.shape[0]
        A = np.zeros((n + 1, n + 1))
        A[:n, :n] = phi
        A[:n, n] = -p.Kv * g_i
        A[n, :n] = feedback_row(p)
        B_u = np.append(p.Kv * p.Ke * g_i, 0.0)
        B_w = np.append(g_w, 0.0)
        C = {name: np.append(row, 0.0) for name, row in ol.C.items()}
        return cls(A, B_u, B_w, C, dict(ol.D), p.loop_time)

    @property
    def states(self) -> tuple[str, ...]:
        """State names; ``memory`` is the feedback saved in the previous loop [V]."""
        return PLANT_STATES + ("memory",)

    def poles_z(self) -> np.ndarray:
        """Eigenvalues of the discrete loop (z-plane)."""
        return np.linalg.eigvals(self.A)

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
        return bool(np.all(np.abs(self.poles_z()) < 1.0))

    def tf(self, output: str, input: str) -> DiscreteTransferFunction:
        """Discrete transfer function ``output(z)/input(z)`` at the sampling instants."""
        if output not in OUTPUTS:
            raise ConfigError("output", "one of " + ", ".join(OUTPUTS), output)
        if input not in INPUTS:
            raise ConfigError("input", "one of " + ", ".join(INPUTS), input)
        b = self.B_w if input == "w" else self.B_u
        feed = self.D[output][1 if input == "w" else 0]
        num, den = ss_to_tf(self.A, b, self.C[output], feed)
        return DiscreteTransferFunction(_trim_leading(num, den), den, self.dt)

    def frequency_response(self, output: str, input: str, f_hz) -> np.ndarray:
        """Complex response at ``f_hz`` [Hz] by solving ``(zI - A) X = b``."""
        b = self.B_w if input == "w" else self.B_u
        feed = self.D[output][1 if input == "w" else 0]
        z = np.exp(2j * np.pi * np.atleast_1d(np.asarray(f_hz, dtype=float)) * self.dt)
        return resolvent_response(self.A, b, self.C[output], feed, z)


def _trim_leading(num: np.ndarray, den: np.ndarray, rtol: float = 1e-12) -> np.ndarray:
    """Drop leading numerator coefficients that are round-off relative to the polynomial."""
    scale = np.max(np.abs(num)) if num.size else 0.0
    nz = np.nonzero(np.abs(num) > rtol * scale)[0] if scale > 0 else np.array([num.size - 1])
    return num[nz[0] :].copy()
