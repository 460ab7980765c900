"""Partial-fraction basis of the optimized MIL controller (report Section 10.4, "optimization-based design").

Each controller path is a real linear combination of fixed, stable, causal
functions, so that the controlled table's impedance is affine in the
coefficients::

    C_z(s) = a_2/s**2 + a_1/s + a_0 + sum_k (terms of pole group k)
    C_w(s) = b_0 + sum_k (terms of pole group k)

A real pole ``p`` contributes ``|p|/(s - p)``; a conjugate pair
``p = -a + jb`` contributes ``|p| 2 (s + a)/((s + a)**2 + b**2)`` and
``|p| 2 b/((s + a)**2 + b**2)`` (the real and imaginary parts of the
residue).  The factors ``|p|`` make every term of unit size at low frequency.
The double integrator of ``C_z`` is that of ``1/H_zu`` (Eq 6-8a).

The filter design of Section 6.4 (third-order Butterworth at ``f_c``, Eq 6-11)
lies inside the span when the Butterworth poles at ``f_c`` are in the basis:
its partial-fraction expansion has exactly these terms, so the optimum can
never be worse than the feasible filter design.

Transfer functions are assembled from the exact poles by polynomial
products (no root finding): :meth:`PoleBasis.transfer_function`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ...errors import ConfigError
from ...systems import TransferFunction
from ...units import TWO_PI

#: Cut-offs [Hz] of the third-order Butterworth pole groups of the default basis (the study of issue 15).
DEFAULT_GROUPS_HZ = (50.0, 80.0, 120.0, 180.0, 270.0, 400.0)

#: Order of the Butterworth pole groups of the default basis (the relative degree of 1/H_zu, Eq 6-8a).
DEFAULT_GROUP_ORDER = 3

#: Relative distance below which two poles count as the same pole.
DUPLICATE_RTOL = 1e-6


def butterworth_poles(fc_hz: float, order: int = DEFAULT_GROUP_ORDER) -> np.ndarray:
    """Poles [rad/s] of the analog Butterworth low-pass of ``order`` at ``fc_hz`` [Hz] (upper half plane and real)."""
    k = np.arange(order)
    p = TWO_PI * fc_hz * np.exp(1j * np.pi * (2 * k + order + 1) / (2 * order))
    p = np.where(np.abs(p.imag) < 1e-12 * np.abs(p), p.real + 0j, p)
    return p[p.imag >= 0]


@dataclass(frozen=True)
class PoleBasis:
    """Fixed stable poles of the two controller paths.

    Parameters
    ----------
    poles : sequence of complex
        Poles [rad/s], one of each conjugate pair (``Im p >= 0``); every pole
        must be stable (``Re p < 0``) and distinct.  The same poles serve both
        paths.
    integrators : bool
        Give ``C_z`` the terms ``1/s**2`` and ``1/s`` (the double integrator
        of ``1/H_zu``, Eq 6-8a); needed for exact DC tracking.
    max_hz : float, optional
        Highest pole frequency allowed [Hz] (the Nyquist frequency of the
        loop, which the implementation step requires).

    Raises
    ------
    ConfigError
        An unstable, marginal or duplicate pole, or a pole above ``max_hz``.
    """

    poles: tuple[complex, ...]
    integrators: bool = True
    max_hz: float | None = None

    def __post_init__(self):
        p = np.asarray(self.poles, dtype=complex).ravel()
        if p.size == 0:
            raise ConfigError("basis", "at least one stable pole")
        if not np.all(np.isfinite(p)):
            raise ConfigError("basis", "finite poles in rad/s", self.poles)
        p = np.where(p.imag < 0, np.conj(p), p)  # one of each pair
        for q in p:
            if not q.real < 0:
                raise ConfigError("basis", "stable poles (negative real part) in rad/s", f"{q:.6g}")
        for i, q in enumerate(p):
            near = np.abs(p[i + 1 :] - q) <= DUPLICATE_RTOL * abs(q)
            if np.any(near):
                raise ConfigError("basis", "distinct poles (no duplicates)", f"{q:.6g} rad/s twice")
        if self.max_hz is not None:
            worst = float(np.max(np.abs(p))) / TWO_PI
            if worst >= self.max_hz:
                raise ConfigError(
                    "basis", f"poles below the Nyquist frequency {self.max_hz:g} Hz", f"{worst:.4g} Hz"
                )
        object.__setattr__(self, "poles", tuple(complex(q) for q in p))

    @classmethod
    def butterworth_groups(
        cls,
        groups_hz: Sequence[float] = DEFAULT_GROUPS_HZ,
        order: int = DEFAULT_GROUP_ORDER,
        max_hz: float | None = None,
    ) -> PoleBasis:
        """Butterworth pole groups of ``order`` at the cut-offs ``groups_hz`` [Hz]."""
        fcs = sorted({float(f) for f in groups_hz})
        for f in fcs:
            if not (np.isfinite(f) and f > 0):
                raise ConfigError("basis", "positive cut-off frequencies in Hz", f)
        poles = np.concatenate([butterworth_poles(f, order) for f in fcs])
        return cls(tuple(poles), True, max_hz)

    # --------------------------------------------------------------- layout
    @property
    def n_z(self) -> int:
        """Number of coefficients of ``C_z`` (``a_2, a_1, a_0`` then the pole terms)."""
        return (3 if self.integrators else 1) + self._n_pole_terms

    @property
    def n_w(self) -> int:
        """Number of coefficients of ``C_w`` (``b_0`` then the pole terms)."""
        return 1 + self._n_pole_terms

    @property
    def _n_pole_terms(self) -> int:
        return sum(1 if q.imag == 0 else 2 for q in self.poles)

    def _pole_columns(self, s: np.ndarray) -> np.ndarray:
        cols: list[np.ndarray] = []
        for q in self.poles:
            m = abs(q)
            if q.imag == 0:
                cols.append(m / (s - q))
            else:
                a, b = -q.real, q.imag
                d = (s + a) ** 2 + b**2
                cols.append(m * 2.0 * (s + a) / d)
                cols.append(m * 2.0 * b / d)
        return np.column_stack(cols)

    def columns_z(self, s) -> np.ndarray:
        """Responses of the ``C_z`` basis at complex ``s`` [rad/s], shape (len(s), n_z)."""
        s = np.atleast_1d(np.asarray(s, dtype=complex))
        head = [1.0 / s**2, 1.0 / s, np.ones_like(s)] if self.integrators else [np.ones_like(s)]
        return np.column_stack([*head, self._pole_columns(s)])

    def columns_w(self, s) -> np.ndarray:
        """Responses of the ``C_w`` basis at complex ``s`` [rad/s], shape (len(s), n_w)."""
        s = np.atleast_1d(np.asarray(s, dtype=complex))
        return np.column_stack([np.ones_like(s), self._pole_columns(s)])

    def dc_row_w(self) -> np.ndarray:
        """``C_w(0)`` as a row on the ``C_w`` coefficients."""
        return np.real(self.columns_w(np.array([0.0]))[0])

    # ----------------------------------------------------------- rendering
    def transfer_function(self, coefficients: np.ndarray, path: str) -> TransferFunction:
        """``C_z`` (``path="z"``) or ``C_w`` (``"w"``) with ``coefficients``, from the exact poles.

        The numerator is the sum of the terms over the common denominator,
        built by polynomial products; no polynomial roots are taken.
        """
        x = np.asarray(coefficients, dtype=float)
        den_parts: list[np.ndarray] = []
        terms: list[tuple[np.ndarray, object]] = []  # (numerator, its own denominator factor or None)
        k = 0
        if path == "z" and self.integrators:
            terms += [(np.array([x[0]]), "s2"), (np.array([x[1]]), "s1"), (np.array([x[2]]), None)]
            k = 3
        else:
            terms.append((np.array([x[0]]), None))
            k = 1
        for i, q in enumerate(self.poles):
            m = abs(q)
            if q.imag == 0:
                den_parts.append(np.array([1.0, -q.real]))
                terms.append((np.array([m * x[k]]), i))
                k += 1
            else:
                a, b = -q.real, q.imag
                den_parts.append(np.array([1.0, 2 * a, a * a + b * b]))
                terms.append((2 * m * (x[k] * np.array([1.0, a]) + x[k + 1] * np.array([0.0, b])), i))
                k += 2
        integ = np.array([1.0, 0.0, 0.0]) if (path == "z" and self.integrators) else np.ones(1)
        den: np.ndarray = integ
        for part in den_parts:
            den = np.polymul(den, part)
        num: np.ndarray = np.zeros(1)
        for coeff, own in terms:
            other = np.ones(1)
            if own == "s2":
                pass
            elif own == "s1":
                other = np.array([1.0, 0.0])
            else:
                other = integ
            for i, part in enumerate(den_parts):
                if i != own:
                    other = np.polymul(other, part)
            num = np.polyadd(num, np.polymul(coeff, other))
        return TransferFunction(num, den)

    def to_dict(self) -> dict:
        """``{"poles": [[re, im], ...] (rad/s), "integrators": bool}``."""
        return {
            "poles_rad_s": [[float(q.real), float(q.imag)] for q in self.poles],
            "integrators": bool(self.integrators),
        }


def default_basis(fc_hz: float, max_hz: float | None = None) -> PoleBasis:
    """The default basis: Butterworth groups of :data:`DEFAULT_GROUPS_HZ` plus the one at ``fc_hz`` [Hz].

    ``fc_hz`` is the cut-off of the reference filter design, whose poles must
    be in the span (it is already one of the default groups for the report's
    80 Hz).  Groups at or above ``max_hz`` [Hz] are dropped.
    """
    groups = [f for f in (*DEFAULT_GROUPS_HZ, fc_hz) if max_hz is None or f < max_hz]
    return PoleBasis.butterworth_groups(groups, DEFAULT_GROUP_ORDER, max_hz)
