"""Exceptions of impedance-mil.

Each subclasses the built-in it specialises, so callers that only know
Python's own exceptions still catch them.  The CLI turns every
:class:`ImilError` (and these subclasses) into a one-line message and exit
status 2; the library itself never prints or exits.
"""

from __future__ import annotations


class ImilError(Exception):
    """Base class of every error impedance-mil raises on purpose."""


class ConfigError(ImilError, ValueError):
    """A configuration value is missing, unknown, of the wrong dimension or out of range.

    The message names the key and what was expected.
    """

    def __init__(self, key: str, expected: str, got: object | None = None):
        self.key = key
        self.expected = expected
        self.got = got
        text = f"{key}: expected {expected}"
        if got is not None:
            text += f", got {got!r}"
        super().__init__(text)


class DataFileError(ImilError, ValueError):
    """A data file (ground motion, valve curve, design file ...) is unreadable or malformed.

    The message names the file and what was wrong.
    """

    def __init__(self, path: object, problem: str):
        self.path = str(path)
        self.problem = problem
        super().__init__(f"{self.path}: {problem}")


class UnstableSystemError(ImilError, ValueError):
    """A parameter set gives an unstable closed loop where a stable one is required."""


class UnstableDesignError(UnstableSystemError):
    """A controller design is unstable or non-causal and cannot be built."""


class DesignWarning(UserWarning):
    """A design is possible but violates a constraint or a sampling limit."""


class LimitTripped(ImilError, RuntimeError):
    """A simulated test tripped a safety limit and stopped, like a real controller.

    Attributes
    ----------
    limit : str
        Name of the limit that tripped (e.g. ``"stroke"``).
    time_s : float
        Time of the trip [s].
    """

    def __init__(self, limit: str, time_s: float, detail: str = ""):
        self.limit = limit
        self.time_s = time_s
        self.detail = detail
        msg = f"limit '{limit}' tripped at t = {time_s:.4f} s"
        if detail:
            msg += f": {detail}"
        super().__init__(msg)
