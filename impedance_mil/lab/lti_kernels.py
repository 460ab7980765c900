"""Compiled stages of a loop tick on an LTI table: the stage namespace of :func:`~impedance_mil.lab.tick.sequence`.

The same stage names as :mod:`impedance_mil.lab.kernels` (``read``,
``record_vs_state``, ``track_step``, ``mil_step``, ``command``, ``truth``,
``record``, ``advance``), on an :class:`~impedance_mil.lab.structures.LTIPlant`
instead of the physical table's :class:`~impedance_mil.lab.structures.VirtualPlant`.
:data:`impedance_mil.lab.tick.run_lti_loop` is the tick sequence compiled
with them: a separate compiled loop, so the physical table's loop is the
code it was, and the LTI table pays for no branch of the other.

What is shared with the physical table, function for function: the sensors
(:func:`~impedance_mil.lab.kernels.measure_quantities`: calibration, noise,
quantization, range, anti-alias filters, ``w_LC``, ``w_FE``), the interlocks
every table has (:func:`~impedance_mil.lab.kernels.check_table` and the
high-frequency instability detector :func:`~impedance_mil.lab.kernels.hf_oscillation_check`), the
controller and VS stages, the output delay's ring buffer
(:func:`~impedance_mil.lab.kernels.delayed_output`) and the records.  What
is the LTI table's own (:mod:`impedance_mil.lab.lti_plant`):

* the true quantities are rows of the coupled state and the held command
  (``LTIArrays.out_t``), read with the command held over the loop that ends
  at the sensing instant (a sampler reads just before the new command);
* there is no hydraulic stage: ``command`` puts u [in] through the output
  delay, and the command due is the model's input over the loop;
* ``advance`` is the exact ZOH step of the coupled linear system (split into
  the run's substeps when a channel has an anti-alias filter, which then
  advances at each substep boundary, as :func:`~impedance_mil.lab.stepping.filter_boundary`
  does for the physical table).
"""

from __future__ import annotations

import math

from numba import njit

from .kernels import (
    check_table,
    delayed_output,
    hf_oscillation_check,
    measure_quantities,
    mil_step,
    record,
    record_vs_state,
    track_step,
)
from .lti_plant import ROW_V
from .stepping import filter_step
from .structures import Q_DP, Q_W, Q_X, Q_Z, Measurements, PlantTruth
from .trips import TripCause


@njit(cache=True, inline="always", error_model="numpy")
def lti_quantities(table, y, u, q):
    """True quantities of the coupled state ``y`` with the command ``u`` [in] into ``q``; returns v [in/s].

    ``q`` in the order of QUANTITIES (z [in/s^2], x [in], dP [psi], actuator
    force [lbf], w [lbf]); zero for a quantity the model lacks.  Column by
    column (``table.out_t`` is the transposed output matrix): the rows'
    sums are independent, not one dependent chain per row.
    """
    out_t = table.out_t
    for k in range(ROW_V):
        q[k] = table.out_u[k] * u
    v = table.out_u[ROW_V] * u
    for j in range(y.shape[0]):
        yj = y[j]
        for k in range(ROW_V):
            q[k] += out_t[j, k] * yj
        v += out_t[j, ROW_V] * yj
    return v


@njit(cache=True, inline="always", error_model="numpy")
def lti_step(phi_t, gamma, y, u, work):
    """``y <- phi y + gamma u``: the exact ZOH step of the coupled system, command ``u`` [in] held.

    ``phi_t`` is ``phi`` transposed: the product is taken column by column
    (``work += phi[:, j] y[j]``, contiguous and independent across rows),
    which measured faster than row-by-row dot products, each a dependent chain.
    """
    n = y.shape[0]
    for i in range(n):
        work[i] = gamma[i] * u
    for j in range(n):
        yj = y[j]
        for i in range(n):
            work[i] += phi_t[j, i] * yj
    for i in range(n):
        y[i] = work[i]


@njit(cache=True, inline="always", error_model="numpy")
def sense_and_check(plant, noise_row, time_s):
    """Stages 1-2 on an :class:`LTIPlant`: sense, then check: ``(Measurements, TripCause, value)``.

    The true x, v, z, dP and w of the sensing are kept in ``plant.held`` for
    :func:`truth`.  Without a dP output the measurements' ``dp`` and ``w_fe``
    are NaN (the dP channel measures nothing).
    """
    t = plant.table
    h = plant.held[0]
    q = plant.sensors.quantities
    v = lti_quantities(t, plant.y, h.u, q)
    m = measure_quantities(plant.sensors, noise_row, plant.readings, time_s, t.mass, t.area)
    if not t.has_dp:
        m = Measurements(m.time_s, m.x, math.nan, m.z, m.w_lc, math.nan)
    h.x, h.v, h.z, h.dp, h.w = q[Q_X], v, q[Q_Z], q[Q_DP] if t.has_dp else math.nan, q[Q_W]
    cause, value = check_table(plant.limits, plant.y, m, h.x, v, t.area * m.dp)
    if cause == TripCause.NONE:
        cause, value = hf_oscillation_check(plant.limits, h, m.z)
    return m, cause, value


@njit(cache=True, inline="always", error_model="numpy")
def read(plant, k):
    """Stages 1-2 of loop ``k``: :func:`sense_and_check` with the loop's noise row, at t = k T."""
    return sense_and_check(plant, plant.noise[k], k * plant.table.loop_time)


@njit(cache=True, inline="always", error_model="numpy")
def lti_command(held, line, u):
    """Step 4 on an LTI table: ``u`` [in] into the output delay; the command due is the model's input."""
    h = held[0]
    h.u = delayed_output(line, h, u)


@njit(cache=True, inline="always", error_model="numpy")
def command(plant, m, u):
    """Stage 4 on an :class:`LTIPlant` (:func:`lti_command`; no hydraulic loop of ours)."""
    lti_command(plant.held, plant.output_line, u)


@njit(cache=True, inline="always", error_model="numpy")
def truth(plant):
    """The true :class:`PlantTruth` of the current loop: NaN for the chambers, spool and valve."""
    h = plant.held[0]
    nan = math.nan
    return PlantTruth(h.x, h.v, h.z, h.dp, nan, nan, nan, h.w, nan, nan)


@njit(cache=True, inline="always", error_model="numpy")
def advance(plant):
    """Stage 5 on an :class:`LTIPlant`: one loop, the command ``held.u`` [in] held (exact ZOH).

    Without anti-alias filters one step of the loop's discretization; with
    them ``plant.substeps`` steps of the substep's, the filters advanced to
    the true quantities at each boundary inside the loop (the last is closed
    by the next sensing, :func:`~impedance_mil.lab.stepping.filter_sense`).
    """
    t = plant.table
    u = plant.held[0].u
    f = plant.sensors.filters
    n_filters = f.channel.shape[0]
    if n_filters == 0:
        lti_step(t.loop_phi_t, t.loop_gamma, plant.y, u, plant.work)
        return
    q = plant.sensors.quantities
    for j in range(plant.substeps):
        if j > 0:
            lti_quantities(t, plant.y, u, q)
            for i in range(n_filters):
                filter_step(f, i, f.gain[i] * q[f.quantity_index[i]])
        lti_step(t.step_phi_t, t.step_gamma, plant.y, u, plant.work)


__all__ = [
    "advance",
    "command",
    "lti_command",
    "lti_quantities",
    "lti_step",
    "mil_step",
    "read",
    "record",
    "record_vs_state",
    "sense_and_check",
    "track_step",
    "truth",
]
