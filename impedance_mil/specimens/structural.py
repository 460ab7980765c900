"""Structural test articles: a rigid mass and a general linear MDOF system.

Both return the interface force ``w`` [lbf] that the specimen applies on the
table, for a given absolute table acceleration ``z`` [in/s**2] (report
Eq 4-7b sign: ``m_st * z = A_p * dP + w``; a rigid mass gives ``w = -m z``).

For an MDOF specimen with relative displacements ``u`` [in] of its degrees
of freedom, influence vector ``r`` and base mass ``m_b``::

    M u'' + C u' + K u = -M r z
    w = -r^T M (u'' + r z) - m_b z = r^T (K u + C u') - m_b z

that is, ``w`` is the base shear of the structure minus the inertia of the
rigidly attached base mass.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from ..errors import ConfigError
from ..systems import TransferFunction
from ..units import G0, TWO_PI, weight_to_mass
from .statespace import SpecimenStateSpace

#: Relative tolerance for symmetry and definiteness checks of M, C, K.
MATRIX_RTOL = 1e-9


class Specimen:
    """Behaviour shared by every test article; subclasses define :meth:`state_space`."""

    @property
    def total_mass(self) -> float:  # pragma: no cover - overridden
        """Total mass [lbf*s**2/in]."""
        raise NotImplementedError

    @property
    def total_weight(self) -> float:
        """Total weight [lbf]."""
        return self.total_mass * G0

    def state_space(self) -> SpecimenStateSpace:  # pragma: no cover - overridden
        """State space with input ``z`` [in/s**2] and output ``w`` [lbf]."""
        raise NotImplementedError

    def impedance(self) -> TransferFunction:
        """Transfer function ``w/z`` [lbf per in/s**2] (s in rad/s).

        Tends to ``-total_mass`` as ``s -> 0``.
        """
        return self.state_space().transfer_function()

    def driving_point_impedance(self, f_hz) -> np.ndarray:
        """Force on the specimen per table velocity, ``-w / v`` [lbf*s/in], at ``f_hz`` [Hz].

        ``v = z / (j 2 pi f)``, so this is ``-H(j w) * j w``.  A passive
        specimen has a non-negative real part at every frequency.
        """
        f = np.atleast_1d(np.asarray(f_hz, dtype=float))
        return -self.state_space().frequency_response(f) * (1j * TWO_PI * f)


@dataclass(frozen=True)
class RigidMass(Specimen):
    """A rigid mass bolted to the table: ``w = -m z`` (no states).

    Parameters
    ----------
    weight_lbf : float
        Weight [lbf], > 0.

    Examples
    --------
    >>> RigidMass(1600.0).state_space().D  # doctest: +ELLIPSIS
    -4.144...
    """

    weight_lbf: float

    def __post_init__(self):
        if not (np.isfinite(self.weight_lbf) and self.weight_lbf > 0):
            raise ConfigError("weight_lbf", "a positive weight [lbf]", self.weight_lbf)

    @property
    def total_mass(self) -> float:
        return weight_to_mass(self.weight_lbf)

    def state_space(self) -> SpecimenStateSpace:
        return SpecimenStateSpace(np.zeros((0, 0)), np.zeros(0), np.zeros(0), -self.total_mass)

    def to_dict(self) -> dict:
        return {"type": "RigidMass", "weight_lbf": float(self.weight_lbf)}


@dataclass(frozen=True)
class ModalProperties:
    """Undamped modes of an MDOF specimen.

    Attributes
    ----------
    frequencies_hz : ndarray
        Natural frequencies [Hz], ascending.
    damping_ratios : ndarray
        Modal damping ratios (diagonal of ``Phi^T C Phi / (2 w)``; exact only
        for classically damped systems).
    effective_masses : ndarray
        Effective modal masses ``(phi^T M r)^2`` [lbf*s**2/in] with mass-normalised
        ``phi``; they add up to ``r^T M r``.
    shapes : ndarray, shape (n, n)
        Mass-normalised mode shapes, one per column.
    """

    frequencies_hz: np.ndarray
    damping_ratios: np.ndarray
    effective_masses: np.ndarray
    shapes: np.ndarray


def _square(name: str, value, n: int | None = None) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 1:
        arr = np.diag(arr)
    if arr.ndim != 2 or arr.shape[0] != arr.shape[1] or (n is not None and arr.shape[0] != n):
        want = f"a {n}x{n} matrix" if n is not None else "a square matrix"
        raise ConfigError(name, want, f"shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ConfigError(name, "finite entries")
    scale = max(float(np.max(np.abs(arr))), 1e-300)
    if np.max(np.abs(arr - arr.T)) > MATRIX_RTOL * scale:
        raise ConfigError(name, "a symmetric matrix")
    return 0.5 * (arr + arr.T)


def _check_definite(name: str, arr: np.ndarray, strict: bool) -> None:
    if arr.size == 0:
        return
    eig = np.linalg.eigvalsh(arr)
    floor = -MATRIX_RTOL * max(float(np.max(np.abs(eig))), 1e-300)
    if (strict and eig[0] <= 0) or eig[0] < floor:
        kind = "positive definite" if strict else "positive semi-definite"
        raise ConfigError(name, f"a {kind} matrix", f"smallest eigenvalue {eig[0]:.4g}")


def modal_damping_matrix(mass, stiffness, damping_ratios) -> np.ndarray:
    """Damping matrix [lbf*s/in] giving the stated modal damping ratios.

    ``C = M Phi diag(2 zeta_k w_k) Phi^T M`` with mass-normalised undamped
    modes ``Phi`` (Chopra, *Dynamics of Structures*, Sec. 11.4).

    Parameters
    ----------
    mass : array_like, (n,) or (n, n)
        Masses or mass matrix [lbf*s**2/in].
    stiffness : array_like, (n, n)
        Stiffness matrix [lbf/in].
    damping_ratios : float or array_like, (n,)
        Damping ratio of each mode in ascending frequency (one value for all).
    """
    M = _square("mass", mass)
    K = _square("stiffness", stiffness, M.shape[0])
    _check_definite("mass", M, strict=True)
    _check_definite("stiffness", K, strict=True)
    zeta = np.broadcast_to(np.asarray(damping_ratios, dtype=float), (M.shape[0],))
    if np.any(~np.isfinite(zeta)) or np.any(zeta < 0):
        raise ConfigError("damping_ratios", "non-negative ratios", damping_ratios)
    lam, phi = scipy.linalg.eigh(K, M)
    omega = np.sqrt(lam)
    Mphi = M @ phi
    return Mphi @ np.diag(2.0 * zeta * omega) @ Mphi.T


@dataclass(frozen=True, eq=False)
class LinearMDOF(Specimen):
    """A linear multi-degree-of-freedom test article on the table.

    Parameters
    ----------
    mass : array_like, (n,) or (n, n)
        Lumped masses or mass matrix [lbf*s**2/in], positive definite.
    stiffness : array_like, (n, n)
        Stiffness matrix [lbf/in] of the DOFs relative to the table,
        positive definite (the specimen is attached to the table).
    damping : array_like, (n, n)
        Viscous damping matrix [lbf*s/in], positive semi-definite.  Use
        :meth:`with_modal_damping` to give modal damping ratios instead.
    influence : array_like, (n,), optional
        Displacement of each DOF for a unit table displacement (default: ones,
        every DOF horizontal in the shaking direction).
    base_mass : float, optional
        Mass rigidly attached to the table [lbf*s**2/in] (default 0).

    Notes
    -----
    States are ``x = [u, u']`` (relative displacements [in], velocities [in/s]).
    """

    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    influence: np.ndarray = field(default=None)
    base_mass: float = 0.0

    def __post_init__(self):
        M = _square("mass", self.mass)
        n = M.shape[0]
        K = _square("stiffness", self.stiffness, n)
        C = _square("damping", self.damping, n)
        _check_definite("mass", M, strict=True)
        _check_definite("stiffness", K, strict=True)
        _check_definite("damping", C, strict=False)
        r = np.ones(n) if self.influence is None else np.asarray(self.influence, dtype=float).ravel()
        if r.size != n or not np.all(np.isfinite(r)):
            raise ConfigError("influence", f"{n} finite numbers", self.influence)
        if not (np.isfinite(self.base_mass) and self.base_mass >= 0):
            raise ConfigError("base_mass", "a non-negative mass [lbf*s**2/in]", self.base_mass)
        for name, arr in (("mass", M), ("stiffness", K), ("damping", C), ("influence", r)):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        object.__setattr__(self, "base_mass", float(self.base_mass))

    # ------------------------------------------------------------ builders
    @classmethod
    def with_modal_damping(
        cls, mass, stiffness, damping_ratios, influence=None, base_mass: float = 0.0
    ) -> LinearMDOF:
        """Build from modal damping ratios (see :func:`modal_damping_matrix`)."""
        C = modal_damping_matrix(mass, stiffness, damping_ratios)
        return cls(mass, stiffness, C, influence, base_mass)

    @classmethod
    def shear_building(
        cls, story_weights_lbf, story_stiffness, damping_ratios, base_weight_lbf: float = 0.0
    ) -> LinearMDOF:
        """A shear building on the table, floors numbered from the bottom.

        Parameters
        ----------
        story_weights_lbf : array_like, (n,)
            Floor weights [lbf], bottom first.
        story_stiffness : array_like, (n,)
            Lateral stiffness of each story [lbf/in]; story ``i`` connects
            floor ``i`` to the floor below (story 0 to the table).
        damping_ratios : float or array_like, (n,)
            Modal damping ratios.
        base_weight_lbf : float, optional
            Weight rigidly attached to the table [lbf] (base slab).
        """
        w = np.asarray(story_weights_lbf, dtype=float).ravel()
        k = np.asarray(story_stiffness, dtype=float).ravel()
        if w.size == 0 or np.any(~(w > 0)):
            raise ConfigError("story_weights_lbf", "positive weights [lbf]", story_weights_lbf)
        if k.size != w.size or np.any(~(k > 0)):
            raise ConfigError("story_stiffness", f"{w.size} positive stiffnesses [lbf/in]", story_stiffness)
        k_above = np.append(k[1:], 0.0)
        K = np.diag(k + k_above) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
        return cls.with_modal_damping(
            weight_to_mass(w), K, damping_ratios, base_mass=weight_to_mass(base_weight_lbf)
        )

    # ---------------------------------------------------------- properties
    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom."""
        return self.mass.shape[0]

    @property
    def total_mass(self) -> float:
        """Mass moving with the table at low frequency, ``r^T M r + m_b`` [lbf*s**2/in]."""
        return float(self.influence @ self.mass @ self.influence) + self.base_mass

    def modes(self) -> ModalProperties:
        """Undamped modes, their damping ratios and effective masses."""
        lam, phi = scipy.linalg.eigh(self.stiffness, self.mass)
        omega = np.sqrt(lam)
        zeta = np.diag(phi.T @ self.damping @ phi) / (2.0 * omega)
        gamma = phi.T @ self.mass @ self.influence
        return ModalProperties(omega / TWO_PI, zeta, gamma**2, phi)

    def state_space(self) -> SpecimenStateSpace:
        n = self.n_dof
        Minv_K = np.linalg.solve(self.mass, self.stiffness)
        Minv_C = np.linalg.solve(self.mass, self.damping)
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv_K, -Minv_C]])
        B = np.concatenate([np.zeros(n), -self.influence])
        C = np.concatenate([self.influence @ self.stiffness, self.influence @ self.damping])
        return SpecimenStateSpace(A, B, C, -self.base_mass)

    def to_dict(self) -> dict:
        return {
            "type": "LinearMDOF",
            "mass": self.mass.tolist(),
            "stiffness": self.stiffness.tolist(),
            "damping": self.damping.tolist(),
            "influence": self.influence.tolist(),
            "base_mass": self.base_mass,
        }
