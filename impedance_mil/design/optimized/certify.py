"""A passivity certificate that does not rest on a grid.

``Re H_vw(j w)`` of a rational force-velocity function can change sign only
where ``Phi(s) = H_vw(s) + H_vw(-s)`` has a zero on the imaginary axis.  Those
zeros are the finite generalized eigenvalues of the Rosenbrock pencil of a
state-space realization of ``Phi`` (``A_Phi = diag(A, -A^T)``,
``B_Phi = [B; C^T]``, ``C_Phi = [C, -B^T]``, ``D_Phi = 2D``): no polynomial
roots and no frequency grid.  Between two consecutive crossings the sign is
constant, so one evaluation per interval decides it.  The certificate holds
when no interval inside the band has ``Re H_vw < 0``.

The realization is built from the partial-fraction basis directly (modal
blocks, :func:`path_state_space`) and the table's state space, so nothing
is converted to polynomials.  It applies to rational models: the
first-order-delay table with a rational VS impedance (the linear SD system,
or the rational equivalent ``s**2/(m s**2 + c_eq s + k_eff)`` of a hysteretic
one; describing-function impedances are tabulated and are checked on the
dense grid instead).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ...systems import TransferFunction
from ...units import TWO_PI
from .basis import PoleBasis

#: Relative size of the real part below which a pencil eigenvalue lies on the imaginary axis.
AXIS_RTOL = 1e-6


@dataclass(frozen=True)
class StateSpace:
    """Real SISO state space ``(A, B, C, D)`` (internal)."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: float

    def response(self, s: np.ndarray) -> np.ndarray:
        n = self.A.shape[0]
        eye = np.eye(n)
        return np.array(
            [self.C @ np.linalg.solve(p * eye - self.A, self.B) + self.D for p in np.atleast_1d(s)]
        )

    def zpk(self) -> dict:
        """Zeros and poles [rad/s] as ``[re, im]`` pairs and the gain, from eigenvalues (no polynomial roots).

        Zeros are the finite generalized eigenvalues of the Rosenbrock pencil
        ``[[A, B], [C, D]] - s [[I, 0], [0, 0]]``; the gain is that of the monic factors.
        """
        n = self.A.shape[0]
        M = np.block([[self.A, self.B[:, None]], [self.C[None, :], np.array([[self.D]])]])
        N = scipy.linalg.block_diag(np.eye(n), np.zeros((1, 1)))
        z = scipy.linalg.eig(M, N, right=False)
        z = z[np.isfinite(z) & (np.abs(z) < 1e12)]
        p = np.linalg.eigvals(self.A)
        s0 = 1j * float(np.max(np.abs(p)) + 1.0)  # a point away from every root
        shape = np.prod(s0 - z) / np.prod(s0 - p)
        gain = float(np.real(self.response(np.array([s0]))[0] / shape))
        pair = lambda r: [[float(v.real), float(v.imag)] for v in sorted(r, key=abs)]  # noqa: E731
        return {"zeros": pair(z), "poles": pair(p), "gain": gain}

    def to_dict(self) -> dict:
        return {
            "A": self.A.tolist(),
            "B": self.B.tolist(),
            "C": self.C.tolist(),
            "D": float(self.D),
        }


def path_state_space(basis: PoleBasis, coefficients: np.ndarray, path: str) -> StateSpace:
    """Modal realization of ``C_z`` (``path="z"``) or ``C_w`` from the basis, without polynomials.

    Real poles are 1x1 blocks, conjugate pairs ``-a +- jb`` the 2x2 blocks
    ``[[-a, -b], [b, -a]]``, the double integrator of ``C_z`` a chain.
    """
    x = np.asarray(coefficients, dtype=float)
    blocks, Bs, Cs = [], [], []
    if path == "z" and basis.integrators:
        blocks.append(np.array([[0.0, 0.0], [1.0, 0.0]]))
        Bs.append(np.array([1.0, 0.0]))
        Cs.append(np.array([x[1], x[0]]))
        D, k = float(x[2]), 3
    else:
        D, k = float(x[0]), 1
    for q in basis.poles:
        m = abs(q)
        if q.imag == 0:
            blocks.append(np.array([[q.real]]))
            Bs.append(np.array([1.0]))
            Cs.append(np.array([m * x[k]]))
            k += 1
        else:
            a, b = -q.real, q.imag
            blocks.append(np.array([[-a, -b], [b, -a]]))
            Bs.append(np.array([1.0, 0.0]))
            Cs.append(2.0 * m * np.array([x[k], x[k + 1]]))
            k += 2
    return StateSpace(scipy.linalg.block_diag(*blocks), np.concatenate(Bs), np.concatenate(Cs), D)


def _tf_state_space(tf: TransferFunction) -> StateSpace:
    A, B, C, D = tf.to_ss()
    return StateSpace(np.atleast_2d(A), np.ravel(B), np.ravel(C), float(np.ravel(D)[0]))


def _series(first: StateSpace, second: StateSpace) -> StateSpace:
    """``second * first`` (first acts first)."""
    n1, n2 = first.A.shape[0], second.A.shape[0]
    A = np.block([[first.A, np.zeros((n1, n2))], [np.outer(second.B, first.C), second.A]])
    B = np.concatenate([first.B, second.B * first.D])
    C = np.concatenate([second.D * first.C, second.C])
    return StateSpace(A, B, C, second.D * first.D)


def _parallel(a: StateSpace, b: StateSpace) -> StateSpace:
    return StateSpace(
        scipy.linalg.block_diag(a.A, b.A), np.concatenate([a.B, b.B]), np.concatenate([a.C, b.C]), a.D + b.D
    )


def closed_velocity(table_ss, target_tf: TransferFunction, C_z: StateSpace, C_w: StateSpace) -> StateSpace:
    """``H_vw = P_vw + P_vu (C_w + C_z Z)`` as one state space.

    ``table_ss`` is the first-order table's
    :class:`~impedance_mil.plant.statespace.TableStateSpace`; ``target_tf``
    the rational VS impedance ``Z``.
    """
    U = _parallel(_series(_tf_state_space(target_tf), C_z), C_w)  # w -> u
    A_t, Bu, Bw = np.asarray(table_ss.A), np.asarray(table_ss.B_u), np.asarray(table_ss.B_w)
    Cv = np.asarray(table_ss.C["v"])
    Dvu, Dvw = (float(v) for v in table_ss.D["v"])
    nt, nu = A_t.shape[0], U.A.shape[0]
    A = np.block([[A_t, np.outer(Bu, U.C)], [np.zeros((nu, nt)), U.A]])
    B = np.concatenate([Bu * U.D + Bw, U.B])
    C = np.concatenate([Cv, Dvu * U.C])
    return StateSpace(A, B, C, Dvu * U.D + Dvw)


@dataclass(frozen=True)
class Certificate:
    """Grid-free passivity verdict of one rational model.

    Attributes
    ----------
    model : str
        Which model (e.g. ``"first-order/linear"``).
    band_hz : (float, float)
        Band certified [Hz].
    passive : bool
        ``Re H_vw >= 0`` everywhere in the band.
    crossings_hz : tuple of float
        Frequencies [Hz] in the band where ``Re H_vw`` is zero.
    negative_hz : tuple of (float, float)
        Sub-bands [Hz] where ``Re H_vw < 0``.
    min_cos_phase : float
        Smallest ``Re H_vw/|H_vw|`` among the interval test points (dimensionless).
    states : int
        Order of the realization of ``H_vw``.
    method : str
        How the crossings were found.
    """

    model: str
    band_hz: tuple[float, float]
    passive: bool
    crossings_hz: tuple[float, ...]
    negative_hz: tuple[tuple[float, float], ...]
    min_cos_phase: float
    states: int
    method: str = "imaginary-axis zeros of H_vw(s) + H_vw(-s) (Rosenbrock pencil eigenvalues)"

    def to_dict(self) -> dict:
        return {
            "model": self.model,
            "band_hz": [float(x) for x in self.band_hz],
            "passive": bool(self.passive),
            "crossings_hz": [float(x) for x in self.crossings_hz],
            "negative_hz": [[float(a), float(b)] for a, b in self.negative_hz],
            "min_cos_phase": float(self.min_cos_phase),
            "states": int(self.states),
            "method": self.method,
        }


def imaginary_crossings_hz(H: StateSpace) -> np.ndarray:
    """Frequencies [Hz] (> 0) where ``Re H(j w) = 0``: imaginary-axis zeros of ``H(s) + H(-s)``."""
    # Balance first (exact power-of-2 similarity): the table's states span ~15 decades
    # (in, psi, mA), and unbalanced the pencil's eigenvalues lose every digit.
    _, (scale, _) = scipy.linalg.matrix_balance(H.A, permute=False, separate=True)
    A = H.A * (1.0 / scale)[:, None] * scale[None, :]
    B, C, D = H.B / scale, H.C * scale, H.D
    n = A.shape[0]
    A_phi = scipy.linalg.block_diag(A, -A.T)
    B_phi = np.concatenate([B, C])
    C_phi = np.concatenate([C, -B])
    M = np.zeros((2 * n + 1, 2 * n + 1))
    M[: 2 * n, : 2 * n] = A_phi
    M[: 2 * n, 2 * n] = B_phi
    M[2 * n, : 2 * n] = C_phi
    M[2 * n, 2 * n] = 2.0 * D
    N = scipy.linalg.block_diag(np.eye(2 * n), np.zeros((1, 1)))
    lam = scipy.linalg.eig(M, N, right=False)
    lam = lam[np.isfinite(lam)]
    on_axis = lam[(np.abs(lam.real) <= AXIS_RTOL * np.abs(lam)) & (lam.imag > 0)]
    return np.sort(on_axis.imag) / TWO_PI


def certify(model: str, H: StateSpace, band_hz: tuple[float, float]) -> Certificate:
    """Certify ``Re H(j 2 pi f) >= 0`` for every ``f`` in ``band_hz`` [Hz] (see the module docstring)."""
    lo, hi = band_hz
    cross = imaginary_crossings_hz(H)
    inside = cross[(cross > lo) & (cross < hi)]
    edges = np.concatenate([[lo], inside, [hi]])
    mids = np.sqrt(edges[:-1] * edges[1:])
    values = H.response(1j * TWO_PI * mids)
    cosphi = np.real(values) / np.abs(values)
    negative = tuple((float(edges[i]), float(edges[i + 1])) for i in np.nonzero(cosphi < 0)[0])
    ends = H.response(1j * TWO_PI * np.array([lo, hi]))
    cos_all = np.concatenate([cosphi, np.real(ends) / np.abs(ends)])
    passive = not negative and bool(np.all(np.real(ends) >= 0))
    return Certificate(
        model,
        (float(lo), float(hi)),
        passive,
        tuple(float(c) for c in inside),
        negative,
        float(np.min(cos_all)),
        int(H.A.shape[0]),
    )
