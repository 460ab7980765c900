"""Compiled pieces of the virtual lab: sensing, plant stepping, safety, and the hot loop.

One loop tick (loop time T, tick k at t_k = k T), as on the RMC75E (Section 7.3.4):

1. **sense** (:func:`plant_sense`): the sensors of a
   :class:`~impedance_mil.specimens.sensors.SensorSuite` read the plant at t_k
   (Table 7.1 calibration, noise, 16-bit quantization, range): ``x``, ``dP``,
   ``z`` and the load-cell force ``w_LC``; ``w_FE = m_st z - A_p dP`` from force
   equilibrium (Section 8.3.2);
2. **safety** (:func:`check_limits`): stroke, velocity, actuator force, valve
   saturation, NaN and divergence;
3. **controller**: open loop (``u`` given), acceleration tracking
   (``z_vs = a_g``) or MIL (VS RK3 step then controller), using the runtime
   kernels of :mod:`impedance_mil.implement`;
4. **hydraulic loop** (:func:`hydraulic_step`):
   ``u_v(k) = K_e (u(k) - x_m(k-1)) - K_p dP_m(k-1)``, held over the loop (ZOH);
5. **advance** (:func:`plant_advance`): the continuous plant (nonlinear table +
   specimen state space) integrated over T with fixed RK4 substeps.

The Python plant interface (:class:`impedance_mil.lab.plant_interface.VirtualTable`)
calls the same ``plant_sense``, ``check_limits``, ``hydraulic_step`` and
``plant_advance``; the compiled :func:`run_loop` is the fast implementation of
that contract.

Plant state ``y = [table states (6), specimen states (n)]``.
"""

from __future__ import annotations

import math

from numba import njit

from ..implement.kernels import controller_step_parts
from ..implement.runtime import mil_step_kernel
from ..plant.nonlinear import (
    IX_P1,
    IX_P2,
    IX_S,
    IX_SD,
    IX_V,
    IX_X,
    N_TABLE_STATES,
    PA_AREA,
    PA_KV,
    PA_LOOP,
    PA_MASS,
    PA_UVMAX,
    table_acceleration,
    table_derivative,
    table_rates,
    valve_command,
)
from ..specimens.sensors import force_from_equilibrium, load_cell_force_kernel, measure_kernel

#: Specimen kinds (how :func:`plant_advance` evaluates the specimen): a general
#: state space in compressed-row form, or a bank of base-excited oscillators.
SPEC_CSR, SPEC_BANK = 0, 1
#: Loop modes.
MODE_OPEN, MODE_TRACK, MODE_MIL = 0, 1, 2
#: Feedback sources of w: reaction load cells or force equilibrium (Section 8.3.2, App. C).
FEEDBACK_LC, FEEDBACK_FE = 0, 1

#: Outputs of :func:`plant_sense`.
SENSE_FIELDS = ("z", "w", "x_meas", "dp_meas", "z_meas", "w_lc", "w_fe")
(M_Z, M_W, M_X, M_DP, M_ZM, M_WLC, M_WFE) = range(7)

#: Safety limits array layout.
(L_STROKE, L_VELOCITY, L_FORCE, L_VALVE_TIME, L_DIVERGE) = range(5)
#: Trip codes (0 = none) and their names.
TRIP_NAMES = ("", "stroke", "velocity", "actuator_force", "valve_saturation", "nan", "divergence")

#: Recorded channels, one column each of the record array.
CHANNELS = (
    "t",
    "a_g",
    "z_vs",
    "u",
    "u_z",
    "u_w",
    "u_v",
    "current",
    "x",
    "v",
    "z",
    "dp",
    "p1",
    "p2",
    "spool",
    "w",
    "w_lc",
    "w_fe",
    "w_used",
    "x_meas",
    "dp_meas",
    "z_meas",
)
(
    C_T,
    C_AG,
    C_ZVS,
    C_U,
    C_UZ,
    C_UW,
    C_UV,
    C_I,
    C_X,
    C_V,
    C_Z,
    C_DP,
    C_P1,
    C_P2,
    C_S,
    C_W,
    C_WLC,
    C_WFE,
    C_WUSED,
    C_XM,
    C_DPM,
    C_ZM,
) = range(len(CHANNELS))


@njit(cache=True, inline="always", error_model="numpy")
def specimen_force_state(Cs, ys):
    """State part ``C x`` [lbf] of the specimen's interface force (``w = C x + D z``)."""
    ws = 0.0
    for i in range(Cs.shape[0]):
        ws += Cs[i] * ys[i]
    return ws


@njit(cache=True, inline="always", error_model="numpy")
def specimen_rates(Av, Ac, Ap, Bs, ys, z, out):
    """Specimen derivative ``A x + B z`` into ``out`` for table acceleration z [in/s^2].

    The specimen's state matrix is in compressed-row form: row ``i`` has the
    values ``Av[Ap[i]:Ap[i+1]]`` in the columns ``Ac[Ap[i]:Ap[i+1]]``.
    """
    for i in range(Bs.shape[0]):
        acc = Bs[i] * z
        for k in range(Ap[i], Ap[i + 1]):
            acc += Av[k] * ys[Ac[k]]
        out[i] = acc


@njit(cache=True, inline="always", error_model="numpy")
def coupled_derivative(pa, y, Av, Ac, Ap, Bs, Cs, Ds, kind, osc_k, osc_c, current, out):
    """Derivative of the table + specimen state; returns the table acceleration z [in/s^2].

    Specimen arrays as in :func:`plant_advance` (the general compressed-row
    form is used whatever ``kind``); this is the derivative that
    :func:`plant_advance` integrates (there with the table states in registers).
    """
    ws = specimen_force_state(Cs, y[N_TABLE_STATES:])
    # the table states lead y (table_derivative reads and writes indices 0..5 only)
    z = table_derivative(pa, y, current, ws, Ds, out)
    specimen_rates(Av, Ac, Ap, Bs, y[N_TABLE_STATES:], z, out[N_TABLE_STATES:])
    return z


@njit(cache=True, inline="always", error_model="numpy")
def plant_advance(pa, y, Av, Ac, Ap, Bs, Cs, Ds, kind, osc_k, osc_c, current, dt, nsub, work):
    """Advance the plant state ``y`` by ``dt`` [s]: ``nsub`` RK4 steps, valve current held [mA].

    Specimen arrays of :func:`impedance_mil.lab.plant_interface.specimen_arrays`:
    the state space ``(Av, Ac, Ap, Bs, Cs, Ds)`` (A in compressed-row form,
    :func:`specimen_rates`) and, for ``kind == SPEC_BANK``, the oscillator
    coefficients ``osc_k = -omega_i^2`` [1/s^2] and ``osc_c = -2 zeta_i
    omega_i`` [1/s] of a bank of base-excited oscillators (states: relative
    displacements q [in], then velocities q' [in/s]; ``q_i'' = -z + osc_k_i
    q_i + osc_c_i q_i'``).  Both kinds take the same RK4 stages; the bank
    evaluates them in one loop per stage (:func:`advance_bank`), the general
    form in :func:`advance_csr`.  ``work`` is a (5, len(y)) scratch array.
    """
    if kind == SPEC_BANK:
        advance_bank(pa, y, Cs, Ds, osc_k, osc_c, current, dt, nsub, work)
    else:
        advance_csr(pa, y, Av, Ac, Ap, Bs, Cs, Ds, current, dt, nsub, work)


@njit(cache=True, inline="always", error_model="numpy")
def bank_inner_stage(ys, tmp, acc, Cs, osc_k, osc_c, z, c):
    """RK4 stage 2 or 3 of :func:`advance_bank`; returns the next stage's ``w_s`` [lbf].

    The bank's derivative at the stage state ``tmp`` for table acceleration
    ``z`` [in/s^2] is added twice to the RK4 sum ``acc``; the next stage's
    state ``ys + c * derivative`` (``c`` [s]: half the substep for stage 2,
    the whole one for stage 3) replaces ``tmp``.
    """
    n = osc_k.shape[0]
    ws = 0.0
    for i in range(n):
        q, qd = tmp[i], tmp[n + i]
        dq, dqd = qd, -z + osc_k[i] * q + osc_c[i] * qd
        acc[i] += 2.0 * dq
        acc[n + i] += 2.0 * dqd
        tq, tqd = ys[i] + c * dq, ys[n + i] + c * dqd
        tmp[i], tmp[n + i] = tq, tqd
        ws += Cs[i] * tq + Cs[n + i] * tqd
    return ws


@njit(cache=True, inline="always", error_model="numpy")
def advance_bank(pa, y, Cs, Ds, osc_k, osc_c, current, dt, nsub, work):
    """:func:`plant_advance` for a bank of oscillators (``kind == SPEC_BANK``).

    Per RK4 stage one loop over the oscillators evaluates the stage
    derivative, adds it to the RK4 sum, forms the next stage's state and the
    state part of its interface force ``w_s = sum C_i y_i`` [lbf] (the
    force is then a by-product of the loop that forms the state).  Same
    stages as :func:`advance_csr`; the force's sum is taken in another
    order, so results agree to round-off, not to the last bit.
    """
    h = dt / nsub
    n = osc_k.shape[0]
    ys = y[N_TABLE_STATES:]
    acc, tmp = work[0], work[1]
    x, v, p1, p2, s, sd = y[IX_X], y[IX_V], y[IX_P1], y[IX_P2], y[IX_S], y[IX_SD]
    for _ in range(nsub):
        ws = 0.0
        for i in range(n):
            ws += Cs[i] * ys[i] + Cs[n + i] * ys[n + i]
        z1, e1, f1, g1 = table_rates(pa, x, v, p1, p2, s, sd, current, ws, Ds)
        ws = 0.0
        for i in range(n):
            q, qd = ys[i], ys[n + i]
            dq, dqd = qd, -z1 + osc_k[i] * q + osc_c[i] * qd
            acc[i], acc[n + i] = dq, dqd
            tq, tqd = q + 0.5 * h * dq, qd + 0.5 * h * dqd
            tmp[i], tmp[n + i] = tq, tqd
            ws += Cs[i] * tq + Cs[n + i] * tqd
        x2, v2, p12, p22, s2, sd2 = (
            x + 0.5 * h * v,
            v + 0.5 * h * z1,
            p1 + 0.5 * h * e1,
            p2 + 0.5 * h * f1,
            s + 0.5 * h * sd,
            sd + 0.5 * h * g1,
        )
        z2, e2, f2, g2 = table_rates(pa, x2, v2, p12, p22, s2, sd2, current, ws, Ds)
        ws = bank_inner_stage(ys, tmp, acc, Cs, osc_k, osc_c, z2, 0.5 * h)
        x3, v3, p13, p23, s3, sd3 = (
            x + 0.5 * h * v2,
            v + 0.5 * h * z2,
            p1 + 0.5 * h * e2,
            p2 + 0.5 * h * f2,
            s + 0.5 * h * sd2,
            sd + 0.5 * h * g2,
        )
        z3, e3, f3, g3 = table_rates(pa, x3, v3, p13, p23, s3, sd3, current, ws, Ds)
        ws = bank_inner_stage(ys, tmp, acc, Cs, osc_k, osc_c, z3, h)
        x4, v4, p14, p24, s4, sd4 = (
            x + h * v3,
            v + h * z3,
            p1 + h * e3,
            p2 + h * f3,
            s + h * sd3,
            sd + h * g3,
        )
        z4, e4, f4, g4 = table_rates(pa, x4, v4, p14, p24, s4, sd4, current, ws, Ds)
        for i in range(n):
            q, qd = tmp[i], tmp[n + i]
            ys[i] += h / 6.0 * (acc[i] + qd)
            ys[n + i] += h / 6.0 * (acc[n + i] + (-z4 + osc_k[i] * q + osc_c[i] * qd))
        x += h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
        v += h / 6.0 * (z1 + 2.0 * z2 + 2.0 * z3 + z4)
        p1 += h / 6.0 * (e1 + 2.0 * e2 + 2.0 * e3 + e4)
        p2 += h / 6.0 * (f1 + 2.0 * f2 + 2.0 * f3 + f4)
        s += h / 6.0 * (sd + 2.0 * sd2 + 2.0 * sd3 + sd4)
        sd += h / 6.0 * (g1 + 2.0 * g2 + 2.0 * g3 + g4)
    y[IX_X], y[IX_V], y[IX_P1], y[IX_P2], y[IX_S], y[IX_SD] = x, v, p1, p2, s, sd


@njit(cache=True, inline="always", error_model="numpy")
def advance_csr(pa, y, Av, Ac, Ap, Bs, Cs, Ds, current, dt, nsub, work):
    """:func:`plant_advance` for a general specimen state space (``kind == SPEC_CSR``).

    Classical RK4 on :func:`coupled_derivative`, written out with the six
    table states as scalars (:func:`~impedance_mil.plant.nonlinear.table_rates`)
    and the specimen states in ``work``; the operations and their order are
    those of the array form, so results are the same to the last bit.  (The
    four stages are spelled out on purpose: a stage helper passing the
    states as tuples measured ~30 % slower.)
    """
    h = dt / nsub
    m = Bs.shape[0]
    ys = y[N_TABLE_STATES:]
    k1, k2, k3, k4, tmp = work[0], work[1], work[2], work[3], work[4]
    x, v, p1, p2, s, sd = y[IX_X], y[IX_V], y[IX_P1], y[IX_P2], y[IX_S], y[IX_SD]
    for _ in range(nsub):
        z1, e1, f1, g1 = table_rates(pa, x, v, p1, p2, s, sd, current, specimen_force_state(Cs, ys), Ds)
        specimen_rates(Av, Ac, Ap, Bs, ys, z1, k1)
        for i in range(m):
            tmp[i] = ys[i] + 0.5 * h * k1[i]
        x2, v2, p12, p22, s2, sd2 = (
            x + 0.5 * h * v,
            v + 0.5 * h * z1,
            p1 + 0.5 * h * e1,
            p2 + 0.5 * h * f1,
            s + 0.5 * h * sd,
            sd + 0.5 * h * g1,
        )
        z2, e2, f2, g2 = table_rates(
            pa, x2, v2, p12, p22, s2, sd2, current, specimen_force_state(Cs, tmp), Ds
        )
        specimen_rates(Av, Ac, Ap, Bs, tmp, z2, k2)
        for i in range(m):
            tmp[i] = ys[i] + 0.5 * h * k2[i]
        x3, v3, p13, p23, s3, sd3 = (
            x + 0.5 * h * v2,
            v + 0.5 * h * z2,
            p1 + 0.5 * h * e2,
            p2 + 0.5 * h * f2,
            s + 0.5 * h * sd2,
            sd + 0.5 * h * g2,
        )
        z3, e3, f3, g3 = table_rates(
            pa, x3, v3, p13, p23, s3, sd3, current, specimen_force_state(Cs, tmp), Ds
        )
        specimen_rates(Av, Ac, Ap, Bs, tmp, z3, k3)
        for i in range(m):
            tmp[i] = ys[i] + h * k3[i]
        x4, v4, p14, p24, s4, sd4 = (
            x + h * v3,
            v + h * z3,
            p1 + h * e3,
            p2 + h * f3,
            s + h * sd3,
            sd + h * g3,
        )
        z4, e4, f4, g4 = table_rates(
            pa, x4, v4, p14, p24, s4, sd4, current, specimen_force_state(Cs, tmp), Ds
        )
        specimen_rates(Av, Ac, Ap, Bs, tmp, z4, k4)
        for i in range(m):
            ys[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        x += h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4)
        v += h / 6.0 * (z1 + 2.0 * z2 + 2.0 * z3 + z4)
        p1 += h / 6.0 * (e1 + 2.0 * e2 + 2.0 * e3 + e4)
        p2 += h / 6.0 * (f1 + 2.0 * f2 + 2.0 * f3 + f4)
        s += h / 6.0 * (sd + 2.0 * sd2 + 2.0 * sd3 + sd4)
        sd += h / 6.0 * (g1 + 2.0 * g2 + 2.0 * g3 + g4)
    y[IX_X], y[IX_V], y[IX_P1], y[IX_P2], y[IX_S], y[IX_SD] = x, v, p1, p2, s, sd


@njit(cache=True, inline="always", error_model="numpy")
def plant_sense(
    pa,
    y,
    Cs,
    Ds,
    qi,
    gain,
    scale,
    offset,
    noise_rms,
    lsb,
    v_low,
    v_high,
    lc_weights,
    chan_idx,
    q,
    noise_row,
    readings,
    out,
):
    """Sensor readings at the current state into ``out`` (layout ``SENSE_FIELDS``).

    ``qi ... q`` are the arrays of :func:`impedance_mil.lab.setup.sensor_arrays`
    (those of a :class:`~impedance_mil.specimens.sensors.SensorSuite`, the
    index of the z, x and dP channels, and a 5-entry quantity buffer);
    ``readings`` receives every channel's reading.
    """
    ws = specimen_force_state(Cs, y[N_TABLE_STATES:])
    z = table_acceleration(pa, y, ws, Ds)
    w = ws + Ds * z
    dp = y[IX_P1] - y[IX_P2]
    q[0] = z
    q[1] = y[IX_X]
    q[2] = dp
    q[3] = pa[PA_AREA] * dp
    q[4] = w
    measure_kernel(q, noise_row, qi, gain, scale, offset, noise_rms, lsb, v_low, v_high, readings)
    out[M_Z] = z
    out[M_W] = w
    out[M_X] = readings[chan_idx[1]]
    out[M_DP] = readings[chan_idx[2]]
    out[M_ZM] = readings[chan_idx[0]]
    out[M_WLC] = load_cell_force_kernel(readings, lc_weights)
    out[M_WFE] = force_from_equilibrium(out[M_ZM], out[M_DP], pa[PA_MASS], pa[PA_AREA])


@njit(cache=True, inline="always", error_model="numpy")
def check_limits(pa, lim, y, meas, uv, sat_ticks):
    """Safety check of one tick; returns ``(trip code, offending value)`` (code 0: all clear).

    ``sat_ticks`` is the number of consecutive loops with the valve command at
    its limit (including this one).
    """
    for i in range(y.shape[0]):
        if not math.isfinite(y[i]):
            return 5, y[i]
    if abs(y[IX_X]) > lim[L_DIVERGE]:
        return 6, y[IX_X]
    if abs(meas[M_X]) > lim[L_STROKE]:
        return 1, meas[M_X]
    if abs(y[IX_V]) > lim[L_VELOCITY]:
        return 2, y[IX_V]
    force = pa[PA_AREA] * meas[M_DP]
    if abs(force) > lim[L_FORCE]:
        return 3, force
    if sat_ticks * pa[PA_LOOP] > lim[L_VALVE_TIME]:
        return 4, uv
    return 0, 0.0


@njit(cache=True, inline="always", error_model="numpy")
def hydraulic_step(pa, u, x_prev, dp_prev, sat_ticks):
    """Step 4 of a tick: returns ``(u_v [V], saturated ticks, valve current [mA])``.

    :func:`~impedance_mil.plant.nonlinear.valve_command` for the position
    command ``u`` [in] and the previous loop's measurements ``x_prev`` [in],
    ``dp_prev`` [psi]; ``sat_ticks`` counts the consecutive loops with ``u_v``
    at its limit (reset when it leaves it), as :func:`check_limits` reads it.
    """
    uv = valve_command(pa, u, x_prev, dp_prev)
    sat = sat_ticks + 1 if abs(uv) >= pa[PA_UVMAX] else 0
    return uv, sat, pa[PA_KV] * uv


# ``_nrt=False``: the loop runs without numba's reference counting.  With it, every
# array view made per tick (a noise row, the specimen part of y, a work row) and
# many array arguments of the inlined kernels cost an atomic increment and
# decrement; perf showed those atomics at about 45 % of the loop's time.  The
# loop allocates nothing (its scratch arrays are arguments, made by the
# caller, who also keeps every array alive for the call), so it needs no NRT.
@njit(cache=True, error_model="numpy", _nrt=False)
def run_loop(
    mode,
    feedback,
    pa,
    nsub,
    y,
    Av,
    Ac,
    Ap,
    Bs,
    Cs,
    Ds,
    spec_kind,
    osc_k,
    osc_c,
    sens,
    noise,
    lim,
    a_g,
    command,
    m_z,
    m_w,
    s_z,
    s_w,
    tmp,
    compensated,
    vs_fns,
    vs_params,
    x_vs,
    vs_work,
    rec,
    vs_rec,
    work,
    scratch,
    out2,
    status,
):
    """The compiled sampled-data loop (module docstring); one code path for every setup.

    Parameters
    ----------
    mode : int
        MODE_OPEN (``command`` is u [in]), MODE_TRACK (``z_vs = a_g``) or MODE_MIL.
    feedback : int
        FEEDBACK_LC or FEEDBACK_FE: which w the VS and the controller use.
    pa : ndarray
        Table parameter array (:meth:`NonlinearTable.parameter_array`).
    nsub : int
        RK4 substeps per loop.
    y : ndarray
        Plant state (table + specimen), advanced in place.
    Av, Ac, Ap, Bs, Cs, Ds
        Specimen state space (input z [in/s^2], output w [lbf]); A in
        compressed-row form (:func:`impedance_mil.lab.plant_interface.specimen_arrays`).
    spec_kind, osc_k, osc_c
        SPEC_CSR, or SPEC_BANK with the oscillator coefficients (:func:`plant_advance`).
    sens : tuple
        Sensor arrays (:func:`impedance_mil.lab.setup.sensor_arrays`).
    noise : ndarray (n, n_channels)
        Standard normal draws per tick and sensor channel.
    lim : ndarray
        Safety limits (``L_*`` layout).
    a_g, command : ndarray (n,)
        Ground acceleration [in/s^2] and open-loop command [in] per tick.
    m_z, m_w, s_z, s_w, tmp, compensated
        Controller arrays of :class:`impedance_mil.implement.MILRuntime`.
    vs_fns, vs_params, x_vs, vs_work
        Virtual system (MODE_MIL).
    rec : ndarray (len(CHANNELS), n)
        Receives the records, one row per channel.
    vs_rec : ndarray (n, n_vs)
        Receives the VS state at the start of each loop.
    work : ndarray (5, len(y))
        Scratch of the plant step.
    scratch : ndarray (7 + n_channels,)
        Scratch of the sensing step (its outputs, then every channel's reading).
    out2 : ndarray (3,)
        Scratch of the MIL step, in the controller's dtype.
    status : ndarray (3,)
        Receives ``[ticks completed, trip code, offending value]``.
    """
    n = a_g.shape[0]
    dt = pa[PA_LOOP]
    qi, gain, scale, offset, noise_rms, lsb, v_low, v_high, lc_w, chan_idx, qbuf = sens
    meas = scratch[:7]
    readings = scratch[7:]
    x_prev = 0.0
    dp_prev = 0.0
    sat = 0
    uv_last = 0.0
    status[0] = n
    status[1] = 0.0
    status[2] = 0.0
    for k in range(n):
        plant_sense(
            pa,
            y,
            Cs,
            Ds,
            qi,
            gain,
            scale,
            offset,
            noise_rms,
            lsb,
            v_low,
            v_high,
            lc_w,
            chan_idx,
            qbuf,
            noise[k],
            readings,
            meas,
        )
        w_used = meas[M_WLC] if feedback == FEEDBACK_LC else meas[M_WFE]
        code, value = check_limits(pa, lim, y, meas, uv_last, sat)
        if code != 0:
            status[0] = k
            status[1] = code
            status[2] = value
            return
        for i in range(x_vs.shape[0]):
            vs_rec[k, i] = x_vs[i]
        if mode == MODE_OPEN:
            u = command[k]
            u_w = 0.0
            z_vs = 0.0
        elif mode == MODE_TRACK:
            u, u_w = controller_step_parts(m_z, m_w, s_z, s_w, tmp, a_g[k], w_used, compensated)
            z_vs = a_g[k]
        else:
            mil_step_kernel(
                m_z,
                m_w,
                s_z,
                s_w,
                tmp,
                compensated,
                vs_fns,
                vs_params,
                x_vs,
                vs_work,
                dt,
                a_g[k],
                w_used,
                out2,
            )
            u = out2[0]
            z_vs = out2[1]
            u_w = out2[2]
        uv, sat, current = hydraulic_step(pa, u, x_prev, dp_prev, sat)
        x_prev = meas[M_X]
        dp_prev = meas[M_DP]
        uv_last = uv
        rec[C_T, k] = k * dt
        rec[C_AG, k] = a_g[k]
        rec[C_ZVS, k] = z_vs
        rec[C_U, k] = u
        rec[C_UZ, k] = u - u_w
        rec[C_UW, k] = u_w
        rec[C_UV, k] = uv
        rec[C_I, k] = current
        rec[C_X, k] = y[IX_X]
        rec[C_V, k] = y[IX_V]
        rec[C_Z, k] = meas[M_Z]
        rec[C_DP, k] = y[IX_P1] - y[IX_P2]
        rec[C_P1, k] = y[IX_P1]
        rec[C_P2, k] = y[IX_P2]
        rec[C_S, k] = y[IX_S]
        rec[C_W, k] = meas[M_W]
        rec[C_WLC, k] = meas[M_WLC]
        rec[C_WFE, k] = meas[M_WFE]
        rec[C_WUSED, k] = w_used
        rec[C_XM, k] = meas[M_X]
        rec[C_DPM, k] = meas[M_DP]
        rec[C_ZM, k] = meas[M_ZM]
        plant_advance(pa, y, Av, Ac, Ap, Bs, Cs, Ds, spec_kind, osc_k, osc_c, current, dt, nsub, work)
