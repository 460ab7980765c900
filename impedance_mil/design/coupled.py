"""Stability of the controlled table coupled with one given linear test article.

Passivity (constraint III) guarantees stability with *any* passive test
article; it is sufficient, not necessary (Section 9.4.2).  For a known
article the interconnection itself can be checked: the controlled table
gives ``z = H_c w`` (Eq 6-5) and the article ``w = Z z`` (its impedance,
``Specimen.impedance()``, ``w = -m z`` for a rigid mass), so the closed-loop
poles are the roots of ``den(H_c) den(Z) - num(H_c) num(Z)``, the
denominator of ``H_c.feedback(Z, sign=+1)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..systems import TransferFunction
from ..units import TWO_PI

#: Closed-loop poles below this frequency [Hz] are excluded from the high-frequency margin.
DEFAULT_ABOVE_HZ = 15.0


@dataclass(frozen=True)
class CoupledStability:
    """Closed-loop poles of the controlled table with one test article.

    Attributes
    ----------
    specimen : str
        Label of the article.
    stable : bool
        Every closed-loop pole has a negative real part.
    max_real_part : float
        Largest real part of the closed-loop poles [rad/s].
    min_damping_ratio : float
        Smallest damping ratio ``-Re p/|p|`` of any closed-loop pole (negative if unstable);
        usually a sloshing mode of the article itself.
    min_damping_hz : float
        Natural frequency of that pole [Hz].
    hf_damping_ratio : float
        Smallest damping ratio among poles above ``above_hz`` (the table-article
        interaction, where the oscillations of Section 9.4.5 appear); the
        coupled-stability margin.
    hf_damping_hz : float
        Natural frequency of that pole [Hz].
    above_hz : float
        Threshold of the high-frequency margin [Hz].
    """

    specimen: str
    stable: bool
    max_real_part: float
    min_damping_ratio: float
    min_damping_hz: float
    hf_damping_ratio: float
    hf_damping_hz: float
    above_hz: float

    def to_dict(self) -> dict:
        return {
            "specimen": self.specimen,
            "stable": bool(self.stable),
            **{
                k: float(getattr(self, k))
                for k in (
                    "max_real_part",
                    "min_damping_ratio",
                    "min_damping_hz",
                    "hf_damping_ratio",
                    "hf_damping_hz",
                    "above_hz",
                )
            },
        }


def closed_loop_poles(H_c: TransferFunction, Z: TransferFunction) -> np.ndarray:
    """Poles [rad/s] of the controlled table ``z = H_c w`` coupled with the article ``w = Z z``.

    Parameters
    ----------
    H_c : TransferFunction
        Controlled impedance [in/s**2 per lbf].
    Z : TransferFunction
        Article impedance ``w/z`` [lbf per in/s**2].
    """
    return H_c.feedback(Z, sign=+1).poles()


def coupled_stability(
    H_c: TransferFunction, Z: TransferFunction, specimen: str = "", above_hz: float = DEFAULT_ABOVE_HZ
) -> CoupledStability:
    """Stability and damping margin of the controlled table with one linear article.

    Parameters
    ----------
    H_c : TransferFunction
        Controlled impedance [in/s**2 per lbf] (``ControlledTable.H_c``).
    Z : TransferFunction
        Article impedance ``w/z`` [lbf per in/s**2].
    specimen : str
        Label.
    above_hz : float
        Lower end [Hz] of the poles counted by the high-frequency margin.

    Examples
    --------
    >>> H = TransferFunction([1.0, 0.0, 0.0], [2.0, 1.0, 100.0])    # a damped oscillator's impedance
    >>> r = coupled_stability(H, TransferFunction.constant(-1.0), "1 lbf*s^2/in", above_hz=0.0)
    >>> r.stable, round(r.min_damping_ratio, 4)                      # 3 s^2 + s + 100
    (True, 0.0289)
    """
    return stability_of_poles(closed_loop_poles(H_c, Z), specimen, above_hz)


def stability_of_poles(
    p: np.ndarray, specimen: str = "", above_hz: float = DEFAULT_ABOVE_HZ
) -> CoupledStability:
    """The :class:`CoupledStability` of closed-loop poles ``p`` [rad/s] (see :func:`coupled_stability`).

    Parameters
    ----------
    p : ndarray of complex
        Closed-loop poles [rad/s].
    specimen : str
        Label.
    above_hz : float
        Lower end [Hz] of the poles counted by the high-frequency margin.
    """
    p = np.asarray(p, dtype=complex)
    if p.size == 0:
        return CoupledStability(specimen, True, float("-inf"), 1.0, float("nan"), 1.0, float("nan"), above_hz)
    wn = np.abs(p)
    zeta = np.where(wn > 0, -p.real / np.maximum(wn, 1e-300), -np.sign(p.real))
    i = int(np.argmin(zeta))
    hf = wn > TWO_PI * above_hz
    j = int(np.argmin(np.where(hf, zeta, np.inf))) if hf.any() else None
    return CoupledStability(
        specimen,
        bool(np.all(p.real < 0)),
        float(p.real.max()),
        float(zeta[i]),
        float(wn[i] / TWO_PI),
        float(zeta[j]) if j is not None else 1.0,
        float(wn[j] / TWO_PI) if j is not None else float("nan"),
        float(above_hz),
    )
