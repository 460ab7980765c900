"""Frequency-response function estimation and model fitting (report Sections 4.5.3-4.5.4).

* :func:`estimate_frf`: H1 estimate ``S_yu / S_uu`` and coherence from a
  periodic test, one FFT per period, averaged over the periods after the
  first (discarded as transient), evaluated at the excited lines.
* :func:`fit_frf`: least-squares fit of a parametric model to a measured FRF
  on log-magnitude and phase (``log(H_model / H_meas)``, real and imaginary
  parts), parameters on a log scale so that they stay positive.  The
  table-specific identification (omega_oil, zeta_oil, d) is
  :func:`impedance_mil.lab.identification.identify_table`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..lazy import LazyModule

#: scipy.optimize, imported on first use (issue 16: a command that only reads a configuration does not need it).
scipy_optimize = LazyModule("scipy.optimize")


@dataclass(frozen=True, eq=False)
class FRF:
    """A measured frequency-response function.

    Attributes
    ----------
    frequency_hz : ndarray
        Frequencies of the excited lines [Hz].
    response : ndarray of complex
        H1 estimate [output unit / input unit].
    coherence : ndarray
        Ordinary coherence (0..1); 1 for noiseless periodic data.
    n_averages : int
        Number of periods averaged.
    std : ndarray or None
        Standard deviation of the estimate at each line [output unit / input unit]
        (:mod:`impedance_mil.signals.frf_estimators`), None when not estimated.
    """

    frequency_hz: np.ndarray
    response: np.ndarray
    coherence: np.ndarray
    n_averages: int
    std: np.ndarray | None = None

    @property
    def magnitude(self) -> np.ndarray:
        """``|H|`` [output unit / input unit]."""
        return np.abs(self.response)

    @property
    def phase_deg(self) -> np.ndarray:
        """Phase of H [deg], unwrapped from the lowest line."""
        return np.degrees(np.unwrap(np.angle(self.response)))

    def band(self, f_min_hz: float, f_max_hz: float) -> FRF:
        """The lines with ``f_min_hz <= f <= f_max_hz`` [Hz]."""
        keep = (self.frequency_hz >= f_min_hz) & (self.frequency_hz <= f_max_hz)
        std = None if self.std is None else self.std[keep]
        return FRF(self.frequency_hz[keep], self.response[keep], self.coherence[keep], self.n_averages, std)


def estimate_frf(u, y, n_points: int, sample_rate_hz: float, lines=None, discard_periods: int = 1) -> FRF:
    """H1 FRF estimate and coherence from a periodic test.

    Parameters
    ----------
    u, y : array_like
        Input and output records [their units], a whole number of periods.
    n_points : int
        Samples per period.
    sample_rate_hz : float
        Sampling rate [Hz].
    lines : array_like of int, optional
        FFT bins (of one period) to evaluate; default every bin 1..n_points/2-1.
    discard_periods : int
        Leading periods dropped as transient (report: the first).

    Returns
    -------
    FRF

    Examples
    --------
    >>> n = 64; t = np.arange(3 * n)
    >>> u = np.cos(2 * np.pi * 5 * t / n); y = 2 * u
    >>> frf = estimate_frf(u, y, n, 1.0, lines=[5])
    >>> round(float(abs(frf.response[0])), 6), round(float(frf.coherence[0]), 6)
    (2.0, 1.0)
    """
    u = np.asarray(u, dtype=float)
    y = np.asarray(y, dtype=float)
    if u.shape != y.shape or u.ndim != 1:
        raise ConfigError("frf", "input and output records of the same length", (u.shape, y.shape))
    n_periods = u.size // n_points
    if n_periods * n_points != u.size:
        raise ConfigError("frf.n_points", f"a divisor of the record length {u.size}", n_points)
    n_avg = n_periods - discard_periods
    if n_avg < 1:
        raise ConfigError(
            "frf.discard_periods", f"fewer than the {n_periods} periods recorded", discard_periods
        )
    if lines is None:
        lines = np.arange(1, n_points // 2)
    lines = np.asarray(lines, dtype=int)
    U = np.fft.rfft(u[discard_periods * n_points :].reshape(n_avg, n_points), axis=1)[:, lines]
    Y = np.fft.rfft(y[discard_periods * n_points :].reshape(n_avg, n_points), axis=1)[:, lines]
    s_uu = np.mean(np.abs(U) ** 2, axis=0)
    s_yy = np.mean(np.abs(Y) ** 2, axis=0)
    s_yu = np.mean(Y * np.conj(U), axis=0)
    if np.any(s_uu == 0):
        raise ConfigError("frf.lines", "lines excited by the input")
    with np.errstate(invalid="ignore", divide="ignore"):
        coh = np.where(s_yy > 0, np.abs(s_yu) ** 2 / (s_uu * s_yy), 0.0)
    return FRF(
        frequency_hz=lines * sample_rate_hz / n_points,
        response=s_yu / s_uu,
        coherence=np.clip(coh, 0.0, 1.0),
        n_averages=int(n_avg),
    )


@dataclass(frozen=True)
class FitResult:
    """Outcome of :func:`fit_frf`.

    Attributes
    ----------
    parameters : dict
        Fitted value of each parameter (in the model's units).
    initial : dict
        Starting values.
    rms_log_error : float
        RMS over lines of ``|log(H_model/H_meas)|`` at the optimum
        (dimensionless; 0.01 ~ 1 % magnitude / 0.57 deg phase).
    success : bool
        Whether the optimizer reported convergence.
    n_lines : int
        Lines used.
    log_covariance : ndarray or None
        Covariance of the natural logarithms of the free parameters (order of
        ``free``): ``s^2 (J^T J)^-1`` at the optimum, ``J`` the Jacobian of the
        weighted residuals and ``s^2`` their mean square per degree of freedom
        (Gauss-Newton linearization; Seber and Wild 1989, Section 5.1).
    chi2_reduced : float or None
        ``s^2``: the weighted residual's mean square per degree of freedom (about 1
        when the weights are the inverse standard deviations of the data and the
        model is right).
    free : tuple of str
        The fitted parameters.
    """

    parameters: dict
    initial: dict
    rms_log_error: float
    success: bool
    n_lines: int
    log_covariance: np.ndarray | None = None
    chi2_reduced: float | None = None
    free: tuple = ()

    def confidence_interval(self, name: str, z: float = 1.96) -> tuple[float, float]:
        """``(low, high)`` of a free parameter, ``exp(log p +- z sigma)`` (z = 1.96: 95 %)."""
        if self.log_covariance is None or name not in self.free:
            raise ConfigError(f"fit.{name}", "a fitted parameter with a covariance", name)
        i = self.free.index(name)
        sigma = float(np.sqrt(max(self.log_covariance[i, i], 0.0)))
        value = self.parameters[name]
        return (value * float(np.exp(-z * sigma)), value * float(np.exp(z * sigma)))


def _log_residual(h_model, h_meas, weight):
    r = np.log(h_model / h_meas)
    # wrap the phase difference into (-pi, pi]
    im = np.angle(np.exp(1j * r.imag))
    return np.concatenate([weight * r.real, weight * im])


def fit_frf(
    frf: FRF,
    model: Callable[[Mapping[str, float], np.ndarray], np.ndarray],
    initial: Mapping[str, float],
    *,
    free: Sequence[str] | None = None,
    f_range_hz: tuple[float, float] | None = None,
    coherence_weighting: bool = True,
    bounds_factor: float = 10.0,
    weights=None,
) -> FitResult:
    """Fit the positive parameters of ``model`` to ``frf`` on log-magnitude and phase.

    Parameters
    ----------
    frf : FRF
        Measured frequency response.
    model : callable
        ``model(params, f_hz) -> complex response``; ``params`` maps names to values.
    initial : mapping
        Starting value of every parameter the model reads (fixed ones included).
    free : sequence of str, optional
        Names fitted (default: all of ``initial``); each must be positive.
    f_range_hz : (float, float), optional
        Band of lines used [Hz].
    coherence_weighting : bool
        Weight each line by ``sqrt(coherence / (1 - coherence))`` (capped),
        the inverse of the H1 estimate's relative standard deviation.
    bounds_factor : float
        Each free parameter stays within ``[x0/bounds_factor, x0*bounds_factor]``.
    weights : array_like, optional
        Weight of each line of ``frf`` (after ``f_range_hz``), in place of the
        coherence weighting: ``sqrt(2) |H| / std`` makes each weighted residual
        of unit variance (the log residual's real and imaginary parts each have
        variance ``std^2 / (2 |H|^2)``).

    Returns
    -------
    FitResult
    """
    free = list(initial) if free is None else list(free)
    for name in free:
        if name not in initial or not initial[name] > 0:
            raise ConfigError(f"fit.{name}", "a positive starting value", initial.get(name))
    data = frf if f_range_hz is None else frf.band(*f_range_hz)
    if data.frequency_hz.size < len(free):
        raise ConfigError("fit.f_range_hz", f"at least {len(free)} lines", data.frequency_hz.size)
    if weights is not None:
        weight = np.asarray(weights, dtype=float)
        if weight.shape != data.frequency_hz.shape or not np.all(np.isfinite(weight) & (weight > 0)):
            raise ConfigError("fit.weights", f"{data.frequency_hz.size} positive finite weights")
    elif coherence_weighting:
        c = np.clip(data.coherence, 0.0, 1.0 - 1e-6)
        weight = np.sqrt(c / (1.0 - c))
        weight = np.minimum(weight, 100.0 * np.median(weight) + 1e-12)
        weight = weight / np.max(weight)
    else:
        weight = np.ones(data.frequency_hz.size)
    x0 = np.log([float(initial[n]) for n in free])
    span = np.log(bounds_factor)

    def residual(theta):
        params = dict(initial)
        params.update({n: float(np.exp(t)) for n, t in zip(free, theta)})
        return _log_residual(model(params, data.frequency_hz), data.response, weight)

    sol = scipy_optimize.least_squares(
        residual, x0, bounds=(x0 - span, x0 + span), x_scale=1.0, xtol=1e-12, ftol=1e-12
    )
    fitted = dict(initial)
    fitted.update({n: float(np.exp(t)) for n, t in zip(free, sol.x)})
    r = np.log(model(fitted, data.frequency_hz) / data.response)
    rms = float(np.sqrt(np.mean(r.real**2 + np.angle(np.exp(1j * r.imag)) ** 2)))
    covariance, chi2 = log_covariance(sol.jac, sol.fun)
    return FitResult(
        parameters=fitted,
        initial=dict(initial),
        rms_log_error=rms,
        success=bool(sol.success),
        n_lines=int(data.frequency_hz.size),
        log_covariance=covariance,
        chi2_reduced=chi2,
        free=tuple(free),
    )


def log_covariance(jacobian, residual) -> tuple[np.ndarray | None, float | None]:
    """``(s^2 (J^T J)^+, s^2)`` of a least-squares fit, ``s^2 = |r|^2 / (n - p)`` (None without dof)."""
    J = np.asarray(jacobian, dtype=float)
    r = np.asarray(residual, dtype=float)
    dof = r.size - J.shape[1]
    if dof <= 0:
        return None, None
    s2 = float(r @ r) / dof
    return s2 * np.linalg.pinv(J.T @ J), s2
