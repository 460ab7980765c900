"""Exceptions of impedance-mil.

Each subclasses the built-in it specialises, so callers that only know
Python's own exceptions still catch them.  The CLI turns every
:class:`ImilError` (and these subclasses) into a one-line message and exit
status 2; the library itself never prints or exits.
"""

from __future__ import annotations

from enum import IntEnum


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

    Parameters
    ----------
    cause : TripCause
        What tripped, a member of :class:`impedance_mil.lab.trips.TripCause` (an
        ``IntEnum``; its name in lower case, ``TripCause.label``, names it in the message).
    time_s : float
        Time of the trip [s].
    detail : str, optional
        Appended to the message (e.g. ``"value 3.0012"``).
    value : float, optional
        The offending value, in the cause's unit (``cause.unit``).

    Attributes
    ----------
    cause : TripCause
    limit : str
        The cause's name (e.g. ``"stroke"``).
    time_s : float
    value : float or None
    """

    def __init__(self, cause: IntEnum, time_s: float, detail: str = "", value: float | None = None):
        self.cause = cause
        self.limit = cause.name.lower()
        self.time_s = time_s
        self.detail = detail
        self.value = value
        msg = f"limit '{self.limit}' tripped at t = {time_s:.4f} s"
        if detail:
            msg += f": {detail}"
        super().__init__(msg)


class MotionRefused(ImilError, ValueError):
    """A motion exceeds the table's limits and the caller did not ask to run it anyway."""


class DesignRefused(ImilError, ValueError):
    """A design violates a constraint the run requires (e.g. III, passivity) and the caller did not force it."""


class NotEvaluatedError(ImilError, KeyError):
    """A result was asked for something it does not hold (e.g. constraints at an unevaluated f_c)."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class MissingDependencyError(ImilError, RuntimeError):
    """An optional package needed for this operation is not installed (the message says which)."""


class IncompleteModelError(ImilError, NotImplementedError):
    """A user-defined model lacks a method the operation needs (the message names it)."""


class ImproperSystemError(ImilError, ValueError):
    """An improper transfer function was given where a proper one is required."""


class SingularSystemError(ImilError, ZeroDivisionError):
    """A transfer function with a zero denominator, or the inverse of a zero transfer function."""


class OperandError(ImilError, TypeError):
    """A system was combined with an object it cannot be combined with."""
