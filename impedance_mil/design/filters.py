"""Low-pass filters that make the MIL controller proper (report Section 6.4, Eq 6-9, 6-10).

The ideal controller ``H_uz = 1/H_zu^st`` is improper by the relative degree
of ``H_zu^st`` (3 for the report's table), so a low-pass filter of at least
that order is needed; its cut-off ``f_c`` [Hz] is then the one design
parameter.  The report uses a third-order Butterworth filter
(MATLAB ``butter(3, 2*pi*fc, 'low', 's')``, Eq 6-10); Bessel (maximally flat
group delay, normalised so that ``|H(f_c)| = -3 dB``) and Chebyshev type I
(equiripple pass band, ``ripple_db``) are also available.  Every filter is
scaled to unit gain at DC, so the controller is exact at low frequency
(for an even-order Chebyshev filter this moves the ripple band above 0 dB).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.signal

from ..errors import ConfigError
from ..systems import TransferFunction
from ..units import TWO_PI

#: Filter families and their scipy designers.
FAMILIES = ("butterworth", "bessel", "chebyshev1")

#: Highest filter order accepted (beyond it the polynomial coefficients lose precision).
MAX_ORDER = 10
#: Largest Chebyshev I pass-band ripple [dB] (10 dB is a gain swing of 3.2, no flat pass band).
MAX_RIPPLE_DB = 10.0


@dataclass(frozen=True)
class LowpassFilter:
    """An analog low-pass filter.

    Parameters
    ----------
    family : str
        ``"butterworth"``, ``"bessel"`` or ``"chebyshev1"``.
    order : int
        Filter order (number of poles), 1..:data:`MAX_ORDER`.
    fc_hz : float
        Cut-off frequency [Hz] (-3 dB for Butterworth and Bessel; edge of the
        ripple band for Chebyshev I).
    ripple_db : float
        Pass-band ripple [dB] of a Chebyshev I filter (ignored otherwise).

    Examples
    --------
    >>> F = LowpassFilter("butterworth", 3, 80.0).tf()   # Eq 6-10
    >>> round(float(F.den[-1]) / 1e8, 2)
    1.27
    """

    family: str
    order: int
    fc_hz: float
    ripple_db: float = 0.5

    def __post_init__(self):
        if self.family not in FAMILIES:
            raise ConfigError("filter", "one of " + ", ".join(FAMILIES), self.family)
        check_order(self.order)
        if not (np.isfinite(self.fc_hz) and self.fc_hz > 0):
            raise ConfigError("fc", "a positive cut-off frequency in Hz", self.fc_hz)
        if self.family == "chebyshev1":
            check_ripple(self.ripple_db)

    def tf(self) -> TransferFunction:
        """The filter as a transfer function in s [rad/s], unit DC gain."""
        wc = TWO_PI * self.fc_hz
        n = int(self.order)
        if self.family == "butterworth":
            b, a = scipy.signal.butter(n, wc, btype="low", analog=True)
        elif self.family == "bessel":
            b, a = scipy.signal.bessel(n, wc, btype="low", analog=True, norm="mag")
        else:
            b, a = scipy.signal.cheby1(n, self.ripple_db, wc, btype="low", analog=True)
        b = np.atleast_1d(b) * (a[-1] / np.atleast_1d(b)[-1])  # unit DC gain
        return TransferFunction(b, a)

    def to_dict(self) -> dict:
        """``{"family", "order", "fc_hz", "ripple_db"}``."""
        return {
            "family": self.family,
            "order": int(self.order),
            "fc_hz": float(self.fc_hz),
            "ripple_db": float(self.ripple_db),
        }


def check_ripple(ripple_db: float) -> float:
    """Refuse a Chebyshev I pass-band ripple [dB] outside (0, :data:`MAX_RIPPLE_DB`) (NaN too).

    Raises
    ------
    ConfigError
        Naming ``ripple_db``.

    Examples
    --------
    >>> check_ripple(0.5)
    0.5
    """
    if not 0 < ripple_db < MAX_RIPPLE_DB:
        raise ConfigError("ripple_db", f"a pass-band ripple between 0 and {MAX_RIPPLE_DB:g} dB", ripple_db)
    return ripple_db


def check_order(order: int) -> int:
    """Refuse a filter order that is not an integer from 1 to :data:`MAX_ORDER`.

    Raises
    ------
    ConfigError
        Naming ``filter order``.
    """
    if isinstance(order, bool) or int(order) != order or not 1 <= order <= MAX_ORDER:
        raise ConfigError("filter order", f"an integer from 1 to {MAX_ORDER}", order)
    return order


def required_order(H: TransferFunction) -> int:
    """Lowest filter order that makes ``F*H`` proper: ``max(0, -relative degree)``."""
    return max(0, -H.relative_degree)


def apply_filter(
    H: TransferFunction, family: str, fc_hz: float, order: int | None = None, ripple_db: float = 0.5
) -> tuple[TransferFunction, int]:
    """Filter one controller path so that it becomes proper.

    Parameters
    ----------
    H : TransferFunction
        Ideal (possibly improper) controller path.
    family : str
        Filter family (:data:`FAMILIES`).
    fc_hz : float
        Cut-off frequency [Hz].
    order : int, optional
        Filter order; default the lowest that makes ``F*H`` proper.
    ripple_db : float
        Chebyshev I pass-band ripple [dB].

    Returns
    -------
    (TransferFunction, int)
        The proper filtered path ``F*H`` and the order used (0: no filter
        needed, ``H`` returned unchanged).

    Raises
    ------
    ConfigError
        ``order`` below the relative degree of ``1/H``'s numerator excess,
        or an invalid family / cut-off.
    """
    need = required_order(H)
    if order is None:
        order = need
    if order < need:
        raise ConfigError(
            "filter order", f"at least {need} (the relative degree of the ideal controller)", order
        )
    if not (np.isfinite(fc_hz) and fc_hz > 0):
        raise ConfigError("fc", "a positive cut-off frequency in Hz", fc_hz)
    if order == 0 or H.is_zero:
        return H, 0
    F = LowpassFilter(family, order, fc_hz, ripple_db).tf()
    return H.mul_cancel(F), order
