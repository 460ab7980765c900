"""Discrete pole-zero maps and structured state-space realizations (report Section 6.5, Steps 4-5).

MATLAB's ``c2d(prescale(ss(H)), dt, 'tustin')`` has no equivalent in scipy or
python-control, and a controllable-canonical realization of the discretized
``H_uz`` is useless in single precision: its characteristic polynomial has a
double root at z = 1 (the double integrator of ``H_uz``) which a float32
rounding of the coefficients moves by ~sqrt(eps) ~ 3e-4, i.e. off the unit
circle.  This module therefore

1. maps the continuous poles and zeros to the z plane one by one
   (Tustin, optionally pre-warped; matched pole-zero; zero-order hold), so that
   a pole at s = 0 lands *exactly* on z = 1;
2. groups the discrete poles and zeros into first- and second-order sections;
3. realizes each section in a form whose eigenvalues are its diagonal entries
   or a rotation block (real pairs: upper-triangular; complex pairs: the
   coupled "normal" form ``[[s, w], [-w, s]]``), so that rounding the matrix to
   float32 moves a pole only by ~eps*|p| and keeps z = 1 exact;
4. cascades the sections into one block-lower-triangular ``(A, B, C, D)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..lti import StateSpace
from ..ss2tf import ss_to_tf
from ..systems import TransferFunction
from ..units import TWO_PI

#: Discretization methods understood by :func:`discrete_zpk`.
METHODS = ("tustin", "zoh", "matched")

#: Relative size (to the largest coefficient) below which a trailing
#: denominator coefficient counts as an exact pole at s = 0.
ORIGIN_RTOL = 1e-12


@dataclass(frozen=True)
class DiscreteZPK:
    """A discrete-time transfer function ``k * prod(z - z_i) / prod(z - p_i)``.

    Attributes
    ----------
    zeros, poles : ndarray of complex
        Zeros and poles in the z plane (conjugate pairs both present).
    gain : float
        Gain of the monic factors.
    loop_time_s : float
        Sampling interval [s].
    """

    zeros: np.ndarray
    poles: np.ndarray
    gain: float
    loop_time_s: float

    def frequency_response(self, f_hz) -> np.ndarray:
        """Complex response at ``f_hz`` [Hz] (z = exp(j*2*pi*f*T))."""
        z = np.exp(1j * TWO_PI * np.asarray(f_hz, float) * self.loop_time_s)
        num = np.prod([z - q for q in self.zeros], axis=0) if self.zeros.size else 1.0
        den = np.prod([z - q for q in self.poles], axis=0) if self.poles.size else 1.0
        return self.gain * num / den


@dataclass(frozen=True)
class Section:
    """One first- or second-order section of a cascade realization.

    Attributes
    ----------
    poles, zeros : tuple of complex
        Its poles and zeros in the z plane.
    form : str
        ``"first-order"``, ``"coupled"`` (complex pair) or ``"triangular"``
        (real pair, including the exact double pole at z = 1).
    A, B, C, D : ndarray
        Its realization (``A`` is 1x1 or 2x2).
    """

    poles: tuple
    zeros: tuple
    form: str
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: float


def continuous_zpk(tf: TransferFunction) -> tuple[np.ndarray, np.ndarray, float, int]:
    """Zeros, poles [rad/s], gain and number of exact poles at s = 0 of ``tf``.

    Trailing denominator coefficients negligible relative to the largest
    (``ORIGIN_RTOL``) are exact poles at the origin; they are returned as exact
    zeros in ``poles`` and not left to root finding.
    """
    den = np.asarray(tf.den, float)
    num = np.asarray(tf.num, float)
    scale = np.max(np.abs(den))
    n0 = 0
    while den.size > 1 and abs(den[-1]) <= ORIGIN_RTOL * scale:
        den = den[:-1]
        n0 += 1
    poles = np.concatenate([np.roots(den) if den.size > 1 else np.zeros(0), np.zeros(n0)])
    zeros = np.roots(num) if num.size > 1 else np.zeros(0)
    gain = float(num[0] / tf.den[0])
    return zeros.astype(complex), poles.astype(complex), gain, n0


def _map_tustin(zeros, poles, gain, dt, prewarp_hz):
    """Bilinear map ``s = c (z - 1)/(z + 1)`` with ``c = 2/dt`` or pre-warped."""
    if prewarp_hz is None:
        c = 2.0 / dt
    else:
        w = TWO_PI * prewarp_hz
        c = w / np.tan(w * dt / 2.0)
    zd = (c + zeros) / (c - zeros)
    pd = (c + poles) / (c - poles)
    # Zeros at s = infinity map to z = -1.
    zd = np.concatenate([zd, -np.ones(poles.size - zeros.size)])
    k = gain * np.real(np.prod(c - zeros) / np.prod(c - poles))
    return zd, pd, float(k)


def _gain_at(zeros, poles, gain, dt, f_ref_hz, h_ref):
    """Gain that makes the discrete zpk match ``h_ref`` in magnitude at ``f_ref_hz``."""
    zz = np.exp(1j * TWO_PI * f_ref_hz * dt)
    shape = np.prod(zz - zeros) / np.prod(zz - poles)
    return float(np.abs(h_ref) / np.abs(shape)) * np.sign(gain)


def discrete_zpk(
    tf: TransferFunction,
    dt: float,
    method: str = "tustin",
    prewarp_hz: float | None = None,
    f_ref_hz: float = 1.0,
) -> DiscreteZPK:
    """Map a proper continuous transfer function to the z plane.

    Parameters
    ----------
    tf : TransferFunction
        Proper continuous-time transfer function (polynomials in s [rad/s]).
    dt : float
        Loop time [s].
    method : {"tustin", "zoh", "matched"}
        Tustin (bilinear, the report's choice), zero-order hold, or matched
        pole-zero (zeros at infinity to z = -1, gain matched at ``f_ref_hz``).
    prewarp_hz : float, optional
        Tustin pre-warping frequency [Hz] (exact response there).
    f_ref_hz : float
        Frequency [Hz] where the matched method matches the gain.

    Returns
    -------
    DiscreteZPK
        Poles at s = 0 are mapped exactly to z = 1 by every method.
    """
    if not tf.is_proper:
        raise ConfigError(
            "transfer function",
            "a proper transfer function (filter applied)",
            f"relative degree {tf.relative_degree}",
        )
    zeros, poles, gain, _ = continuous_zpk(tf)
    if method == "tustin":
        zd, pd, k = _map_tustin(zeros, poles, gain, dt, prewarp_hz)
    elif method == "matched":
        zd = np.concatenate([np.exp(zeros * dt), -np.ones(poles.size - zeros.size)])
        pd = np.exp(poles * dt)
        k = _gain_at(zd, pd, gain, dt, f_ref_hz, tf.frequency_response(f_ref_hz))
    elif method == "zoh":
        zd, pd, k = _map_zoh(tf, dt, poles)
    else:
        raise ConfigError("method", f"one of {', '.join(METHODS)}", method)
    return DiscreteZPK(np.asarray(zd, complex), np.asarray(pd, complex), k, dt)


def _map_zoh(tf, dt, poles):
    """ZOH: zeros and gain from the exact discretization (:meth:`StateSpace.zoh`), poles exp(p*dt) exactly."""
    sysd = tf.to_lti().zoh(dt)
    num, _ = ss_to_tf(sysd)
    zd = np.roots(num)
    pd = np.exp(poles * dt)
    zd = zd[np.isfinite(zd)]
    # Gain from the exact ZOH response at a frequency away from poles and zeros.
    f_ref = 0.1 / dt / TWO_PI
    zz = np.exp(1j * TWO_PI * f_ref * dt)
    h = sysd.frequency_response(f_ref)
    k = h / (np.prod(zz - zd) / np.prod(zz - pd))
    return zd, pd, float(np.real(k))


# ----------------------------------------------------------------- sections
def _split(roots, tol=1e-9):
    """Complex roots with positive imaginary part, and the real roots (sorted)."""
    roots = np.asarray(roots, complex)
    scale = max(1.0, float(np.max(np.abs(roots)))) if roots.size else 1.0
    cplx = [r for r in roots if r.imag > tol * scale]
    real = sorted(float(r.real) for r in roots if abs(r.imag) <= tol * scale)
    return cplx, real


def _group_poles(poles) -> list[tuple]:
    """Group poles into sections: complex pairs, then real pairs (equal/nearest first)."""
    cplx, real = _split(poles)
    groups = [(p, np.conj(p)) for p in cplx]
    real = sorted(real, key=lambda r: -r)  # z = 1 (integrators) first, then slower to faster
    while len(real) >= 2:
        groups.append((complex(real.pop(0)), complex(real.pop(0))))
    if real:
        groups.append((complex(real[0]),))
    return groups


def _take_zeros(groups, zeros) -> list[tuple]:
    """Assign to each pole group the same number of zeros, nearest first."""
    cplx, real = _split(zeros)
    pool_c = list(cplx)
    pool_r = list(real)
    out = []
    # Poles nearest the unit circle choose first (as scipy's ``pairing='nearest'``).
    order = sorted(range(len(groups)), key=lambda i: -abs(groups[i][0]))
    chosen = [None] * len(groups)
    for i in order:
        g = groups[i]
        need = len(g)
        p = g[0]
        picked: list[complex] = []
        if (
            need == 2
            and pool_c
            and (len(pool_r) < 2 or min(abs(c - p) for c in pool_c) <= min(abs(r - p) for r in pool_r))
        ):
            c = min(pool_c, key=lambda c: abs(c - p))
            pool_c.remove(c)
            picked = [c, np.conj(c)]
        while len(picked) < need and pool_r:
            r = min(pool_r, key=lambda r: abs(r - p))
            pool_r.remove(r)
            picked.append(complex(r))
        if len(picked) < need and pool_c:
            # A first-order section cannot take half a complex pair; should not happen
            # after discretization (as many zeros as poles).
            raise ConfigError("realization", "a pairable set of zeros", "unpaired complex zero")
        chosen[i] = tuple(picked)
    for i in range(len(groups)):
        out.append(chosen[i])
    return out


def _realize_section(poles, zeros, gain) -> Section:
    """Realize ``gain * prod(z - zeros) / prod(z - poles)`` (one or two poles)."""
    if len(poles) == 1:
        p = poles[0].real
        z1 = zeros[0].real if zeros else None
        r = gain * (p - z1) if z1 is not None else gain
        d = gain if z1 is not None else 0.0
        b = np.sqrt(abs(r)) if r != 0 else 1.0
        return Section(
            tuple(poles),
            tuple(zeros),
            "first-order",
            np.array([[p]]),
            np.array([b]),
            np.array([r / b]),
            float(d),
        )
    p1, p2 = poles
    zs = list(zeros) + [None] * (2 - len(zeros))
    # Numerator and denominator polynomials (monic den) in z.
    num = gain * np.real(np.poly([z for z in zs if z is not None]))
    num = np.concatenate([np.zeros(3 - num.size), num])
    den = np.real(np.poly([p1, p2]))
    d = num[0]
    r1 = num[1] - d * den[1]
    r0 = num[2] - d * den[2]
    if abs(p1.imag) > 0:
        s, w = p1.real, abs(p1.imag)
        A = np.array([[s, w], [-w, s]])
        beta = np.sqrt(np.hypot(r1, (r0 + r1 * s) / w)) or 1.0
        c1 = r1 / beta
        c2 = -(r0 / beta + c1 * s) / w
        return Section(
            tuple(poles), tuple(zeros), "coupled", A, np.array([beta, 0.0]), np.array([c1, c2]), float(d)
        )
    a, b = p1.real, p2.real
    A = np.array([[a, 1.0], [0.0, b]])
    beta = np.sqrt(np.hypot(r1, r0 + r1 * a)) or 1.0
    c2 = r1 / beta
    c1 = (r0 + r1 * a) / beta
    return Section(
        tuple(poles), tuple(zeros), "triangular", A, np.array([0.0, beta]), np.array([c1, c2]), float(d)
    )


def sections_from_zpk(zpk: DiscreteZPK, f_norm_hz: float) -> list[Section]:
    """Cascade sections of ``zpk``; integrator sections last (nearest the output).

    Each section except the last is scaled to unit gain at ``f_norm_hz`` [Hz];
    the last carries the remaining gain.
    """
    groups = _group_poles(zpk.poles)
    zero_groups = _take_zeros(groups, zpk.zeros)
    zz = np.exp(1j * TWO_PI * f_norm_hz * zpk.loop_time_s)
    # Order: sections with poles at z = 1 go last; the others keep their grouping order.
    order = sorted(range(len(groups)), key=lambda i: abs(groups[i][0] - 1.0) < 1e-15)
    sections = []
    remaining = zpk.gain
    for pos, i in enumerate(order):
        p, z = groups[i], zero_groups[i]
        if pos < len(order) - 1:
            shape = np.prod([zz - q for q in z]) / np.prod([zz - q for q in p])
            g = 1.0 / abs(shape)
            remaining /= g
        else:
            g = remaining
        sections.append(_realize_section(p, z, g))
    return sections


def cascade(sections: list[Section]) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Series connection ``S_1 -> S_2 -> ...`` as one ``(A, B, C, D)`` (float64)."""
    A = np.zeros((0, 0))
    B = np.zeros(0)
    C = np.zeros(0)
    D = 1.0
    for s in sections:
        n, m = A.shape[0], s.A.shape[0]
        A2 = np.zeros((n + m, n + m))
        A2[:n, :n] = A
        A2[n:, :n] = np.outer(s.B, C)
        A2[n:, n:] = s.A
        B2 = np.concatenate([B, s.B * D])
        C2 = np.concatenate([s.D * C, s.C])
        A, B, C, D = A2, B2, C2, s.D * D
    return A, B, C, float(D)


def canonical_realization(zpk: DiscreteZPK) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Controllable-canonical ``(A, B, C, D)`` of ``zpk`` (for comparison only).

    This is what ``ss()`` without ``prescale`` yields: poorly conditioned in
    single precision.
    """
    num = zpk.gain * np.real(np.poly(zpk.zeros))
    den = np.real(np.poly(zpk.poles))
    sys = StateSpace.from_polynomials(num, den, zpk.loop_time_s)
    return sys.A, sys.B[:, 0], sys.C[0], float(sys.D[0, 0])
