"""Compiled (numba) arithmetic of the discrete MIL controller (report Section 6.5, Step 6).

These kernels are the single definition of the controller arithmetic: the
Python runtime (:class:`~impedance_mil.implement.runtime.MILRuntime`) calls
them, the virtual lab's compiled loop can call them with the runtime's
arrays, and the C and ST generators render the same operations in the same
order, so that generated code reproduces the runtime bit for bit (compilers
must not contract multiply-adds or reassociate: no ``-ffast-math``).

Layout, per channel with n states:

``m`` : (n+1, n+1) system matrix ``[[A - I, B], [C, D]]`` (delta form).
``s`` : (2, n) state ``s[0]`` and its Kahan compensation ``s[1]``.

Operations, with input ``v`` (``z_vs`` [in/s**2] or ``w`` [lbf])::

    y    = D*v;     for j: y    = y    + C[j]*x[j]                 (output)
    t[i] = B[i]*v;  for j: t[i] = t[i] + (A-I)[i,j]*x[j]           (increment)
    r = t[i] - c[i];  x' = x[i] + r;  c[i] = (x' - x[i]) - r;  x[i] = x'

and ``u = y_z + y_w`` (the corrected form of the report's Step 6 listing, in
which ``u_w`` is computed from the H_uw states and ``w``; see docs/errata.md).
Arithmetic is carried out in the dtype of the arrays: inputs are rounded to
it through the scratch vector, and no float64 literal enters an expression.
"""

from __future__ import annotations

import numba


@numba.njit(cache=True, nogil=True, inline="always")
def channel_output(m, s, v):
    """Output ``D v + C x`` of one channel (in the arrays' dtype)."""
    n = s.shape[1]
    y = m[n, n] * v
    for j in range(n):
        y = y + m[n, j] * s[0, j]
    return y


@numba.njit(cache=True, nogil=True, inline="always")
def channel_update(m, s, v, tmp, compensated):
    """Advance one channel: ``x <- x + ((A - I) x + B v)``, Kahan-compensated if asked."""
    n = s.shape[1]
    for i in range(n):
        acc = m[i, n] * v
        for j in range(n):
            acc = acc + m[i, j] * s[0, j]
        tmp[i] = acc
    for i in range(n):
        if compensated:
            r = tmp[i] - s[1, i]
            t = s[0, i] + r
            s[1, i] = (t - s[0, i]) - r
            s[0, i] = t
        else:
            s[0, i] = s[0, i] + tmp[i]


@numba.njit(cache=True, nogil=True, inline="always")
def controller_step_parts(m_z, m_w, s_z, s_w, tmp, z_vs, w, compensated):
    """One loop of the MIL controller: return ``(u, u_w)`` [in] and advance the states.

    Parameters
    ----------
    m_z, m_w : ndarray
        System matrices ``[[A - I, B], [C, D]]`` of H_uz and H_uw.
    s_z, s_w : ndarray
        States and compensations, shape (2, n); updated in place.
    tmp : ndarray
        Scratch vector, length >= max(n_z, n_w, 1), in the arrays' dtype.
    z_vs : float
        Target acceleration [in/s**2] of this loop.
    w : float
        Measured feedback force [lbf].
    compensated : bool
        Kahan-compensated state accumulation (the runtime's default).

    Returns
    -------
    tuple of float
        Displacement command ``u = u_z + u_w`` and its feedback part ``u_w``
        [in], in the arrays' dtype (the virtual lab records both; computing
        ``u_w`` here once keeps the record equal to what the command used).
    """
    # Round the inputs to the arrays' dtype through the scratch vector, so that a
    # float64 argument cannot promote float32 arithmetic.
    tmp[0] = z_vs
    zv = tmp[0]
    tmp[0] = w
    wv = tmp[0]
    u_w = channel_output(m_w, s_w, wv)
    u = channel_output(m_z, s_z, zv) + u_w
    channel_update(m_z, s_z, zv, tmp, compensated)
    channel_update(m_w, s_w, wv, tmp, compensated)
    return u, u_w


@numba.njit(cache=True, nogil=True, inline="always")
def controller_step(m_z, m_w, s_z, s_w, tmp, z_vs, w, compensated):
    """:func:`controller_step_parts` returning only the command ``u`` [in]."""
    return controller_step_parts(m_z, m_w, s_z, s_w, tmp, z_vs, w, compensated)[0]


@numba.njit(cache=True, nogil=True)
def controller_run(m_z, m_w, s_z, s_w, tmp, z_vs, w, compensated, u):
    """Step the controller over whole records ``z_vs``, ``w``; write ``u`` [in]."""
    for k in range(z_vs.shape[0]):
        u[k] = controller_step(m_z, m_w, s_z, s_w, tmp, z_vs[k], w[k], compensated)
