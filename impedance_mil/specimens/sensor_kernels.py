"""Compiled measurement of the sensors (numba): the kernels the lab loop reads the plant with.

Split from :mod:`impedance_mil.specimens.sensors` (the :class:`~impedance_mil.specimens.sensors.Sensor`
and :class:`~impedance_mil.specimens.sensors.SensorSuite` objects, with the plain-numpy
reference :meth:`~impedance_mil.specimens.sensors.SensorSuite.measure`), which re-exports these
names: describing a lab's sensors does not import numba (issue 16, start-up).
"""

from __future__ import annotations

import math

import numba


@numba.njit(cache=True, inline="always")
def measure_kernel(
    quantities, draws, quantity_index, gain, scale, offset, noise_rms, lsb, v_low, v_high, out
):
    """Compiled measurement of one sample of every channel (same maths as :meth:`SensorSuite.measure`).

    Parameters
    ----------
    quantities : ndarray, (5,)
        True [z (in/s**2), x_st (in), dP (psi), actuator force (lbf), w (lbf)],
        the order of :data:`QUANTITIES`.
    draws : ndarray, (n_channels,)
        Standard-normal numbers from a seeded Generator (:meth:`SensorSuite.draw_noise`).
    quantity_index, gain, scale, offset, noise_rms, lsb, v_low, v_high : ndarray
        The arrays of a :class:`SensorSuite`.
    out : ndarray, (n_channels,)
        Receives the readings in physical units.

    Returns
    -------
    ndarray
        ``out``.
    """
    for i in range(out.size):
        out[i] = read_channel(
            gain[i] * quantities[quantity_index[i]],
            draws[i],
            scale[i],
            offset[i],
            noise_rms[i],
            lsb[i],
            v_low[i],
            v_high[i],
        )
    return out


@numba.njit(cache=True, inline="always")
def read_channel(value, draw, scale, offset, noise_rms, lsb, v_low, v_high):
    """Compiled reading of one channel [unit] for its analog ``value`` [unit] (before noise).

    ``draw`` is the channel's standard-normal number; the other arguments are
    the channel's entries of the :class:`SensorSuite` arrays.  Noise, the
    converter's rounding and its limits, as :meth:`SensorSuite.measure`.
    """
    volts = (value - offset) / scale + noise_rms * draw
    volts = math.floor(volts / lsb + 0.5) * lsb
    volts = min(max(volts, v_low), v_high)
    return scale * volts + offset


@numba.njit(cache=True, inline="always")
def load_cell_force_kernel(readings, load_cell_weights):
    """Compiled ``w_LC`` [lbf]: ``sum(load_cell_weights * readings)``."""
    total = 0.0
    for i in range(readings.size):
        total += load_cell_weights[i] * readings[i]
    return total


@numba.njit(cache=True, inline="always")
def force_from_equilibrium(table_acceleration, differential_pressure, table_mass, piston_area):
    """``w_FE = m_st z - A_p dP`` [lbf] (Eq 4-7b, Section 8.3.2); compiled, takes floats or arrays.

    Parameters
    ----------
    table_acceleration : float or ndarray
        Measured table acceleration z [in/s**2].
    differential_pressure : float or ndarray
        Measured dP [psi].
    table_mass : float
        Moving mass of the table m_st [lbf*s**2/in] (4.14, Table 4.1).
    piston_area : float
        Actuator piston area A_p [in**2] (2.1, Table 4.1).

    Notes
    -----
    Appendix C prints ``w_FE = A_p dP - m_st z_exp``, the negative of this
    (the force the table applies on the specimen); see docs/errata.md.
    """
    return table_mass * table_acceleration - piston_area * differential_pressure
