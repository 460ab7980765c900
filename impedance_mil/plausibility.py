"""Physical plausibility of parameter sets: impossible values are errors, odd ones warnings.

A unit check (:mod:`impedance_mil.config`) makes sure a value has the right
dimension and sign; this module asks whether it could belong to a real
servo-hydraulic shake table at all.  Every rule lives here, with its reason,
and ``docs/limits.md`` lists them with their values.

Two kinds of bound per key, both in internal units (:mod:`impedance_mil.units`):

* **error** bounds: outside them the value is impossible for a hydraulic
  shake table (a moving mass of 1e308 lbf*s**2/in, a model constant d of
  1e-300), or the model's arithmetic loses meaning.  A
  :class:`~impedance_mil.errors.ConfigError` names the key.
* **warning** bounds: outside them the value is possible but odd, typically a
  unit slip (100 times the report's value or more).  A
  :class:`PlausibilityWarning` names the key; the work goes on.

Virtual systems (:data:`VS_BOUNDS`) are bounded by the dimension of each
parameter, so a user's own type is bounded too, with error bounds only;
specimens by their weight (:data:`SPECIMEN_BOUNDS`).

Cross-key rules of a table: the return pressure is below the supply
pressure; the loop time is shorter than half the oil-column period (the
controller must sample the mode it damps, f_oil below the Nyquist
frequency); a loop time longer than the shortest valve time constant is a
warning.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .errors import ConfigError
from .units import TWO_PI


class PlausibilityWarning(UserWarning):
    """A parameter is possible but odd (e.g. 100 times the report's value); the message names it."""


@dataclass(frozen=True)
class Bound:
    """Broad plausibility bounds of one key, in its internal unit.

    Parameters
    ----------
    unit : str
        Internal unit, for messages.
    error_low, error_high : float or None
        Values below ``error_low`` or above ``error_high`` are impossible (None: no bound).
    warn_low, warn_high : float or None
        Values outside are odd but possible (None: no bound).
    reason : str
        Why the bounds are where they are (shown in messages and ``docs/limits.md``).
    """

    unit: str
    error_low: float | None
    warn_low: float | None
    warn_high: float | None
    error_high: float | None
    reason: str


#: Bounds of the table parameters (report Table 4.1 values in the reasons).
TABLE_BOUNDS: dict[str, Bound] = {
    "Ke": Bound(
        "V/in", 5e-6, 0.05, 500.0, 5e6, "report 5 V/in; gains more than 1e6 times off are no servo loop"
    ),
    "Kp": Bound("V/psi", None, None, 0.1, 1e3, "report 0.001 V/psi; 1e6 times more is no servo loop"),
    "Kv": Bound(
        "mA/V", 3e-6, 0.03, 300.0, 3e6, "report 3 mA/V; gains more than 1e6 times off are no servo loop"
    ),
    "loop_time": Bound(
        "s", None, None, 0.01, 1.0, "report 500 us; controllers run at 100 Hz to 100 kHz, not at 1 Hz"
    ),
    "piston_area": Bound("in^2", 1e-4, 0.1, 1e3, 1e5, "report 2.1 in^2; 1e5 in^2 is a piston of 30 ft"),
    "mid_stroke": Bound("in", 1e-3, 0.1, 100.0, 1e4, "report 3.2 in; 1e4 in is a half stroke of 830 ft"),
    "mass": Bound(
        "lbf*s^2/in",
        1e-5,
        0.01,
        1e4,
        1e7,
        "report 4.14 (1600 lb); the largest tables carry about 2.6e6 lb (6.9e3), 1e7 is 3.9e9 lb",
    ),
    "d": Bound(
        "psi/(s*mA)",
        0.1,
        1e3,
        1e7,
        1e11,
        "report 1e5; at 25 mA, d = 0.1 takes 20 min to build 3000 psi and 1e11 takes a nanosecond",
    ),
    "valve_poles_hz": Bound(
        "Hz", 1e-3, 1.0, 2e3, 1e6, "report 70 and 110 Hz; servovalves respond at 1-1000 Hz"
    ),
    "zeta_oil": Bound("-", None, None, 0.5, None, "report 0.09; oil columns are lightly damped"),
    "f_oil_hz": Bound("Hz", 1e-2, 1.0, 500.0, 1e5, "report 27 Hz; oil columns of tables sit at 2-300 Hz"),
    "supply_pressure": Bound(
        "psi",
        1.0,
        500.0,
        1e4,
        1e5,
        "report 3000 psi; hydraulic systems run at 1000-5000 psi, steel yields near 1e5",
    ),
    "return_pressure": Bound("psi", None, None, None, 1e5, "report 0 psi; below the supply pressure"),
    "rated_flow": Bound(
        "in^3/s", 1e-4, 0.5, 1e4, 1e7, "report 57.75 in^3/s (15 gpm); 1e4 in^3/s is 2600 gpm"
    ),
    "rated_pressure_drop": Bound(
        "psi", 1.0, 100.0, 1e4, 1e5, "report 1000 psi (catalogue rating); 1e5 psi is no hydraulic system"
    ),
    "rated_current": Bound("mA", 1e-3, 1.0, 500.0, 1e5, "report 25 mA; servovalves take 10-200 mA"),
    "valve_command_limit": Bound("V", 1e-3, 1.0, 100.0, 1e4, "report 10 V; analog commands are 10 V"),
    "valve_time_constant": Bound(
        "s", 1.6e-7, 8e-5, 0.16, 160.0, "servovalves respond at 1-1000 Hz (T = 0.16 ms to 0.16 s)"
    ),
    "valve_frequency_hz": Bound("Hz", 1e-3, 1.0, 2e3, 1e6, "servovalves respond at 1-1000 Hz"),
    "valve_damping": Bound(
        "-", None, 0.05, 5.0, 1e3, "valve spools are damped 0.3-1.5; 1e3 is two poles 1e6 apart"
    ),
    "platen_damping": Bound(
        "lbf*s/in", None, None, 1e5, 1e9, "report none (0); 1e5 damps the report's table 12 times critically"
    ),
    "coulomb_friction": Bound(
        "lbf", None, None, 1e5, 1e10, "report none; rail friction is a few % of the table's weight"
    ),
    "output_gain": Bound("-", 1e-6, 0.1, 10.0, 1e6, "report 1 (the displacement sensor scaled to inches)"),
    "grounded_stiffness": Bound(
        "lbf/in", None, None, 1e7, 1e13, "report none; a steel bar 1 ft^2 by 1 in is 4e9 lbf/in"
    ),
}


#: Bounds of the virtual-system parameters, by internal unit (the dimension of the
#: parameter, so a user's own type is bounded too).  Only error bounds: a VS is a
#: model, and a designer may try odd ones; these only refuse values no structure
#: or isolator has (the report's Tables 9.1-9.3 values in the reasons).
VS_BOUNDS: dict[str, Bound] = {
    "force_pound*second**2/inch": Bound(
        "lbf*s**2/in",
        1e-5,
        None,
        None,
        1e7,
        "a mass: report m_vs 5.18 (2000 lb); 1e-5 is 0.004 lb, 1e7 is 3.9e9 lb, as for the table's mass",
    ),
    "force_pound/inch": Bound(
        "lbf/in",
        None,
        None,
        None,
        1e13,
        "a stiffness: report k_s 113-1754, k_i up to 3513 lbf/in; a steel bar 1 ft^2 by 1 in is 4e9, "
        "tests model rigid storeys with 1e10",
    ),
    "force_pound*second/inch": Bound(
        "lbf*s/in", None, None, None, 1e9, "a damping: report c 0.11-64 lbf*s/in; 1e9 is a rigid link"
    ),
    "force_pound": Bound(
        "lbf", None, None, None, 1e10, "a force: report w_ps 3600 lbf, q_d 504-1176 lbf; 1e10 lbf is 4.5e6 t"
    ),
    "inch": Bound(
        "in",
        1e-6,
        None,
        None,
        1e5,
        "a length: report u_y 0.008-0.4 in, radii 2.8-83.5 in; 1e-6 in is below any yield, 1e5 in is 1.6 mi",
    ),
    "second": Bound("s", 1e-4, None, None, 1e4, "a period: report T_s 1.5-4 s; 1e4 s is 2.8 h"),
    "hertz": Bound(
        "Hz",
        1e-4,
        None,
        None,
        1e5,
        "a frequency: report f 0.5-2 Hz; 1e-4 and 1e5 Hz are periods of 2.8 h and 10 us",
    ),
    "second/inch": Bound(
        "s/in", None, None, None, 1e6, "a rate parameter: report a = 2.54 s/in; 1e6 is a step change"
    ),
    "dimensionless": Bound(
        "-",
        None,
        None,
        None,
        1e3,
        "a ratio: report friction 0.02-0.2, alpha 0.1, zeta up to 0.3, Bouc-Wen n = 2; 1e3 is none of them",
    ),
}
#: Bound of a VS parameter in a unit :data:`VS_BOUNDS` does not list (a user's own type).
VS_ANY_BOUND = Bound("(its unit)", None, None, None, 1e15, "any parameter: 1e15 in internal units")

#: Bounds of specimen values (in lbf: the weight of a rigid mass or of a storey).
SPECIMEN_BOUNDS: dict[str, Bound] = {
    "weight": Bound(
        "lbf",
        None,
        None,
        1e7,
        1e9,
        "report 3600 lbf (Section 8.2); the largest tables carry about 2.6e6 lb, 1e9 lb is 4.5e5 t",
    ),
}


def _fmt(value: float) -> str:
    return f"{value:.6g}"


def check_value(key: str, value: float, bound: Bound) -> str | None:
    """Check one value against its bounds.

    Parameters
    ----------
    key : str
        Name of the key, for messages.
    value : float
        The value, in the bound's internal unit.
    bound : Bound

    Returns
    -------
    str or None
        A warning text naming the key when the value is odd, else None.

    Raises
    ------
    ConfigError
        The value is not finite or is outside the error bounds.

    Examples
    --------
    >>> check_value("mass", 4.14, TABLE_BOUNDS["mass"]) is None
    True
    >>> check_value("mass", 1e308, TABLE_BOUNDS["mass"])
    Traceback (most recent call last):
    ...
    impedance_mil.errors.ConfigError: mass: expected a plausible value, at most 1e+07 lbf*s^2/in (report 4.14 (1600 lb); the largest tables carry about 2.6e6 lb (6.9e3), 1e7 is 3.9e9 lb), got 1e+308
    """
    if not math.isfinite(value):
        raise ConfigError(key, "a finite number", value)
    if bound.error_low is not None and value < bound.error_low:
        raise ConfigError(
            key, f"a plausible value, at least {_fmt(bound.error_low)} {bound.unit} ({bound.reason})", value
        )
    if bound.error_high is not None and value > bound.error_high:
        raise ConfigError(
            key, f"a plausible value, at most {_fmt(bound.error_high)} {bound.unit} ({bound.reason})", value
        )
    if bound.warn_low is not None and value < bound.warn_low:
        return f"{key} = {_fmt(value)} {bound.unit} is unusually small (below {_fmt(bound.warn_low)}; {bound.reason})"
    if bound.warn_high is not None and value > bound.warn_high:
        return f"{key} = {_fmt(value)} {bound.unit} is unusually large (above {_fmt(bound.warn_high)}; {bound.reason})"
    return None


def check_bounds(values: Mapping[str, Any], bounds: Mapping[str, Bound], *, where: str = "") -> list[str]:
    """Check every value that has a bound (a list or tuple value: each element).

    Returns
    -------
    list of str
        The warnings (odd values), each naming its key.

    Raises
    ------
    ConfigError
        An impossible value (the key is named, with ``where`` as prefix).
    """
    out = []
    for key, bound in bounds.items():
        if key not in values:
            continue
        raw = values[key]
        for value in raw if isinstance(raw, (list, tuple)) else (raw,):
            text = check_value(f"{where}{key}", float(value), bound)
            if text is not None:
                out.append(text)
    return out


def table_warnings(values: Mapping[str, Any], *, where: str = "") -> list[str]:
    """Plausibility of a table's parameters (:data:`TABLE_BOUNDS` and the cross-key rules).

    Parameters
    ----------
    values : mapping
        The table's parameters in internal units (``TableParameters`` fields;
        missing keys are skipped).
    where : str
        Prefix of the keys in messages (e.g. a file name).

    Returns
    -------
    list of str
        Warnings, each naming its key (odd but possible values).

    Raises
    ------
    ConfigError
        An impossible value or combination, naming the key.

    Examples
    --------
    >>> table_warnings({"supply_pressure": 3000.0, "return_pressure": 3000.0})
    Traceback (most recent call last):
    ...
    impedance_mil.errors.ConfigError: return_pressure: expected a pressure below the supply pressure 3000 psi (oil flows from supply to return), got 3000.0
    """
    out = check_bounds(values, TABLE_BOUNDS, where=where)
    supply, ret = values.get("supply_pressure"), values.get("return_pressure")
    if supply is not None and ret is not None and not ret < supply:
        raise ConfigError(
            f"{where}return_pressure",
            f"a pressure below the supply pressure {_fmt(supply)} psi (oil flows from supply to return)",
            ret,
        )
    loop, f_oil = values.get("loop_time"), values.get("f_oil_hz")
    if loop is not None and f_oil is not None and loop > 0 and not loop < 0.5 / f_oil:
        raise ConfigError(
            f"{where}loop_time",
            f"a loop time below half the oil-column period, {_fmt(0.5 / f_oil)} s (f_oil = {_fmt(f_oil)} Hz "
            "must be below the Nyquist frequency of the controller)",
            loop,
        )
    fastest = _fastest_valve_hz(values) if loop is not None and loop > 0 else None
    if loop is not None and fastest is not None:
        shortest = 1.0 / (TWO_PI * fastest)
        if loop > shortest:
            out.append(
                f"{where}loop_time = {_fmt(loop)} s is longer than the shortest valve time constant "
                f"{_fmt(shortest)} s (valve pole {_fmt(fastest)} Hz): the controller cannot follow the valve"
            )
    return out


def _fastest_valve_hz(values: Mapping[str, Any]) -> float | None:
    """The fastest valve pole [Hz] of a table's values (two poles, a time constant or a frequency)."""
    poles = values.get("valve_poles_hz")
    if poles:
        return max(float(p) for p in poles)
    if values.get("valve_time_constant"):
        return 1.0 / (TWO_PI * float(values["valve_time_constant"]))
    if values.get("valve_frequency_hz"):
        zeta = float(values.get("valve_damping") or 0.0)
        # the faster pole of an overdamped pair, w (zeta + sqrt(zeta^2 - 1)); |p| = w below zeta = 1
        return float(values["valve_frequency_hz"]) * (zeta + math.sqrt(zeta**2 - 1.0) if zeta > 1.0 else 1.0)
    return None


def vs_bound(unit: str) -> Bound:
    """The bound of a VS parameter in internal ``unit`` (pint expression; spaces ignored)."""
    return VS_BOUNDS.get(unit.replace(" ", ""), VS_ANY_BOUND)


def check_vs_value(key: str, value: float, unit: str) -> float:
    """Refuse a VS parameter outside the broad bounds of its dimension (:data:`VS_BOUNDS`).

    The magnitude is checked (a parameter that may be negative is bounded
    both ways); zero passes the lower bound (a zero damping is no slip).

    Parameters
    ----------
    key : str
        Name of the parameter (with its file prefix), for messages.
    value : float
        Its value in internal ``unit``.
    unit : str
        The parameter's internal unit (pint expression).

    Returns
    -------
    float
        ``value``.

    Raises
    ------
    ConfigError
        The value is not finite or is outside the bounds, naming ``key``.

    Examples
    --------
    >>> check_vs_value("m_vs", 5.18, "force_pound * second**2 / inch")
    5.18
    >>> check_vs_value("m_vs", 1e308, "force_pound * second**2 / inch")
    Traceback (most recent call last):
    ...
    impedance_mil.errors.ConfigError: m_vs: expected a plausible value, at most 1e+07 lbf*s**2/in (a mass: report m_vs 5.18 (2000 lb); 1e-5 is 0.004 lb, 1e7 is 3.9e9 lb, as for the table's mass), got 1e+308
    """
    if value != 0.0 or not math.isfinite(value):
        check_value(key, abs(value), vs_bound(unit))
    return value


def check_specimen_weight(key: str, weight_lbf: float) -> float:
    """Refuse an impossible specimen weight [lbf] and warn about an odd one (:data:`SPECIMEN_BOUNDS`).

    Returns
    -------
    float
        ``weight_lbf``.

    Raises
    ------
    ConfigError
        The weight is not finite or above the error bound, naming ``key``.

    Examples
    --------
    >>> check_specimen_weight("weight", 3600.0)
    3600.0
    >>> check_specimen_weight("weight", 1e308)
    Traceback (most recent call last):
    ...
    impedance_mil.errors.ConfigError: weight: expected a plausible value, at most 1e+09 lbf (report 3600 lbf (Section 8.2); the largest tables carry about 2.6e6 lb, 1e9 lb is 4.5e5 t), got 1e+308
    """
    text = check_value(key, weight_lbf, SPECIMEN_BOUNDS["weight"])
    warn_all([text] if text is not None else [])
    return weight_lbf


def warn_all(texts: list[str], stacklevel: int = 3) -> None:
    """Issue each text as a :class:`PlausibilityWarning`."""
    for text in texts:
        warnings.warn(text, PlausibilityWarning, stacklevel=stacklevel)


def check_table(values: Mapping[str, Any], *, where: str = "") -> None:
    """Refuse an impossible table and warn about odd values (:func:`table_warnings`).

    Raises
    ------
    ConfigError
        An impossible value or combination, naming the key.
    """
    warn_all(table_warnings(values, where=where))


def one_line_warning(
    message: Any, category: type, filename: str, lineno: int, line: str | None = None
) -> str:
    """Format a warning of this package as one line, ``imil: warning: MESSAGE`` (others as Python does).

    For :data:`warnings.formatwarning` in a command-line program.
    """
    if category.__module__.split(".")[0] == __name__.split(".")[0]:
        return f"imil: warning: {message}\n"
    return _DEFAULT_FORMAT(message, category, filename, lineno, line)


_DEFAULT_FORMAT = warnings.formatwarning
