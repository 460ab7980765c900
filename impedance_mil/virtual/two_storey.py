"""A user-defined VS beyond the report: an isolated two-storey frame.

The test article stands on the roof of a base-isolated two-storey frame, so
the table must imitate the roof acceleration.  This module is also the
worked example of extending :class:`~impedance_mil.virtual.VirtualSystem`:
a frozen dataclass with ``kind``, ``user_n_states``, :meth:`derivative`,
:meth:`outputs` and :meth:`linear_part`; stepping and simulation come from
the base class through its Python path (``kind_code == KIND_PYTHON``; the
virtual lab steps it through ``MILRuntime`` and the plant interface instead
of the compiled loop).

Model (relative to the ground, u = [u_b, u_1, u_2], v = du/dt)::

    M dv/dt + C v + K u = -M 1 a_g + e_2 w,    z_vs = dv_2/dt + a_g

with ``M = diag(m_b, m_1, m_vs)``, the isolator (k_b, c_b) under the base
slab and storeys (k_1, c_1), (k_2, c_2) above it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..systems import TransferFunction
from ..units import G0, TWO_PI
from .base import LinearPart, VirtualSystem, VSOutput, _nonnegative, _positive, _state
from .targets import TEST_ARTICLE_WEIGHT


@dataclass(frozen=True)
class IsolatedTwoStorey(VirtualSystem):
    """Base-isolated two-storey frame carrying the test article on its roof.

    Parameters
    ----------
    m_vs : float
        Roof mass, where the article stands [lbf*s**2/in].
    m_b, m_1 : float
        Base-slab and first-floor masses [lbf*s**2/in].
    k_b, c_b : float
        Isolator stiffness [lbf/in] and damping [lbf*s/in].
    k_1, c_1, k_2, c_2 : float
        First- and second-storey stiffness [lbf/in] and damping [lbf*s/in].

    Notes
    -----
    States ``[u_b, u_1, u_2, v_b, v_1, v_2]`` [in, in/s].  ``outputs()``
    reports the roof displacement and velocity and the isolator force
    ``k_b*u_b + c_b*v_b`` [lbf].
    """

    m_b: float
    m_1: float
    k_b: float
    c_b: float
    k_1: float
    c_1: float
    k_2: float
    c_2: float

    kind = "ISO2"
    user_n_states = 6

    def __post_init__(self):
        super().__post_init__()
        for key in ("m_b", "m_1", "k_b", "k_1", "k_2"):
            _positive(key, getattr(self, key))
        for key in ("c_b", "c_1", "c_2"):
            _nonnegative(key, getattr(self, key))
        A, B = self._matrices()
        object.__setattr__(self, "_A", A)
        object.__setattr__(self, "_B", B)

    def _matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """State matrix A (6x6) and input matrix B (6x2, inputs [a_g, w])."""
        M = np.array([self.m_b, self.m_1, self.m_vs])
        K = _chain(self.k_b, self.k_1, self.k_2)
        C = _chain(self.c_b, self.c_1, self.c_2)
        A = np.zeros((6, 6))
        A[:3, 3:] = np.eye(3)
        A[3:, :3] = -K / M[:, None]
        A[3:, 3:] = -C / M[:, None]
        B = np.zeros((6, 2))
        B[3:, 0] = -1.0
        B[5, 1] = 1.0 / self.m_vs
        return A, B

    def derivative(self, x, a_g: float, w: float) -> np.ndarray:
        """dx/dt for ground acceleration ``a_g`` [in/s**2] and roof force ``w`` [lbf]."""
        return self._A @ _state(x) + self._B @ np.array([float(a_g), float(w)])

    def outputs(self, x, a_g: float, w: float) -> VSOutput:
        """Roof acceleration (absolute), roof displacement/velocity, isolator force."""
        xs = _state(x)
        roof_accel = self._A[5] @ xs + self._B[5] @ np.array([float(a_g), float(w)])
        return VSOutput(
            z_vs=float(roof_accel + a_g),
            displacement=float(xs[2]),
            velocity=float(xs[5]),
            force=float(self.k_b * xs[0] + self.c_b * xs[3]),
        )

    def linear_part(self) -> LinearPart:
        """H_zag and H_zw of the roof acceleration (the system is linear: no f_h)."""
        C = self._A[5]
        return LinearPart(
            H_zag=TransferFunction.from_ss(self._A, self._B[:, 0], C, self._B[5, 0] + 1.0).minreal(),
            H_zw=TransferFunction.from_ss(self._A, self._B[:, 1], C, self._B[5, 1]).minreal(),
        )

    def modes(self) -> list[tuple[float, float]]:
        """(frequency [Hz], damping ratio) of each mode, from the poles, lowest first."""
        poles = np.linalg.eigvals(self._A)
        poles = poles[poles.imag > 0]
        return sorted((abs(p) / TWO_PI, -p.real / abs(p)) for p in poles)


def _chain(k_b: float, k_1: float, k_2: float) -> np.ndarray:
    """Stiffness (or damping) matrix of ground - base - floor 1 - roof springs in series."""
    return np.array([[k_b + k_1, -k_1, 0.0], [-k_1, k_1 + k_2, -k_2], [0.0, -k_2, k_2]])


def example_two_storey(
    isolation_period: float = 2.0,
    isolation_damping: float = 0.15,
    storey_frequency: float = 5.0,
    storey_damping: float = 0.02,
    floor_weight: float = 2000.0,
    w_ps: float | None = None,
) -> IsolatedTwoStorey:
    """A plausible isolated two-storey frame sized like the report's systems.

    Parameters
    ----------
    isolation_period : float
        Period of the whole building plus article on the isolators [s].
    isolation_damping : float
        Damping ratio of that isolation mode.
    storey_frequency : float
        Fixed-base frequency of a single storey carrying one floor [Hz].
    storey_damping : float
        Damping ratio of that storey.
    floor_weight : float
        Weight of each of the three slabs (base, floor 1, roof) [lbf].
    w_ps : float, optional
        Weight of the test article on the roof [lbf] (used for sizing only);
        default the report's article (``TEST_ARTICLE_WEIGHT``, from the report's setup).
    """
    w_ps = TEST_ARTICLE_WEIGHT if w_ps is None else w_ps
    m = floor_weight / G0
    total = 3.0 * m + w_ps / G0
    k_b = (TWO_PI / isolation_period) ** 2 * total
    k_s = (TWO_PI * storey_frequency) ** 2 * (m + w_ps / G0)
    c_s = 2.0 * storey_damping * math.sqrt(k_s * (m + w_ps / G0))
    return IsolatedTwoStorey(
        m_vs=m,
        m_b=m,
        m_1=m,
        k_b=k_b,
        c_b=2.0 * isolation_damping * math.sqrt(k_b * total),
        k_1=k_s,
        c_1=c_s,
        k_2=k_s,
        c_2=c_s,
    )
