"""The fluid-filled cylindrical vessel of report Section 3.2.

Hydrodynamic model: Eurocode 8 Part 4 (EN 1998-4:2006), Annex A, for a
ground-supported vertical cylindrical tank, which follows the exact
potential-flow solution of Veletsos & Yang (1977) and Veletsos (1984):

* **Convective (sloshing) modes** (EN 1998-4 A.2.1.3), ``n = 1, 2, ...``::

      omega_n**2 = g * lambda_n / R * tanh(lambda_n * gamma)
      m_cn / m   = 2 * tanh(lambda_n * gamma) / (gamma * lambda_n * (lambda_n**2 - 1))

  with ``gamma = H / R``, ``R`` the inner radius, ``H`` the liquid depth,
  ``m`` the liquid mass and ``lambda_n`` the roots of ``J1'(lambda) = 0``
  (1.8412, 5.3314, 8.5363, ...).

* **Impulsive mass** of the rigid tank (EN 1998-4 A.2.1.2)::

      m_i / m = 2 * gamma * sum_{n>=0} I1(nu_n / gamma) / (nu_n**3 * I1'(nu_n / gamma)),
      nu_n = (2n + 1) * pi / 2

  The impulsive and all convective masses add up to ``m`` exactly.

* **Flexible-wall impulsive mode** (EN 1998-4 A.3.2.2, the simplified
  procedure of Malhotra, Wenk & Wieland 2000)::

      T_imp = C_i * H * sqrt(rho) / sqrt(E * s / R)

  with ``C_i`` from their Table 1 (EN 1998-4 Table A.2), ``s`` the wall
  thickness and ``E`` the steel modulus.  For this vessel it lies between
  about 190 Hz (42 in of water) and 400 Hz (18 in), consistent with the
  report's footnote 21 (Section 6): "the dominant horizontal frequencies of
  the fluid-filled vessel considered herein are greater than 60 Hz".

* **Damping**: 0.5 % for sloshing and 2 % for the impulsive mode of a steel
  tank, the values used by Malhotra et al. (2000) and EN 1998-4 A.3.2.2.

The specimen is a set of parallel single-degree-of-freedom oscillators on a
rigid base mass (dry steel, plus whatever is not in an oscillator), built
as a :class:`~impedance_mil.specimens.structural.LinearMDOF`.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from functools import lru_cache

import numpy as np
import scipy.special

from ..errors import ConfigError
from ..report_config import report_config
from ..units import G0, TWO_PI, weight_to_mass
from .statespace import SpecimenStateSpace
from .structural import LinearMDOF, Specimen

#: Unit weight of fresh water [lbf/in**3] (62.4 lbf/ft**3; the report gives none).
WATER_UNIT_WEIGHT = 62.4 / 1728.0

#: Young's modulus of carbon steel [psi].
STEEL_MODULUS = 29.0e6

#: Number of terms of the impulsive-mass series (truncation error < 1e-8 of m).
_IMPULSIVE_TERMS = 20000

#: Malhotra et al. (2000) Table 1 / EN 1998-4 Table A.2: H/R and C_i [-].
_MALHOTRA_H_OVER_R = np.array([0.3, 0.5, 0.7, 1.0, 1.5, 2.0, 2.5, 3.0])
_MALHOTRA_CI = np.array([9.28, 7.74, 6.97, 6.36, 6.06, 6.21, 6.56, 7.03])


def convective_roots(n_modes: int) -> np.ndarray:
    """First ``n_modes`` roots ``lambda_n`` of ``J1'(lambda) = 0`` (1.8412, 5.3314, ...)."""
    return scipy.special.jnp_zeros(1, n_modes)


def convective_mass_ratios(gamma: float, n_modes: int) -> np.ndarray:
    """Convective masses ``m_cn / m`` of the first modes (EN 1998-4 Eq A.12).

    Parameters
    ----------
    gamma : float
        Liquid depth over inner radius, ``H / R`` [-], > 0.
    n_modes : int
        Number of modes.
    """
    lam = convective_roots(n_modes)
    return 2.0 * np.tanh(lam * gamma) / (gamma * lam * (lam**2 - 1.0))


def convective_frequencies_hz(radius_in: float, depth_in: float, n_modes: int) -> np.ndarray:
    """Sloshing frequencies [Hz] (EN 1998-4 Eq A.11), ``g`` = :data:`~impedance_mil.units.G0`.

    Parameters
    ----------
    radius_in : float
        Inner radius of the tank [in].
    depth_in : float
        Liquid depth [in], > 0.
    n_modes : int
        Number of modes.
    """
    lam = convective_roots(n_modes)
    omega2 = G0 * lam / radius_in * np.tanh(lam * depth_in / radius_in)
    return np.sqrt(omega2) / TWO_PI


@lru_cache(maxsize=256)
def impulsive_mass_ratio(gamma: float) -> float:
    """Impulsive mass of a rigid tank over the liquid mass, ``m_i / m`` (EN 1998-4 Eq A.6).

    Parameters
    ----------
    gamma : float
        Liquid depth over inner radius, ``H / R`` [-], >= 0.

    Notes
    -----
    The series takes ~5 ms (20 000 Bessel-function terms) and a vessel asks
    for it several times per :meth:`FluidVessel.state_space` /
    :meth:`FluidVessel.to_dict`, so results are memoized per ``gamma``
    (a pure function of one float: the cache changes no result).
    """
    if gamma <= 0.0:
        return 0.0
    nu = (2.0 * np.arange(_IMPULSIVE_TERMS) + 1.0) * np.pi / 2.0
    x = nu / gamma
    i0 = scipy.special.ive(0, x)  # exponentially scaled: the ratio below is unaffected
    i1 = scipy.special.ive(1, x)
    ratio = i1 / (i0 - i1 / x)  # I1(x) / I1'(x), with I1' = I0 - I1/x
    return float(2.0 * gamma * np.sum(ratio / nu**3))


def malhotra_ci(gamma: float) -> float:
    """Coefficient ``C_i`` of the impulsive period (Malhotra et al. 2000, Table 1).

    Linear interpolation in ``H/R``; outside the tabulated range 0.3-3.0 the
    nearest end value is used (below 0.3 the impulsive mass is < 18 % of the
    liquid and its frequency is far above the band of interest).
    """
    return float(np.interp(gamma, _MALHOTRA_H_OVER_R, _MALHOTRA_CI))


def flexible_impulsive_frequency_hz(
    depth_in: float, radius_in: float, thickness_in: float, liquid_density: float, modulus_psi: float
) -> float:
    """Frequency [Hz] of the flexible-wall impulsive mode (EN 1998-4 A.3.2.2).

    ``T_imp = C_i * H * sqrt(rho) / sqrt(E * s / R)`` (Malhotra et al. 2000).

    Parameters
    ----------
    depth_in : float
        Liquid depth ``H`` [in], > 0.
    radius_in : float
        Tank radius ``R`` [in].
    thickness_in : float
        Wall thickness ``s`` [in].
    liquid_density : float
        Mass density of the liquid [lbf*s**2/in**4].
    modulus_psi : float
        Young's modulus of the wall [psi].
    """
    ci = malhotra_ci(depth_in / radius_in)
    period = ci * depth_in * np.sqrt(liquid_density) / np.sqrt(modulus_psi * thickness_in / radius_in)
    return float(1.0 / period)


@dataclass(frozen=True)
class Oscillator:
    """One hydrodynamic component acting as a base-excited SDOF oscillator.

    Attributes
    ----------
    name : str
        ``"convective-1"``, ``"convective-2"``, ... or ``"impulsive-flexible"``.
    mass : float
        Modal mass [lbf*s**2/in].
    frequency_hz : float
        Natural frequency [Hz].
    damping_ratio : float
        Viscous damping ratio [-].
    """

    name: str
    mass: float
    frequency_hz: float
    damping_ratio: float


@dataclass(frozen=True)
class FluidVessel(Specimen):
    """The water-filled steel vessel of report Section 3.2 (48 in OD, 3/16 in wall, 48 in tall).

    Parameters
    ----------
    water_depth_in : float
        Depth of water [in], 0 to ``height_in`` (the report tests 0, 18, 30,
        36 and 42 in).
    outer_diameter_in : float
        Outside diameter of the shell [in] (48, Section 3.2).
    wall_thickness_in : float
        Shell thickness [in] (3/16, Section 3.2).
    height_in : float
        Height of the shell [in] (48, Section 3.2).
    dry_weight_lbf : float
        Weight of the empty vessel with flange, head and base plate [lbf]
        ("approximately 1200 lb", Section 8.2; see docs/errata.md for the
        1.25 kip of Section 3.2).
    water_unit_weight : float
        Unit weight of the liquid [lbf/in**3] (fresh water, 62.4 lbf/ft**3).
    n_convective_modes : int
        Number of sloshing modes kept as oscillators (>= 1); the mass of the
        higher modes moves with the rigid base.
    convective_damping : float
        Damping ratio of the sloshing modes [-] (0.005).
    impulsive_damping : float
        Damping ratio of the flexible-wall impulsive mode [-] (0.02).
    flexible_impulsive_fraction : float
        Share of the impulsive liquid mass that moves on the flexible-wall
        mode (1.0, as in Malhotra et al. 2000); the rest is rigid on the base.
    steel_modulus_psi : float
        Young's modulus of the shell [psi].
    impulsive_frequency_hz : float or None
        Override of the flexible-wall impulsive frequency [Hz]; ``None`` uses
        :func:`flexible_impulsive_frequency_hz`.

    Examples
    --------
    >>> v = FluidVessel.report_default()
    >>> round(v.convective_modes()[0].frequency_hz, 2)
    0.87
    """

    water_depth_in: float
    outer_diameter_in: float = 48.0
    wall_thickness_in: float = 3.0 / 16.0
    height_in: float = 48.0
    dry_weight_lbf: float = 1200.0
    water_unit_weight: float = WATER_UNIT_WEIGHT
    n_convective_modes: int = 3
    convective_damping: float = 0.005
    impulsive_damping: float = 0.02
    flexible_impulsive_fraction: float = 1.0
    steel_modulus_psi: float = STEEL_MODULUS
    impulsive_frequency_hz: float | None = None

    def __post_init__(self):
        positive = (
            "outer_diameter_in",
            "height_in",
            "dry_weight_lbf",
            "water_unit_weight",
            "steel_modulus_psi",
            "convective_damping",
            "impulsive_damping",
        )
        for key in positive:
            value = getattr(self, key)
            if not (np.isfinite(value) and value > 0):
                raise ConfigError(key, "a positive number", value)
        if not (0 < self.wall_thickness_in < 0.5 * self.outer_diameter_in):
            raise ConfigError(
                "wall_thickness_in", "0 < thickness < outer radius [in]", self.wall_thickness_in
            )
        if not (np.isfinite(self.water_depth_in) and 0 <= self.water_depth_in <= self.height_in):
            raise ConfigError("water_depth_in", f"a depth from 0 to {self.height_in} in", self.water_depth_in)
        if int(self.n_convective_modes) != self.n_convective_modes or self.n_convective_modes < 1:
            raise ConfigError("n_convective_modes", "an integer >= 1", self.n_convective_modes)
        if not 0 <= self.flexible_impulsive_fraction <= 1:
            raise ConfigError(
                "flexible_impulsive_fraction", "a fraction from 0 to 1", self.flexible_impulsive_fraction
            )
        f_imp = self.impulsive_frequency_hz
        if f_imp is not None and not (np.isfinite(f_imp) and f_imp > 0):
            raise ConfigError("impulsive_frequency_hz", "a positive frequency [Hz] or None", f_imp)

    @classmethod
    def report_default(cls, **overrides) -> FluidVessel:
        """The vessel of the MIL experiments: 36 in of water (Section 3.2; the report's setup file)."""
        return cls(**{"water_depth_in": report_config().specimen.water_depth_in, **overrides})

    # ------------------------------------------------------------ geometry
    @property
    def inner_radius_in(self) -> float:
        """Inner radius ``R`` [in]."""
        return 0.5 * self.outer_diameter_in - self.wall_thickness_in

    @property
    def water_weight_lbf(self) -> float:
        """Weight of the water [lbf]."""
        return np.pi * self.inner_radius_in**2 * self.water_depth_in * self.water_unit_weight

    @property
    def liquid_mass(self) -> float:
        """Mass of the water [lbf*s**2/in]."""
        return weight_to_mass(self.water_weight_lbf)

    @property
    def total_mass(self) -> float:
        return weight_to_mass(self.dry_weight_lbf) + self.liquid_mass

    @property
    def depth_ratio(self) -> float:
        """``gamma = H / R`` [-]."""
        return self.water_depth_in / self.inner_radius_in

    # ------------------------------------------------------- hydrodynamics
    @property
    def impulsive_mass(self) -> float:
        """Impulsive liquid mass of the rigid tank ``m_i`` [lbf*s**2/in]."""
        return impulsive_mass_ratio(self.depth_ratio) * self.liquid_mass

    def convective_modes(self) -> tuple[Oscillator, ...]:
        """The sloshing oscillators kept in the model (empty for an empty vessel)."""
        if self.water_depth_in == 0:
            return ()
        n = int(self.n_convective_modes)
        masses = convective_mass_ratios(self.depth_ratio, n) * self.liquid_mass
        freqs = convective_frequencies_hz(self.inner_radius_in, self.water_depth_in, n)
        return tuple(
            Oscillator(f"convective-{k + 1}", float(m), float(f), self.convective_damping)
            for k, (m, f) in enumerate(zip(masses, freqs))
        )

    def flexible_impulsive_mode(self) -> Oscillator | None:
        """The flexible-wall impulsive oscillator, or ``None`` without water."""
        mass = self.flexible_impulsive_fraction * self.impulsive_mass
        if self.water_depth_in == 0 or mass == 0:
            return None
        freq = self.impulsive_frequency_hz
        if freq is None:
            freq = flexible_impulsive_frequency_hz(
                self.water_depth_in,
                self.inner_radius_in,
                self.wall_thickness_in,
                self.water_unit_weight / G0,
                self.steel_modulus_psi,
            )
        return Oscillator("impulsive-flexible", mass, float(freq), self.impulsive_damping)

    def oscillators(self) -> tuple[Oscillator, ...]:
        """Every oscillator of the model: sloshing modes, then the flexible impulsive mode.

        Computed once per distinct vessel (the result is an immutable tuple).
        """
        return _oscillators(self)

    @property
    def rigid_mass(self) -> float:
        """Mass moving rigidly with the table [lbf*s**2/in].

        Dry steel, the impulsive liquid not on the flexible mode, and the
        convective mass of the sloshing modes not kept as oscillators.
        """
        return self.total_mass - sum(o.mass for o in self.oscillators())

    def as_mdof(self) -> LinearMDOF:
        """The vessel as parallel oscillators on a rigid base mass."""
        osc = self.oscillators()
        m = np.array([o.mass for o in osc])
        omega = TWO_PI * np.array([o.frequency_hz for o in osc])
        zeta = np.array([o.damping_ratio for o in osc])
        return LinearMDOF(m, m * omega**2, 2.0 * zeta * m * omega, base_mass=self.rigid_mass)

    def state_space(self) -> SpecimenStateSpace:
        """States: relative displacements then velocities of :meth:`oscillators` [in, in/s].

        Computed once per distinct vessel (the state space is immutable: its
        arrays are read-only), so repeated simulations do not rebuild it.
        """
        return _state_space(self)

    def to_dict(self) -> dict:
        params = {k: getattr(self, k) for k in self.__dataclass_fields__}
        return {
            "type": "FluidVessel",
            **params,
            "total_weight_lbf": self.total_weight,
            "rigid_mass": self.rigid_mass,
            "oscillators": [asdict(o) for o in self.oscillators()],
        }


# The vessel is a frozen value object (hashable, equal by its fields) and its
# oscillators and state space are immutable, so they are memoized per vessel:
# every simulate() call asks for them and building them takes milliseconds.
@lru_cache(maxsize=64)
def _oscillators(vessel: FluidVessel) -> tuple[Oscillator, ...]:
    flex = vessel.flexible_impulsive_mode()
    return vessel.convective_modes() + ((flex,) if flex is not None else ())


@lru_cache(maxsize=64)
def _state_space(vessel: FluidVessel) -> SpecimenStateSpace:
    if not vessel.oscillators():
        return SpecimenStateSpace(np.zeros((0, 0)), np.zeros(0), np.zeros(0), -vessel.total_mass)
    return vessel.as_mdof().state_space()
