"""State-space building blocks of the shake-table model (report Eq 4-9, 4-3, 4-11).

States of the open-loop model (Eq 4-11): ``x`` table displacement [in], ``v``
velocity [in/s], ``dp`` differential pressure [psi], ``spool`` servovalve
state in equivalent current [mA] (unit DC gain from u_i), ``spool_rate``
[mA/s].  Sign convention (Eq 4-7b): ``m_st z = A_p dP + w``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.signal

from ..errors import ConfigError
from ..systems import TransferFunction
from .parameters import TableParameters

#: Outputs: acceleration z [in/s^2], displacement x [in], velocity v [in/s], dP [psi].
OUTPUTS = ("z", "x", "v", "dp")
#: Inputs: position command u [in], test-article force w [lbf].
INPUTS = ("u", "w")
#: Names of the states of Eq 4-11.
PLANT_STATES = ("x", "v", "dp", "spool", "spool_rate")
#: Coefficients below this fraction of the terms summed into them are round-off.
ROUNDOFF_RTOL = 1e-9
#: Above this condition number of (balanced) A, zeros at the origin are not searched for.
MAX_MOMENT_CONDITION = 1e6


@dataclass(frozen=True, eq=False)
class TableStateSpace:
    """State-space model ``x' = A x + B_u u + B_w w``, ``y = C[y] x + D[y] (u, w)``.

    Attributes
    ----------
    A : ndarray, shape (n, n)
        State matrix [1/s].
    B_u : ndarray, shape (n,)
        Input vector of the command (``u`` [in] closed loop, ``u_i`` [mA] open loop).
    B_w : ndarray, shape (n,)
        Input vector of the test-article force w [lbf].
    C : dict of str to ndarray
        Output rows for ``"z"``, ``"x"``, ``"v"``, ``"dp"``.
    D : dict of str to tuple of float
        Feedthrough (from the command, from w) of each output.
    states : tuple of str
        State names.
    input_name : str
        ``"u"`` (closed loop) or ``"u_i"`` (open loop, Eq 4-11).
    """

    A: np.ndarray
    B_u: np.ndarray
    B_w: np.ndarray
    C: Mapping[str, np.ndarray]
    D: Mapping[str, tuple[float, float]]
    states: tuple[str, ...]
    input_name: str = "u"

    def input_vector(self, input: str) -> np.ndarray:
        """``B_u`` for the command input, ``B_w`` for ``"w"``."""
        if input == "w":
            return self.B_w
        if input in (self.input_name, "u"):
            return self.B_u
        raise ConfigError("input", f"one of {self.input_name}, w", input)

    def tf(self, output: str, input: str) -> TransferFunction:
        """Transfer function ``output/input`` (numerator and denominator from the state space)."""
        if output not in self.C:
            raise ConfigError("output", "one of " + ", ".join(self.C), output)
        b = self.input_vector(input)
        feed = self.D[output][1 if input == "w" else 0]
        num, den = ss_to_tf(self.A, b, self.C[output], feed)
        return TransferFunction(num, den)

    def poles(self) -> np.ndarray:
        """Eigenvalues of A [rad/s]."""
        return np.linalg.eigvals(self.A)

    def frequency_response(self, output: str, input: str, f_hz) -> np.ndarray:
        """Complex response at ``f_hz`` [Hz] by solving ``(sI - A) X = b`` (no polynomials)."""
        s = 2j * np.pi * np.atleast_1d(np.asarray(f_hz, dtype=float))
        feed = self.D[output][1 if input == "w" else 0]
        return resolvent_response(self.A, self.input_vector(input), self.C[output], feed, s)


def resolvent_response(
    A: np.ndarray, b: np.ndarray, c: np.ndarray, d: float, points: np.ndarray
) -> np.ndarray:
    """``c (p I - A)^-1 b + d`` at each complex point p (s or z)."""
    eye = np.eye(A.shape[0])
    return np.array([c @ np.linalg.solve(p * eye - A, b) + d for p in np.atleast_1d(points)])


def ss_to_tf(
    A: np.ndarray, b: np.ndarray, c: np.ndarray, d: float = 0.0, rtol: float = ROUNDOFF_RTOL
) -> tuple[np.ndarray, np.ndarray]:
    """SISO transfer function of ``(A, b, c, d)`` with exact structural zeros.

    Three conversions are computed: the Faddeev-LeVerrier recursion
    ``(sI - A)^-1 = sum_k M_k s^(n-k) / det(sI - A)``, ``M_{k+1} = A M_k +
    a_k I`` (most accurate for the small 5-6 state models),
    :func:`scipy.signal.ss2tf`, and poles and transmission zeros from
    (generalized) eigenvalues (best for the stiff Pade-augmented models).  The one whose response best matches the
    resolvent ``c (sI - A)^-1 b + d`` at points spread over the poles is
    kept.  A is balanced first (exact power-of-2 scaling).  Structural zeros are then made exact: leading coefficients whose
    terms are all structurally zero (same recursion on ``|A|``), and
    trailing coefficients when the low-frequency moments ``c A^-(k+1) b``
    vanish to ``rtol`` (zeros at the origin, e.g. the double zero of z/u,
    Eq 4-15a).  This matters when the function is inverted.

    Parameters
    ----------
    A : ndarray, shape (n, n)
    b, c : ndarray, shape (n,)
    d : float
    rtol : float
        Relative round-off threshold of the moments (dimensionless).

    Returns
    -------
    num, den : ndarray
        Coefficients in descending powers of s (or z), both of length n + 1;
        ``den`` is monic.
    """
    A, T = scipy.linalg.matrix_balance(np.asarray(A, dtype=float), permute=False)
    scaling = np.diag(T)  # powers of 2: the similarity is exact and keeps structural zeros
    b = np.asarray(b, dtype=float) / scaling
    c = np.asarray(c, dtype=float) * scaling
    n = A.shape[0]
    num_lv, den_lv, structural = _leverrier(A, b, c, float(d))
    nums, den_sp = scipy.signal.ss2tf(A, b.reshape(n, 1), c.reshape(1, n), float(d))
    num_sp = np.zeros(n + 1)
    num_sp[n + 1 - nums.shape[1] :] = nums[0]
    origin_zeros = _zeros_at_origin(A, b, c, float(d), rtol)
    den_sp = np.asarray(den_sp, dtype=float)
    candidates = []
    for num, den in ((num_lv, den_lv), (num_sp, den_sp), (_zeros_numerator(A, b, c, d, n), den_sp)):
        num = num.copy()
        num[structural] = 0.0
        if origin_zeros:
            num[n + 1 - origin_zeros :] = 0.0
        candidates.append((num, den))
    scale = np.abs(np.linalg.eigvals(A))
    scale = scale[scale > 0]
    top = scale.max() * 10 if scale.size else 10.0
    points = 1j * np.geomspace(scale.min() / 10 if scale.size else 0.1, top, 16)
    ref = resolvent_response(A, b, c, d, points)
    errors = [
        np.max(
            np.abs(np.polyval(nm, points) / np.polyval(dn, points) - ref) / np.maximum(np.abs(ref), 1e-300)
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
    """Faddeev-LeVerrier coefficients, and which numerator coefficients are structurally zero."""
    n = A.shape[0]
    absA, absb, absc = np.abs(A), np.abs(b), np.abs(c)
    den, num = np.zeros(n + 1), np.zeros(n + 1)
    structural = np.zeros(n + 1, dtype=bool)
    den[0], num[0], structural[0] = 1.0, d, d == 0.0
    M, pattern = np.eye(n), np.eye(n)
    for k in range(1, n + 1):
        AM = A @ M
        den[k] = -np.trace(AM) / k
        num[k] = c @ M @ b + d * den[k]
        structural[k] = d == 0.0 and absc @ pattern @ absb == 0.0
        M = AM + den[k] * np.eye(n)
        pattern = absA @ pattern + np.eye(n)
    return num, den, structural


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


def plant_state_space(p: TableParameters) -> TableStateSpace:
    """Open-loop model Eq 4-11: inputs valve current u_i [mA] and force w [lbf].

    Built from the servovalve (Eq 4-3, scaled to unit DC gain from u_i) and the
    actuator-table model (Eq 4-9 with Eq 4-10a/b).
    """
    a1, a2 = p.valve_poles
    gamma, delta = a1 * a2, a1 + a2
    w2, eps = p.omega_oil**2, 2.0 * p.zeta_oil * p.omega_oil
    m, ap = p.mass, p.piston_area
    A = np.array(
        [
            [0.0, 1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, ap / m, 0.0, 0.0],
            [0.0, -w2 * m / ap, -eps, p.d, 0.0],
            [0.0, 0.0, 0.0, 0.0, 1.0],
            [0.0, 0.0, 0.0, -gamma, -delta],
        ]
    )
    B_i = np.array([0.0, 0.0, 0.0, 0.0, gamma])
    B_w = np.array([0.0, 1.0 / m, 0.0, 0.0, 0.0])
    C = {"z": A[1].copy(), "x": np.eye(5)[0], "v": np.eye(5)[1], "dp": np.eye(5)[2]}
    D = {"z": (0.0, 1.0 / m), "x": (0.0, 0.0), "v": (0.0, 0.0), "dp": (0.0, 0.0)}
    return TableStateSpace(A, B_i, B_w, C, D, PLANT_STATES, input_name="u_i")


def feedback_row(p: TableParameters) -> np.ndarray:
    """Row ``k`` with ``k x = K_e x_st + K_p dP`` [V], the delayed feedback of Section 4.3.4."""
    return np.array([p.Ke, 0.0, p.Kp, 0.0, 0.0])
