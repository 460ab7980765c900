"""The linear model of a sensor channel (anti-alias filter x converter delay) and of the fed-back force.

A channel of :class:`~impedance_mil.specimens.sensors.Sensor` reads its
true value through its Butterworth anti-alias filter ``F(s)``
(:meth:`~impedance_mil.specimens.sensors.Sensor.anti_alias_filter`) and its
converter delay ``tau`` (``delay_s``): ``S(s) = F(s) e^{-s tau}``.
:func:`channel_response` gives it exactly at given frequencies;
:func:`channel_transfer_function` as a rational function, the delay by its
Pade approximation of a stated order (for poles).

The controller feeds back a force measured through such channels: with
``w_m = S_w(s) w`` the controlled impedance of Eq 6-5 becomes
``H_c = H_zw + H_zu H_wu S_w`` (the table feels the true force, the
controller the measured one).  :func:`sensed_impedance` forms it and
:func:`force_channel` finds ``S_w`` of a suite for the feedback ``lc``
(the load cells' weighted sum) or ``fe`` (``m_st z - A_p dP``, a channel
model only when the accelerometer and the dP cell have the same dynamics).
"""

from __future__ import annotations

import numpy as np

from ..errors import ConfigError
from ..lazy import LazyModule
from ..plant.linear import DEFAULT_PADE_ORDER, MAX_PADE_ORDER
from ..specimens.sensors import Sensor, SensorSuite
from ..systems import TransferFunction
from ..units import TWO_PI
from .constraints import ControlledTable

#: python-control, imported on first use (issue 16, start-up).
control = LazyModule("control")


def has_dynamics(sensor: Sensor) -> bool:
    """The channel has an anti-alias filter or a converter delay."""
    return sensor.bandwidth_hz is not None or sensor.delay_s > 0


def channel_response(sensor: Sensor, f_hz) -> np.ndarray:
    """Exact frequency response ``F(j w) e^{-j w tau}`` [-] of the channel at ``f_hz`` [Hz]."""
    f = np.asarray(f_hz, dtype=float)
    lp = sensor.anti_alias_filter()
    filt = np.ones(f.shape, complex) if lp is None else np.asarray(lp.frequency_response(f)).reshape(f.shape)
    return filt * np.exp(-1j * TWO_PI * f * sensor.delay_s)


def channel_transfer_function(sensor: Sensor, pade_order: int = DEFAULT_PADE_ORDER) -> TransferFunction:
    """``F(s)`` times the Pade approximation of order ``pade_order`` of ``e^{-s tau}`` (unit DC gain).

    Parameters
    ----------
    sensor : Sensor
        The channel (``bandwidth_hz``, ``filter_order``, ``delay_s`` [s]).
    pade_order : int
        Order of the delay's Pade approximation, 1 ... 10 (default 6: its
        phase error is below 1e-6 rad up to ``w tau`` = 1).

    Examples
    --------
    >>> s = Sensor("lc", "interface_force", "lbf", 200.0, bandwidth_hz=100.0, filter_order=1)
    >>> channel_transfer_function(s).den
    array([  1.        , 628.31853072])
    """
    if isinstance(pade_order, bool) or pade_order not in range(1, MAX_PADE_ORDER + 1):
        raise ConfigError("pade_order", f"a whole number from 1 to {MAX_PADE_ORDER}", pade_order)
    lp = sensor.anti_alias_filter()
    tf = TransferFunction.constant(1.0) if lp is None else TransferFunction.from_lti(lp)
    if sensor.delay_s > 0:
        num, den = control.pade(sensor.delay_s, pade_order)
        tf = tf * TransferFunction(np.asarray(num, float), np.asarray(den, float))
    return tf


def force_channel(
    suite: SensorSuite, feedback: str, pade_order: int = DEFAULT_PADE_ORDER
) -> TransferFunction | None:
    """``S_w(s)``, the measured over the true fed-back force; None when its channels have no dynamics.

    ``lc``: ``w_LC = sum_i sign(g_i) reading_i`` with reading_i = ``S_i g_i w``,
    so ``S_w = sum_i |g_i| S_i`` (the shares sum to 1 for a complete set).
    ``fe``: ``w_FE = m_st z_m - A_p dP_m`` is ``S w`` when the accelerometer
    and the dP cell share ``S``; otherwise no single channel model exists and
    a ConfigError says so.
    """
    if feedback == "lc":
        cells = [s for s in suite.sensors if s.quantity == "interface_force"]
        if not any(has_dynamics(s) for s in cells):
            return None
        # cells of the same dynamics are summed by their shares first (one term per kind of cell)
        shares: dict[tuple, float] = {}
        kinds: dict[tuple, Sensor] = {}
        for s in cells:
            kind = (s.bandwidth_hz, s.filter_order if s.bandwidth_hz is not None else None, s.delay_s)
            shares[kind] = shares.get(kind, 0.0) + abs(s.gain)
            kinds.setdefault(kind, s)
        terms = [channel_transfer_function(kinds[k], pade_order) * share for k, share in shares.items()]
        total = terms[0]
        for term in terms[1:]:
            total = total + term
        return total
    if feedback == "fe":
        z = next(s for s in suite.sensors if s.quantity == "table_acceleration")
        dp = next(s for s in suite.sensors if s.quantity == "differential_pressure")
        if not (has_dynamics(z) or has_dynamics(dp)):
            return None
        same = (z.bandwidth_hz, z.filter_order, z.delay_s) == (dp.bandwidth_hz, dp.filter_order, dp.delay_s)
        if not same:
            raise ConfigError(
                "sensors",
                f"the same filter and delay on {z.name} and {dp.name} for a linear model of w_FE",
            )
        return channel_transfer_function(z, pade_order)
    raise ConfigError("feedback", "'lc' or 'fe'", feedback)


def sensed_impedance(ct: ControlledTable, force_sensor: TransferFunction | None) -> TransferFunction:
    """``H_c = H_zw + H_zu H_wu S_w`` [in/s**2 per lbf]: the controller sees the force through ``S_w``.

    ``force_sensor`` None gives ``ct.H_c`` itself (the channels are ideal).
    """
    if force_sensor is None:
        return ct.H_c
    return (ct.H_zw_st + ct.H_zu_st.mul_cancel(ct.H_wu * force_sensor)).minreal()
