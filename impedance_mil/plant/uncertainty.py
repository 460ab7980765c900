"""An uncertainty set of a table: ranges of its uncertain parameters, and the tables they give.

A lab file's ``[uncertainty]`` section (:func:`impedance_mil.lab.labfile.load_lab`)
gives a range to some parameters of the table (issue 17, item 3)::

    [uncertainty]
    f_oil_hz = "±10 %"                            # relative to the table's value
    zeta_oil = { min = 0.25, max = "40 %" }       # absolute, in any unit of the dimension
    d = { min = "8e4 psi/s/mA", max = "1.2e5 psi/s/mA" }
    valve_poles_hz = "±20 %"                      # both poles scaled by one factor (relative only)
    extra_delay = { min = 0, max = "1 loop" }     # loops, or a time that is whole loops
    foundation_stiffness = "±50 %"                # a dynamic of the lab's [dynamics] (plant.table_dynamics)

Each range is a closed interval; the set is the box of the ranges (the
parameters vary independently: ``d`` is not derived again from a changed
oil column).  :data:`UNCERTAIN_KEYS` lists the parameters a set may name.
The set is sampled at the vertices of the box (:meth:`UncertaintySet.vertices`)
and at a seeded Latin-hypercube sample (:meth:`UncertaintySet.latin_hypercube`);
:meth:`UncertaintySet.apply` makes the table of one sample point.
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..config import quantity
from ..errors import ConfigError
from .parameters import TableParameters
from .table_dynamics import TableDynamics

#: Largest output delay of a sampled table [loops] (the lab's limit, lab.setup.MAX_OUTPUT_DELAY).
MAX_TOTAL_DELAY = 100

#: The extra-delay key: loops added to the controller's output delay (N of the table).
EXTRA_DELAY = "extra_delay"


@dataclass(frozen=True)
class UncertainKey:
    """One parameter an uncertainty set may name.

    Attributes
    ----------
    unit : str
        Internal unit (pint), the dimension a range must have.
    help : str
        What it is.
    valve : str or None
        The valve kind that has the parameter (None: every table).
    relative_only : bool
        The range must be relative (``"±10 %"``): ``valve_poles_hz`` scales both poles.
    """

    unit: str
    help: str
    valve: str | None = None
    relative_only: bool = False


#: Parameters of an uncertainty set (lab file ``[uncertainty]``), by key.
UNCERTAIN_KEYS: dict[str, UncertainKey] = {
    "f_oil_hz": UncertainKey("hertz", "oil-column frequency [Hz]"),
    "zeta_oil": UncertainKey("dimensionless", "oil-column damping ratio [-]"),
    "d": UncertainKey("psi / second / milliampere", "flow gain d of Eq 4-12 [psi/(s*mA)]"),
    "valve_poles_hz": UncertainKey(
        "dimensionless", "factor on both servovalve poles (two-pole valve)", "two-pole", True
    ),
    "valve_frequency_hz": UncertainKey("hertz", "second-order valve frequency [Hz]", "second-order"),
    "valve_damping": UncertainKey("dimensionless", "second-order valve damping [-]", "second-order"),
    "valve_time_constant": UncertainKey("second", "first-order valve time constant [s]", "first-order"),
    EXTRA_DELAY: UncertainKey("dimensionless", "loops added to the controller's output delay"),
    "pressure_friction": UncertainKey("force_pound / psi", "seal friction per psi of P1 + P2 [lbf/psi]"),
    "load_pressure_friction": UncertainKey(
        "force_pound / psi", "seal friction per psi of |P1 - P2| [lbf/psi]"
    ),
    "spool_rate_limit": UncertainKey("milliampere / second", "spool rate limit [mA/s]"),
    "foundation_stiffness": UncertainKey("force_pound / inch", "mount stiffness k_f [lbf/in]"),
}

#: The keys that vary the table's optional dynamics (``TableParameters.dynamics``, issue 17):
#: the lab must set each in ``[dynamics]`` (its nominal value).
DYNAMICS_KEYS = ("pressure_friction", "load_pressure_friction", "spool_rate_limit", "foundation_stiffness")

#: Unit of each range in JSON (``valve_poles_hz`` is a factor, dimensionless).
RANGE_UNITS = {
    "f_oil_hz": "Hz",
    "d": "psi/s/mA",
    "valve_frequency_hz": "Hz",
    "valve_time_constant": "s",
    "pressure_friction": "lbf/psi",
    "load_pressure_friction": "lbf/psi",
    "spool_rate_limit": "mA/s",
    "foundation_stiffness": "lbf/in",
}

_RELATIVE = re.compile(r"^\s*(?:±|\+-|\+/-)\s*([0-9]*\.?[0-9]+(?:[eE][+-]?[0-9]+)?)\s*(?:%|percent)\s*$")


@dataclass(frozen=True)
class ParameterRange:
    """The range of one uncertain parameter, internal units.

    Attributes
    ----------
    key : str
        A key of :data:`UNCERTAIN_KEYS`.
    low, high : float
        Ends of the range (``valve_poles_hz``: factors on the poles; ``extra_delay``:
        whole loops).
    nominal : float
        The table's own value (1 for a factor, 0 for the extra delay).
    relative : float or None
        The relative half-width (0.1 for ``"±10 %"``) when given so, else None.
    """

    key: str
    low: float
    high: float
    nominal: float
    relative: float | None = None

    @property
    def integer(self) -> bool:
        """Whole values only (the extra delay in loops)."""
        return self.key == EXTRA_DELAY

    def at(self, u: float) -> float:
        """The value at the fraction ``u`` in [0, 1] of the range (whole loops: each loop an equal share)."""
        if self.integer:
            count = int(round(self.high - self.low)) + 1
            return float(self.low + min(int(u * count), count - 1))
        return float(self.low + u * (self.high - self.low))

    @property
    def unit(self) -> str:
        """The unit of :attr:`low`, :attr:`high`, :attr:`nominal` as JSON names it (internal units)."""
        return RANGE_UNITS.get(self.key, "")

    def to_dict(self) -> dict[str, Any]:
        """``min``, ``max``, ``nominal`` with their ``unit`` (the extra delay: ``min_loops`` ...)."""
        if self.integer:
            return {"min_loops": self.low, "max_loops": self.high, "nominal_loops": self.nominal}
        return {
            "min": self.low,
            "max": self.high,
            "nominal": self.nominal,
            "unit": self.unit,
            "relative_fraction": self.relative,
        }


@dataclass(frozen=True)
class UncertaintySet:
    """The box of parameter ranges of one table (a lab file's ``[uncertainty]``).

    Attributes
    ----------
    ranges : tuple of ParameterRange
        One per uncertain parameter, in the file's order.
    """

    ranges: tuple[ParameterRange, ...]

    @property
    def keys(self) -> tuple[str, ...]:
        return tuple(r.key for r in self.ranges)

    def nominal(self) -> dict[str, float]:
        """The nominal point (the table as its file states it)."""
        return {r.key: r.nominal for r in self.ranges}

    def vertices(self) -> list[dict[str, float]]:
        """The corners of the box (a degenerate range counts once), in a fixed order."""
        ends = [sorted({r.low, r.high}) for r in self.ranges]
        return [dict(zip(self.keys, corner, strict=True)) for corner in itertools.product(*ends)]

    def latin_hypercube(self, n: int, seed: int) -> list[dict[str, float]]:
        """``n`` points of a Latin-hypercube sample of the box, reproducible from ``seed``.

        Each parameter's range is cut into ``n`` equal strata; each stratum holds
        one point (uniform in it) and the strata are paired at random between
        parameters (numpy ``default_rng(seed)``).  Whole loops take the value of
        the loop whose share holds the point (:meth:`ParameterRange.at`).
        """
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise ConfigError("samples", "a non-negative whole number of sample points", n)
        rng = np.random.default_rng(seed)
        columns = [(rng.permutation(n) + rng.random(n)) / max(n, 1) for _ in self.ranges]
        return [
            {r.key: r.at(float(col[i])) for r, col in zip(self.ranges, columns, strict=True)}
            for i in range(n)
        ]

    def apply(self, table: TableParameters, point: Mapping[str, float]) -> TableParameters:
        """The table at one point of the set (``point``: key -> value, as :meth:`vertices` gives)."""
        changes: dict[str, Any] = {}
        dynamics: dict[str, float] = {}
        for key, value in point.items():
            if key in DYNAMICS_KEYS:
                dynamics[key] = value
            elif key == EXTRA_DELAY:
                changes["output_delay_loops"] = table.output_delay_loops + int(round(value))
            elif key == "valve_poles_hz":
                changes[key] = tuple(f * value for f in table.valve_poles_hz)
            elif key in UNCERTAIN_KEYS:
                changes[key] = value
            else:
                raise ConfigError(f"uncertainty.{key}", "one of the keys " + ", ".join(UNCERTAIN_KEYS))
        if dynamics:
            changes["dynamics"] = replace(table.dynamics or TableDynamics(), **dynamics)
        return table.replace(**changes) if changes else table

    def to_dict(self) -> dict[str, Any]:
        """The set as plain data: each key's range (internal units; ``valve_poles_hz``: a factor)."""
        return {r.key: r.to_dict() for r in self.ranges}


def parse_uncertainty(section: Any, table: TableParameters, where: str = "") -> UncertaintySet:
    """Read a lab file's ``[uncertainty]`` section for ``table`` (its nominal values).

    Parameters
    ----------
    section : mapping
        Key -> ``"±P %"`` or ``{min = ..., max = ...}`` (any unit of the key's
        dimension; a bare number is in the internal unit; ``extra_delay`` in
        loops, ``"N loops"`` or a time that is a whole number of loops).
    table : TableParameters
        The nominal table (its valve kind, loop time and output delay).
    where : str
        Prefix of error keys (``"mylab.toml: "``).

    Raises
    ------
    ConfigError
        Naming ``uncertainty.KEY``: an unknown key, a key of another valve
        kind, a wrong dimension, ``min > max``, a relative range of 100 % or
        more, a delay that is not whole loops, or a range whose ends give an
        invalid table (e.g. ``zeta_oil`` of 1 or more).
    """
    if not isinstance(section, Mapping) or not section:
        raise ConfigError(f"{where}uncertainty", "a TOML table of parameter ranges", section)
    ranges = []
    for key, raw in section.items():
        name = f"{where}uncertainty.{key}"
        spec = UNCERTAIN_KEYS.get(str(key))
        if spec is None:
            raise ConfigError(name, "one of the keys " + ", ".join(UNCERTAIN_KEYS))
        if spec.valve is not None and spec.valve != table.valve:
            raise ConfigError(
                name, f"a key of the table's valve ({table.valve!r}); {key} is of {spec.valve!r}"
            )
        rng = _range(str(key), raw, spec, table, name)
        _check_ends(rng, table, name)
        ranges.append(rng)
    return UncertaintySet(tuple(ranges))


def _nominal(key: str, table: TableParameters, name: str = "") -> float:
    if key in DYNAMICS_KEYS:
        value = None if table.dynamics is None else getattr(table.dynamics, key)
        if not value:  # a dynamic that is off has no nominal to vary around
            raise ConfigError(name, f"the lab's [dynamics] to set {key} (its nominal value) first")
        return float(value)
    if key == EXTRA_DELAY:
        return 0.0
    if key == "valve_poles_hz":
        return 1.0
    return float(getattr(table, key))


def _range(key: str, raw: Any, spec: UncertainKey, table: TableParameters, name: str) -> ParameterRange:
    nominal = _nominal(key, table, name)
    if isinstance(raw, str):
        match = _RELATIVE.match(raw)
        if match is None or key == EXTRA_DELAY:
            raise ConfigError(name, _expected(key, spec), raw)
        half = float(match.group(1)) / 100.0
        if not half < 1.0:
            raise ConfigError(name, "a relative half-width below 100 %", raw)
        return ParameterRange(key, nominal * (1.0 - half), nominal * (1.0 + half), nominal, half)
    if not isinstance(raw, Mapping) or spec.relative_only:
        raise ConfigError(name, _expected(key, spec), raw)
    unknown = sorted(set(raw) - {"min", "max"})
    if unknown or not {"min", "max"} <= set(raw):
        raise ConfigError(f"{name}.{unknown[0]}" if unknown else name, "a range { min = ..., max = ... }")
    low, high = (_value(key, raw[end], spec, table, f"{name}.{end}") for end in ("min", "max"))
    if not low <= high:
        raise ConfigError(name, f"min <= max, got min {low:g} and max {high:g} (internal units)")
    return ParameterRange(key, low, high, nominal)


def _expected(key: str, spec: UncertainKey) -> str:
    if spec.relative_only:
        return f'a relative range such as "±10 %" ({spec.help})'
    if key == EXTRA_DELAY:
        return '{ min = ..., max = ... } in loops ("1 loop") or a time of whole loops ("0.5 ms")'
    return f'a relative range such as "±10 %" or {{ min = ..., max = ... }} in {spec.unit}'


def _value(key: str, raw: Any, spec: UncertainKey, table: TableParameters, name: str) -> float:
    if key != EXTRA_DELAY:
        return quantity(name, raw, spec.unit, "nonnegative")
    text = raw.split() if isinstance(raw, str) else []
    if text[-1:] in (["loop"], ["loops"]):
        raw = text[0] if len(text) == 2 else raw
    if isinstance(raw, str) and any(c.isalpha() for c in raw):
        if not table.loop_time > 0:
            raise ConfigError(name, "a delay in loops (the table is analog: loop_time 0)", raw)
        loops = quantity(name, raw, "second", "nonnegative") / table.loop_time
    else:
        loops = quantity(name, raw, "dimensionless", "nonnegative")
    if not math.isclose(loops, round(loops), abs_tol=1e-9):
        raise ConfigError(name, f"a whole number of loops of {table.loop_time * 1e6:g} us", raw)
    return float(round(loops))


def _check_ends(rng: ParameterRange, table: TableParameters, name: str) -> None:
    """Each end of the range gives a valid table (with the others at their nominal values)."""
    one = UncertaintySet((rng,))
    for value in (rng.low, rng.high):
        if rng.key == EXTRA_DELAY and table.output_delay_loops + value > MAX_TOTAL_DELAY:
            raise ConfigError(name, f"a total output delay of at most {MAX_TOTAL_DELAY} loops", value)
        if rng.key == "zeta_oil" and not value < 1.0:
            raise ConfigError(name, "an oil-column damping ratio below 1", value)
        try:
            one.apply(table, {rng.key: value})
        except ConfigError as exc:
            raise ConfigError(name, f"a range giving a valid table ({exc})", value) from None
