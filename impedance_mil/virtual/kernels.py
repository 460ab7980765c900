"""Compiled dynamics of the built-in virtual systems: the single definition.

Every built-in virtual system (VS) of report Section 5 is written here once,
as numba ``@njit`` functions on flat float64 arrays.  The Python classes in
:mod:`impedance_mil.virtual.models` call these same functions, the lab loop
calls them from its compiled loop, and the C / Structured-Text generators
render the equations below.  Nothing here allocates per step.

Kinds, parameter vectors and states
-----------------------------------
Internal units (in, lbf, s; mass in lbf*s**2/in).  ``F`` is the isolator
shear force (Eq 5-3, restoring, positive with the displacement); the force
on the basemat is ``-F``, so ``m_vs * z_vs = w - F``.

``KIND_SD = 1`` spring-damper (Eq 5-1, corrected, see docs/errata.md)
    ``params = [m_vs, k_s, c]``; ``x = [x, v]``.
    ``F = k_s*x + c*v``.
``KIND_LR = 2`` lead-rubber with Bouc-Wen hysteresis (Eq 5-3..5-5)
    ``params = [m_vs, k_i, alpha, q_d, c, n]``; ``x = [x, v, h]``.
    ``u_y = q_d / ((1 - alpha)*k_i)``;
    ``F = alpha*k_i*x + c*v + q_d*h``;
    ``dh/dt = v/u_y * (1 - 0.5*|h|**n * (1 + sign(v*h)))`` (Eq 5-4 with |h|).
``KIND_FP = 3`` single concave Friction Pendulum (Eq 5-9..5-11)
    ``params = [m_vs, k_s, mu_max, mu_min, a, u_y, W, n]``; ``x = [x, v, h]``.
    ``mu(v) = mu_max - (mu_max - mu_min)*exp(-a*|v|)`` (Eq 5-10);
    ``F = k_s*x + mu(v)*W*h``; ``dh/dt`` as for LR with ``u_y``.

For all kinds ``dx/dt = v`` and ``dv/dt = (w - F)/m_vs - a_g``; the output
is the absolute basemat acceleration ``z_vs = (w - F)/m_vs`` [in/s**2].

The nonlinear input of the linear part (Figures 5.3, 5.5) is
``f_h = v/u_y * 0.5*|h|**n*(1 + sign(v*h))`` [1/s] for LR (so that
``dh/dt = v/u_y - f_h``, Eq 5-7c) and ``f_h = mu(v)*W*h`` [lbf] for FP.

Time stepping
-------------
:func:`vs_step_rk3` is the explicit third-order Runge-Kutta scheme of the
report's RMC programs (Figure 7.9): stages at ``x``, ``x + k1/2``,
``x + 3*k2/4`` and weights ``2/9, 3/9, 4/9`` (Ralston's RK3), with ``a_g``
and ``w`` held over the step.  ``work`` must hold ``4*n_states`` floats.
"""

from __future__ import annotations

import math

import numba
import numpy as np

#: Kind code of a user-defined VS without a compiled kernel (Python path).
KIND_PYTHON = -1
#: Kind code of the linear spring-damper VS.
KIND_SD = 1
#: Kind code of the lead-rubber (Bouc-Wen) VS.
KIND_LR = 2
#: Kind code of the single concave Friction Pendulum VS.
KIND_FP = 3

#: Number of entries of ``params`` per kind.
N_PARAMS = {KIND_SD: 3, KIND_LR: 6, KIND_FP: 8}
#: Names of the entries of ``params`` per kind (the layout above).
PARAM_NAMES = {
    KIND_SD: ("m_vs", "k_s", "c"),
    KIND_LR: ("m_vs", "k_i", "alpha", "q_d", "c", "n"),
    KIND_FP: ("m_vs", "k_s", "mu_max", "mu_min", "a", "u_y", "W", "n"),
}
#: Number of states of the linear part per kind (Figures 5.3, 5.5).
N_LINEAR_STATES = {KIND_SD: 2, KIND_LR: 3, KIND_FP: 2}
#: Names of the state entries per kind.
STATE_NAMES = {
    KIND_SD: ("x", "v"),
    KIND_LR: ("x", "v", "h"),
    KIND_FP: ("x", "v", "h"),
}

#: Ralston RK3 tableau used by the report (Figure 7.9): stage offsets ...
RK3_A21 = 0.5
RK3_A32 = 0.75
#: ... and weights.
RK3_B1 = 2.0 / 9.0
RK3_B2 = 3.0 / 9.0
RK3_B3 = 4.0 / 9.0

_JIT = dict(cache=True, nogil=True)
#: Per-step kernels are inlined into their callers at numba-IR level (the lab loop,
#: the runtime): with the other per-step kernels, measured 1.6 -> 1.05 us per lab loop.
_STEP = dict(_JIT, inline="always")


@numba.njit(**_STEP)
def vs_n_states(kind_code):
    """Number of states of a built-in kind (0 for an unknown kind)."""
    if kind_code == KIND_SD:
        return 2
    if kind_code == KIND_LR or kind_code == KIND_FP:
        return 3
    return 0


@numba.njit(**_STEP)
def _sign(value):
    if value > 0.0:
        return 1.0
    if value < 0.0:
        return -1.0
    return 0.0


@numba.njit(**_STEP)
def _bouc_wen_nonlinear(v, h, inv_uy, n):
    """``v/u_y * 0.5*|h|**n*(1 + sign(v*h))`` [1/s]: the nonlinear part of dh/dt."""
    return inv_uy * 0.5 * abs(h) ** n * (1.0 + _sign(v * h)) * v


@numba.njit(**_STEP)
def _friction(params, v):
    """Mokha et al. friction coefficient mu(v) of Eq 5-10 for FP params."""
    mu_max = params[2]
    mu_min = params[3]
    return mu_max - (mu_max - mu_min) * math.exp(-params[4] * abs(v))


@numba.njit(**_STEP)
def _lr_inv_uy(params):
    return (1.0 - params[2]) * params[1] / params[3]


@numba.njit(**_STEP)
def vs_force(kind_code, params, x):
    """Isolator shear force F [lbf] (restoring, Eq 5-3 / 5-11b) at state ``x``."""
    if kind_code == KIND_SD:
        return params[1] * x[0] + params[2] * x[1]
    if kind_code == KIND_LR:
        return params[2] * params[1] * x[0] + params[4] * x[1] + params[3] * x[2]
    if kind_code == KIND_FP:
        return params[1] * x[0] + _friction(params, x[1]) * params[6] * x[2]
    return math.nan


@numba.njit(**_STEP)
def _nonlinear_input_vh(kind_code, params, v, h):
    """f_h of :func:`vs_nonlinear_input` from the velocity ``v`` and hysteretic variable ``h``."""
    if kind_code == KIND_LR:
        return _bouc_wen_nonlinear(v, h, _lr_inv_uy(params), params[5])
    if kind_code == KIND_FP:
        return _friction(params, v) * params[6] * h
    return 0.0


@numba.njit(**_STEP)
def vs_nonlinear_input(kind_code, params, x):
    """Nonlinear input f_h of the linear part (Figures 5.3, 5.5); 0 for SD.

    LR: [1/s] entering ``dh/dt = v/u_y - f_h``; FP: [lbf] entering
    ``m_vs*dv/dt = w - k_s*x - f_h - m_vs*a_g``.
    """
    if kind_code == KIND_LR or kind_code == KIND_FP:
        return _nonlinear_input_vh(kind_code, params, x[1], x[2])
    return 0.0


@numba.njit(**_STEP)
def vs_output_z(kind_code, params, x, a_g, w):
    """Absolute basemat acceleration z_vs = (w - F)/m_vs [in/s**2].

    ``a_g`` is accepted for a uniform signature; z_vs does not depend on it
    directly (it enters through the state).
    """
    return (w - vs_force(kind_code, params, x)) / params[0]


@numba.njit(**_STEP)
def _linear_derivative_at(kind_code, params, x, xo, a_g, w, f_h, out, oo):
    """:func:`vs_linear_derivative` of the state ``x[xo:]`` into ``out[oo:]`` (no slicing)."""
    out[oo] = x[xo + 1]
    if kind_code == KIND_SD:
        out[oo + 1] = (w - params[1] * x[xo] - params[2] * x[xo + 1]) / params[0] - a_g
    elif kind_code == KIND_LR:
        out[oo + 1] = (
            w - params[2] * params[1] * x[xo] - params[4] * x[xo + 1] - params[3] * x[xo + 2]
        ) / params[0] - a_g
        out[oo + 2] = _lr_inv_uy(params) * x[xo + 1] - f_h
    elif kind_code == KIND_FP:
        out[oo + 1] = (w - params[1] * x[xo] - f_h) / params[0] - a_g


@numba.njit(**_STEP)
def _derivative_at(kind_code, params, x, xo, a_g, w, out, oo):
    """:func:`vs_derivative` of the state ``x[xo:]`` into ``out[oo:]`` (no slicing)."""
    f_h = 0.0
    if kind_code == KIND_LR or kind_code == KIND_FP:
        f_h = _nonlinear_input_vh(kind_code, params, x[xo + 1], x[xo + 2])
    _linear_derivative_at(kind_code, params, x, xo, a_g, w, f_h, out, oo)
    if kind_code == KIND_FP:
        inv_uy = 1.0 / params[5]
        out[oo + 2] = inv_uy * x[xo + 1] - _bouc_wen_nonlinear(x[xo + 1], x[xo + 2], inv_uy, params[7])


@numba.njit(**_STEP)
def vs_linear_derivative(kind_code, params, x, a_g, w, f_h, out):
    """Derivative of the linear part (Eq 5-1, 5-7, 5-12) with f_h as an input.

    Writes the first ``N_LINEAR_STATES[kind]`` entries of ``out``: for SD
    and LR the whole state, for FP only ``[x, v]`` (its hysteretic variable
    lives in the nonlinear block, Figure 5.5).  Units as in
    :func:`vs_derivative`; ``f_h`` as in :func:`vs_nonlinear_input`.
    """
    _linear_derivative_at(kind_code, params, x, 0, a_g, w, f_h, out, 0)


@numba.njit(**_STEP)
def vs_derivative(kind_code, params, x, a_g, w, out):
    """State derivative dx/dt written into ``out`` (Eq 5-1, 5-5, 5-11).

    The linear part in feedback with its nonlinear input (Figures 5.3, 5.5).

    Parameters
    ----------
    kind_code : int
        KIND_SD, KIND_LR or KIND_FP.
    params : ndarray of float64
        Layout of the module docstring.
    x : ndarray of float64
        State [in, in/s, (h)].
    a_g : float
        Ground acceleration [in/s**2].
    w : float
        Force from the test article on the basemat [lbf].
    out : ndarray of float64
        Receives dx/dt (same length as ``x``).
    """
    _derivative_at(kind_code, params, x, 0, a_g, w, out, 0)


@numba.njit(**_STEP)
def vs_step_rk3(kind_code, params, x, a_g, w, dt, work):
    """Advance ``x`` in place by one step ``dt`` [s] with the report's RK3.

    Stages at ``x``, ``x + dt*k1/2`` and ``x + 3*dt*k2/4``; update
    ``x += dt*(2*k1 + 3*k2 + 4*k3)/9`` (Figure 7.9).  ``a_g`` [in/s**2] and
    ``w`` [lbf] are held over the step.  ``work`` holds >= 4*n_states floats:
    ``k1, k2, k3`` and the stage state, addressed by offset (no array views,
    whose reference counting cost more than a spring-damper's arithmetic).
    """
    n = vs_n_states(kind_code)
    o2 = n
    o3 = 2 * n
    os_ = 3 * n
    _derivative_at(kind_code, params, x, 0, a_g, w, work, 0)
    for i in range(n):
        work[os_ + i] = x[i] + RK3_A21 * dt * work[i]
    _derivative_at(kind_code, params, work, os_, a_g, w, work, o2)
    for i in range(n):
        work[os_ + i] = x[i] + RK3_A32 * dt * work[o2 + i]
    _derivative_at(kind_code, params, work, os_, a_g, w, work, o3)
    for i in range(n):
        x[i] += dt * (RK3_B1 * work[i] + RK3_B2 * work[o2 + i] + RK3_B3 * work[o3 + i])


@numba.njit(**_JIT)
def vs_simulate(kind_code, params, x, a_g, w, dt, z, disp, vel, force, f_h):
    """Run the VS over input histories, one RK3 step per sample.

    As in the report's programs, the outputs of sample ``k`` are computed
    from the state at the start of step ``k`` (before the update).  ``x`` is
    advanced in place and holds the final state on return.

    Parameters
    ----------
    a_g, w : ndarray of float64
        Ground acceleration [in/s**2] and test-article force [lbf] per sample.
    dt : float
        Step [s].
    z, disp, vel, force, f_h : ndarray of float64
        Receive z_vs [in/s**2], displacement [in], velocity [in/s],
        isolator force [lbf] and the nonlinear input f_h per sample.
    """
    n = vs_n_states(kind_code)
    work = np.empty(4 * max(n, 1))
    for k in range(a_g.shape[0]):
        z[k] = vs_output_z(kind_code, params, x, a_g[k], w[k])
        disp[k] = x[0]
        vel[k] = x[1]
        force[k] = vs_force(kind_code, params, x)
        f_h[k] = vs_nonlinear_input(kind_code, params, x)
        vs_step_rk3(kind_code, params, x, a_g[k], w[k], dt, work)
