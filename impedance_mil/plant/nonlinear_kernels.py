"""The compiled derivative of the nonlinear virtual table (numba kernels on a parameter array).

Split from :mod:`impedance_mil.plant.nonlinear`, which defines the state and parameter layouts
(``IX_*``, ``PA_*``), the orifice law and :class:`~impedance_mil.plant.nonlinear.NonlinearTable`,
and re-exports these kernels under their names (``from impedance_mil.plant.nonlinear import
table_derivative`` as before): building a table from its parameters (``imil lab show``) does not
import numba (issue 16, start-up).  The Python methods, the linearization and the compiled lab
loop all call these kernels.
"""

from __future__ import annotations

import math

from numba import njit

from .nonlinear import (
    IX_P1,
    IX_P2,
    IX_S,
    IX_SD,
    IX_V,
    IX_X,
    PA_AREA,
    PA_CSTOP,
    PA_FC,
    PA_FCLOAD,
    PA_FCSUM,
    PA_FV,
    PA_GOUT,
    PA_KAPPA,
    PA_KE,
    PA_KG,
    PA_KL,
    PA_KP,
    PA_KQ,
    PA_KSTOP,
    PA_MASS,
    PA_MID,
    PA_MOUNT,
    PA_PLAM,
    PA_PR,
    PA_PS,
    PA_SMAX,
    PA_SRATE,
    PA_UVMAX,
    PA_VDEAD,
    PA_VDELTA,
    PA_VGAMMA,
    PA_VQ,
    PA_VSMOOTH,
    orifice_law,
)
from .table_dynamics import smooth_saturation

#: The orifice law of :func:`~impedance_mil.plant.nonlinear.orifice_law`, compiled (one definition).
orifice = njit(cache=True, inline="always", error_model="numpy")(orifice_law)

#: The spool-velocity saturation of :func:`~impedance_mil.plant.table_dynamics.smooth_saturation`, compiled.
saturation = njit(cache=True, inline="always", error_model="numpy")(smooth_saturation)


@njit(cache=True, inline="always", error_model="numpy")
def port_flows(pa, s, p1, p2):
    """Flow into chamber 1 and out of chamber 2 [in^3/s] for spool ``s`` [mA] (Eq 4-5)."""
    smax = pa[PA_SMAX]
    opening = min(max(s, -smax), smax)
    kq = pa[PA_KQ]
    plam = pa[PA_PLAM]
    if opening >= 0.0:
        q1 = kq * opening * orifice(pa[PA_PS] - p1, plam)
        q2 = kq * opening * orifice(p2 - pa[PA_PR], plam)
    else:
        q1 = kq * opening * orifice(p1 - pa[PA_PR], plam)
        q2 = kq * opening * orifice(pa[PA_PS] - p2, plam)
    return q1, q2


@njit(cache=True, inline="always", error_model="numpy")
def acceleration(pa, x, v, p1, p2, w_state, w_feed):
    """Table acceleration z [in/s^2] (Eq 4-7b with friction and end stops), from scalars.

    ``m_st z = A_p dP + w - F_friction - k_g x + F_endstop`` with ``w = w_state + w_feed z``
    (``k_g`` the grounded stiffness); ``x`` [in], ``v`` [in/s], chamber pressures
    ``p1``, ``p2`` [psi].
    """
    force = pa[PA_AREA] * (p1 - p2) + w_state
    # Rails and seals: smoothed Coulomb + viscous (platen) friction; end-of-stroke cushion.
    vs = pa[PA_VSMOOTH]
    fc = pa[PA_FC]
    if pa[PA_FCSUM] != 0.0 or pa[PA_FCLOAD] != 0.0:
        # seals pressed by the chamber pressures (issue 17; skipped when off: the report's model
        # to the last bit); |dP| smoothed over p_lam, and the level kept >= 0 (no cavitation floor)
        dp, plam = p1 - p2, pa[PA_PLAM]
        fc += pa[PA_FCSUM] * (p1 + p2) + pa[PA_FCLOAD] * (math.sqrt(dp * dp + plam * plam) - plam)
        fc = max(fc, 0.0)
    force -= fc * v / math.sqrt(v * v + vs * vs) + pa[PA_FV] * v
    force -= pa[PA_KG] * x  # grounded stiffness (0: an exact no-op)
    xm = pa[PA_MID]
    if x > xm:
        force -= pa[PA_KSTOP] * (x - xm) + pa[PA_CSTOP] * v
    elif x < -xm:
        force -= pa[PA_KSTOP] * (x + xm) + pa[PA_CSTOP] * v
    return force / (pa[PA_MASS] - w_feed)


@njit(cache=True, inline="always", error_model="numpy")
def table_acceleration(pa, xt, w_state, w_feed):
    """Table acceleration z [in/s^2] at the state array ``xt`` (:func:`acceleration`)."""
    return acceleration(pa, xt[IX_X], xt[IX_V], xt[IX_P1], xt[IX_P2], w_state, w_feed)


@njit(cache=True, inline="always", error_model="numpy")
def table_rates(pa, x, v, p1, p2, s, sd, current, w_state, w_feed):
    """The nontrivial table derivatives from scalar states: ``(z, dP1/dt, dP2/dt, d2s/dt2)``.

    The other two are ``dx/dt = v`` and ``ds/dt = sd``.  States: ``x`` [in],
    ``v`` [in/s], ``p1``, ``p2`` [psi], spool ``s`` [mA] and its rate ``sd``
    [mA/s]; ``current`` [mA], ``w_state``, ``w_feed`` as in
    :func:`table_derivative`.  Returns z [in/s^2], [psi/s], [psi/s], [mA/s^2].

    The valve (:class:`~impedance_mil.plant.parameters.ValveDynamics`): the last
    derivative is ``gamma (current - q s) - delta sd`` and the port opening
    ``q s + (1 - q) sd``.  A second-order valve has ``q = 1``: ``s'' = gamma
    (i - s) - delta s'``.  A first-order valve has ``q = 0``, ``delta =
    gamma = 1/T``: the ``spool_rate`` slot then holds the spool, ``sd' = (i -
    sd)/T``, and the ``spool`` slot its time integral [mA*s], a decoupled
    state nothing reads (the lab's RK4 integrates ``s' = sd`` in every case).
    """
    area = pa[PA_AREA]
    xm = pa[PA_MID]
    z = acceleration(pa, x, v, p1, p2, w_state, w_feed)
    # Chambers (Eq 4-8c,d) with stroke-dependent volumes.
    vdead = pa[PA_VDEAD]
    mount = pa[PA_MOUNT]
    # Piston stroke relative to the cylinder body: x, or with a compliant mount (issue 17)
    # x - x_b, the massless mount deflected by the actuator's reaction, x_b = -A_p dP / k_f.
    xr = x if mount == 0.0 else x + area * mount * (p1 - p2)
    v1 = max(area * (xm + xr) + vdead, 0.5 * vdead)
    v2 = max(area * (xm - xr) + vdead, 0.5 * vdead)
    q = pa[PA_VQ]
    q1, q2 = port_flows(pa, q * s + (1.0 - q) * sd, p1, p2)
    leak = pa[PA_KL] * (p1 - p2)
    if mount == 0.0:
        dp1 = pa[PA_KAPPA] / v1 * (q1 - area * v - leak)
        dp2 = pa[PA_KAPPA] / v2 * (area * v + leak - q2)
    else:
        # The relative velocity v + c/A_p dP' (c = A_p^2/k_f) makes the two pressure rates
        # implicit: P1' = a1 (r1 - c D), P2' = a2 (r2 + c D), D = P1' - P2'; solved for D.
        a1, a2 = pa[PA_KAPPA] / v1, pa[PA_KAPPA] / v2
        r1, r2 = q1 - area * v - leak, area * v + leak - q2
        c = area * area * mount
        d = (a1 * r1 - a2 * r2) / (1.0 + (a1 + a2) * c)
        dp1 = a1 * (r1 - c * d)
        dp2 = a2 * (r2 + c * d)
    # Servovalve (Eq 4-3, or first/second order), spool in mA-equivalent.
    rate = pa[PA_SRATE]
    if rate == 0.0:
        return z, dp1, dp2, pa[PA_VGAMMA] * (current - q * s) - pa[PA_VDELTA] * sd
    # Pilot-stage flow saturation (issue 17): the spool velocity the pilot asks for is limited
    # smoothly to +-rate.  Second order: s'' = delta (sat(gamma (i - s) / delta) - s'), a lag of
    # a bounded demand (no windup; the unlimited valve when sat is the identity).  First order:
    # the spool (sd) moves at sat(gamma (i - sd)).
    if q == 1.0:
        demand = pa[PA_VGAMMA] * (current - s) / pa[PA_VDELTA]
        return z, dp1, dp2, pa[PA_VDELTA] * (saturation(demand, rate) - sd)
    return z, dp1, dp2, saturation(pa[PA_VGAMMA] * (current - sd), rate)


@njit(cache=True, inline="always", error_model="numpy")
def table_derivative(pa, xt, current, w_state, w_feed, out):
    """Time derivative of the table states; returns the table acceleration z [in/s^2].

    Parameters
    ----------
    pa : ndarray
        Parameter array (:meth:`NonlinearTable.parameter_array`).
    xt : ndarray
        Table state (layout ``TABLE_STATE_NAMES``).
    current : float
        Valve current u_i [mA].
    w_state, w_feed : float
        Force of the test article on the table is ``w = w_state + w_feed * z``
        [lbf] (``w_feed`` [lbf*s^2/in] is the specimen's feedthrough, e.g.
        ``-M`` for a rigid mass M); the algebraic loop is solved here.
    out : ndarray
        Receives the derivative.
    """
    z, dp1, dp2, sdd = table_rates(
        pa, xt[IX_X], xt[IX_V], xt[IX_P1], xt[IX_P2], xt[IX_S], xt[IX_SD], current, w_state, w_feed
    )
    out[IX_X] = xt[IX_V]
    out[IX_V] = z
    out[IX_P1] = dp1
    out[IX_P2] = dp2
    out[IX_S] = xt[IX_SD]
    out[IX_SD] = sdd
    return z


@njit(cache=True, inline="always", error_model="numpy")
def valve_command(pa, u, x_prev, dp_prev):
    """Digital hydraulic loop of Section 4.3.4 [V], limited to +-valve_command_limit.

    ``u`` [in] is the position command of this loop, ``x_prev`` [in] and
    ``dp_prev`` [psi] the measurements of the previous loop; the displacement
    enters through the sensor's gain g (``output_gain``, 1 in the report):
    ``u_v = K_e (u - g x) - K_p dP``.
    """
    uv = pa[PA_KE] * (u - pa[PA_GOUT] * x_prev) - pa[PA_KP] * dp_prev
    lim = pa[PA_UVMAX]
    return min(max(uv, -lim), lim)
