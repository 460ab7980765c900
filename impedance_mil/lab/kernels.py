"""Compiled stages of a loop tick: sensing, safety, controller, hydraulic loop, plant step.

The kernels of one tick (the order is written once, in
:func:`impedance_mil.lab.tick.sequence`):

1. **sense** (:func:`plant_sense`): the sensors of a
   :class:`~impedance_mil.specimens.sensors.SensorSuite` read the plant at t_k
   (Table 7.1 calibration, an optional anti-alias filter and converter delay, noise, 16-bit
   quantization, range): ``x``, ``dP``,
   ``z`` and the load-cell force ``w_LC``; ``w_FE = m_st z - A_p dP`` from force
   equilibrium (Section 8.3.2);
2. **safety** (:func:`check_limits`): stroke, velocity, actuator force, valve
   saturation, NaN and divergence, and a growing high-frequency oscillation of
   the measured acceleration (:func:`hf_oscillation_check`, the criterion of
   :mod:`impedance_mil.lab.oscillation`), returned as a
   :class:`~impedance_mil.lab.trips.TripCause`;
3. **controller** (:func:`track_step`, :func:`mil_step`): the runtime kernels
   of :mod:`impedance_mil.implement`, the VS through its tick;
4. **hydraulic loop** (:func:`hydraulic_command`):
   ``u_v(k) = K_e (u(k) - x_m(k-1)) - K_p dP_m(k-1)``, applied over loop
   ``k + N - 1`` (N the controller's output delay in loops, 1 for the
   report's) and held over it (ZOH);
5. **advance** (:func:`~impedance_mil.lab.stepping.plant_advance`): the
   continuous plant (nonlinear table + specimen state space) integrated over
   T with fixed RK4 substeps.

This module is the compiled *stage namespace* of the tick sequence: its
:func:`read`, :func:`record_vs_state`, :func:`track_step`, :func:`mil_step`,
:func:`command`, :func:`truth`, :func:`record` and :func:`advance` take a
:class:`~impedance_mil.lab.structures.VirtualPlant`, a
:class:`~impedance_mil.lab.structures.LoopControl` and the
:class:`~impedance_mil.lab.structures.Records`, and are inlined into the
compiled loop (``inline="always"``, at numba-IR level).
:class:`~impedance_mil.lab.plant_interface.VirtualTable`, the same plant
behind the Python :class:`PlantInterface`, calls the kernels these stages
call (:func:`sense_and_check`, :func:`hydraulic_command`, :func:`plant_truth`,
:func:`~impedance_mil.lab.stepping.plant_advance`), with only the arrays each
needs (a call from Python pays for every array it passes).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..implement.kernels import controller_step_parts
from ..implement.runtime import mil_step_kernel
from ..plant.nonlinear import (
    IX_P1,
    IX_P2,
    IX_S,
    IX_V,
    IX_X,
    N_TABLE_STATES,
    PA_AREA,
    PA_KV,
    PA_LOOP,
    PA_MASS,
    PA_UVMAX,
    table_acceleration,
    valve_command,
)
from ..specimens.sensors import force_from_equilibrium, load_cell_force_kernel, measure_kernel, read_channel
from .stepping import (
    SPEC_BANK,
    SPEC_CSR,
    coupled_derivative,
    delay_sense,
    delayed_value,
    filter_sense,
    load_cell_force,
    plant_advance,
    specimen_force_state,
)
from .structures import (
    HF_STATE_FIELDS,
    Q_DP,
    Q_FORCE,
    Q_W,
    Q_X,
    Q_Z,
    Measurements,
    PlantTruth,
    record_loop,
)
from .trips import TripCause

#: The detector's state alone (for :func:`hf_window_history`).
HF_STATE = np.dtype(HF_STATE_FIELDS, align=True)


@njit(cache=True, inline="always", error_model="numpy")
def channel_reading(sensors, c, value, noise_row):
    """Channel ``c``'s reading of the analog ``value`` (its calibration, noise, quantization, range)."""
    return read_channel(
        value,
        noise_row[c],
        sensors.scale[c],
        sensors.offset[c],
        sensors.noise_rms[c],
        sensors.lsb[c],
        sensors.v_low[c],
        sensors.v_high[c],
    )


@njit(cache=True, inline="always", error_model="numpy")
def measure_quantities(sensors, noise_row, readings, time_s, mass, area):
    """The :class:`Measurements` of the true quantities in ``sensors.quantities`` (order of QUANTITIES).

    Every channel's reading goes into ``readings`` (calibration, noise
    ``noise_row``, quantization, range); a channel with an anti-alias filter
    reads the filter's output (``sensors.filters``, brought to this instant by
    :func:`~impedance_mil.lab.stepping.filter_sense`).  ``w_FE = m_st z - A_p dP``
    from the table's ``mass`` [lbf*s^2/in] and piston ``area`` [in^2] (NaN
    when unknown); ``time_s`` [s] is stamped on the measurements.
    """
    q = sensors.quantities
    measure_kernel(
        q,
        noise_row,
        sensors.quantity_index,
        sensors.gain,
        sensors.scale,
        sensors.offset,
        sensors.noise_rms,
        sensors.lsb,
        sensors.v_low,
        sensors.v_high,
        readings,
    )
    f = sensors.filters
    if f.channel.shape[0] > 0:
        # A filtered channel reads its filter's output instead of the true value.
        filter_sense(f, q)
        for i in range(f.channel.shape[0]):
            c = f.channel[i]
            readings[c] = channel_reading(sensors, c, f.state[i, 0], noise_row)
    d = sensors.delays
    if d.channel.shape[0] > 0:
        # A delayed channel reads its analog value (filtered or true) some loops back.
        delay_sense(d, f, q, sensors.gain, sensors.quantity_index)
        for i in range(d.channel.shape[0]):
            c = d.channel[i]
            readings[c] = channel_reading(sensors, c, delayed_value(d, i), noise_row)
    z_meas = readings[sensors.z_channel]
    dp_meas = readings[sensors.dp_channel]
    return Measurements(
        time_s,
        readings[sensors.x_channel],
        dp_meas,
        z_meas,
        load_cell_force_kernel(readings, sensors.load_cell_weights),
        force_from_equilibrium(z_meas, dp_meas, mass, area),
    )


@njit(cache=True, inline="always", error_model="numpy")
def plant_sense(pa, y, specimen, sensors, noise_row, readings, time_s):
    """Sensor readings of the plant state ``y``: ``(Measurements, true z [in/s^2], true w [lbf])``.

    The load cells read the specimen's load-cell output (``w`` itself unless
    the specimen stands on a mounting, :func:`~impedance_mil.lab.stepping.load_cell_force`).

    ``pa`` is the table's parameter array, ``specimen`` a
    :class:`~impedance_mil.lab.structures.SpecimenArrays`, ``sensors`` a
    :class:`~impedance_mil.lab.structures.SensorArrays`, ``noise_row`` one
    standard-normal draw per channel; ``readings`` receives every channel's
    reading; ``time_s`` [s] is stamped on the measurements.  A channel with an
    anti-alias filter reads the filter's output (``sensors.filters``, brought
    to this instant by :func:`~impedance_mil.lab.stepping.filter_sense`).
    """
    ws = specimen_force_state(specimen.C, y[N_TABLE_STATES:])
    z = table_acceleration(pa, y, ws, specimen.D)
    w = ws + specimen.D * z
    dp = y[IX_P1] - y[IX_P2]
    q = sensors.quantities
    q[Q_Z] = z
    q[Q_X] = y[IX_X]
    q[Q_DP] = dp
    q[Q_FORCE] = pa[PA_AREA] * dp
    q[Q_W] = load_cell_force(y[N_TABLE_STATES:], z, w, specimen.C_lc, specimen.D_lc, specimen.lc_own)
    m = measure_quantities(sensors, noise_row, readings, time_s, pa[PA_MASS], pa[PA_AREA])
    return m, z, w


@njit(cache=True, inline="always", error_model="numpy")
def check_table(limits, y, m, x, v, force):
    """The interlocks every table has: ``(TripCause, offending value)`` (``TripCause.NONE``: all clear).

    NaN anywhere in the plant state ``y``, divergence of the true
    displacement ``x`` [in], the stroke (measured x), the true velocity ``v``
    [in/s], the measured acceleration and dP, and the actuator ``force``
    ``A_p dP_m`` [lbf], against the :class:`~impedance_mil.lab.structures.LimitValues`
    ``limits`` (an inf threshold never trips; a NaN value never trips).
    """
    for i in range(y.shape[0]):
        if not math.isfinite(y[i]):
            return TripCause.NAN, y[i]
    if abs(x) > limits.divergence:
        return TripCause.DIVERGENCE, x
    if abs(m.x) > limits.stroke:
        return TripCause.STROKE, m.x
    if abs(v) > limits.velocity:
        return TripCause.VELOCITY, v
    if abs(m.z) > limits.acceleration:
        return TripCause.ACCELERATION, m.z
    if abs(m.dp) > limits.pressure:
        return TripCause.PRESSURE, m.dp
    if abs(force) > limits.actuator_force:
        return TripCause.ACTUATOR_FORCE, force
    return TripCause.NONE, 0.0


@njit(cache=True, inline="always", error_model="numpy")
def hf_oscillation_check(limits, h, z):
    """The high-frequency instability interlock on the measured acceleration ``z`` [in/s^2] of this loop.

    ``h`` is the held record (:data:`~impedance_mil.lab.structures.HELD_STATE`
    or :data:`~impedance_mil.lab.structures.LTI_HELD_STATE`, whose
    :data:`~impedance_mil.lab.structures.HF_STATE_FIELDS` it updates).  ``z``
    goes through the high-pass ``limits.hf_filter`` and its square into the
    current window; at a window's end its rms counts as growth when it exceeds
    ``limits.hf_growth`` times the previous window's, itself at least
    ``limits.hf_floor``.  Returns ``(TripCause.HF_OSCILLATION, window rms
    [in/s^2])`` at the end of the ``limits.hf_windows``-th growing window in a
    row, else ``(TripCause.NONE, 0)``.  The criterion and its sources are in
    :mod:`impedance_mil.lab.oscillation` (report Figures 9.33-9.34; Gálmez and
    Fermandois 2020).
    """
    f = limits.hf_filter
    if f.window_loops == 0:
        return TripCause.NONE, 0.0
    y = f.b0 * z + f.b1 * h.hf_x1 + f.b2 * h.hf_x2 - f.a1 * h.hf_y1 - f.a2 * h.hf_y2
    h.hf_x2 = h.hf_x1
    h.hf_x1 = z
    h.hf_y2 = h.hf_y1
    h.hf_y1 = y
    h.hf_sum += y * y
    h.hf_n += 1
    if h.hf_n < f.window_loops:
        return TripCause.NONE, 0.0
    rms = math.sqrt(h.hf_sum / h.hf_n)
    h.hf_sum = 0.0
    h.hf_n = 0
    if h.hf_prev >= limits.hf_floor and rms > limits.hf_growth * h.hf_prev:
        h.hf_count += 1
    else:
        h.hf_count = 0
    h.hf_prev = rms
    if h.hf_count >= limits.hf_windows:
        return TripCause.HF_OSCILLATION, rms
    return TripCause.NONE, 0.0


@njit(cache=True, error_model="numpy")
def hf_window_history(limits, z):
    """The detector of :func:`hf_oscillation_check` run over the accelerations ``z`` [in/s^2], one per loop.

    Returns ``(rms, count)``: each window's rms [in/s^2] and the count of
    consecutive growing windows at its end (the detector does not stop: the
    history goes on past a trip).  For analysis (the margin of a stable run,
    :func:`impedance_mil.lab.oscillation` documents the criterion); the loop
    itself runs :func:`hf_oscillation_check`.
    """
    held = np.zeros(1, HF_STATE)
    n_windows = z.shape[0] // max(limits.hf_filter.window_loops, 1)
    rms = np.zeros(n_windows)
    count = np.zeros(n_windows, np.int64)
    j = 0
    h = held[0]
    for k in range(z.shape[0]):
        hf_oscillation_check(limits, h, z[k])
        if h.hf_n == 0 and j < n_windows:
            rms[j] = h.hf_prev
            count[j] = h.hf_count
            j += 1
    return rms[:j], count[:j]


@njit(cache=True, inline="always", error_model="numpy")
def check_limits(pa, limits, y, m, held):
    """Safety check of one tick: ``(TripCause, offending value)`` (``TripCause.NONE``: all clear).

    ``limits`` is a :class:`~impedance_mil.lab.structures.LimitValues`, ``m``
    this loop's :class:`~impedance_mil.lab.structures.Measurements`, ``held``
    the plant's :data:`~impedance_mil.lab.structures.HELD_STATE` record: the
    last valve command ``u_v`` [V], ``sat`` (consecutive loops with the valve
    command at its limit) and the running averages of the valve interlocks.
    """
    cause, value = check_table(limits, y, m, y[IX_X], y[IX_V], pa[PA_AREA] * m.dp)
    if cause != TripCause.NONE:
        return cause, value
    if held.sat * pa[PA_LOOP] > limits.valve_saturation_time:
        return TripCause.VALVE_SATURATION, held.u_v
    if held.duty > limits.valve_duty:
        return TripCause.VALVE_DUTY, held.duty
    current_rms = math.sqrt(held.current_sq)
    if current_rms > limits.valve_current:
        return TripCause.VALVE_CURRENT, current_rms
    slew_rms = math.sqrt(held.slew_sq)
    if slew_rms > limits.command_slew:
        return TripCause.COMMAND_OSCILLATION, slew_rms
    return hf_oscillation_check(limits, held, m.z)


@njit(cache=True, inline="always", error_model="numpy")
def valve_output(pa, uv, sat_ticks):
    """The valve command ``uv`` [V] as the valve receives it: ``(saturated ticks, valve current [mA])``.

    ``sat_ticks`` counts the consecutive loops with ``uv`` at its limit (reset
    when it leaves it), as :func:`check_limits` reads it.
    """
    sat = sat_ticks + 1 if abs(uv) >= pa[PA_UVMAX] else 0
    return sat, pa[PA_KV] * uv


@njit(cache=True, inline="always", error_model="numpy")
def delayed_output(line, h, uv):
    """Put this loop's valve command ``uv`` [V] into the ring buffer ``line``; return the one due now.

    ``line`` holds the commands of the last N = ``line.size`` loops (the
    controller's output delay in loops) and ``h.head`` the slot of the next
    write.  The command computed at loop k is applied over loop k + N - 1:
    N = 1 (the report's controller) applies it at once, the previous loop's
    measurements in it making the one-loop delay of the feedback.
    """
    line[h.head] = uv
    h.head = (h.head + 1) % line.shape[0]
    return line[h.head]


# ----------------------------------------------------------------- the stages of a tick
# The names below are the stages impedance_mil.lab.tick.sequence calls; the plant
# interface's renderings (impedance_mil.lab.interface_stages) have the same names.
@njit(cache=True, inline="always", error_model="numpy")
def sense_and_check(plant, noise_row, time_s):
    """Stages 1-2 on a :class:`VirtualPlant`: sense, then check: ``(Measurements, TripCause, value)``.

    ``noise_row`` is this loop's draws, ``time_s`` [s] its time.  The true z and
    w of the sensing are kept in ``plant.held`` for :func:`truth`.
    """
    m, z, w = plant_sense(
        plant.table, plant.y, plant.specimen, plant.sensors, noise_row, plant.readings, time_s
    )
    held = plant.held[0]
    held.z = z
    held.w = w
    cause, value = check_limits(plant.table, plant.limits, plant.y, m, held)
    return m, cause, value


@njit(cache=True, inline="always", error_model="numpy")
def read(plant, k):
    """Stages 1-2 of loop ``k``: :func:`sense_and_check` with the loop's noise row, at t = k T."""
    return sense_and_check(plant, plant.noise[k], k * plant.table[PA_LOOP])


@njit(cache=True, inline="always", error_model="numpy")
def record_vs_state(log, k, control):
    """Record the VS state at the start of loop ``k`` (``control.vs.x``; nothing without a VS)."""
    x = control.vs.x
    for i in range(x.shape[0]):
        log.vs_states[k, i] = x[i]


@njit(cache=True, inline="always", error_model="numpy")
def track_step(control, a_g, w):
    """Stage 3, tracking (``z_vs = a_g`` [in/s^2], feedback ``w`` [lbf]): ``(u, u_w)`` [in]."""
    c = control.controller
    return controller_step_parts(c.m_z, c.m_w, c.s_z, c.s_w, c.tmp, a_g, w, c.compensated)


@njit(cache=True, inline="always", error_model="numpy")
def mil_step(control, vs_tick, a_g, w):
    """Stage 3, MIL: the VS tick, then the controller: ``(u [in], z_vs [in/s^2], u_w [in])``."""
    return mil_step_kernel(control.controller, vs_tick, control.vs, control.dt, a_g, w)


@njit(cache=True, inline="always", error_model="numpy")
def hydraulic_command(pa, limits, held, line, m, u):
    """Step 4 for the command ``u`` [in] of the loop read as ``m``; updates ``held`` and ``line``.

    :func:`~impedance_mil.plant.nonlinear.valve_command` of ``u`` and the
    previous loop's measurements ``x_prev`` [in], ``dp_prev`` [psi], through
    the output delay (:func:`delayed_output`, ring buffer ``line``), then
    :func:`valve_output`.  ``held`` is the one-element
    :data:`~impedance_mil.lab.structures.HELD_STATE` array: the previous
    loop's measurements feed the valve command, this loop's replace them.
    The running averages of the valve interlocks (saturation duty,
    mean-square current and mean-square slew of the valve command the valve
    receives) are exponentially weighted with the time constant
    ``limits.interlock_window`` [s], as a servo controller's duty and rms
    monitors are.
    """
    h = held[0]
    loop = pa[PA_LOOP]
    uv = delayed_output(line, h, valve_command(pa, u, h.x_prev, h.dp_prev))
    sat, current = valve_output(pa, uv, h.sat)
    weight = min(1.0, loop / limits.interlock_window)
    slew = (uv - h.u_v) / loop
    h.duty += weight * ((1.0 if sat > 0 else 0.0) - h.duty)
    h.current_sq += weight * (current * current - h.current_sq)
    h.slew_sq += weight * (slew * slew - h.slew_sq)
    h.u_v = uv
    h.sat = sat
    h.current = current
    h.x_prev = m.x
    h.dp_prev = m.dp


@njit(cache=True, inline="always", error_model="numpy")
def command(plant, m, u):
    """Stage 4 on a :class:`VirtualPlant`: the hydraulic loop (:func:`hydraulic_command`)."""
    hydraulic_command(plant.table, plant.limits, plant.held, plant.output_line, m, u)


@njit(cache=True, inline="always", error_model="numpy")
def plant_truth(y, held):
    """The true :class:`PlantTruth` of the plant state ``y`` and the ``held`` state of the loop."""
    h = held[0]
    return PlantTruth(
        y[IX_X], y[IX_V], h.z, y[IX_P1] - y[IX_P2], y[IX_P1], y[IX_P2], y[IX_S], h.w, h.u_v, h.current
    )


@njit(cache=True, inline="always", error_model="numpy")
def truth(plant):
    """The true :class:`PlantTruth` of the current loop, after its command (:func:`plant_truth`)."""
    return plant_truth(plant.y, plant.held)


#: Stage "record": :func:`impedance_mil.lab.structures.record_loop`, compiled.
record = njit(inline="always", error_model="numpy")(record_loop)


@njit(cache=True, inline="always", error_model="numpy")
def advance(plant):
    """Stage 5 on a :class:`VirtualPlant`: one loop of the plant, this loop's valve current held."""
    s = plant.specimen
    plant_advance(
        plant.table,
        plant.y,
        s.A_val,
        s.A_col,
        s.A_ptr,
        s.B,
        s.C,
        s.D,
        s.kind,
        s.osc_k,
        s.osc_c,
        s.C_lc,
        s.D_lc,
        s.lc_own,
        plant.held[0].current,
        plant.table[PA_LOOP],
        plant.substeps,
        plant.work,
        plant.sensors.filters,
    )


__all__ = [
    "SPEC_BANK",
    "SPEC_CSR",
    "advance",
    "check_limits",
    "check_table",
    "command",
    "coupled_derivative",
    "delayed_output",
    "measure_quantities",
    "hydraulic_command",
    "hf_oscillation_check",
    "hf_window_history",
    "mil_step",
    "plant_advance",
    "plant_sense",
    "plant_truth",
    "read",
    "record",
    "record_vs_state",
    "sense_and_check",
    "track_step",
    "truth",
    "valve_output",
]
