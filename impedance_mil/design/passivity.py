"""Passivity of a force-velocity transfer function, in degrees (report Section 9.4.2).

A linear one-port is passive when it is stable and the phase of its
force-velocity transfer function stays within +-90 deg at every frequency,
i.e. its Nyquist plot lies in the closed right half plane (Eq 9-1d: the
work per cycle is ``pi F v cos(phi)/omega``).  The *passivity margin*

    margin(f) = 90 deg - |phase H_vw(j 2 pi f)|

is the angle by which the Nyquist plot stays away from the imaginary axis;
its minimum over a band is the "degree of passivity" asked for in
Section 10.4.  It is negative where the system injects energy.

The linear table model (Eq 4-14a) replaces the loop delay ``exp(-s tau)``
by ``1 - s tau``; the phase of the two differs by
``omega tau - atan(omega tau)``, which is 0.56 deg at 100 Hz and 3.9 deg at
200 Hz for tau = 500 us.  A margin deficit smaller than this model error
cannot be told apart from zero: :func:`delay_model_tolerance_deg` is the
tolerance used by constraint III.  The bare table model itself is
non-passive by 0.23 deg near 99 Hz, inside this tolerance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..lazy import LazyModule
from ..systems import TransferFunction
from ..units import TWO_PI
from .forms import AXIS_RTOL, imaginary_axis, right_half_plane

#: scipy.optimize, imported on first use (issue 16: a command that only reads a configuration does not need it).
scipy_optimize = LazyModule("scipy.optimize")

#: Points per decade of the frequency grid used to find the worst margin.
POINTS_PER_DECADE = 400


@dataclass(frozen=True)
class PassivityResult:
    """Passivity of a force-velocity transfer function over a band.

    Attributes
    ----------
    stable : bool
        All poles in the open left half plane, or simple poles on the imaginary axis.
    margin_deg : float
        Minimum of ``90 - |phase|`` over the band [deg]; negative where the
        Nyquist plot enters the left half plane.
    worst_hz : float
        Frequency of that minimum [Hz].
    tolerant_margin_deg : float
        Minimum of ``90 - |phase| + tolerance(f)`` [deg]: the margin left after
        crediting the model tolerance at each frequency; the verdict uses it.
    tolerant_worst_hz : float
        Frequency of that minimum [Hz].
    passive : bool
        ``stable and tolerant_margin_deg >= 0``.
    """

    stable: bool
    margin_deg: float
    worst_hz: float
    tolerant_margin_deg: float
    tolerant_worst_hz: float
    passive: bool


def delay_model_tolerance_deg(f_hz, loop_time_s: float) -> np.ndarray:
    """Phase error of the first-order delay model ``1 - s tau`` against ``exp(-s tau)`` [deg].

    Parameters
    ----------
    f_hz : array_like
        Frequency [Hz].
    loop_time_s : float
        Loop delay tau [s] (Section 4.3.4).
    """
    x = TWO_PI * np.asarray(f_hz, dtype=float) * loop_time_s
    return np.degrees(x - np.arctan(x))


def log_grid_hz(band_hz: tuple[float, float], points_per_decade: int) -> np.ndarray:
    """Log-spaced frequencies [Hz] spanning ``band_hz`` [Hz], at least 50 points.

    The one frequency grid of the constraints (I, II) and of the passivity search.
    """
    lo, hi = float(band_hz[0]), float(band_hz[1])
    return np.logspace(np.log10(lo), np.log10(hi), max(int(points_per_decade * np.log10(hi / lo)), 50))


def is_passive_stable(H: TransferFunction, rtol: float = AXIS_RTOL) -> bool:
    """Stable in the sense needed for passivity: open-LHP poles, or simple poles on the jw axis."""
    p = H.poles()
    if p.size == 0:
        return True
    if right_half_plane(p, rtol).size:
        return False
    axis = imaginary_axis(p, rtol)
    for i, a in enumerate(axis):
        if np.any(np.abs(np.delete(axis, i) - a) <= 1e-6 * max(abs(a), 1.0)):
            return False
    return True


def passivity(
    H_vw: TransferFunction,
    band_hz: tuple[float, float],
    loop_time_s: float = 0.0,
    extra_tolerance_deg: float = 0.0,
    response=None,
) -> PassivityResult:
    """Passivity margin of a force-velocity transfer function over a band.

    Parameters
    ----------
    H_vw : TransferFunction
        Velocity per force [in/s per lbf] (Eq 9-2).
    band_hz : (float, float)
        Frequency band [Hz] in which the margin is evaluated.
    loop_time_s : float
        Loop delay [s] for :func:`delay_model_tolerance_deg`; 0 for no model tolerance.
    extra_tolerance_deg : float
        Additional tolerance [deg] added at every frequency (user-settable).
    response : callable, optional
        ``response(f_hz)`` giving the complex response of ``H_vw`` more
        precisely than its polynomials (e.g. factor by factor); the poles of
        ``H_vw`` still decide stability.

    Returns
    -------
    PassivityResult
    """
    f = log_grid_hz(band_hz, POINTS_PER_DECADE)

    def tol(x):
        return delay_model_tolerance_deg(x, loop_time_s) + extra_tolerance_deg

    resp = response if response is not None else H_vw.frequency_response

    def margin(x):
        return 90.0 - np.abs(np.degrees(np.angle(resp(x))))

    raw_f, raw = _refined_minimum(margin, f)
    tol_f, tolerant = _refined_minimum(lambda x: margin(x) + tol(x), f)
    stable = is_passive_stable(H_vw)
    return PassivityResult(stable, raw, raw_f, tolerant, tol_f, bool(stable and tolerant >= 0.0))


def _refined_minimum(fun, f: np.ndarray) -> tuple[float, float]:
    """Minimum of ``fun`` over the grid ``f`` [Hz], refined in log-frequency around the best points."""
    values = fun(f)
    order = np.argsort(values)[:3]
    best_f, best = float(f[order[0]]), float(values[order[0]])
    logf = np.log10(f)
    for i in order:
        a, b = logf[max(i - 1, 0)], logf[min(i + 1, f.size - 1)]
        if b <= a:
            continue
        res = scipy_optimize.minimize_scalar(
            lambda x: float(fun(np.array([10.0**x]))[0]),
            bounds=(a, b),
            method="bounded",
            options={"xatol": 1e-6},
        )
        if res.fun < best:
            best_f, best = float(10.0**res.x), float(res.fun)
    return best_f, best
