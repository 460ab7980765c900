"""Order reduction of an optimized controller path by balanced singular perturbation (issue 15, "Realization").

Each path of the optimized controller is a modal state space built from the
partial-fraction basis (:func:`.certify.path_state_space`): the double
integrator of ``C_z`` (Eq 6-8a) and the stable pole blocks.  The integrators
are kept exactly; the stable part ``G`` is balanced (its controllability and
observability Gramians made equal and diagonal, the Hankel singular values
``sigma_1 >= sigma_2 >= ...`` on the diagonal) and its weakest states are
removed by *singular perturbation* (residualization): their derivatives are
set to zero instead of the states themselves.  Like truncation it keeps the
reduced part stable and obeys the a-priori bound

    max_w |G(jw) - G_r(jw)| <= 2 (sigma_{r+1} + ... + sigma_n)

(Liu and Anderson 1989, the same bound as balanced truncation), and, unlike
truncation, it keeps the DC gain exactly, so the DC tracking equalities of
the design (``C_w(0)``, and with ``a_2``, ``a_1`` the low-frequency
behaviour of ``C_z``) survive the reduction.  Nothing goes through
polynomial roots: Gramians from Lyapunov equations, their square roots from
symmetric eigen-decompositions, the balancing from one SVD.

>>> import numpy as np
>>> A = np.diag([-1.0, -2.0, -1000.0]); B = np.ones(3); C = np.array([1.0, 1.0, 1e-4])
>>> r = reduce_stable(A, B, C, 0.0, 2)
>>> r.order, bool(r.bound < 1e-7)
(2, True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ...errors import ConfigError
from ...systems import TransferFunction
from .certify import StateSpace

#: Hankel singular values below this fraction of the largest are numerically zero: removed first.
NUMERICAL_ZERO_RTOL = 1e-13

#: Reduction methods: balanced singular perturbation (default) and balanced truncation.
METHODS = ("residualize", "truncate")


@dataclass(frozen=True)
class ReducedStable:
    """A stable SISO part after balanced singular perturbation.

    Attributes
    ----------
    A, B, C, D :
        The reduced realization (``D`` in the path's unit).
    hankel : np.ndarray
        Hankel singular values of the full stable part, descending (path unit).
    bound : float
        ``2 * sum`` of the removed Hankel singular values: the H-infinity bound
        of the error (path unit).
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: float
    hankel: np.ndarray
    bound: float

    @property
    def order(self) -> int:
        return int(self.A.shape[0])


def _psd_factor(W: np.ndarray) -> np.ndarray:
    """``L`` with ``L L^T = W`` for a symmetric positive semi-definite ``W`` (negative round-off clipped)."""
    lam, U = np.linalg.eigh(0.5 * (W + W.T))
    return U * np.sqrt(np.clip(lam, 0.0, None))


def hankel_singular_values(A: np.ndarray, B: np.ndarray, C: np.ndarray) -> np.ndarray:
    """Hankel singular values of the stable SISO system ``(A, B, C)``, descending."""
    return _balance(A, B, C)[0]


def _balance(A, B, C):
    """Hankel singular values and the square-root balancing factors of the stable ``(A, B, C)``."""
    Wc = scipy.linalg.solve_continuous_lyapunov(A, -np.outer(B, B))
    Wo = scipy.linalg.solve_continuous_lyapunov(A.T, -np.outer(C, C))
    Lc, Lo = _psd_factor(Wc), _psd_factor(Wo)
    U, sig, Vt = np.linalg.svd(Lo.T @ Lc)
    return sig, Lc, Lo, U, Vt


def reduce_stable(A, B, C, D: float, order: int, method: str = "residualize") -> ReducedStable:
    """Balanced singular perturbation of a stable SISO ``(A, B, C, D)`` to ``order`` states.

    Parameters
    ----------
    A, B, C : array_like
        Stable realization (``A`` n x n, ``B`` and ``C`` of length n).
    D : float
        Feedthrough.
    order : int
        States kept, ``0 <= order``; at or above the number of numerically
        non-zero Hankel singular values the part is only made minimal.
    method : {"residualize", "truncate"}
        Singular perturbation (DC gain exact) or truncation (exact at infinite
        frequency); the same error bound.

    Raises
    ------
    ConfigError
        A negative order.
    """
    A, B, C = (np.asarray(v, dtype=float) for v in (A, B, C))
    if order < 0:
        raise ConfigError("reduce", "a non-negative order", order)
    if method not in METHODS:
        raise ConfigError("reduce method", " or ".join(METHODS), method)
    n = A.shape[0]
    if n == 0:
        return ReducedStable(A, B, C, float(D), np.zeros(0), 0.0)
    sig, Lc, Lo, U, Vt = _balance(A, B, C)
    # Balanced realization of the numerically non-zero part (the rest is removed by truncation,
    # whose error is below the bound of those values: the round-off of the Gramians).
    k = int(np.sum(sig > NUMERICAL_ZERO_RTOL * sig[0])) if sig[0] > 0 else 0
    r = min(order, k)
    s_half = 1.0 / np.sqrt(sig[:k])
    T = Lc @ Vt[:k].T * s_half
    Ti = (s_half[:, None] * U[:, :k].T) @ Lo.T
    Ab, Bb, Cb = Ti @ A @ T, Ti @ B, C @ T
    A11, A12, A21, A22 = Ab[:r, :r], Ab[:r, r:], Ab[r:, :r], Ab[r:, r:]
    if r < k and method == "residualize":
        # Residualize x2: 0 = A21 x1 + A22 x2 + B2 u (A22 is stable, hence invertible).
        X = np.linalg.solve(A22, np.column_stack([A21, Bb[r:]]))
        Ar = A11 - A12 @ X[:, :r]
        Br = Bb[:r] - A12 @ X[:, r]
        Cr = Cb[:r] - Cb[r:] @ X[:, :r]
        Dr = float(D) - float(Cb[r:] @ X[:, r])
    else:
        Ar, Br, Cr, Dr = A11, Bb[:r], Cb[:r], float(D)
    return ReducedStable(Ar, Br, Cr, Dr, sig, float(2.0 * np.sum(sig[r:])))


@dataclass(frozen=True)
class ReducedPath:
    """One controller path after reduction: the realization and what was removed.

    Attributes
    ----------
    state_space : StateSpace
        Reduced path: integrator chain (kept exactly) and the reduced stable part.
    order_before, order_after : int
        Number of states before and after.
    hankel : np.ndarray
        Hankel singular values of the stable part (path unit).
    bound : float
        H-infinity bound of the error, ``2 * sum`` of the removed values (path unit).
    """

    state_space: StateSpace
    order_before: int
    order_after: int
    hankel: np.ndarray
    bound: float


def reduce_path(path: StateSpace, integrators: int, order: int, method: str = "residualize") -> ReducedPath:
    """Reduce a controller path whose first ``integrators`` states are a decoupled integrator chain.

    Parameters
    ----------
    path : StateSpace
        Modal realization from :func:`.certify.path_state_space`.
    integrators : int
        States of the integrator chain at the top (2 for ``C_z`` with the
        double integrator, else 0); they are kept.
    order : int
        States of the reduced path, integrators included (at least ``integrators``).
    method : {"residualize", "truncate"}
        See :func:`reduce_stable`.
    """
    n = path.A.shape[0]
    if order < integrators:
        raise ConfigError(
            "reduce", f"an order of at least {integrators} (the integrators of the path)", order
        )
    i = integrators
    part = reduce_stable(path.A[i:, i:], path.B[i:], path.C[i:], path.D, order - i, method)
    A = scipy.linalg.block_diag(path.A[:i, :i], part.A)
    B = np.concatenate([path.B[:i], part.B])
    C = np.concatenate([path.C[:i], part.C])
    return ReducedPath(StateSpace(A, B, C, part.D), n, A.shape[0], part.hankel, part.bound)


def transfer_function(path: StateSpace) -> TransferFunction:
    """The transfer function of a path from its eigenvalues and invariant zeros (no polynomial roots).

    Poles are the eigenvalues of ``A``, zeros the finite generalized
    eigenvalues of the Rosenbrock pencil (:meth:`.certify.StateSpace.zpk`);
    the polynomials are products of those factors.
    """
    zpk = path.zpk()
    return TransferFunction.from_zpk(
        [complex(a, b) for a, b in zpk["zeros"]], [complex(a, b) for a, b in zpk["poles"]], zpk["gain"]
    )
