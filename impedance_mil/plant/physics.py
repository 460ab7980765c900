"""Physical formulas of the shake-table model (report Eq 4-10a/b, 4-12) and the servovalve's dynamics.

Pure functions of values in the report's units (:mod:`impedance_mil.units`);
:mod:`impedance_mil.plant.parameters` reads table files with them, and
:mod:`impedance_mil.plant.nonlinear` builds the virtual table's valve from
:class:`ValveDynamics`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def oil_column_frequency(bulk_modulus: float, piston_area: float, mass: float, mid_stroke: float) -> float:
    """Oil-column angular frequency, Eq 4-10a: ``sqrt(2 A_p kappa / (m_st x_m))``.

    Parameters
    ----------
    bulk_modulus : float
        Oil bulk modulus kappa [psi].
    piston_area : float
        Piston area A_p [in^2].
    mass : float
        Moving table mass m_st [lbf*s^2/in].
    mid_stroke : float
        Mid-stroke position x_m [in].

    Returns
    -------
    float
        omega_oil [rad/s].

    Examples
    --------
    >>> round(oil_column_frequency(1e5, 2.1, 4.14, 3.2), 1)  # report: 178 rad/s
    178.1
    """
    return math.sqrt(2.0 * piston_area * bulk_modulus / (mass * mid_stroke))


def bulk_modulus_from_frequency(
    omega_oil: float, piston_area: float, mass: float, mid_stroke: float
) -> float:
    """Bulk modulus kappa [psi] that gives ``omega_oil`` [rad/s] (Eq 4-10a inverted)."""
    return omega_oil**2 * mass * mid_stroke / (2.0 * piston_area)


def oil_column_damping(
    leakage_coefficient: float, bulk_modulus: float, piston_area: float, mass: float, mid_stroke: float
) -> float:
    """Oil-column damping ratio, Eq 4-10b: ``K_l sqrt(m_st kappa / (2 A_p^3 x_m))``.

    Parameters
    ----------
    leakage_coefficient : float
        Leakage (flow-pressure) coefficient K_l [in^3/s/psi].
    bulk_modulus, piston_area, mass, mid_stroke : float
        kappa [psi], A_p [in^2], m_st [lbf*s^2/in], x_m [in], as for :func:`oil_column_frequency`.

    Returns
    -------
    float
        zeta_oil [-].
    """
    return leakage_coefficient * math.sqrt(mass * bulk_modulus / (2.0 * piston_area**3 * mid_stroke))


def model_constant_d(
    bulk_modulus: float,
    piston_area: float,
    mid_stroke: float,
    orifice_coefficient: float,
    supply_pressure: float,
    fluid_density: float,
    valve_flow_gain: float,
    spool_flow_gain: float,
) -> float:
    """Model constant d of Eq 4-11, from Eq 4-12 (as corrected in docs/errata.md).

    ``d = 2 kappa / (A_p x_m) * C_d G sqrt(P_S / rho) * K_r / K_s``: the
    pressure-rate gain of Eq 4-9 per inch of spool times the spool travel
    per mA of Eq 4-2/4-3.  (The report prints ``K_r/K_s`` under the square
    root, which is dimensionally inconsistent.)

    Parameters
    ----------
    bulk_modulus : float
        kappa [psi].
    piston_area : float
        A_p [in^2].
    mid_stroke : float
        x_m [in].
    orifice_coefficient : float
        C_d G at null, discharge coefficient times area gradient [in].
    supply_pressure : float
        P_S [psi].
    fluid_density : float
        rho [lbf*s^2/in^4].
    valve_flow_gain : float
        K_r = Q_max / u_i,max [in^3/s/mA].
    spool_flow_gain : float
        K_s, flow per spool travel [in^2/s].

    Returns
    -------
    float
        d [psi/(s*mA)].
    """
    pressure_rate_per_spool = (
        2.0
        * bulk_modulus
        / (piston_area * mid_stroke)
        * orifice_coefficient
        * math.sqrt(supply_pressure / fluid_density)
    )
    return pressure_rate_per_spool * valve_flow_gain / spool_flow_gain


def flow_gain_d(
    omega_oil: float,
    mass: float,
    piston_area: float,
    rated_flow: float,
    rated_current: float,
    rated_pressure_drop: float,
    supply_pressure: float,
    return_pressure: float,
) -> float:
    """Model constant d [psi/(s*mA)] implied by the valve's rating and the oil column (Eq 4-12).

    The physics of :meth:`NonlinearTable.from_linear
    <impedance_mil.plant.nonlinear.NonlinearTable.from_linear>` (docs/errata.md,
    Eq 4-12) without its dead volume and laminar regularisation: the orifice
    flow gain ``K_q = Q_r / (i_r sqrt(dP_r / 2))`` (the rated drop across the
    two metering edges), linearized at rest with ``(P_S - P_R)/2`` across each
    edge, times the oil stiffness ``2 kappa / V_0 = omega_oil^2 m_st / A_p^2``
    (Eq 4-10a, ``V_0 = A_p x_m``)::

        d = omega_oil^2 m_st / A_p^2 * Q_r / i_r * sqrt((P_S - P_R) / dP_r)

    Parameters
    ----------
    omega_oil : float
        Oil-column frequency [rad/s].
    mass : float
        m_st [lbf*s^2/in].
    piston_area : float
        A_p [in^2].
    rated_flow : float
        Q_r [in^3/s] at ``rated_pressure_drop``.
    rated_current : float
        i_r [mA].
    rated_pressure_drop : float
        dP_r, the valve drop at rated flow [psi].
    supply_pressure, return_pressure : float
        P_S, P_R [psi].

    Returns
    -------
    float
        d [psi/(s*mA)].

    Examples
    --------
    >>> round(flow_gain_d(2 * math.pi * 27, 4.14, 2.1, 57.75, 25, 1000, 3000, 0) / 1e5, 3)  # report: 1e5
    1.081
    """
    stiffness = omega_oil**2 * mass / piston_area**2
    return (
        stiffness
        * rated_flow
        / rated_current
        * math.sqrt((supply_pressure - return_pressure) / rated_pressure_drop)
    )


@dataclass(frozen=True)
class ValveDynamics:
    """The servovalve as a unit-DC-gain transfer function from u_i to the spool [mA-equivalent].

    Order 2 (``"two-pole"``, Eq 4-3, and ``"second-order"``):
    ``gamma / (s^2 + delta s + gamma)``, ``gamma`` [1/s^2], ``delta`` [1/s].
    Order 1 (``"first-order"``): ``gamma / (s + gamma)``, ``gamma = 1/T`` [1/s], ``delta = 0``.

    Attributes
    ----------
    order : int
        1 or 2.
    gamma : float
        [1/s^order].
    delta : float
        [1/s] (0 for order 1).
    """

    order: int
    gamma: float
    delta: float

    def poles(self) -> np.ndarray:
        """The valve's poles [rad/s] (a complex pair for ``delta^2 < 4 gamma``)."""
        if self.order == 1:
            return np.array([-self.gamma], dtype=complex)
        return np.roots([1.0, self.delta, self.gamma]).astype(complex)
