"""Linear-system value objects: continuous-time SISO transfer functions.

Why our own class and not ``control.TransferFunction``: the MIL controller
needs algebra on *improper* transfer functions (``H_uz = 1/H_zu`` has
relative degree -3 until a filter is applied) and pole-zero cancellation
with a *relative* tolerance.  python-control's ``minreal`` uses an absolute
``tol`` on root distances, which with poles at 2*pi*110 rad/s and at the
origin either cancels too much or too little.  Conversions to and from
python-control and the state-space object :class:`~impedance_mil.lti.StateSpace`
(``from_lti``, ``to_lti``; round-off safe, :func:`~impedance_mil.ss2tf.ss_to_tf`)
are provided for everything else.

Convention: coefficients in descending powers of s, frequencies in Hz at
the interface (:meth:`TransferFunction.frequency_response`) and rad/s
inside the polynomials.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from .errors import ConfigError, ImproperSystemError, OperandError, SingularSystemError
from .lazy import LazyModule
from .lti import StateSpace
from .ss2tf import ROUNDOFF_RTOL, ss_to_tf
from .units import TWO_PI

#: python-control, imported on first use: only the conversions need it (issue 16, start-up).
control = LazyModule("control")

#: Default relative tolerance for pole-zero cancellation.
CANCEL_RTOL = 1e-6

#: Relative size below which the sum of two coefficients counts as exact cancellation.
SUM_RTOL = 1e-12


def _trim(coeffs: np.ndarray) -> np.ndarray:
    """Drop leading coefficients that are exactly zero.

    Coefficients of polynomials in s [rad/s] routinely span 20 orders of
    magnitude (``1e-12 s**5 ... + 1``), so no tolerance relative to the largest
    coefficient is safe here; near-cancellation is removed where it arises
    (:func:`_padd`, :func:`~impedance_mil.ss2tf.ss_to_tf`).
    """
    c = np.atleast_1d(np.asarray(coeffs, dtype=float))
    if c.size == 0:
        return np.zeros(1)
    nz = np.nonzero(c)[0]
    if nz.size == 0:
        return np.zeros(1)
    return c[nz[0] :].copy()


def _padd(a: np.ndarray, b: np.ndarray, rtol: float = SUM_RTOL) -> np.ndarray:
    """Sum of two polynomials; a coefficient that cancels to rounding level becomes exactly 0."""
    n = max(a.size, b.size)
    pa, pb = np.pad(a, (n - a.size, 0)), np.pad(b, (n - b.size, 0))
    out = pa + pb
    out[np.abs(out) <= rtol * (np.abs(pa) + np.abs(pb))] = 0.0
    return out


def _real_poly(roots: Iterable[complex]) -> np.ndarray:
    r = np.asarray(list(roots), dtype=complex)
    if r.size == 0:
        return np.ones(1)
    return np.real(np.poly(r))


@dataclass(frozen=True, eq=False)
class TransferFunction:
    """A continuous-time SISO transfer function ``num(s)/den(s)``.

    Parameters
    ----------
    num, den : array_like
        Polynomial coefficients in descending powers of s.  The result is
        normalised so that ``den`` is monic; improper functions
        (``deg num > deg den``) are allowed.

    Examples
    --------
    >>> H = TransferFunction([1.0], [1.0, 2.0])
    >>> (H * H.inv()).minreal().num
    array([1.])
    """

    num: np.ndarray
    den: np.ndarray

    def __post_init__(self):
        num = _trim(self.num)
        den = _trim(self.den)
        if den.size == 1 and den[0] == 0:
            raise SingularSystemError("transfer function with a zero denominator")
        lead = den[0]
        object.__setattr__(self, "num", num / lead)
        object.__setattr__(self, "den", den / lead)
        self.num.setflags(write=False)
        self.den.setflags(write=False)

    # ------------------------------------------------------------------ build
    @classmethod
    def constant(cls, k: float) -> TransferFunction:
        """The static gain ``k``."""
        return cls([float(k)], [1.0])

    @classmethod
    def s(cls) -> TransferFunction:
        """The Laplace variable ``s``."""
        return cls([1.0, 0.0], [1.0])

    @classmethod
    def from_ss(cls, A, B, C, D=0.0) -> TransferFunction:
        """Transfer function of a SISO state-space model ``(A, B, C, D)`` (see :meth:`from_lti`)."""
        return cls.from_lti(StateSpace(A, B, C, D))

    @classmethod
    def from_lti(
        cls, sys: StateSpace, cancel_rtol: float | None = None, roundoff_rtol: float = ROUNDOFF_RTOL
    ) -> TransferFunction:
        """Transfer function of a continuous SISO :class:`~impedance_mil.lti.StateSpace`.

        The polynomials come from :func:`~impedance_mil.ss2tf.ss_to_tf`:
        round-off coefficients at either end of the numerator are exact
        zeros, so the relative degree and the zeros at the origin are right.

        Parameters
        ----------
        sys : StateSpace
            Continuous (``dt = 0``), one input and one output (see ``StateSpace.channel``).
        cancel_rtol : float, optional
            Cancel pole-zero pairs closer than this relative tolerance
            (:meth:`minreal`; dimensionless), e.g. :data:`CANCEL_RTOL`.
            None keeps every eigenvalue of ``A`` as a pole.  The polynomials
            are returned unchanged when no pair cancels.
        roundoff_rtol : float
            Threshold of :func:`~impedance_mil.ss2tf.ss_to_tf` (dimensionless).

        Raises
        ------
        ValueError
            ``sys`` is discrete or not SISO (a :class:`~impedance_mil.errors.ConfigError`).
        """
        if sys.is_discrete:
            raise ConfigError(
                "state_space", "a continuous system (dt = 0) for a transfer function in s", sys.dt
            )
        tf = cls(*ss_to_tf(sys, roundoff_rtol))
        if cancel_rtol is None:
            return tf
        reduced = tf.minreal(cancel_rtol)
        return reduced if reduced.order < tf.order else tf

    @classmethod
    def from_zpk(cls, zeros, poles, gain: float) -> TransferFunction:
        """Build from zeros, poles [rad/s] and the gain of the monic factors."""
        return cls(gain * _real_poly(zeros), _real_poly(poles))

    @classmethod
    def from_control(cls, sys) -> TransferFunction:
        """Convert a continuous SISO ``control.TransferFunction`` or ``control.StateSpace``.

        A state space goes through :meth:`from_lti` (round-off safe), not
        through python-control's own conversion.
        """
        if isinstance(sys, control.TransferFunction):
            if sys.ninputs != 1 or sys.noutputs != 1 or sys.isdtime(strict=True):
                raise ConfigError("system", "a continuous SISO transfer function", str(sys))
            return cls(np.asarray(sys.num[0][0], float), np.asarray(sys.den[0][0], float))
        return cls.from_lti(StateSpace.from_control(sys))

    # ------------------------------------------------------------- properties
    @property
    def order(self) -> int:
        """Degree of the denominator."""
        return self.den.size - 1

    @property
    def relative_degree(self) -> int:
        """``deg den - deg num``; negative for an improper function."""
        if self.is_zero:
            return 0
        return (self.den.size - 1) - (self.num.size - 1)

    @property
    def is_zero(self) -> bool:
        return self.num.size == 1 and self.num[0] == 0

    @property
    def is_proper(self) -> bool:
        return self.relative_degree >= 0

    @property
    def is_strictly_proper(self) -> bool:
        return self.relative_degree > 0

    def poles(self) -> np.ndarray:
        """Roots of the denominator [rad/s]."""
        return np.roots(self.den) if self.den.size > 1 else np.zeros(0, complex)

    def zeros(self) -> np.ndarray:
        """Roots of the numerator [rad/s]."""
        return np.roots(self.num) if self.num.size > 1 else np.zeros(0, complex)

    def is_stable(self, margin: float = 0.0) -> bool:
        """True when every pole has real part < ``-margin`` [rad/s]."""
        p = self.poles()
        return bool(np.all(p.real < -margin)) if p.size else True

    def dcgain(self) -> float:
        """Value at s = 0 (inf where the function has a pole at the origin)."""
        if self.den[-1] == 0:
            return float("inf") if self.num[-1] != 0 else float("nan")
        return float(self.num[-1] / self.den[-1])

    # --------------------------------------------------------------- evaluate
    def __call__(self, s):
        """Evaluate at complex frequency ``s`` [rad/s]."""
        s = np.asarray(s, dtype=complex)
        return np.polyval(self.num, s) / np.polyval(self.den, s)

    def frequency_response(self, f_hz) -> np.ndarray:
        """Complex response at frequencies ``f_hz`` [Hz]."""
        return self(1j * TWO_PI * np.asarray(f_hz, dtype=float))

    # ---------------------------------------------------------------- algebra
    def _coerce(self, other) -> TransferFunction:
        if isinstance(other, TransferFunction):
            return other
        if isinstance(other, (int, float, np.number)):
            return TransferFunction.constant(float(other))
        return NotImplemented

    def __add__(self, other):
        o = self._coerce(other)
        if o is NotImplemented:
            return o
        num = _padd(np.polymul(self.num, o.den), np.polymul(o.num, self.den))
        return TransferFunction(num, np.polymul(self.den, o.den))

    __radd__ = __add__

    def __neg__(self):
        return TransferFunction(-self.num, self.den)

    def __sub__(self, other):
        o = self._coerce(other)
        if o is NotImplemented:
            return o
        return self + (-o)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, other):
        o = self._coerce(other)
        if o is NotImplemented:
            return o
        return TransferFunction(np.polymul(self.num, o.num), np.polymul(self.den, o.den))

    __rmul__ = __mul__

    def __truediv__(self, other):
        o = self._coerce(other)
        if o is NotImplemented:
            return o
        return self * o.inv()

    def __rtruediv__(self, other):
        return self.inv() * other

    def inv(self) -> TransferFunction:
        """The reciprocal ``den/num`` (may be improper)."""
        if self.is_zero:
            raise SingularSystemError("inverse of a zero transfer function")
        return TransferFunction(self.den, self.num)

    def feedback(self, other=1.0, sign: int = -1) -> TransferFunction:
        """Closed loop ``self / (1 - sign*self*other)`` (negative feedback by default)."""
        o = self._coerce(other)
        num = np.polymul(self.num, o.den)
        den = _padd(np.polymul(self.den, o.den), -sign * np.polymul(self.num, o.num))
        return TransferFunction(num, den)

    # ----------------------------------------------------------- cancellation
    def minreal(self, rtol: float = CANCEL_RTOL) -> TransferFunction:
        """Cancel common poles and zeros with a relative tolerance.

        A zero ``z`` and a pole ``p`` cancel when
        ``|z - p| <= rtol * max(|z|, |p|)``; common factors of ``s`` (exact
        roots at the origin, recognised from trailing coefficients that are
        negligible relative to the polynomial's scale) cancel first.

        Parameters
        ----------
        rtol : float
            Relative tolerance (dimensionless).
        """
        if self.is_zero:
            return TransferFunction.constant(0.0)
        num, den = self.num.copy(), self.den.copy()
        # Strip common powers of s exactly, so that the origin is not left to root-finding.
        while num.size > 1 and den.size > 1 and _negligible_tail(num) and _negligible_tail(den):
            num, den = num[:-1], den[:-1]
        gain = num[0] / den[0]
        zeros = list(np.roots(num)) if num.size > 1 else []
        poles = list(np.roots(den)) if den.size > 1 else []
        kept_zeros = []
        for z in zeros:
            match = _nearest_cancelling_pole(z, poles, num, den, rtol)
            if match is None:
                kept_zeros.append(z)
            else:
                poles.pop(match)
        return TransferFunction(gain * _real_poly(kept_zeros), _real_poly(poles))

    def mul_cancel(self, other, rtol: float = CANCEL_RTOL) -> TransferFunction:
        """Product ``self*other`` with pole-zero cancellation done factor by factor.

        The cross ratios ``num_a/den_b`` and ``num_b/den_a`` are reduced
        before multiplying, so common factors are found among the roots of
        the low-degree factors (accurate to rounding) instead of among the
        roots of the product polynomials (where clustered roots lose digits).

        Parameters
        ----------
        other : TransferFunction or float
        rtol : float
            Relative tolerance of the cancellation (dimensionless).
        """
        o = self._coerce(other)
        if o is NotImplemented:
            raise OperandError(f"cannot multiply a TransferFunction by {type(other).__name__}")
        left = TransferFunction(self.num, o.den).minreal(rtol)
        right = TransferFunction(o.num, self.den).minreal(rtol)
        return (left * right).minreal(rtol)

    def div_cancel(self, other, rtol: float = CANCEL_RTOL) -> TransferFunction:
        """Quotient ``self/other`` with factor-wise cancellation (see :meth:`mul_cancel`)."""
        o = self._coerce(other)
        if o is NotImplemented:
            raise OperandError(f"cannot divide a TransferFunction by {type(other).__name__}")
        return self.mul_cancel(o.inv(), rtol)

    # ------------------------------------------------------------ comparisons
    def isclose(self, other: TransferFunction, rtol: float = 1e-9) -> bool:
        """Coefficient-wise comparison after normalisation (same degrees required)."""
        if self.num.size != other.num.size or self.den.size != other.den.size:
            return False
        return bool(
            np.allclose(self.num, other.num, rtol=rtol, atol=0)
            and np.allclose(self.den, other.den, rtol=rtol, atol=0)
        )

    # ------------------------------------------------------------- conversion
    def to_control(self):
        """As a ``control.TransferFunction`` (proper functions only for simulation)."""
        return control.tf(self.num, self.den)

    def to_lti(self, input: str = "u0", output: str = "y0") -> StateSpace:
        """Controllable-canonical :class:`~impedance_mil.lti.StateSpace` of a proper function.

        Raises
        ------
        ImproperSystemError
            The function is improper.
        """
        return StateSpace.from_polynomials(self.num, self.den, 0.0, input, output)

    def to_ss(self):
        """Controllable-canonical ``(A, B, C, D)`` of a proper function (the matrices of :meth:`to_lti`)."""
        if not self.is_proper:
            raise ImproperSystemError("an improper transfer function has no state-space realization")
        sys = self.to_lti()
        return sys.A, sys.B, sys.C, sys.D

    @classmethod
    def from_dict(cls, data) -> TransferFunction:
        """Inverse of :meth:`to_dict`.

        Raises
        ------
        ConfigError
            ``data`` is not a mapping with numeric lists ``num`` and ``den`` (a ValueError).
        """
        try:
            num = np.asarray(data["num"], dtype=float)
            den = np.asarray(data["den"], dtype=float)
        except (KeyError, TypeError, ValueError) as exc:
            raise ConfigError("transfer function", f"{{'num': [...], 'den': [...]}} ({exc})") from None
        if num.ndim != 1 or den.ndim != 1 or not (np.all(np.isfinite(num)) and np.all(np.isfinite(den))):
            raise ConfigError("transfer function", "num and den as flat lists of finite numbers")
        return cls(num, den)

    def to_dict(self) -> dict:
        """``{"num": [...], "den": [...]}`` in descending powers of s."""
        return {"num": [float(c) for c in self.num], "den": [float(c) for c in self.den]}

    def to_zpk(self) -> dict:
        """``{"zeros": [[re, im], ...], "poles": [[re, im], ...], "gain": k}``: roots [rad/s], sorted by size.

        ``H = k prod(s - z_i) / prod(s - p_i)`` (the gain of the monic factors,
        ``num[0]/den[0]``; 0 for the zero function, with no zeros); the layout
        of a zpk table file (:mod:`impedance_mil.plant.lti_table`) and of the
        optimized design's ``zpk``.
        """

        def pairs(roots) -> list[list[float]]:
            return [[float(r.real), float(r.imag)] for r in sorted(np.asarray(roots, complex), key=abs)]

        gain = 0.0 if self.is_zero else float(self.num[0] / self.den[0])
        return {
            "zeros": [] if self.is_zero else pairs(self.zeros()),
            "poles": pairs(self.poles()),
            "gain": gain,
        }

    def __repr__(self) -> str:
        return f"TransferFunction(num={self.num.tolist()}, den={self.den.tolist()})"


def _negligible_tail(c: np.ndarray, rtol: float = 1e-12) -> bool:
    """True when the polynomial has a root at the origin.

    Scale-free test: exactly zero, or the smallest root ``~ c[-1]/c[-2]`` is
    ``rtol`` times smaller than the next root scale ``~ c[-2]/c[-3]``.
    """
    if c[-1] == 0:
        return True
    if c.size < 3 or c[-2] == 0 or c[-3] == 0:
        return False
    return abs(c[-1] * c[-3]) <= rtol * c[-2] ** 2


def _backward_error(coeffs: np.ndarray, r: complex) -> float:
    """Relative backward error of ``r`` as a root of the polynomial ``coeffs``."""
    scale = np.polyval(np.abs(coeffs), abs(r))
    return float(abs(np.polyval(coeffs, r)) / scale) if scale > 0 else 0.0


def _nearest_cancelling_pole(z: complex, poles: list, num: np.ndarray, den: np.ndarray, rtol: float):
    """Index of the pole that cancels the zero ``z``, or None.

    A pair cancels when ``|z - p| <= rtol*max(|z|, |p|)``, or, for clustered
    roots whose computed positions lose digits, when ``|z - p|`` is within
    ``sqrt(rtol)`` relative and each is a root of the other polynomial to a
    relative backward error ``rtol``.
    """
    best, match = np.inf, None
    for i, p in enumerate(poles):
        dist = abs(z - p)
        size = max(abs(z), abs(p))
        ok = dist <= rtol * size or (
            dist <= np.sqrt(rtol) * size
            and _backward_error(num, p) <= rtol
            and _backward_error(den, z) <= rtol
        )
        if ok and dist < best:
            match, best = i, dist
    return match


def pole_table(poles: np.ndarray) -> list[dict]:
    """Frequency [Hz], damping ratio and position [rad/s] of each pole.

    Poles are sorted by frequency; a conjugate pair appears twice (as in the
    report's Tables 4.2 and 4.3).  A pole at the origin has frequency 0 and
    damping ``nan``; a pole in the right half plane has negative damping.
    """
    rows = []
    for p in sorted(np.asarray(poles, dtype=complex), key=lambda q: (abs(q), q.imag)):
        w = abs(p)
        rows.append(
            {
                "frequency_hz": float(w / TWO_PI),
                "damping": float(-p.real / w) if w > 0 else float("nan"),
                "real": float(p.real),
                "imag": float(p.imag),
            }
        )
    return rows
