"""Accurate reference integration of a VS, independent of the RK3 scheme.

Used to verify the report's RK3 stepping (third-order convergence) and for
post-test comparisons where accuracy matters more than speed.  The inputs
are held constant over each sample, exactly as in :meth:`VirtualSystem.simulate`,
so the two differ only by the integration error of RK3.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from ..errors import ConfigError
from .base import VirtualSystem, inputs_of, state_of


def reference_states(
    vs: VirtualSystem, a_g, w=None, dt: float = 0.0005, x0=None, rtol: float = 1e-12, atol: float = 1e-14
) -> np.ndarray:
    """States at every sample boundary, integrated with DOP853 at tight tolerances.

    Parameters
    ----------
    vs : VirtualSystem
    a_g : array_like
        Ground acceleration per sample [in/s**2], held over each sample.
    w : array_like or float, optional
        Test-article force per sample [lbf], held; zero when omitted.
    dt : float
        Sample period [s].
    x0 : array_like, optional
        Initial state; at rest when omitted.
    rtol, atol : float
        Tolerances of :func:`scipy.integrate.solve_ivp`.

    Returns
    -------
    ndarray, shape (len(a_g) + 1, n_states)
        Row k is the state at time ``k*dt``.
    """
    if not dt > 0:
        raise ConfigError("dt", "a positive time step in s", dt)
    a, ww = inputs_of(a_g, w)
    x = vs.initial_state() if x0 is None else state_of(x0).copy()
    out = np.empty((a.size + 1, x.size))
    out[0] = x
    for k in range(a.size):
        sol = solve_ivp(
            lambda _t, s, ak=a[k], wk=ww[k]: vs.derivative(s, ak, wk),
            (0.0, dt),
            x,
            method="DOP853",
            rtol=rtol,
            atol=atol,
        )
        x = sol.y[:, -1]
        out[k + 1] = x
    return out
