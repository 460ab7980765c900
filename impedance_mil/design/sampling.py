"""Which frequencies a sampled controller can implement: the one rule for design and export.

A cut-off (or a pre-warp frequency) of a controller that runs every
``loop_time_s`` seconds must lie strictly between 0 and the Nyquist frequency
``1 / (2 loop_time_s)``: the discretization (:func:`impedance_mil.implement.discretize`,
``imil export``) refuses any other, and the automatic choice of f_c
(:func:`impedance_mil.design.feasibility.choose_fc`, ``imil design --fc auto``)
proposes only such a cut-off.  An analog loop (``loop_time_s == 0``, design
analysis only) has no such limit.

>>> implementable_fc(999.0, 0.0005), implementable_fc(1000.0, 0.0005)
(True, False)
"""

from __future__ import annotations

import math

from ..errors import ConfigError


def implementable_fc(f_hz: float, loop_time_s: float) -> bool:
    """Whether ``f_hz`` [Hz] lies in (0, Nyquist) of a ``loop_time_s`` [s] loop (any positive f if analog).

    Parameters
    ----------
    f_hz : float
        Cut-off or pre-warp frequency [Hz].
    loop_time_s : float
        Controller loop time [s]; 0 for an analog loop.
    """
    if not (math.isfinite(f_hz) and f_hz > 0):
        return False
    return loop_time_s <= 0 or f_hz < 0.5 / loop_time_s


def check_implementable_fc(key: str, f_hz: float, loop_time_s: float) -> None:
    """Refuse a frequency that :func:`implementable_fc` rejects, naming ``key``.

    Parameters
    ----------
    key : str
        Name of the frequency in the message (``fc_hz``, ``prewarp_hz``, ``--fc`` ...).
    f_hz : float
        The frequency [Hz].
    loop_time_s : float
        Controller loop time [s].

    Raises
    ------
    ConfigError
        ``f_hz`` is not positive or not below the Nyquist frequency.
    """
    if not implementable_fc(f_hz, loop_time_s):
        raise ConfigError(
            key,
            f"a frequency in (0, {0.5 / loop_time_s:g}) Hz, below the Nyquist "
            f"frequency of the {loop_time_s * 1e6:g} us loop",
            f_hz,
        )
