"""Compiled plant stepping: the table and specimen integrated over one loop (RK4 substeps).

:func:`plant_advance` advances the plant state ``y = [table states (6),
specimen states (n)]`` by one loop with the valve current held;
:func:`coupled_derivative` is the derivative it integrates (for the
solve_ivp reference and the linearization tests).  The specimen arrays are
those of :class:`~impedance_mil.lab.structures.SpecimenArrays`, passed field
by field: ``plant_advance(pa, y, *specimen_arrays(specimen), current, dt,
nsub, work, filters)``.  The sensors' anti-alias filters
(:class:`~impedance_mil.lab.structures.FilterArrays`) advance with the plant,
one exact step per substep (:func:`filter_step`): inside a loop at the
substep boundaries here, the loop's last substep when the next loop senses
(:func:`filter_sense`, where the true values at the loop's end are known).
"""

from __future__ import annotations

from numba import njit

from ..plant.nonlinear import (
    IX_P1,
    IX_P2,
    IX_S,
    IX_SD,
    IX_V,
    IX_X,
    N_TABLE_STATES,
    PA_AREA,
    table_derivative,
    table_rates,
)
from .structures import Q_DP, Q_FORCE, Q_X, Q_Z

#: Specimen kinds (how :func:`plant_advance` evaluates the specimen): a general
#: state space in compressed-row form, or a bank of base-excited oscillators.
SPEC_CSR, SPEC_BANK = 0, 1


@njit(cache=True, inline="always", error_model="numpy")
def filter_step(f, i, u1):
    """Advance filter ``i`` of the :class:`FilterArrays` ``f`` by one substep to the input ``u1``.

    The input goes linearly from the previous boundary's value to ``u1``
    [unit of the channel] (first-order hold, exact for that input).
    """
    s0, s1 = f.state[i, 0], f.state[i, 1]
    u0 = f.previous[i]
    f.state[i, 0] = f.phi[i, 0, 0] * s0 + f.phi[i, 0, 1] * s1 + f.g0[i, 0] * u0 + f.g1[i, 0] * u1
    f.state[i, 1] = f.phi[i, 1, 0] * s0 + f.phi[i, 1, 1] * s1 + f.g0[i, 1] * u0 + f.g1[i, 1] * u1
    f.previous[i] = u1


@njit(cache=True, inline="always", error_model="numpy")
def filter_sense(f, quantities):
    """The filters at a sensing instant, ``quantities`` the true values (order of QUANTITIES).

    Closes the last substep of the previous loop (:func:`filter_step`); at the
    first sensing (``f.primed[0] == 0``) sets each filter at rest at its input
    instead (the table has stood at equilibrium).  The filtered value of
    filter ``i`` is then ``f.state[i, 0]``.
    """
    for i in range(f.channel.shape[0]):
        u = f.gain[i] * quantities[f.quantity_index[i]]
        if f.primed[0]:
            filter_step(f, i, u)
        else:
            f.state[i, 0], f.state[i, 1], f.previous[i] = u, 0.0, u
    f.primed[0] = 1


@njit(cache=True, inline="always", error_model="numpy")
def delay_sense(d, f, quantities, gain, quantity_index):
    """Push each delayed channel's analog value at this sensing into its ring of :class:`DelayArrays` ``d``.

    The analog value is the output of the channel's anti-alias filter
    (``f``, already brought to this instant by :func:`filter_sense`) when it
    has one, else ``gain * quantities[quantity_index]`` of the channel.  At
    the first sensing the rings are filled with it (the table at rest).
    """
    n = d.line.shape[1]
    head = (d.head[0] + 1) % n if d.primed[0] else 0
    for i in range(d.channel.shape[0]):
        c = d.channel[i]
        k = d.filter_index[i]
        a = f.state[k, 0] if k >= 0 else gain[c] * quantities[quantity_index[c]]
        if d.primed[0]:
            d.line[i, head] = a
        else:
            d.line[i, :] = a
    d.head[0] = head
    d.primed[0] = 1


@njit(cache=True, inline="always", error_model="numpy")
def delayed_value(d, i):
    """Delayed analog value of entry ``i`` of ``d``: ``whole + frac`` loops back, linear between the loops."""
    n = d.line.shape[1]
    newer = d.line[i, (d.head[0] - d.whole[i] + n) % n]
    older = d.line[i, (d.head[0] - d.whole[i] - 1 + n) % n]
    return newer + d.frac[i] * (older - newer)


@njit(cache=True, inline="always", error_model="numpy")
def filter_boundary(f, pa, z, x, p1, p2, w):
    """The filters over one substep, to the true values at its end (z [in/s^2], x [in], p1, p2 [psi], w [lbf])."""
    dp = p1 - p2
    for i in range(f.channel.shape[0]):
        k = f.quantity_index[i]
        if k == Q_Z:
            q = z
        elif k == Q_X:
            q = x
        elif k == Q_DP:
            q = dp
        elif k == Q_FORCE:
            q = pa[PA_AREA] * dp
        else:
            q = w
        filter_step(f, i, f.gain[i] * q)


@njit(cache=True, inline="always", error_model="numpy")
def specimen_force_state(Cs, ys):
    """State part ``C x`` [lbf] of the specimen's interface force (``w = C x + D z``)."""
    ws = 0.0
    for i in range(Cs.shape[0]):
        ws += Cs[i] * ys[i]
    return ws


@njit(cache=True, inline="always", error_model="numpy")
def load_cell_force(ys, z, w, C_lc, D_lc, lc_own):
    """The force the load cells read [lbf]: ``w`` [lbf] itself unless ``lc_own``, else ``C_lc ys + D_lc z``.

    ``ys`` are the specimen states, ``z`` the table acceleration [in/s^2]
    (:class:`~impedance_mil.lab.structures.SpecimenArrays`; a mounting's load
    cells read another force than the one on the table).
    """
    if lc_own:
        return specimen_force_state(C_lc, ys) + D_lc * z
    return w


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
def coupled_derivative(pa, y, Av, Ac, Ap, Bs, Cs, Ds, kind, osc_k, osc_c, C_lc, D_lc, lc_own, current, out):
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
def plant_advance(
    pa, y, Av, Ac, Ap, Bs, Cs, Ds, kind, osc_k, osc_c, C_lc, D_lc, lc_own, current, dt, nsub, work, filters
):
    """Advance the plant state ``y`` by ``dt`` [s]: ``nsub`` RK4 steps, valve current held [mA].

    Specimen arrays of :func:`impedance_mil.lab.plant_interface.specimen_arrays`:
    the state space ``(Av, Ac, Ap, Bs, Cs, Ds)`` (A in compressed-row form,
    :func:`specimen_rates`) and, for ``kind == SPEC_BANK``, the oscillator
    coefficients ``osc_k = -omega_i^2`` [1/s^2] and ``osc_c = -2 zeta_i
    omega_i`` [1/s] of a bank of base-excited oscillators (states: relative
    displacements q [in], then velocities q' [in/s]; ``q_i'' = -z + osc_k_i
    q_i + osc_c_i q_i'``) and the load cells' output ``(C_lc, D_lc, lc_own)``
    the filters of the load-cell channels read (:func:`load_cell_force`).  Both kinds take the same RK4 stages; the bank
    evaluates them in one loop per stage (:func:`advance_bank`), the general
    form in :func:`advance_csr` (called, not inlined: :data:`advance_csr_called`).
    ``work`` is a (5, len(y)) scratch array.
    ``filters`` are the sensors' :class:`~impedance_mil.lab.structures.FilterArrays`
    (none: ``FilterArrays.none()``), stepped at the substep boundaries
    inside the loop (:func:`filter_boundary`) with the true values the RK4
    step evaluates there anyway; the loop's last substep is closed by the
    next sensing (:func:`filter_sense`).
    """
    if kind == SPEC_BANK:
        advance_bank(pa, y, Cs, Ds, osc_k, osc_c, C_lc, D_lc, lc_own, current, dt, nsub, work, filters)
    else:
        # A call, not inlined (advance_csr_called): the default specimens take the bank path.
        advance_csr_called(
            pa, y, Av, Ac, Ap, Bs, Cs, Ds, C_lc, D_lc, lc_own, current, dt, nsub, work, filters
        )


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
def advance_bank(pa, y, Cs, Ds, osc_k, osc_c, C_lc, D_lc, lc_own, current, dt, nsub, work, filters):
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
    n_filters = filters.channel.shape[0]
    for j in range(nsub):
        ws = 0.0
        for i in range(n):
            ws += Cs[i] * ys[i] + Cs[n + i] * ys[n + i]
        z1, e1, f1, g1 = table_rates(pa, x, v, p1, p2, s, sd, current, ws, Ds)
        if j > 0 and n_filters > 0:
            filter_boundary(
                filters, pa, z1, x, p1, p2, load_cell_force(ys, z1, ws + Ds * z1, C_lc, D_lc, lc_own)
            )
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


def advance_csr(pa, y, Av, Ac, Ap, Bs, Cs, Ds, C_lc, D_lc, lc_own, current, dt, nsub, work, filters):
    """:func:`plant_advance` for a general specimen state space (``kind == SPEC_CSR``).

    Compiled as :data:`advance_csr_called` (a call from the loop, not inlined).

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
    n_filters = filters.channel.shape[0]
    for j in range(nsub):
        ws = specimen_force_state(Cs, ys)
        z1, e1, f1, g1 = table_rates(pa, x, v, p1, p2, s, sd, current, ws, Ds)
        if j > 0 and n_filters > 0:
            filter_boundary(
                filters, pa, z1, x, p1, p2, load_cell_force(ys, z1, ws + Ds * z1, C_lc, D_lc, lc_own)
            )
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


#: :func:`advance_csr` compiled as a function of its own, which :func:`plant_advance` calls
#: instead of inlining it (issue 16, goal 4).  Every stage of the compiled loop is inlined into
#: one function, and numba's and LLVM's passes cost more than in proportion to its size; the
#: compressed-row path (four more inlined table derivatives) is taken only by a specimen that is
#: not a bank of oscillators (a coupled MDOF), never by the default vessel.  Out of line the
#: loop's compile took 13.3-13.6 s of CPU instead of 16.8-17.8 s (alternating, load 3.2-3.5), the
#: default loop's speed the same (bench_lab, 1025-1029x against 1023-1063x), and the results of
#: either path are the same bit for bit (same operations, no fast-math).  ``_nrt=False`` as the
#: loop's (lab/tick.py): it allocates nothing, and its array views would pay reference counting.
advance_csr_called = njit(cache=True, error_model="numpy", _nrt=False)(advance_csr)
