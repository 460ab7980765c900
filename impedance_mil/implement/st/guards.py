"""The safety layer of the generated Structured Text (:mod:`impedance_mil.implement.safety`).

Both function blocks (``P_controller`` and ``P_mil``) take the extra inputs
``loop_time_s`` (the measured loop time [s]; 0.0: not checked) and ``reset``
(TRUE for one scan: clear the fault word, put the controller and the VS at
rest, keep the held command) and give the outputs ``fault`` (latched and
sticky bits, :class:`~impedance_mil.implement.safety.Fault`) and ``active``
(the bits of this scan).  NaN is found by ``v <> v`` and infinity by
``ABS(v) > real_max``: the PLC compiler must keep IEEE comparisons (as it
must keep the order of the compensated sums).

Conditions are written with every operand of ``AND``/``OR`` in parentheses,
so that they read the same under any precedence of the bit operators.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..io_units import IOUnits
from ..safety import HOLD, CommandLimits, Fault, rendered_limits

#: ST name of each fault bit's constant.
BIT_NAMES = {f: f"F_{f.name}" for f in Fault}


def word(value: int) -> str:
    """An IEC 61131-3 WORD literal (``16#0001``)."""
    return f"16#{value:04X}"


def real_max(precision: str) -> float:
    """The largest finite value of the precision (infinity is beyond it)."""
    return float(np.finfo(np.float32 if precision == "single" else np.float64).max)


def constants(
    limits: CommandLimits, loop_time_s: float, precision: str, real: str, lit: Callable[[float], str]
) -> list[str]:
    """VAR CONSTANT lines of the safety layer: the bits, the limits, the loop-time check."""
    lines = ["    (* safety layer (docs/implement.md, Safety layer): fault bits and limits *)"]
    lines += [f"    {BIT_NAMES[f]} : WORD := {word(int(f))};" for f in Fault]
    lines.append(f"    F_HOLD : WORD := {word(int(HOLD))};")
    values = {
        **rendered_limits(limits, loop_time_s, precision),
        "real_max": real_max(precision),
        "loop_time_design": loop_time_s,
        "loop_time_tol": limits.loop_time_rtol * loop_time_s,
    }
    lines += [f"    {k} : {real} := {lit(v)};" for k, v in values.items()]
    return lines


def out_of_range(values: Sequence[str], limit: str) -> str:
    """A condition TRUE when any value is NaN or beyond ``+-limit`` (infinity included)."""
    return " OR ".join(f"({v} <> {v}) OR (ABS({v}) > {limit})" for v in values)


def reset_block(states: Sequence[str]) -> list[str]:
    """``reset``: clear the faults and put every state at rest (the held command stays)."""
    return [
        "(* reset: clear the fault word, controller and VS at rest; the held command stays *)",
        "IF reset THEN",
        *[f"    {s} := 0.0;" for s in states],
        f"    fault := {word(0)};",
        "END_IF;",
    ]


def input_checks(inputs: Sequence[tuple[str, str]]) -> list[str]:
    """This scan's bits from the loop time and the inputs ``(name, limit)``; latched in ``fault``."""
    out = [
        f"active := {word(0)};",
        "(* optional loop-time check: loop_time_s is the measured loop time, 0.0 when not measured *)",
        "IF loop_time_s <> 0.0 THEN",
        "    IF (loop_time_s <> loop_time_s) OR (ABS(loop_time_s - loop_time_design) > loop_time_tol) THEN",
        f"        active := active OR {BIT_NAMES[Fault.LOOP_TIME]};",
        "    END_IF;",
        "END_IF;",
        "(* inputs: NaN or infinite, or beyond their range *)",
    ]
    for name, limit in inputs:
        out += [
            f"IF ({name} <> {name}) OR (ABS({name}) > real_max) THEN",
            f"    active := active OR {BIT_NAMES[Fault.INPUT_NAN]};",
            f"ELSIF ABS({name}) > {limit} THEN",
            f"    active := active OR {BIT_NAMES[Fault.INPUT_RANGE]};",
            "END_IF;",
        ]
    return [*out, "fault := fault OR active;"]


def overflow(values: Sequence[str]) -> list[str]:
    """Latch :attr:`Fault.OVERFLOW` when a value is NaN, infinite or beyond ``value_limit``."""
    return [
        f"    IF {out_of_range(values, 'value_limit')} THEN",
        f"        active := active OR {BIT_NAMES[Fault.OVERFLOW]};",
        "        fault := fault OR active;",
        "    END_IF;",
    ]


def command(extra_hold: Sequence[str] = (), u: str = "u") -> list[str]:
    """The safe command ``u`` from ``u_raw``: held during a fault, else clamped and rate limited.

    ``u`` names the command [in] (``u_int`` when the block's output is in other I/O units).
    """
    return [
        "(* the safe command: held during a fault, else clamped to the stroke and rate limited;",
        f"   when neither acts, {u} is u_raw unchanged *)",
        f"IF (fault AND F_HOLD) = {word(0)} THEN",
        f"    {u} := u_raw;",
        f"    IF {u} > stroke THEN",
        f"        {u} := stroke;",
        f"        active := active OR {BIT_NAMES[Fault.CLAMP]};",
        f"    ELSIF {u} < -stroke THEN",
        f"        {u} := -stroke;",
        f"        active := active OR {BIT_NAMES[Fault.CLAMP]};",
        "    END_IF;",
        f"    IF {u} - u_safe > du_max THEN",
        f"        {u} := u_safe + du_max;",
        f"        active := active OR {BIT_NAMES[Fault.RATE]};",
        f"    ELSIF {u} - u_safe < -du_max THEN",
        f"        {u} := u_safe - du_max;",
        f"        active := active OR {BIT_NAMES[Fault.RATE]};",
        "    END_IF;",
        "    fault := fault OR active;",
        f"    u_safe := {u};",
        "ELSE",
        f"    {u} := u_safe;",
        *[f"    {line}" for line in extra_hold],
        "END_IF;",
    ]


def header(limits: CommandLimits, loop_time_s: float, io_units: IOUnits | None = None) -> str:
    """The program comment's paragraph on the safety layer (limits and where they came from).

    With I/O units other than the internal ones, the input ranges are also stated in them.
    """
    io = io_units or IOUnits.internal()
    in_io = "" if io.is_internal else f"   (in the I/O units: {io.input_ranges(limits)});\n"
    return (
        "   Safety layer (docs/implement.md, Safety layer): inputs loop_time_s (measured loop time [s],\n"
        "   0.0: not checked) and reset (TRUE for one scan after a fault); outputs fault (latched and\n"
        "   sticky bits) and active (this scan's bits):\n"
        + "".join(f"     {word(int(f))} {BIT_NAMES[f]}\n" for f in Fault)
        + f"   stroke clamp +-{limits.stroke_in:.6g} in ({limits.source('stroke')});\n"
        f"   rate limit {limits.max_rate_in_s:.6g} in/s = {limits.rate_step_in(loop_time_s):.6g} in per loop "
        f"({limits.source('rate')});\n"
        f"   input ranges |z_vs|, |a_g| <= {limits.accel_limit_in_s2:.6g} in/s^2, |w| <= "
        f"{limits.force_limit_lbf:.6g} lbf\n   ({limits.source('inputs')});\n"
        + in_io
        + f"   loop-time tolerance {limits.loop_time_rtol:g} of the designed loop time.\n"
        "   A fault of F_HOLD latches and holds the last safe command until reset; the clamp and\n"
        "   the rate limit act without holding.  When no guard acts, u is what the runtime computes."
    )
