"""Bounds on work: the largest records, grids and counts a request may ask for.

A mistyped option (``--cycles 1e7``, ``--periods log:0.01:10:100000000``)
must get a one-line error naming it, not an allocation of 149 GiB.  Each
bound is far above what the report's work needs (``docs/limits.md`` gives
the reasons); the functions that allocate check them first, so the check
lives in the library and every caller (CLI, campaign, script) gets it.

This module sits at the bottom of the package (standard library and
:mod:`impedance_mil.errors` only).
"""

from __future__ import annotations

import math

from .errors import ConfigError

#: Longest record [samples] of a ground motion, an excitation or a test signal:
#: 2**22 = 4.19 million samples, 35 min at the report's 2000 Hz (33.5 MB per channel).
#: The report's records have 5372 samples (El Centro, 0.01 s) or 107 k once resampled to 0.5 ms.
MAX_RECORD_SAMPLES = 1 << 22

#: Largest ground-motion file read [bytes]: a record of MAX_RECORD_SAMPLES as text is about 60 MB.
MAX_MOTION_FILE_BYTES = 1 << 28

#: Largest recording file read [bytes]: MAX_RECORD_SAMPLES rows of eight channels as CSV text is about 700 MB.
MAX_RECORDING_FILE_BYTES = 1 << 31

#: Most oscillator periods of one response spectrum (report Figure 8.1: 100).
MAX_SPECTRUM_PERIODS = 10_000

#: Most oscillator steps (periods x samples) of one response spectrum: about 10 s at 5 ns a step.
MAX_SPECTRUM_STEPS = 2_000_000_000

#: Most points per decade of a frequency grid of the optimized design (its default dense check grid: 2000).
#: The grid spans about five decades (0.01 Hz to the Nyquist frequency), so 1e5 a decade is 5e5 points.
MAX_GRID_PER_DECADE = 100_000

#: Most clipping iterations of a minimum-crest-factor multisine (report: 100).
MAX_MULTISINE_ITERATIONS = 10_000


def check_count(key: str, value: float, limit: int, what: str) -> int:
    """``value`` as an int, refused when it is not finite or exceeds ``limit``.

    Parameters
    ----------
    key : str
        The option or key that asked for the work (named in the message).
    value : float
        The requested size (samples, periods, iterations ...).
    limit : int
        The bound (see this module's constants).
    what : str
        What is counted, plural (``"samples"``).

    Raises
    ------
    ConfigError
        ``value`` is NaN, infinite or larger than ``limit``.

    Examples
    --------
    >>> check_count("--periods", 100, MAX_SPECTRUM_PERIODS, "periods")
    100
    >>> check_count("--periods", 1e8, MAX_SPECTRUM_PERIODS, "periods")
    Traceback (most recent call last):
    ...
    impedance_mil.errors.ConfigError: --periods: expected at most 10000 periods (docs/limits.md), got 100000000
    """
    if not math.isfinite(value) or value > limit:
        shown = value if not math.isfinite(value) else int(math.ceil(value))
        raise ConfigError(key, f"at most {limit} {what} (docs/limits.md)", shown)
    return int(value)
