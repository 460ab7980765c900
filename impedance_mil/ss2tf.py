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

from .errors import ConfigError
from .lazy import LazyModule
from .lti import StateSpace

#: scipy.linalg and scipy.signal, imported on first use (:class:`~impedance_mil.lazy.LazyModule`):
#: a command that only reads a configuration does not convert (issue 16, start-up).
scipy_linalg = LazyModule("scipy.linalg")
scipy_signal = LazyModule("scipy.signal")

#: Coefficients below this fraction of the magnitude of the terms summed into them are round-off.
ROUNDOFF_RTOL = 1e-9
#: Trailing numerator terms below this fraction of the largest, on the low-frequency scale, are zeros at the origin.
ORIGIN_ZERO_RTOL = 1e-12
#: Poles below this fraction of the largest pole magnitude count as at the origin (no frequency scale).
ORIGIN_POLE_RTOL = 1e-9


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
      ``h_k = c x_k`` (``x_k = A^(k-1) b``) counts as zero when
      ``|h_k| <= rtol |c| |x_k|``, the size of the terms summed into it
      (element by element, so the test holds for badly scaled matrices
      such as a companion form; structural zeros come out exactly zero);
    * zeros at the origin (e.g. the double zero of z/u, Eq 4-15a): a
      trailing coefficient ``c_j`` of ``s**j`` that is negligible on the
      system's low-frequency scale ``omega`` (the smallest pole magnitude
      not at the origin), ``|c_j| omega**j <= 1e-12 max_i |c_i| omega**i``
      (:data:`ORIGIN_ZERO_RTOL`); for polynomials in z, ``omega = 1`` (the
      unit circle).  Round-off from the model's own basis or a
      change of units is far below that (6e-17 measured on the table); a genuine
      coefficient is dropped only when zeros are that close to the origin
      (one zero within 1e-12 omega, or k zeros whose magnitudes multiply to
      less than ``1e-12 omega**k``).

    Parameters
    ----------
    sys : StateSpace
        A SISO system (select a channel with :meth:`StateSpace.channel`).
    rtol : float
        Relative round-off threshold of the Markov parameters (dimensionless).

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
    A, T = scipy_linalg.matrix_balance(sys.A, permute=False)
    scaling = np.diag(T)  # powers of 2: the similarity is exact and keeps structural zeros
    b = sys.B[:, 0] / scaling
    c = sys.C[0] * scaling
    d = float(sys.D[0, 0])
    n = A.shape[0]
    num_lv, den_lv = _leverrier(A, b, c, d)
    nums, den_sp = scipy_signal.ss2tf(A, b.reshape(n, 1), c.reshape(1, n), d)
    num_sp = np.zeros(n + 1)
    num_sp[n + 1 - nums.shape[1] :] = nums[0]
    leading_zeros = _zeros_at_infinity(A, b, c, d, rtol)
    # The scale the trailing coefficients are judged on: the slowest pole in s; in z the
    # unit circle, where the response lives (z = 0 is a delay, not a frequency).
    omega_lo = 1.0 if sys.is_discrete else _low_frequency_scale(A)
    den_sp = np.asarray(den_sp, dtype=float)
    candidates = []
    for num, den in ((num_lv, den_lv), (num_sp, den_sp), (_zeros_numerator(A, b, c, d, n), den_sp)):
        num = num.copy()
        num[:leading_zeros] = 0.0
        num = _exact_trailing(num, omega_lo, ORIGIN_ZERO_RTOL)
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
        z = scipy_linalg.eigvals(M, N)
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
    """Number of leading numerator coefficients that vanish: 0 if d != 0, else 1 + vanishing Markov parameters.

    ``h_k = c x_k`` with ``x_k = A^(k-1) b`` counts as zero below ``rtol``
    times ``|c| |x_k|``, the size of the terms summed into it.
    """
    if d != 0.0:
        return 0
    absc = np.abs(c)
    x = b.copy()
    count = 1
    for _ in range(A.shape[0]):
        if abs(c @ x) > rtol * (absc @ np.abs(x)):
            break
        count += 1
        x = A @ x
    return count


def _low_frequency_scale(A: np.ndarray) -> float:
    """Smallest pole magnitude [rad/s] not at the origin (poles below 1e-9 of the largest count as at the origin).

    0 when every pole is at the origin (no frequency scale).
    """
    mags = np.abs(np.linalg.eigvals(A))
    mags = mags[mags > ORIGIN_POLE_RTOL * mags.max()] if mags.size and mags.max() > 0 else mags[:0]
    return float(mags.min()) if mags.size else 0.0


def _exact_trailing(num: np.ndarray, omega: float, rtol: float) -> np.ndarray:
    """Trailing coefficients negligible on the frequency scale ``omega`` set to exact zeros.

    The coefficient ``c_j`` of ``s**j`` is compared through ``|c_j| omega**j``
    with the largest such term (in logarithms: no overflow for high orders).
    """
    if omega <= 0 or not np.any(num):
        return num
    powers = np.arange(num.size - 1, -1, -1, dtype=float)
    with np.errstate(divide="ignore"):
        log_terms = np.log(np.abs(num)) + powers * np.log(omega)
    limit = np.max(log_terms) + np.log(rtol)
    out = num.copy()
    for k in range(num.size - 1, -1, -1):
        if log_terms[k] > limit:
            break
        out[k] = 0.0
    return out
