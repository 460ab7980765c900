"""Compiled helpers shared by every virtual-system type (numba).

The equations of a VS type live in its definition; the per-type kernels
(rates, outputs, the loop tick) are generated from it by
:mod:`impedance_mil.virtual.codegen`.  This module holds what does not
depend on the type: the ``sign`` function the generated code calls, and the
loop over input histories, which calls the per-type kernels as first-class
functions (so it is compiled once for every type).

Kernel signatures (float64; ``p`` the parameter vector of
:attr:`VSDefinition.kernel_constants`, ``x`` the state):

- ``derivative(p, x, a_g, w, out)``: ``out[i] = d x_i/dt``;
- ``outputs(p, x, a_g, w, out)``: ``out = [z_vs, displacement, velocity,
  force, f_h...]`` (:data:`OUTPUT_FIELDS`, then the nonlinear inputs);
- ``tick(p, x, a_g, w, dt, work) -> z_vs``: ``z_vs`` from the state at the
  start of the loop, then one RK3 step of ``x`` in place (``work``: 4 n
  floats), in float64 (``tick64``) or float32 (``tick32``).
"""

from __future__ import annotations

import numba

#: Leading entries of the ``outputs`` kernel's vector.
OUTPUT_FIELDS = ("z_vs", "displacement", "velocity", "force")
#: Index of each output field.
OUT_Z, OUT_DISP, OUT_VEL, OUT_FORCE = range(4)

_JIT = dict(cache=True, nogil=True)

# The loops over a history take the type's kernels as arguments typed by their dispatchers, so
# they are compiled once per VS type and process and *not cached*: numba's cache index keys them
# by those dispatcher types and pickles every key again at each save, which fails ("underlying
# object has vanished") once a process has dropped an earlier type's dispatcher (seen in the test
# suite: 85 index entries, 4 failed runs).  The per-type kernels themselves stay cached.
_LOOP_JIT = dict(cache=False, nogil=True)


@numba.njit(**_JIT, inline="always")
def sign(value):
    """-1, 0 or 1 as a float64 (the hand-written kernels' ``_sign``: its literals promote float32)."""
    if value > 0.0:
        return 1.0
    if value < 0.0:
        return -1.0
    return 0.0


@numba.njit(**_LOOP_JIT)
def simulate_records(fns, p, x, a_g, w, dt, work, out, rec):
    """Run a VS over input histories, one RK3 step per sample.

    As in the report's programs, the outputs of sample ``k`` are those of the
    state at the start of step ``k``.  ``fns = (outputs, tick64)``;
    ``rec[k]`` receives the outputs vector of sample ``k`` (``out`` is its
    scratch); ``x`` is advanced in place.
    """
    outputs = fns[0]
    tick = fns[1]
    for k in range(a_g.shape[0]):
        outputs(p, x, a_g[k], w[k], out)
        for j in range(out.shape[0]):
            rec[k, j] = out[j]
        tick(p, x, a_g[k], w[k], dt, work)


@numba.njit(**_LOOP_JIT)
def outputs_along(fns, p, states, out, rec):
    """``rec[k] = outputs(states[k])`` with ``a_g = w = 0``, ``fns = (outputs,)`` (the force and
    kinematics of recorded states; ``z_vs`` there is that of zero inputs)."""
    outputs = fns[0]
    for k in range(states.shape[0]):
        outputs(p, states[k], 0.0, 0.0, out)
        for j in range(out.shape[0]):
            rec[k, j] = out[j]


_A8 = numba.float64[::1]
_A4 = numba.float32[::1]


@numba.njit(numba.float64(_A8, _A8, numba.float64, numba.float64, numba.float64, _A8), **_JIT)
def no_vs_tick64(p, x, a_g, w, dt, work):
    """The tick of "no virtual system" (tracking and open-loop runs): z_vs = 0, nothing to step."""
    return 0.0


@numba.njit(numba.float32(_A4, _A4, numba.float32, numba.float32, numba.float32, _A4), **_JIT)
def no_vs_tick32(p, x, a_g, w, dt, work):
    """:func:`no_vs_tick64` for float32 arrays."""
    return numba.float32(0.0)
