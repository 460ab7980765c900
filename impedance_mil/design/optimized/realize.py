"""Realization of the optimized controller, with optional order reduction (issue 15, "Realization").

The two paths come from the partial-fraction basis as modal state spaces
(:func:`.certify.path_state_space`; orders 20 and 18 with the default basis).
Without reduction their transfer functions are assembled from the exact
poles by polynomial products (:meth:`.basis.PoleBasis.transfer_function`).
With reduction each path's stable part is reduced by balanced singular
perturbation (:mod:`.reduce`, H-infinity error bound ``2 * sum`` of the
removed Hankel singular values, DC gain exact), the double integrator of
``C_z`` kept; the transfer functions come from the eigenvalues and invariant
zeros of the reduced realization.  No polynomial roots are taken.

``"auto"`` takes, per path, the smallest order whose measured relative error
over [band of interest low end, Nyquist] is below a tolerance and whose poles
lie below the Nyquist frequency (the implementation step's rule), then
re-evaluates constraints I, II, III and the grid-free certificate on the
reduced controller; if any verdict differs from the full controller's the
tolerance is made ten times smaller, down to no reduction.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...errors import ConfigError
from ...systems import TransferFunction
from ...units import TWO_PI
from .basis import PoleBasis
from .certify import StateSpace, path_state_space
from .exchange import log_points
from .reduce import ReducedPath, reduce_path, transfer_function

#: Tolerances ``"auto"`` tries: the setting, then this many tenfold smaller ones.
AUTO_STEPS = 5

#: Points per decade of the grid on which the reduction error is measured.
ERROR_PER_DECADE = 500

#: Verdicts a reduction must keep: the three constraints and the certificate.
VERDICT_KEYS = ("I", "II", "III", "certified")

#: Unit of each path (the sign convention of design/forms.py).
PATH_UNITS = {"H_uz": "in/in", "H_uw": "in/lbf"}


@dataclass(frozen=True)
class Realization:
    """The controller as implemented: both paths' realizations and transfer functions.

    Attributes
    ----------
    C_z, C_w : StateSpace
        Realizations of ``H_uz`` [in/in] and ``H_uw`` [in/lbf].
    H_uz, H_uw : TransferFunction
        Their transfer functions.
    record : dict or None
        The reduction (orders before/after, Hankel singular values, bounds,
        measured errors, verdicts before/after); None without reduction.
    verdicts : dict or None
        Verdicts of the realized controller when a reduction was evaluated.
    """

    C_z: StateSpace
    C_w: StateSpace
    H_uz: TransferFunction
    H_uw: TransferFunction
    record: dict | None = None
    verdicts: dict | None = None


#: ``verdicts(C_z, C_w, H_uz, H_uw) -> {"I": bool, "II": bool, "III": bool, "certified": bool}``.
Verdicts = Callable[[StateSpace, StateSpace, TransferFunction, TransferFunction], dict]


def _errors(full: StateSpace, reduced: StateSpace, f_hz: np.ndarray, band_hz) -> dict[str, float]:
    """Measured max absolute error (path unit) and max relative errors in the band and up to Nyquist."""
    s = 1j * TWO_PI * f_hz
    a, b = full.response(s), reduced.response(s)
    err = np.abs(b - a)
    rel = err / np.abs(a)
    inband = (f_hz >= band_hz[0]) & (f_hz <= band_hz[1])
    return {
        "max_abs": float(np.max(err)),
        "max_relative_in_band": float(np.max(rel[inband])),
        "max_relative_to_nyquist": float(np.max(rel)),
    }


def _fast_pole_hz(path: StateSpace) -> float:
    return float(np.max(np.abs(np.linalg.eigvals(path.A)))) / TWO_PI if path.A.size else 0.0


def _smallest_order(full: StateSpace, integrators: int, tol: float, f_hz, nyquist_hz: float) -> int:
    """Smallest order whose relative error on ``f_hz`` is below ``tol`` and poles below ``nyquist_hz``."""
    n = full.A.shape[0]
    s = 1j * TWO_PI * f_hz
    a = full.response(s)
    for order in range(integrators, n):
        r = reduce_path(full, integrators, order).state_space
        if _fast_pole_hz(r) < nyquist_hz and np.max(np.abs(r.response(s) / a - 1.0)) <= tol:
            return order
    return n


def _reduced(full: StateSpace, integrators: int, order: int, nyquist_hz: float, name: str) -> ReducedPath:
    r = reduce_path(full, integrators, min(order, full.A.shape[0]))
    fast = _fast_pole_hz(r.state_space)
    if fast >= nyquist_hz:
        raise ConfigError(
            "reduce",
            f"an order whose reduced {name} has its poles below the Nyquist frequency {nyquist_hz:g} Hz "
            "(try another order or auto)",
            f"{order} (a pole at {fast:.0f} Hz)",
        )
    return r


def realize(
    basis: PoleBasis,
    xz: np.ndarray,
    xw: np.ndarray,
    request: str | int,
    tolerance: float,
    band_hz: tuple[float, float],
    nyquist_hz: float,
    verdicts: Verdicts,
) -> Realization:
    """Realize the coefficients ``xz``, ``xw`` on ``basis``, reduced as ``request`` asks.

    Parameters
    ----------
    basis : PoleBasis
    xz, xw : np.ndarray
        Coefficients of ``C_z`` and ``C_w``.
    request : {"none", "auto"} or int
        See :class:`.problem.OptimizationSettings` (``reduce``).
    tolerance : float
        First relative path error tried by ``"auto"`` (dimensionless).
    band_hz : (float, float)
        Band of interest [Hz]; the error is measured from its low end to ``nyquist_hz``.
    nyquist_hz : float
        Nyquist frequency of the loop [Hz]; every reduced pole must lie below it.
    verdicts : callable
        Evaluates I, II, III and the certificate of a realized controller.

    Raises
    ------
    ConfigError
        An explicit order whose reduced path has a pole at or above the Nyquist frequency.
    """
    Cz, Cw = path_state_space(basis, xz, "z"), path_state_space(basis, xw, "w")
    full = Realization(Cz, Cw, basis.transfer_function(xz, "z"), basis.transfer_function(xw, "w"))
    if request == "none":
        return full
    iz = 2 if basis.integrators else 0
    f = log_points((band_hz[0], nyquist_hz), ERROR_PER_DECADE)
    before = verdicts(full.C_z, full.C_w, full.H_uz, full.H_uw)
    tried: list[dict[str, Any]] = []
    if request == "auto":
        chosen = None
        for k in range(AUTO_STEPS):
            tol = tolerance * 10.0**-k
            oz = _smallest_order(Cz, iz, tol, f, nyquist_hz)
            ow = _smallest_order(Cw, 0, tol, f, nyquist_hz)
            if (oz, ow) == (Cz.A.shape[0], Cw.A.shape[0]):
                break
            rz, rw = reduce_path(Cz, iz, oz), reduce_path(Cw, 0, ow)
            cand = _render(rz, rw)
            after = verdicts(cand.C_z, cand.C_w, cand.H_uz, cand.H_uw)
            tried.append({"tolerance": tol, "orders": [oz, ow], "verdicts": after})
            if all(after[key] == before[key] for key in VERDICT_KEYS):
                chosen = (rz, rw, cand, after, tol)
                break
        if chosen is None:
            record = {"request": "auto", "reduced": False, "verdicts_full": before, "tried": tried}
            return Realization(full.C_z, full.C_w, full.H_uz, full.H_uw, record, before)
        rz, rw, cand, after, tol = chosen
    else:
        rz = _reduced(Cz, iz, int(request), nyquist_hz, "H_uz")
        rw = _reduced(Cw, 0, int(request), nyquist_hz, "H_uw")
        cand, tol = _render(rz, rw), None
        after = verdicts(cand.C_z, cand.C_w, cand.H_uz, cand.H_uw)
    record = {
        "request": request,
        "reduced": True,
        "method": "balanced singular perturbation (residualization) of each path's stable part; "
        "the double integrator of H_uz kept",
        "tolerance": tol,
        "tried": tried,
        "orders_before": {"H_uz": rz.order_before, "H_uw": rw.order_before},
        "orders_after": {"H_uz": rz.order_after, "H_uw": rw.order_after},
        "hankel_singular_values": {"H_uz": rz.hankel.tolist(), "H_uw": rw.hankel.tolist()},
        "error_bound": {"H_uz": rz.bound, "H_uw": rw.bound},
        "units": PATH_UNITS,
        "measured_band_hz": [float(band_hz[0]), float(nyquist_hz)],
        "measured_error": {
            "H_uz": _errors(Cz, rz.state_space, f, band_hz),
            "H_uw": _errors(Cw, rw.state_space, f, band_hz),
        },
        "verdicts_full": before,
        "verdicts_reduced": after,
        "meaning": "error_bound: H-infinity bound of |H - H_reduced| over all frequencies, 2 * sum of the "
        "removed Hankel singular values (path unit); measured_error: max |H - H_reduced| (path unit) and "
        "max |H_reduced/H - 1| in the band of interest and up to the Nyquist frequency",
    }
    return Realization(cand.C_z, cand.C_w, cand.H_uz, cand.H_uw, record, after)


def _render(rz: ReducedPath, rw: ReducedPath) -> Realization:
    """Transfer functions of reduced paths (eigenvalues and invariant zeros, no polynomial roots)."""
    return Realization(
        rz.state_space, rw.state_space, transfer_function(rz.state_space), transfer_function(rw.state_space)
    )
