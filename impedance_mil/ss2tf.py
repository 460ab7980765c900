"""Round-off-safe conversion of a SISO state space to polynomials (the one ss -> tf of the toolkit).

Used by :meth:`impedance_mil.systems.TransferFunction.from_lti` (and
``from_ss``) for continuous systems, and by the sampled-data table for
polynomials in z.  Why not :func:`scipy.signal.ss2tf` alone: it leaves
round-off where the numerator degree drops (a ``1e-12 s**5`` on a strictly
proper path), so the relative degree comes out wrong and the inverse of the
function, which the MIL controller is, is improper.  See :func:`ss_to_tf`.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.signal

from .errors import ConfigError
from .lti import StateSpace

#: Coefficients below this fraction of the magnitude of the terms summed into them are round-off.
ROUNDOFF_RTOL = 1e-9
#: Above this condition number of (balanced) A, zeros at the origin are not searched for by moments.
MAX_MOMENT_CONDITION = 1e6


def ss_to_tf(sys: StateSpace, rtol: float = ROUNDOFF_RTOL) -> tuple[np.ndarray, np.ndarray]:
    """Numerator and denominator of a SISO :class:`~impedance_mil.lti.StateSpace`, round-off safe.

    Polynomials in s [rad/s] (continuous) or z (discrete), descending powers,
    both of length n + 1 (a static gain: ``([D], [1])``), monic ``den``.

    Three conversions are computed: the Faddeev-LeVerrier recursion
    ``(sI - A)^-1 = sum_k M_k s^(n-k) / det(sI - A)``, ``M_{k+1} = A M_k +
    a_k I`` (most accurate for the small 5-6 state models),
    :func:`scipy.signal.ss2tf`, and poles and transmission zeros from
    (generalized) eigenvalues (best for the stiff Pade-augmented models).
    The one whose response best matches the resolvent ``c (sI - A)^-1 b +
    d`` (:meth:`StateSpace.evaluate`) at points spread over the poles is
    kept.  A is balanced first (exact power-of-2 scaling).

    Numerator coefficients that are round-off become exact zeros, so the
    relative degree and the zeros at the origin are right (they matter when
    the function is inverted):

    * zeros at infinity (the relative degree): with ``d = 0`` the leading
      coefficients are the Markov parameters ``h_k = c A^(k-1) b`` combined
      with the denominator (``num_1 = h_1``, ``num_2 = h_2 + a_1 h_1`` ...),
      so the first ``r`` vanish exactly when ``h_1 ... h_r`` do;
      ``h_k`` counts as zero when ``|h_k| <= rtol |c| |A^(k-1) b|`` (the
      round-off of that product, whatever the basis of the matrices;
      structural zeros come out exactly zero);
    * zeros at the origin: trailing coefficients when the low-frequency
      moments ``c A^-(k+1) b`` vanish to ``rtol`` (e.g. the double zero of
      z/u, Eq 4-15a).

    Parameters
    ----------
    sys : StateSpace
        A SISO system (select a channel with :meth:`StateSpace.channel`).
    rtol : float
        Relative round-off threshold (dimensionless).

    Returns
    -------
    num, den : ndarray

    Raises
    ------
    ConfigError
        ``sys`` is not SISO.

    Examples
    --------
    >>> sys = StateSpace([[0.0, 1.0], [-4.0, -0.4]], [0.0, 1.0], [1.0, 0.0], 0.0)
    >>> num, den = ss_to_tf(sys)
    >>> num.tolist(), den.tolist()
    ([0.0, 0.0, 1.0], [1.0, 0.4, 4.0])
    """
    if not sys.is_siso:
        raise ConfigError(
            "state_space", "a SISO system (select one with StateSpace.channel)", sys.shape_text()
        )
    if sys.n_states == 0:
        return np.array([float(sys.D[0, 0])]), np.ones(1)
    A, T = scipy.linalg.matrix_balance(sys.A, permute=False)
    scaling = np.diag(T)  # powers of 2: the similarity is exact and keeps structural zeros
    b = sys.B[:, 0] / scaling
    c = sys.C[0] * scaling
    d = float(sys.D[0, 0])
    n = A.shape[0]
    num_lv, den_lv = _leverrier(A, b, c, d)
    nums, den_sp = scipy.signal.ss2tf(A, b.reshape(n, 1), c.reshape(1, n), d)
    num_sp = np.zeros(n + 1)
    num_sp[n + 1 - nums.shape[1] :] = nums[0]
    leading_zeros = _zeros_at_infinity(A, b, c, d, rtol)
    origin_zeros = _zeros_at_origin(A, b, c, d, rtol)
    den_sp = np.asarray(den_sp, dtype=float)
    candidates = []
    for num, den in ((num_lv, den_lv), (num_sp, den_sp), (_zeros_numerator(A, b, c, d, n), den_sp)):
        num = num.copy()
        num[:leading_zeros] = 0.0
        if origin_zeros:
            num[n + 1 - origin_zeros :] = 0.0
        candidates.append((num, den))
    balanced = StateSpace(A, b, c, d)
    scale = np.abs(balanced.poles())
    scale = scale[scale > 0]
    top = scale.max() * 10 if scale.size else 10.0
    points = 1j * np.geomspace(scale.min() / 10 if scale.size else 0.1, top, 16)
    ref = balanced.evaluate(points)
    with np.errstate(over="ignore", invalid="ignore"):  # a candidate that overflows has error inf
        errors = [
            np.max(
                np.abs(np.polyval(nm, points) / np.polyval(dn, points) - ref)
                / np.maximum(np.abs(ref), 1e-300)
            )
            for nm, dn in candidates
        ]
    return candidates[int(np.argmin(errors))]


def _zeros_numerator(A, b, c, d, n):
    """Numerator from the transmission zeros (generalized eigenvalues) and the first Markov parameter."""
    M = np.block([[A, b[:, None]], [c[None, :], np.array([[d]])]])
    N = np.zeros_like(M)
    N[:n, :n] = np.eye(n)
    with np.errstate(all="ignore"):
        z = scipy.linalg.eigvals(M, N)
    z = z[np.isfinite(z) & (np.abs(z) < 1e300)]
    gain, power = d, np.eye(n)
    for _ in range(n + 1):
        if gain != 0.0:
            break
        gain = c @ power @ b
        power = A @ power
    out = np.zeros(n + 1)
    poly = gain * np.real(np.poly(z)) if z.size else np.array([gain])
    out[n + 1 - poly.size :] = poly
    return out


def _leverrier(A, b, c, d):
    """Faddeev-LeVerrier numerator and denominator coefficients."""
    n = A.shape[0]
    den, num = np.zeros(n + 1), np.zeros(n + 1)
    den[0], num[0] = 1.0, d
    M = np.eye(n)
    for k in range(1, n + 1):
        AM = A @ M
        den[k] = -np.trace(AM) / k
        num[k] = c @ M @ b + d * den[k]
        M = AM + den[k] * np.eye(n)
    return num, den


def _zeros_at_infinity(A, b, c, d, rtol):
    """Number of leading numerator coefficients that vanish: 0 if d != 0, else 1 + vanishing Markov parameters."""
    if d != 0.0:
        return 0
    norm_c = np.linalg.norm(c)
    x = b.copy()
    count = 1
    for _ in range(A.shape[0]):
        if abs(c @ x) > rtol * norm_c * np.linalg.norm(x):
            break
        count += 1
        x = A @ x
    return count


def _zeros_at_origin(A, b, c, d, rtol):
    """Number of vanishing low-frequency moments of ``d + c (sI - A)^-1 b`` (0 if A is singular)."""
    try:
        inv = np.linalg.inv(A)
    except np.linalg.LinAlgError:
        return 0
    if not np.all(np.isfinite(inv)) or np.linalg.cond(A) > MAX_MOMENT_CONDITION:
        return 0
    norm_c = np.linalg.norm(c)
    x = b.copy()
    count = 0
    for k in range(A.shape[0]):
        x = inv @ x
        moment = (d if k == 0 else 0.0) - c @ x  # H(s) = d - sum_k c A^-(k+1) b s^k
        bound = norm_c * np.linalg.norm(x) + (abs(d) if k == 0 else 0.0)
        if abs(moment) > rtol * bound:
            break
        count += 1
    return count
