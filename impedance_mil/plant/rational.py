"""Rational transfer-function fit to a measured FRF, with stable poles and confidence intervals.

The model is ``H(s) = (s / w0)^q N(s / w0) / D(s / w0)``: ``q`` known zeros at the
origin (2 for the table acceleration against a position command, ``z = s^2 x``),
a numerator ``N`` of degree ``m`` and a monic denominator ``D`` of degree ``n``
(the *order*), in the frequency scaled by ``w0 = 2 pi f_max`` so that the
coefficients stay of order one.

1. **Sanathanan-Koerner iterations** (Sanathanan and Koerner 1963, "Transfer
   function synthesis as a ratio of two complex polynomials", IEEE Trans.
   Automatic Control 8(1):56-58): the linear least-squares problem
   ``min sum |w_k / (|H_k| D_prev(s_k))|^2 |s_k^q N(s_k) - H_k D(s_k)|^2`` is solved
   again with the previous denominator until the poles settle.  The weights
   ``w_k / |H_k|`` make it the first-order expansion of the log error below.
   Unstable poles are reflected into the left half-plane after each iteration
   (as in vector fitting: Gustavsen and Semlyen 1999, IEEE Trans. Power Delivery
   14(3):1052-1061).
2. **Refinement** by Levenberg-Marquardt (``scipy.optimize.least_squares``) on
   the weighted log error ``w_k log(H_model / H_k)`` (real part and wrapped phase,
   as :func:`impedance_mil.signals.frf.fit_frf`), the poles parameterized so that
   they are stable by construction: a real pole ``-exp(a)``, a pair
   ``s^2 + 2 exp(b) exp(c) s + exp(2 c)``.
3. **Confidence intervals** from the Jacobian at the optimum,
   ``cov = s^2 (J^T J)^-1`` (Seber and Wild 1989, *Nonlinear Regression*, Section 5.1),
   propagated to the pole frequencies, dampings and the DC gain (delta method).

:func:`select_order` fits every order up to a bound and keeps the one with the
smallest Bayesian information criterion ``RSS + p ln(2 N)`` (Schwarz 1978), RSS
the weighted residual sum of squares (a chi-square when the weights are the
inverse standard deviations of the estimate).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..lazy import LazyModule
from ..signals.frf import FRF, log_covariance

#: scipy.optimize, imported on first use (issue 16: a command that only reads a configuration does not need it).
scipy_optimize = LazyModule("scipy.optimize")

#: SK iterations at most, and the relative change of the poles that stops them.
SK_ITERATIONS = 60
SK_TOLERANCE = 1e-10
#: Largest order fitted by :func:`select_order` unless told.
MAX_AUTO_ORDER = 8
#: Largest numerator degree tried by :func:`select_order`, and the orders it goes on without a better fit.
MAX_AUTO_NUM_ORDER = 3
AUTO_PATIENCE = 2
#: Two-sided 95 % normal quantile of the confidence intervals.
Z95 = 1.959963984540054


@dataclass(frozen=True)
class Pole:
    """One real pole or one complex pair of a fitted model.

    Attributes
    ----------
    frequency_hz : float
        Natural frequency ``|p| / 2 pi`` [Hz].
    damping : float
        ``-Re p / |p|`` (1 for a real pole).
    ci95_frequency_hz, ci95_damping : (float, float)
        95 % confidence intervals (NaN without a covariance).
    pair : bool
        A complex pair (listed once, positive imaginary part).
    """

    frequency_hz: float
    damping: float
    ci95_frequency_hz: tuple[float, float]
    ci95_damping: tuple[float, float]
    pair: bool

    @property
    def roots_hz(self) -> list[complex]:
        """The pole(s) [Hz]: ``p / 2 pi``."""
        f, z = self.frequency_hz, self.damping
        if not self.pair:
            return [complex(-f)]
        im = f * np.sqrt(max(1.0 - z * z, 0.0))
        return [complex(-z * f, im), complex(-z * f, -im)]

    def to_dict(self) -> dict:
        return {
            "frequency_hz": self.frequency_hz,
            "damping": self.damping,
            "ci95_frequency_hz": list(self.ci95_frequency_hz),
            "ci95_damping": list(self.ci95_damping),
            "complex_pair": self.pair,
        }


@dataclass(frozen=True, eq=False)
class RationalFit:
    """A fitted rational model ``H(s) = num(s) / den(s)``, s in rad/s.

    Attributes
    ----------
    num, den : ndarray
        Coefficients in descending powers of s, ``den`` monic (output unit / input unit).
    poles : tuple of Pole
        Sorted by frequency.
    zeros_at_origin : int
        ``q``.
    dc_gain : float
        ``lim s->0 H(s) / s^q`` (for ``z/u`` with q = 2: the DC gain of ``x/u``).
    ci95_dc_gain : (float, float)
    order, num_order : int
        Degrees of the denominator and of ``N``.
    rms_log_error : float
        RMS ``|log(H_model / H_meas)|`` over the lines (0.01 ~ 1 % / 0.6 deg).
    chi2_reduced : float or None
        Weighted residual mean square per degree of freedom.
    bic : float
        Bayesian information criterion of the fit.
    n_lines : int
    """

    num: np.ndarray
    den: np.ndarray
    poles: tuple[Pole, ...]
    zeros_at_origin: int
    dc_gain: float
    ci95_dc_gain: tuple[float, float]
    order: int
    num_order: int
    rms_log_error: float
    chi2_reduced: float | None
    bic: float
    n_lines: int

    def response(self, f_hz) -> np.ndarray:
        """``H(j 2 pi f)`` at ``f_hz`` [Hz]."""
        s = 2j * np.pi * np.asarray(f_hz, dtype=float)
        return np.polyval(self.num, s) / np.polyval(self.den, s)

    @property
    def poles_hz(self) -> list[float]:
        """Natural frequencies [Hz] of the real poles and of the complex pairs (each pair once)."""
        return [p.frequency_hz for p in self.poles]

    @property
    def zeros_hz(self) -> list[complex]:
        """Zeros [Hz] of ``num`` (``roots / 2 pi``), the zeros at the origin included."""
        return [complex(z) / (2 * np.pi) for z in np.roots(self.num)] if self.num.size > 1 else []

    def to_dict(self) -> dict:
        return {
            "order": self.order,
            "num_order": self.num_order,
            "zeros_at_origin": self.zeros_at_origin,
            "poles_hz": self.poles_hz,
            "poles": [p.to_dict() for p in self.poles],
            "zeros_hz": [[z.real, z.imag] for z in self.zeros_hz],
            "dc_gain": self.dc_gain,
            "ci95_dc_gain": list(self.ci95_dc_gain),
            "num": self.num.tolist(),
            "den": self.den.tolist(),
            "rms_log_error": self.rms_log_error,
            "chi2_reduced": self.chi2_reduced,
            "bic": self.bic,
            "n_lines": self.n_lines,
        }


# ------------------------------------------------------------------ SK
def _stable(poles: np.ndarray) -> np.ndarray:
    """Poles reflected into the open left half-plane (a pole on the axis moved just left of it)."""
    re = -np.abs(poles.real)
    re = np.where(re == 0.0, -1e-6, re)
    return re + 1j * poles.imag


def _sk_poles(x, h, weight, q: int, n: int, m: int) -> np.ndarray:
    """Sanathanan-Koerner iterations; poles in the scaled variable (stable)."""
    den_prev = np.ones_like(x)
    poles = np.zeros(n, dtype=complex)
    xq = x**q
    base = weight / np.abs(h)
    for _ in range(SK_ITERATIONS):
        w = base / np.abs(den_prev)
        cols = [w * xq * x**i for i in range(m + 1)] + [-w * h * x**i for i in range(n)]
        A = np.column_stack(cols)
        rhs = w * h * x**n
        A_real = np.vstack([A.real, A.imag])
        b_real = np.concatenate([rhs.real, rhs.imag])
        scale = np.linalg.norm(A_real, axis=0)
        scale[scale == 0] = 1.0
        coef = np.linalg.lstsq(A_real / scale, b_real, rcond=None)[0] / scale
        a = np.concatenate([[1.0], coef[m + 1 :][::-1]])
        new = _stable(np.roots(a)) if n else np.zeros(0, complex)
        den_prev = np.polyval(np.real(np.poly(new)), x) if n else np.ones_like(x)
        change = (
            np.max(np.abs(np.sort_complex(new) - np.sort_complex(poles)) / np.maximum(np.abs(new), 1e-12))
            if n
            else 0.0
        )
        poles = new
        if change < SK_TOLERANCE:
            break
    return poles


# ------------------------------------------------------------------ refinement
def _split(poles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Real poles and the upper members of the complex pairs."""
    tol = 1e-9 * np.maximum(np.abs(poles), 1e-12)
    real = poles[np.abs(poles.imag) <= tol].real
    upper = poles[poles.imag > tol]
    return real, upper


def _pole_params(real: np.ndarray, upper: np.ndarray) -> np.ndarray:
    a = np.log(-real)
    wn = np.abs(upper)
    zeta = -upper.real / wn
    return np.concatenate([a, np.log(zeta), np.log(wn)])


def _den_from(theta: np.ndarray, n_real: int, n_pair: int) -> np.ndarray:
    den = np.array([1.0])
    for a in theta[:n_real]:
        den = np.polymul(den, [1.0, np.exp(a)])
    lz, lw = theta[n_real : n_real + n_pair], theta[n_real + n_pair : n_real + 2 * n_pair]
    for z, w in zip(np.exp(lz), np.exp(lw)):
        den = np.polymul(den, [1.0, 2.0 * z * w, w * w])
    return den


def _log_residual(model, h, weight):
    r = np.log(model / h)
    return np.concatenate([weight * r.real, weight * np.angle(np.exp(1j * r.imag))])


@dataclass(frozen=True)
class _Layout:
    n_real: int
    n_pair: int
    m: int
    q: int

    @property
    def n_pole_params(self) -> int:
        return self.n_real + 2 * self.n_pair

    def model(self, theta, x):
        den = _den_from(theta, self.n_real, self.n_pair)
        num = theta[self.n_pole_params :][::-1]  # b_m .. b_0
        return x**self.q * np.polyval(num, x) / np.polyval(den, x)

    def log_jacobian(self, theta, x) -> np.ndarray:
        """``d log H / d theta`` (complex, lines x parameters): each factor's logarithmic derivative."""
        nr, npair = self.n_real, self.n_pair
        cols = []
        for a in theta[:nr]:
            cols.append(-np.exp(a) / (x + np.exp(a)))
        z, w = np.exp(theta[nr : nr + npair]), np.exp(theta[nr + npair : nr + 2 * npair])
        factors = [x * x + 2 * zk * wk * x + wk * wk for zk, wk in zip(z, w)]
        cols += [-(2 * zk * wk * x) / fk for zk, wk, fk in zip(z, w, factors)]
        cols += [-(2 * zk * wk * x + 2 * wk * wk) / fk for zk, wk, fk in zip(z, w, factors)]
        n_x = np.polyval(theta[self.n_pole_params :][::-1], x)
        cols += [x**i / n_x for i in range(self.m + 1)]
        return np.column_stack(cols)


def _numerator_ls(x, h, weight, q, m, den) -> np.ndarray:
    """Numerator coefficients b_0..b_m for a fixed denominator (linear in them)."""
    d = np.polyval(den, x)
    w = weight / np.abs(h)
    A = np.column_stack([w * x**q * x**i / d for i in range(m + 1)])
    A_real = np.vstack([A.real, A.imag])
    b = np.concatenate([(w * h).real, (w * h).imag])
    return np.linalg.lstsq(A_real, b, rcond=None)[0]


def fit_rational(
    frf: FRF, order: int, *, num_order: int | None = None, zeros_at_origin: int = 0, weights=None
) -> RationalFit:
    """Fit ``H(s) = s^q N(s) / D(s)`` of denominator degree ``order`` to ``frf`` (see the module docstring).

    Parameters
    ----------
    frf : FRF
        Measured response at its lines [output unit / input unit].
    order : int
        Degree of the denominator (number of poles), >= 1.
    num_order : int, optional
        Degree of ``N`` (default ``order - zeros_at_origin - 1``, at least 0: a strictly proper model).
    zeros_at_origin : int
        ``q`` (2 for ``z/u``).
    weights : array_like, optional
        Weight of each line (default ``sqrt(2) |H| / frf.std`` when the FRF carries
        its standard deviation, else 1).

    Returns
    -------
    RationalFit

    Examples
    --------
    >>> f = np.linspace(1, 100, 200); s = 2j * np.pi * f
    >>> h = 1 / (1 + s / (2 * np.pi * 20))
    >>> fit = fit_rational(FRF(f, h, np.ones(f.size), 1), 1, num_order=0)
    >>> round(fit.poles_hz[0], 6), round(fit.dc_gain, 6)
    (20.0, 1.0)
    """
    if isinstance(order, bool) or int(order) != order or order < 1:
        raise ConfigError("--order", "a whole number of poles >= 1", order)
    q = int(zeros_at_origin)
    m = max(order - q - 1, 0) if num_order is None else int(num_order)
    if m < 0 or q < 0:
        raise ConfigError("--num-order", "a non-negative numerator degree", num_order)
    f = np.asarray(frf.frequency_hz, dtype=float)
    h = np.asarray(frf.response, dtype=complex)
    n_params = order + m + 1
    if 2 * f.size <= n_params or np.any(h == 0):
        raise ConfigError("--order", f"fewer parameters than the {2 * f.size} values of the FRF", order)
    if weights is None:
        weights = np.sqrt(2.0) * np.abs(h) / frf.std if frf.std is not None else np.ones(f.size)
    weight = np.asarray(weights, dtype=float)
    w0 = 2.0 * np.pi * float(f.max())
    x = 2j * np.pi * f / w0
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):  # trial steps may overflow
        return _fit(x, h, weight, q, order, m, w0)


def _fit(x, h, weight, q: int, order: int, m: int, w0: float) -> RationalFit:
    real, upper = _split(_sk_poles(x, h, weight, q, order, m))
    layout = _Layout(real.size, upper.size, m, q)
    theta0 = _pole_params(real, upper)
    b0 = _numerator_ls(x, h, weight, q, m, _den_from(theta0, layout.n_real, layout.n_pair))
    start = np.concatenate([theta0, b0])

    def jacobian(th):
        d = layout.log_jacobian(th, x) * weight[:, None]
        return np.vstack([d.real, d.imag])

    sol = scipy_optimize.least_squares(
        lambda th: _log_residual(layout.model(th, x), h, weight),
        start,
        jac=jacobian,
        method="lm",
        xtol=1e-12,
        ftol=1e-12,
    )
    return _result(sol, layout, x, h, weight, w0, order)


def _result(sol, layout: _Layout, x, h, weight, w0: float, order: int) -> RationalFit:
    theta = sol.x
    cov, chi2 = log_covariance(sol.jac, sol.fun)
    npp = layout.n_pole_params
    den_x = _den_from(theta, layout.n_real, layout.n_pair)
    num_x = theta[npp:][::-1]
    # back to s [rad/s]: x = s / w0; monic in s
    n, m, q = order, layout.m, layout.q
    den = den_x / w0 ** np.arange(n, -1, -1) * w0**n
    num = np.concatenate([num_x / w0 ** (np.arange(m, -1, -1) + q), np.zeros(q)]) * w0**n
    poles = _poles(theta, cov, layout, w0)
    dc = _dc_gain(theta, layout, w0)
    dc_ci = _dc_interval(theta, cov, layout, w0)
    model = layout.model(theta, x)
    r = np.log(model / h)
    rms = float(np.sqrt(np.mean(r.real**2 + np.angle(np.exp(1j * r.imag)) ** 2)))
    rss = float(sol.fun @ sol.fun)
    return RationalFit(
        num=num,
        den=den,
        poles=poles,
        zeros_at_origin=q,
        dc_gain=dc,
        ci95_dc_gain=dc_ci,
        order=order,
        num_order=m,
        rms_log_error=rms,
        chi2_reduced=chi2,
        bic=rss + theta.size * float(np.log(sol.fun.size)),
        n_lines=int(h.size),
    )


def _interval(value: float, log_var: float) -> tuple[float, float]:
    if not np.isfinite(log_var) or log_var < 0:
        return (float("nan"), float("nan"))
    s = float(np.sqrt(log_var))
    return (value * float(np.exp(-Z95 * s)), value * float(np.exp(Z95 * s)))


def _poles(theta, cov, layout: _Layout, w0: float) -> tuple[Pole, ...]:
    hz = w0 / (2.0 * np.pi)
    var = np.diag(cov) if cov is not None else np.full(theta.size, np.nan)
    poles = []
    for i in range(layout.n_real):
        f = float(np.exp(theta[i]) * hz)
        poles.append(Pole(f, 1.0, _interval(f, var[i]), (1.0, 1.0), False))
    for k in range(layout.n_pair):
        iz, iw = layout.n_real + k, layout.n_real + layout.n_pair + k
        z, f = float(np.exp(theta[iz])), float(np.exp(theta[iw]) * hz)
        poles.append(Pole(f, z, _interval(f, var[iw]), _interval(z, var[iz]), True))
    return tuple(sorted(poles, key=lambda p: p.frequency_hz))


def _dc_gain(theta, layout: _Layout, w0: float) -> float:
    den = _den_from(theta, layout.n_real, layout.n_pair)
    with np.errstate(divide="ignore", invalid="ignore"):
        return float(theta[layout.n_pole_params] / den[-1]) / w0**layout.q


def _dc_interval(theta, cov, layout: _Layout, w0: float) -> tuple[float, float]:
    """95 % interval of the DC gain by the delta method (central differences of the gain)."""
    if cov is None:
        return (float("nan"), float("nan"))
    grad = np.zeros(theta.size)
    for i in range(theta.size):
        step = 1e-6 * max(1.0, abs(theta[i]))
        up, down = theta.copy(), theta.copy()
        up[i] += step
        down[i] -= step
        grad[i] = (_dc_gain(up, layout, w0) - _dc_gain(down, layout, w0)) / (2 * step)
    sigma = float(np.sqrt(max(grad @ cov @ grad, 0.0)))
    dc = _dc_gain(theta, layout, w0)
    return (dc - Z95 * sigma, dc + Z95 * sigma)


def select_order(
    frf: FRF, *, max_order: int = MAX_AUTO_ORDER, zeros_at_origin: int = 0, weights=None
) -> RationalFit:
    """The fit of smallest BIC over orders 1..``max_order`` and numerator degrees 0..min(order, 3).

    The search stops after :data:`AUTO_PATIENCE` orders without a smaller BIC
    (see the module docstring).
    """
    best: RationalFit | None = None
    stale = 0
    for order in range(1, int(max_order) + 1):
        improved = False
        for m in range(0, min(order, MAX_AUTO_NUM_ORDER) + 1):
            if 2 * frf.frequency_hz.size <= order + m + 1:
                continue
            try:
                fit = fit_rational(frf, order, num_order=m, zeros_at_origin=zeros_at_origin, weights=weights)
            except (np.linalg.LinAlgError, ValueError):
                continue
            if np.isfinite(fit.bic) and (best is None or fit.bic < best.bic):
                best, improved = fit, True
        stale = 0 if improved else stale + 1
        if stale >= AUTO_PATIENCE:
            break
    if best is None:
        raise ConfigError("--order", "an order the FRF can support (too few lines)", "auto")
    return best
