"""Compiled helpers shared by every virtual-system type (numba).

The equations of a VS type live in its definition; the per-type kernels
(rates, outputs, the loop tick) are generated from it by
:mod:`impedance_mil.virtual.codegen`.  This module holds what does not
depend on the type: the ``sign`` function the generated code calls, the
output layout and the "no virtual system" ticks.  (The loops over input
histories are generated with each type's kernels:
:data:`impedance_mil.virtual.codegen.HISTORY_LOOPS`.)

Kernel signatures (float64; ``p`` the parameter vector of
:attr:`VSDefinition.kernel_constants`, ``x`` the state):

- ``derivative(p, x, a_g, w, out)``: ``out[i] = d x_i/dt``;
- ``outputs(p, x, a_g, w, out)``: ``out = [z_vs, displacement, velocity,
  force, f_h...]`` (:data:`OUTPUT_FIELDS`, then the nonlinear inputs);
- ``tick(p, x, a_g, w, dt, work) -> z_vs``: ``z_vs`` from the state at the
  start of the loop, then one RK3 step of ``x`` in place (``work``: 4 n
  floats), in float64 (``tick64``) or float32 (``tick32``);
- ``simulate_records(p, x, a_g, w, dt, work, out, rec)``: one RK3 step per
  sample of the histories ``a_g``, ``w``; ``rec[:, k]`` the outputs vector of
  sample ``k`` (of the state at the start of its step; ``rec`` output-major),
  ``x`` advanced in place;
- ``outputs_along(p, states, out, rec)``: ``rec[:, k] = outputs(states[k])``
  with ``a_g = w = 0``.
"""

from __future__ import annotations

import numba

#: Leading entries of the ``outputs`` kernel's vector.
OUTPUT_FIELDS = ("z_vs", "displacement", "velocity", "force")
#: Index of each output field.
OUT_Z, OUT_DISP, OUT_VEL, OUT_FORCE = range(4)

_JIT = dict(cache=True, nogil=True)


@numba.njit(**_JIT, inline="always")
def sign(value):
    """-1, 0 or 1 as a float64 (the hand-written kernels' ``_sign``: its literals promote float32)."""
    if value > 0.0:
        return 1.0
    if value < 0.0:
        return -1.0
    return 0.0


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
