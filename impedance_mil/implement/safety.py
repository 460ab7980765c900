"""The safety layer of the generated controller: command limits, guards, the fault word.

What reaches a real controller must stop what a real controller would stop.
Every step of the generated C and Structured Text (:mod:`.c`, :mod:`.st`)

1. checks its inputs (``z_vs`` or ``a_g`` [in/s^2], ``w`` [lbf]): NaN or
   infinite -> :attr:`Fault.INPUT_NAN`; beyond :attr:`CommandLimits.accel_limit_in_s2`
   or :attr:`CommandLimits.force_limit_lbf` -> :attr:`Fault.INPUT_RANGE`;
2. checks the internal values after the update (controller and VS states, the
   VS target ``z_vs`` of the MIL step, the unclamped command): NaN, infinite
   or beyond :data:`VALUE_LIMIT` -> :attr:`Fault.OVERFLOW`;
3. clamps the command to the stroke (:attr:`Fault.CLAMP`) and limits its rate
   (:attr:`Fault.RATE`);
4. optionally checks the loop time the host measured against the designed one
   (:attr:`Fault.LOOP_TIME`).

A fault of :data:`HOLD` latches: the step returns the last safe command and
no longer advances the states until the host calls the reset.  The clamp and
the rate limit act without holding; their bits are sticky in the fault word
and current in the word of the last step.

The guards only compare: when none acts, the generated code computes exactly
what the runtime computes (tests/implement/test_codegen_guards.py).

Why :data:`VALUE_LIMIT` prevents overflow: coefficients (checked at export by
:func:`check_renderable`) and states are both within it, so every product in
the next update is within ``VALUE_LIMIT**2`` (1e36 in single precision, below
its largest value 3.4e38, with room for sums of a hundred terms), and inputs
are within the (much smaller) input limits.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..config import quantity
from ..errors import ConfigError
from ..signals.limits import TableLimits
from .renderable import VALUE_LIMIT, check_renderable

__all__ = [
    "COEFFICIENTS",
    "DEFAULT_LOOP_TIME_RTOL",
    "FAULT_TEXT",
    "HOLD",
    "INPUT_RANGE_FACTOR",
    "VALUE_LIMIT",
    "CommandLimits",
    "Fault",
    "check_renderable",
    "command_limits",
    "rendered_limits",
]


class Fault(enum.IntFlag):
    """Bits of the generated code's fault word (``P_fault(s)`` in C, ``fault`` in ST)."""

    INPUT_NAN = 0x0001
    """An input (``z_vs``, ``a_g``, ``w``) is NaN or infinite (holds)."""
    INPUT_RANGE = 0x0002
    """An input is finite but beyond its range (holds)."""
    OVERFLOW = 0x0004
    """A state, the VS target or the unclamped command is non-finite or beyond :data:`VALUE_LIMIT` (holds)."""
    LOOP_TIME = 0x0008
    """The loop time the host measured differs from the designed one beyond the tolerance (holds)."""
    CLAMP = 0x0010
    """The command was clamped to the stroke (does not hold)."""
    RATE = 0x0020
    """The command was rate limited (does not hold)."""


#: Faults that latch and make the step hold the last safe command until the reset.
HOLD = Fault.INPUT_NAN | Fault.INPUT_RANGE | Fault.OVERFLOW | Fault.LOOP_TIME

#: One line per bit, for the generated code's comments.
FAULT_TEXT = {
    Fault.INPUT_NAN: "an input is NaN or infinite (holds)",
    Fault.INPUT_RANGE: "an input is beyond its range (holds)",
    Fault.OVERFLOW: "a state, the VS target or the raw command is out of range (holds)",
    Fault.LOOP_TIME: "the measured loop time is off the designed one (holds)",
    Fault.CLAMP: "the command was clamped to the stroke",
    Fault.RATE: "the command was rate limited",
}

#: The input ranges are this many times the table's capacity: its force capacity
#: ``A_p (P_S - P_R)`` for ``w`` [lbf], that force over the table's mass for ``z_vs`` and
#: ``a_g`` [in/s^2].  No sensor of a working test reads ten times what the table can do.
INPUT_RANGE_FACTOR = 10.0

#: Default tolerance of the loop-time check, relative to the designed loop time: a loop
#: 5 % off moves every discrete pole and zero of the controller by 5 % in frequency.
DEFAULT_LOOP_TIME_RTOL = 0.05


@dataclass(frozen=True)
class CommandLimits:
    """The limits rendered into the generated code's safety layer.

    Attributes
    ----------
    stroke_in : float
        The command is clamped to ``+-stroke_in`` [in] (from mid-stroke).
    max_rate_in_s : float
        Largest command rate [in/s]; the step changes the command by at most
        ``max_rate_in_s * loop_time`` [in].
    accel_limit_in_s2 : float
        Range of ``z_vs`` and ``a_g`` [in/s^2].
    force_limit_lbf : float
        Range of ``w`` [lbf].
    loop_time_rtol : float
        Tolerance of the loop-time check, relative to the designed loop time.
    sources : Mapping[str, str]
        Where each limit came from (``stroke``, ``rate``, ``inputs``), stated in
        the generated header.
    """

    stroke_in: float
    max_rate_in_s: float
    accel_limit_in_s2: float
    force_limit_lbf: float
    loop_time_rtol: float = DEFAULT_LOOP_TIME_RTOL
    sources: Mapping[str, str] = ()  # type: ignore[assignment]

    def __post_init__(self) -> None:
        for key in ("stroke_in", "max_rate_in_s", "accel_limit_in_s2", "force_limit_lbf", "loop_time_rtol"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ConfigError(key, "a positive finite number", value)
            if value <= 0:
                raise ConfigError(key, "a positive finite number", value)
            object.__setattr__(self, key, float(value))
        object.__setattr__(self, "sources", dict(self.sources or {}))

    def rate_step_in(self, loop_time_s: float) -> float:
        """Largest change of the command in one loop [in]: ``max_rate_in_s * loop_time_s``."""
        return self.max_rate_in_s * loop_time_s

    def source(self, name: str) -> str:
        """Where ``name`` (``stroke``, ``rate``, ``inputs``) came from (``"given"`` if not stated)."""
        return self.sources.get(name, "given")


#: Keys of a design's table the limits are derived from (``return_pressure`` may be absent: 0 psi).
_TABLE_KEYS = (
    "piston_area",
    "mid_stroke",
    "mass",
    "supply_pressure",
    "rated_flow",
    "rated_pressure_drop",
)


#: Keys of an LTI table's stated capacity the limits are derived from (:mod:`impedance_mil.plant.capacity`).
_CAPACITY_KEYS = ("stroke", "velocity", "force", "mass")


def command_limits(
    table: Mapping[str, Any] | None,
    *,
    stroke: Any = None,
    max_rate: Any = None,
    where: str = "design table.",
    capacity: Mapping[str, float] | None = None,
) -> CommandLimits:
    """The command limits of a design: from its table, or its stated capacity, or explicit values.

    Parameters
    ----------
    table : Mapping or None
        The design's table parameters (``TableParameters.to_dict()``, internal
        units).  The stroke is its ``mid_stroke`` [in]; the rate limit is the
        valve's no-load velocity capacity ``Q_rated sqrt((P_S - P_R)/dP_rated)/A_p``
        [in/s] (:meth:`impedance_mil.signals.limits.TableLimits.from_numbers`);
        the input ranges are :data:`INPUT_RANGE_FACTOR` times the force
        capacity ``A_p (P_S - P_R)`` [lbf] and that force over ``mass`` [in/s^2].
    stroke, max_rate : float or str, optional
        Explicit stroke [in] and rate limit [in/s] (``imil export --stroke
        "3 in" --max-rate "40 in/s"``): bare numbers in those units or strings
        with units.  They may not exceed the table's capacity.
    where : str
        Prefix of the table's keys in messages.
    capacity : Mapping, optional
        For a design from a table given as a linear model (no physical
        ``table``): its stated capacity (``[capacity]`` of the table file,
        internal units): ``stroke`` [in], ``velocity`` [in/s], ``force`` [lbf]
        (the stall force, the input ranges' base as above) and ``mass``
        [lbf*s**2/in].  Used when ``table`` is empty (such a design has no
        physical parameters).

    Raises
    ------
    ConfigError
        A table (or capacity) key the limits need is missing (naming it), or an
        explicit limit is not a positive length/velocity or exceeds the table's.
    """
    table = table or {}
    if not table:  # a design from a table given as a linear model: no physical parameters
        own = _stated_capacity(capacity or {})
    else:
        own = _physical_capacity(table, where)
    chosen, sources = {}, {}
    for name, value, unit, option in (
        ("stroke", stroke, "inch", "--stroke"),
        ("rate", max_rate, "inch / second", "--max-rate"),
    ):
        number, what = own[name]
        if value is None:
            chosen[name], sources[name] = number, f"the design's table: {what} {number:.6g}"
            continue
        given = quantity(option, value, unit, "positive")
        if given > number * (1.0 + 1e-12):
            shown = unit.replace("inch", "in").replace(" / second", "/s")
            raise ConfigError(option, f"at most the table's {what}, {number:.6g} {shown}", value)
        chosen[name], sources[name] = given, f"{option} {value}"
    force, force_what = own["force"]
    sources["inputs"] = (
        f"{INPUT_RANGE_FACTOR:g} x the design table's {force_what} = {force:.6g} lbf, and that force over its mass"
    )
    return CommandLimits(
        stroke_in=chosen["stroke"],
        max_rate_in_s=chosen["rate"],
        accel_limit_in_s2=INPUT_RANGE_FACTOR * force / own["mass"][0],
        force_limit_lbf=INPUT_RANGE_FACTOR * force,
        sources=sources,
    )


def _physical_capacity(table: Mapping[str, Any], where: str) -> dict[str, tuple[float, str]]:
    """Stroke, rate, force and mass of a physical table, each with what it is."""
    for key in _TABLE_KEYS:
        if table.get(key) is None:
            raise ConfigError(
                f"{where}{key}",
                "present: the generated code's stroke clamp, rate limit and input ranges come from the table",
            )
    capacity = TableLimits.from_numbers(
        piston_area=table["piston_area"],
        mid_stroke=table["mid_stroke"],
        table_mass=table["mass"],
        supply_pressure=table["supply_pressure"],
        return_pressure=table.get("return_pressure") or 0.0,
        rated_flow=table["rated_flow"],
        rated_pressure_drop=table["rated_pressure_drop"],
    )
    return {
        "stroke": (capacity.stroke_in, "mid_stroke"),
        "rate": (capacity.velocity_in_s, "valve velocity capacity"),
        "force": (capacity.force_lbf, "force capacity A_p (P_S - P_R)"),
        "mass": (float(table["mass"]), "mass"),
    }


def _stated_capacity(capacity: Mapping[str, float]) -> dict[str, tuple[float, str]]:
    """Stroke, rate, force and mass stated by an LTI table's ``[capacity]``, each with what it is."""
    for key in _CAPACITY_KEYS:
        if capacity.get(key) is None:
            raise ConfigError(
                f"design capacity.{key}",
                "present: the generated code's stroke clamp, rate limit and input ranges of a table given "
                "as a linear model come from its [capacity] section (stroke, velocity, force, mass)",
            )
    return {
        "stroke": (float(capacity["stroke"]), "stated stroke (capacity.stroke)"),
        "rate": (float(capacity["velocity"]), "stated velocity capacity (capacity.velocity)"),
        "force": (float(capacity["force"]), "stated stall force (capacity.force)"),
        "mass": (float(capacity["mass"]), "stated mass"),
    }


#: What :func:`check_renderable` calls a channel's system matrix in its message.
COEFFICIENTS = "discrete coefficients [[A - I, B], [C, D]]"


def rendered_limits(limits: CommandLimits, loop_time_s: float, precision: str) -> dict[str, float]:
    """The limits as the generated code holds them: ``stroke`` [in], ``du_max`` [in per loop],
    ``accel_limit`` [in/s^2], ``force_limit`` [lbf], ``value_limit``.

    Raises
    ------
    ConfigError
        A limit the precision cannot hold (:func:`check_renderable`).
    """
    values = {
        "stroke": limits.stroke_in,
        "du_max": limits.rate_step_in(loop_time_s),
        "accel_limit": limits.accel_limit_in_s2,
        "force_limit": limits.force_limit_lbf,
    }
    for key, value in values.items():
        check_renderable(f"limits.{key}", value, precision, "a limit")
    return {**values, "value_limit": VALUE_LIMIT[precision]}
