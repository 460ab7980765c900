"""Shake-table model parameters (report Table 4.1) and the physical formulas behind them.

Every field is in the report's units (see :mod:`impedance_mil.units`).  A
table file is TOML whose values carry units (``mass = "1600 lb"``,
``loop_time = "500 us"``) or are bare numbers in the report's unit.

Two physical alternatives are accepted in files and ``--set`` overrides:
``bulk_modulus`` [psi] instead of ``f_oil_hz`` (Eq 4-10a) and
``leakage_coefficient`` [in^3/s/psi] instead of ``zeta_oil`` (Eq 4-10b).

A general physical table (issue 13) adds optional keys; left out, the table
is the report's (Eq 4-11): the servovalve kind ``valve`` (:data:`VALVE_KINDS`:
``"two-pole"``, the default, with ``valve_poles_hz``; ``"first-order"`` with
``valve_time_constant`` [s]; ``"second-order"`` with ``valve_frequency_hz``
[Hz] and ``valve_damping`` [-]), ``platen_damping`` [lbf*s/in],
``coulomb_friction`` [lbf] (the nonlinear table only), ``output_gain`` [-]
(the displacement sensor's gain in the hydraulic loop) and
``grounded_stiffness`` [lbf/in].  ``d`` may be left out: it is then derived
from the valve's rated flow (:func:`flow_gain_d`).

The pressure and valve ratings (:data:`REPORT_RATINGS`) may be left out of a
table file: they then take the report's values, read from the report's table
file (``data/report/config.toml`` names it), and :func:`ratings_from_report`
says which a file left out.  No value of Table 4.1 is written in this module.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..config import Field, parse_fields, read_toml
from ..errors import ConfigError
from ..plausibility import check_table
from ..report_config import report_config
from ..units import INTERNAL_UNITS, TWO_PI
from .physics import (
    ValveDynamics,
    bulk_modulus_from_frequency,
    flow_gain_d,
    model_constant_d,
    oil_column_damping,
    oil_column_frequency,
)
from .table_dynamics import TableDynamics

__all__ = [
    "ALTERNATIVES",
    "DEFAULT_VALVE",
    "FIELDS",
    "OPTIONAL_KEYS",
    "REPORT_RATINGS",
    "VALVE_KEYS",
    "VALVE_KINDS",
    "TableParameters",
    "ValveDynamics",
    "bulk_modulus_from_frequency",
    "default_table_path",
    "flow_gain_d",
    "merge_overrides",
    "model_constant_d",
    "oil_column_damping",
    "oil_column_frequency",
    "ratings_from_report",
    "table_mapping",
]

#: Keys of a table file: internal unit, range check and meaning.
FIELDS: dict[str, Field] = {
    "Ke": Field("volt / inch", "positive", help="proportional (position error) gain K_e [V/in]"),
    "Kp": Field("volt / psi", "nonnegative", help="differential-pressure gain K_p [V/psi]"),
    "Kv": Field("milliampere / volt", "positive", help="voltage-to-current gain K_v [mA/V]"),
    "loop_time": Field("second", "nonnegative", help="controller loop time tau_s [s] (0 = analog)"),
    "piston_area": Field("inch**2", "positive", help="piston area A_p [in^2]"),
    "mid_stroke": Field("inch", "positive", help="mid-stroke position x_m [in]"),
    "mass": Field(INTERNAL_UNITS["mass"], "positive", help="moving table mass m_st"),
    "d": Field("psi / second / milliampere", "positive", help="model constant d (Eq 4-12)"),
    "valve_poles_hz": Field("hertz", "positive", count=2, help="servovalve poles [Hz]"),
    "zeta_oil": Field("dimensionless", "fraction", help="oil-column damping ratio"),
    "f_oil_hz": Field("hertz", "positive", help="oil-column frequency [Hz]"),
    "supply_pressure": Field("psi", "positive", help="supply pressure P_S"),
    "return_pressure": Field("psi", "nonnegative", help="return pressure P_R"),
    "rated_flow": Field("inch**3 / second", "positive", help="rated valve flow Q_max"),
    "rated_pressure_drop": Field("psi", "positive", help="valve pressure drop at rated flow"),
    "rated_current": Field("milliampere", "positive", help="rated valve current"),
    "valve_command_limit": Field("volt", "positive", help="valve command limit |u_v|"),
    "valve_time_constant": Field("second", "positive", help="first-order servovalve time constant T [s]"),
    "valve_frequency_hz": Field("hertz", "positive", help="second-order servovalve natural frequency [Hz]"),
    "valve_damping": Field("dimensionless", "positive", help="second-order servovalve damping ratio [-]"),
    "platen_damping": Field(
        "force_pound * second / inch", "nonnegative", help="viscous platen damping c_p [lbf*s/in]"
    ),
    "coulomb_friction": Field(
        "force_pound", "nonnegative", help="Coulomb (rail) friction [lbf], nonlinear table only"
    ),
    "output_gain": Field("dimensionless", "positive", help="displacement sensor gain g in the loop [-]"),
    "grounded_stiffness": Field(
        "force_pound / inch", "nonnegative", help="stiffness from the platen to ground k_g [lbf/in]"
    ),
}

#: Servovalve kinds (key ``valve``) and the keys each takes; ``"two-pole"`` is Eq 4-3.
VALVE_KINDS: dict[str, tuple[str, ...]] = {
    "two-pole": ("valve_poles_hz",),
    "first-order": ("valve_time_constant",),
    "second-order": ("valve_frequency_hz", "valve_damping"),
}
#: The valve kind of a table file that does not say (the report's).
DEFAULT_VALVE = "two-pole"
#: Keys of every valve kind.
VALVE_KEYS = tuple(key for keys in VALVE_KINDS.values() for key in keys)
#: Optional keys of the general model and their value when left out (None: not given;
#: :meth:`NonlinearTable.from_linear <impedance_mil.plant.nonlinear.NonlinearTable.from_linear>`
#: then keeps its own friction defaults, and the linear model has no platen damping).
OPTIONAL_KEYS: dict[str, float | None] = {
    "platen_damping": None,
    "coulomb_friction": None,
    "output_gain": 1.0,
    "grounded_stiffness": 0.0,
}

#: Ratings a table file may leave out: they then take the values of the report's table file.
REPORT_RATINGS = (
    "supply_pressure",
    "return_pressure",
    "rated_flow",
    "rated_pressure_drop",
    "rated_current",
    "valve_command_limit",
)

#: Physical alternatives: key -> (replaced key, Field).
ALTERNATIVES: dict[str, tuple[str, Field]] = {
    "bulk_modulus": ("f_oil_hz", Field("psi", "positive", help="oil bulk modulus kappa (Eq 4-10a)")),
    "leakage_coefficient": (
        "zeta_oil",
        Field("inch**3 / second / psi", "nonnegative", help="piston leakage coefficient K_l (Eq 4-10b)"),
    ),
}


def _check_positive(name: str, value: float, allow_zero: bool = False) -> None:
    ok = value >= 0 if allow_zero else value > 0
    if not (math.isfinite(value) and ok):
        raise ConfigError(
            name, "a non-negative finite value" if allow_zero else "a positive finite value", value
        )


@dataclass(frozen=True)
class TableParameters:
    """Parameters of the uniaxial shake-table model (report Table 4.1), internal units.

    Parameters
    ----------
    Ke : float
        Proportional gain K_e [V/in] (0 allowed here for root loci; files need > 0).
    Kp : float
        Differential-pressure gain K_p [V/psi].
    Kv : float
        Voltage-to-current gain K_v [mA/V].
    loop_time : float
        Controller loop time tau_s [s]; 0 is an analog controller.
    piston_area : float
        A_p [in^2].
    mid_stroke : float
        x_m [in].
    mass : float
        Moving table mass m_st [lbf*s^2/in].
    d : float
        Model constant of Eq 4-11/4-12 [psi/(s*mA)].
    valve_poles_hz : tuple of float
        Servovalve poles alpha_1/2pi, alpha_2/2pi [Hz] (Eq 4-2).
    zeta_oil : float
        Oil-column damping ratio [-].
    f_oil_hz : float
        Oil-column frequency omega_oil/2pi [Hz].
    supply_pressure, return_pressure : float
        P_S, P_R [psi].
    rated_flow : float
        Rated valve flow Q_max [in^3/s] at ``rated_pressure_drop`` [psi].
    rated_pressure_drop : float
        [psi].
    rated_current : float
        Rated valve current u_i,max [mA].
    valve_command_limit : float
        Limit of the valve command |u_v| [V].
    valve : {"two-pole", "first-order", "second-order"}
        Servovalve kind (:data:`VALVE_KINDS`); ``valve_poles_hz`` is ``()``
        unless ``"two-pole"``, and the keys of the other kinds are None.
    valve_time_constant : float or None
        First-order valve ``1/(T s + 1)``: T [s].
    valve_frequency_hz, valve_damping : float or None
        Second-order valve ``w^2/(s^2 + 2 zeta w s + w^2)``: w/2pi [Hz] and
        zeta [-] (below 1: a complex pair).
    platen_damping : float or None
        Viscous platen damping c_p [lbf*s/in], ``m z = A_p dP + w - k_g x - c_p v``;
        None (not given) is 0 in the linear model.
    coulomb_friction : float or None
        Coulomb (rail) friction [lbf]: the nonlinear table only (its smoothed
        sign law has no linearization at rest); the linear model ignores it.
    output_gain : float
        Gain g [-] of the displacement sensor in the hydraulic loop:
        ``u_v = K_e (u - g x) - K_p dP``, so that the DC gain of x/u is 1/g.
    grounded_stiffness : float
        Stiffness k_g [lbf/in] from the platen to ground (a reaction spring,
        a specimen to ground).
    output_delay_loops : int
        The controller's output delay N [loops] (default 1, the report's
        controller): the valve command computed at loop k is applied over
        loop k + N - 1, so the command reaches the valve N - 1 loops and the
        feedback N loops late (:mod:`impedance_mil.plant.linear`).  Not a
        key of a table file: a lab's ``[controller] output_delay`` sets it
        (:func:`impedance_mil.lab.labfile.load_lab`).
    dynamics : TableDynamics or None
        Optional dynamics of the virtual table beyond the report's model
        (:mod:`impedance_mil.plant.table_dynamics`, issue 17); None: none.  Not
        a key of a table file: a lab's ``[dynamics]`` sets it; the nonlinear
        table takes it (:meth:`NonlinearTable.from_linear
        <impedance_mil.plant.nonlinear.NonlinearTable.from_linear>`), the
        linear model of Eq 4-11 does not (see
        :func:`impedance_mil.plant.table_dynamics_model.linearized_plant`).

    Examples
    --------
    >>> p = TableParameters.report_default()
    >>> p.Ke, p.Kp, p.d
    (5.0, 0.001, 100000.0)
    >>> p.replace(Ke=4.0).Ke
    4.0
    """

    Ke: float
    Kp: float
    Kv: float
    loop_time: float
    piston_area: float
    mid_stroke: float
    mass: float
    d: float
    valve_poles_hz: tuple[float, ...]
    zeta_oil: float
    f_oil_hz: float
    supply_pressure: float
    return_pressure: float
    rated_flow: float
    rated_pressure_drop: float
    rated_current: float
    valve_command_limit: float
    valve: str = DEFAULT_VALVE
    valve_time_constant: float | None = None
    valve_frequency_hz: float | None = None
    valve_damping: float | None = None
    platen_damping: float | None = None
    coulomb_friction: float | None = None
    output_gain: float = 1.0
    grounded_stiffness: float = 0.0
    output_delay_loops: int = 1
    dynamics: TableDynamics | None = None

    def __post_init__(self):
        delay = self.output_delay_loops
        if isinstance(delay, bool) or not isinstance(delay, (int, np.integer)) or delay < 1:
            raise ConfigError("output_delay_loops", "a whole number of loops, at least 1", delay)
        object.__setattr__(self, "output_delay_loops", int(delay))
        for name in ("Ke", "Kp", "loop_time", "zeta_oil", "return_pressure"):
            _check_positive(name, float(getattr(self, name)), allow_zero=True)
        for name in (
            "Kv",
            "piston_area",
            "mid_stroke",
            "mass",
            "d",
            "f_oil_hz",
            "supply_pressure",
            "rated_flow",
            "rated_pressure_drop",
            "rated_current",
            "valve_command_limit",
        ):
            _check_positive(name, float(getattr(self, name)))
        self._check_valve()
        for name in ("platen_damping", "coulomb_friction", "grounded_stiffness"):
            if getattr(self, name) is not None:
                _check_positive(name, float(getattr(self, name)), allow_zero=True)
        _check_positive("output_gain", float(self.output_gain))
        for name in FIELDS:
            if name != "valve_poles_hz" and getattr(self, name) is not None:
                object.__setattr__(self, name, float(getattr(self, name)))

    def _check_valve(self) -> None:
        """The valve kind is known, its keys are given and the keys of other kinds are not."""
        if self.valve not in VALVE_KINDS:
            raise ConfigError("valve", "one of " + ", ".join(VALVE_KINDS), self.valve)
        own = VALVE_KINDS[self.valve]
        poles = tuple(float(f) for f in self.valve_poles_hz)
        object.__setattr__(self, "valve_poles_hz", poles)
        for key in VALVE_KEYS:
            value = getattr(self, key)
            given = len(value) > 0 if key == "valve_poles_hz" else value is not None
            if given and key not in own:
                raise ConfigError(
                    key, f"no key of another valve kind (valve = {self.valve!r} takes {', '.join(own)})"
                )
            if not given and key in own:
                raise ConfigError(key, f"a value for valve = {self.valve!r}")
        if self.valve == "two-pole":
            if len(poles) != 2:
                raise ConfigError("valve_poles_hz", "two frequencies in Hz", self.valve_poles_hz)
            for f in poles:
                _check_positive("valve_poles_hz", f)
        for key in own:
            if key != "valve_poles_hz":
                _check_positive(key, float(getattr(self, key)))

    # ------------------------------------------------------------ constructors
    @classmethod
    def report_default(cls) -> TableParameters:
        """Table 4.1 of the report, with d = 1e5 (docs/errata.md, Table 4.1).

        Parsed once per process and file version (a campaign worker asks for it
        in every run: 65 ms of pint parsing each, issue 16, goal 5); the object
        is frozen, so sharing it is safe.
        """
        path = default_table_path()
        stat = path.stat()
        if cls is not TableParameters:  # a subclass parses its own
            return cls.from_toml(path)
        return _parsed_table_file(path, stat.st_mtime_ns, stat.st_size)

    @classmethod
    def from_mapping(cls, mapping: Mapping[str, Any], *, where: str = "") -> TableParameters:
        """Build from raw values (bare numbers in report units or strings with units).

        The ratings of :data:`REPORT_RATINGS` that ``mapping`` leaves out take
        the values of the report's table file.  ``valve`` (default
        ``"two-pole"``) says which valve keys are required (:data:`VALVE_KINDS`);
        a ``d`` left out is derived from the ratings and the oil column
        (:func:`flow_gain_d`); a ``d`` given wins.

        Raises
        ------
        ConfigError
            Unknown or missing key (an unknown key's message lists every key,
            the physical alternatives and the general model's), a key of
            another valve kind, wrong dimension, NaN, out of range, or a
            physically impossible table (:func:`impedance_mil.plausibility.table_warnings`;
            odd values give a ``PlausibilityWarning``).
        """
        raw = {**_report_ratings(mapping), **mapping}
        known = sorted({*FIELDS, *ALTERNATIVES, "valve"})
        unknown = sorted(set(raw) - set(known))
        if unknown:
            raise ConfigError(f"{where}{unknown[0]}", "one of the known keys " + ", ".join(known))
        kind = _valve_kind(raw.pop("valve", DEFAULT_VALVE), where)
        for key in VALVE_KEYS:
            if key in raw and key not in VALVE_KINDS[kind]:
                raise ConfigError(
                    f"{where}{key}",
                    f"no key of another valve kind (valve = {kind!r} takes {', '.join(VALVE_KINDS[kind])})",
                )
        physical: dict[str, float] = {}
        for key, (replaced, spec) in ALTERNATIVES.items():
            if key in raw:
                if replaced in raw:
                    raise ConfigError(f"{where}{key}", f"either {key} or {replaced}, not both")
                physical[key] = parse_fields({key: spec}, {key: raw.pop(key)}, where=where)[key]
                raw[replaced] = 0.5  # valid placeholder, replaced below
        derive_d = "d" not in raw
        if derive_d:
            raw["d"] = 1.0  # valid placeholder, derived below
        wanted = [
            key
            for key in FIELDS
            if (key not in VALVE_KEYS and key not in OPTIONAL_KEYS)
            or key in VALVE_KINDS[kind]
            or (key in OPTIONAL_KEYS and key in raw)
        ]
        values = parse_fields({key: FIELDS[key] for key in wanted}, raw, where=where)
        args = (values["piston_area"], values["mass"], values["mid_stroke"])
        if "bulk_modulus" in physical:
            values["f_oil_hz"] = oil_column_frequency(physical["bulk_modulus"], *args) / TWO_PI
        if "leakage_coefficient" in physical:
            kappa = bulk_modulus_from_frequency(TWO_PI * values["f_oil_hz"], *args)
            values["zeta_oil"] = oil_column_damping(physical["leakage_coefficient"], kappa, *args)
            if not values["zeta_oil"] < 1:
                raise ConfigError(
                    f"{where}leakage_coefficient",
                    "a value giving zeta_oil < 1",
                    physical["leakage_coefficient"],
                )
        if derive_d:
            values["d"] = flow_gain_d(
                TWO_PI * values["f_oil_hz"],
                values["mass"],
                values["piston_area"],
                values["rated_flow"],
                values["rated_current"],
                values["rated_pressure_drop"],
                values["supply_pressure"],
                values["return_pressure"],
            )
        check_table(values, where=where)
        return cls(**{"valve_poles_hz": (), **values, "valve": kind})

    @classmethod
    def from_toml(cls, path: str | Path, overrides: Mapping[str, Any] | None = None) -> TableParameters:
        """Read a table file; ``overrides`` (e.g. from ``--set``) win over the file.

        An override of a physical alternative (``bulk_modulus``) replaces the
        key it stands for (``f_oil_hz``) from the file, and vice versa.

        Raises
        ------
        DataFileError
            The file is missing or not TOML.
        ConfigError
            A key is unknown, missing or invalid (the message names it).
        """
        return cls.from_mapping(merge_overrides(table_mapping(read_toml(path), path), overrides or {}))

    # -------------------------------------------------------------- utilities
    def replace(self, **changes: Any) -> TableParameters:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """The table's keys (:data:`FIELDS`) in internal units; ``valve_poles_hz`` as a list.

        The keys of the valve kind only, ``valve`` unless the default, and the
        optional keys (:data:`OPTIONAL_KEYS`) that differ from their default:
        the report's table gives exactly the keys of its file.

        ``output_delay_loops`` is the controller's (a lab's), not a key of a
        table file, and is not in it.
        """
        own = VALVE_KINDS[self.valve]
        out: dict[str, Any] = {}
        for key, value in asdict(self).items():
            if key == own[0] and self.valve != DEFAULT_VALVE:
                out["valve"] = self.valve
            if key in own:
                out[key] = list(value) if key == "valve_poles_hz" else value
            elif key in OPTIONAL_KEYS:
                if value != OPTIONAL_KEYS[key]:
                    out[key] = value
            elif key in FIELDS and key not in VALVE_KEYS:
                out[key] = value
        return out

    def with_valve(self, valve: str, **keys: Any) -> TableParameters:
        """A copy with another servovalve kind and its keys (the keys of the old kind cleared).

        Examples
        --------
        >>> p = TableParameters.report_default().with_valve("first-order", valve_time_constant=0.01)
        >>> p.valve, p.valve_poles_hz, p.valve_dynamics.gamma
        ('first-order', (), 100.0)
        """
        cleared: dict[str, Any] = {key: None for key in VALVE_KEYS}
        cleared["valve_poles_hz"] = ()
        return replace(self, **{**cleared, "valve": valve, **keys})

    # ------------------------------------------------------- derived quantities
    @property
    def omega_oil(self) -> float:
        """Oil-column angular frequency [rad/s]."""
        return TWO_PI * self.f_oil_hz

    @property
    def valve_poles(self) -> tuple[float, ...]:
        """Servovalve pole magnitudes [rad/s]: alpha_1, alpha_2 of Eq 4-3 (poles at -alpha);
        ``1/T`` for a first-order valve; ``|p|`` of each pole of a second-order one."""
        if self.valve == "two-pole":
            return (TWO_PI * self.valve_poles_hz[0], TWO_PI * self.valve_poles_hz[1])
        return tuple(float(abs(pole)) for pole in self.valve_dynamics.poles())

    @property
    def valve_dynamics(self) -> ValveDynamics:
        """The servovalve's transfer function (:class:`ValveDynamics`), unit DC gain."""
        if self.valve == "first-order":
            return ValveDynamics(1, 1.0 / float(self.valve_time_constant or 0.0), 0.0)
        if self.valve == "second-order":
            omega = TWO_PI * float(self.valve_frequency_hz or 0.0)
            return ValveDynamics(2, omega**2, 2.0 * float(self.valve_damping or 0.0) * omega)
        a1, a2 = self.valve_poles
        return ValveDynamics(2, a1 * a2, a1 + a2)

    @property
    def bulk_modulus(self) -> float:
        """Bulk modulus kappa [psi] consistent with ``f_oil_hz`` (Eq 4-10a)."""
        return bulk_modulus_from_frequency(self.omega_oil, self.piston_area, self.mass, self.mid_stroke)

    @property
    def leakage_coefficient(self) -> float:
        """Leakage coefficient K_l [in^3/s/psi] consistent with ``zeta_oil`` (Eq 4-10b)."""
        unit = oil_column_damping(1.0, self.bulk_modulus, self.piston_area, self.mass, self.mid_stroke)
        return self.zeta_oil / unit

    @property
    def valve_flow_gain(self) -> float:
        """Static valve flow gain K_r = Q_max / u_i,max [in^3/s/mA] (Section 4.3.2)."""
        return self.rated_flow / self.rated_current


def _valve_kind(value: Any, where: str) -> str:
    """The ``valve`` key: one of :data:`VALVE_KINDS`."""
    if not isinstance(value, str) or value not in VALVE_KINDS:
        raise ConfigError(f"{where}valve", "one of " + ", ".join(VALVE_KINDS), value)
    return value


@functools.cache
def _parsed_table_file(path: Path, mtime_ns: int, size: int) -> TableParameters:
    """``TableParameters.from_toml(path)``, kept per file version (``mtime_ns`` [ns] and ``size`` [bytes] key it)."""
    return TableParameters.from_toml(path)


def default_table_path() -> Path:
    """Path of the report's table file (Table 4.1 as corrected), as the report's setup names it."""
    return report_config().table_file


def ratings_from_report(mapping: Mapping[str, Any]) -> tuple[str, ...]:
    """The ratings of :data:`REPORT_RATINGS` a table mapping leaves out (they take the report's values)."""
    return tuple(key for key in REPORT_RATINGS if key not in mapping)


def _report_ratings(mapping: Mapping[str, Any]) -> dict[str, Any]:
    """The report's raw values of the ratings ``mapping`` leaves out (none read when it has them all)."""
    missing = ratings_from_report(mapping)
    if not missing:
        return {}
    report = table_mapping(read_toml(default_table_path()), default_table_path())
    return {key: report[key] for key in missing if key in report}


def merge_overrides(mapping: Mapping[str, Any], overrides: Mapping[str, Any]) -> dict[str, Any]:
    """``mapping`` with ``overrides`` winning; an override of a physical alternative
    (``bulk_modulus``) replaces the key it stands for (``f_oil_hz``), and vice versa;
    an override of ``valve`` drops the file's keys of the other valve kinds."""
    merged = dict(mapping)
    for key, value in dict(overrides).items():
        if key == "valve" and isinstance(value, str):  # the file's keys of another valve kind go
            for other in VALVE_KEYS:
                if other not in VALVE_KINDS.get(value, ()) and other not in overrides:
                    merged.pop(other, None)
        for alt, (replaced, _) in ALTERNATIVES.items():
            if key == alt:
                merged.pop(replaced, None)
            elif key == replaced:
                merged.pop(alt, None)
        merged[key] = value
    return merged


def table_mapping(data: Mapping[str, Any], path: str | Path) -> Mapping[str, Any]:
    """The parameters of a parsed table file: its ``[table]`` section, or the whole file without one."""
    table = data.get("table", data)
    if not isinstance(table, Mapping):
        raise ConfigError(f"{path}: table", "a TOML table of parameters", table)
    return table
