"""A lab file: one laboratory setup (table, interlocks, sensors, controller, default article).

Sections (TOML, every value with a unit or in the report's unit)::

    [table]        file = "my_table.toml" (relative to the lab file), and/or table keys inline
    [limits]       stroke, velocity, acceleration, actuator_force, pressure, valve_command,
                   hf_cutoff (or "none"), hf_window, hf_growth, hf_windows, hf_floor,
                   valve_current, valve_duty, valve_saturation_time, command_slew,
                   interlock_window, divergence
    [sensors]      clipping = "warn" | "fail", and [sensors.NAME] channels (lab.labsensors)
    [controller]   loop_time, output_delay (samples), precision, feedback, substeps,
                   adc_bits, adc_range, dac_range, io_units (of the exported code)
    [specimen]     kind (vessel, rigid, none or a specimen file), water_depth, article_weight
    [uncertainty]  ranges of uncertain table parameters (plant.uncertainty): f_oil_hz = "±10 %",
                   extra_delay = { min = 0, max = "1 loop" } ...
    [dynamics]     optional dynamics beyond the report's model, one sub-table each (issue 17):
                   [dynamics.friction], [dynamics.valve], [dynamics.foundation] (plant.table_dynamics);
                   [dynamics.platen] modal_mass or mass_fraction, frequency, damping;
                   [dynamics.load_cells] stiffness, damping, base_mass (lab.dynamics_file,
                   specimens.mounting)
    units          "us" or "si" (top level): the units of what the commands print

``--lab report`` (the default) is the report's setup: the lab sections of
``data/report/config.toml``.  A bare table file (``--table``) is a lab with
only a ``[table]``: every other value is a documented generic default
(:data:`GENERIC_DEFAULTS`), never the report's, and :attr:`LabSetup.defaults`
lists them so that a run says which.  :func:`load_lab` validates everything
and names the section and key of the first problem.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..config import Field, parse_fields, quantity, read_toml
from ..display import UnitSystem, unit_system
from ..errors import ConfigError
from ..implement.io_units import IOUnits
from ..lazy import LazyModule
from ..plant import TableParameters
from ..plant.nonlinear import NonlinearTable
from ..plant.parameters import merge_overrides, ratings_from_report, table_mapping
from ..plant.table_dynamics import TABLE_DYNAMICS_SECTIONS, parse_table_dynamics
from ..plant.table_kind import is_lti_table_file
from ..report_config import REPORT_CONFIG_PATH, SUBSTEP_POLICIES
from .calibration_record import CalibrationRecord, parse_calibration
from .dynamics_file import DYNAMICS_PARSERS, DynamicsSetup, parse_dynamics
from .lab_units import LAB_UNITS as LAB_UNITS  # re-exported: the units of to_dict()
from .labsensors import Converter, SensorSetup, channel_dynamics, sensor_setup
from .setup import MAX_OUTPUT_DELAY, SafetyLimits, accelerometer_noise

if TYPE_CHECKING:  # the LTI table's modules and the uncertainty ranges are imported on first use (below)
    from ..plant.table_files import TableDefinition
    from ..plant.uncertainty import UncertaintySet

# A lab of a physical table does not import the LTI table's model, its readers and its lab
# (the LTI core, ~0.1 MB of source: ``imil lab show``, issue 16, start-up).  A table is a
# TableDefinition: an LTI table is the one that is not TableParameters.
#: The table-file reader of either kind, imported when a lab's table is an LTI table file.
table_files = LazyModule("impedance_mil.plant.table_files")
#: An LTI table's lab: its limits and generic sensor ranges (:mod:`impedance_mil.lab.lti_lab`).
lti_lab = LazyModule("impedance_mil.lab.lti_lab")
#: An LTI table as the virtual lab runs it (:mod:`impedance_mil.lab.lti_plant`).
lti_plant = LazyModule("impedance_mil.lab.lti_plant")
#: The ``[uncertainty]`` ranges, read when a lab has the section (:mod:`impedance_mil.plant.uncertainty`).
uncertainty_ranges = LazyModule("impedance_mil.plant.uncertainty")

#: Name of the shipped lab of the report (its sections live in data/report/config.toml).
REPORT_LAB = "report"

#: Sections of a lab file.
LAB_SECTIONS = (
    "table",
    "limits",
    "sensors",
    "controller",
    "specimen",
    "uncertainty",
    "dynamics",
    "calibration",
)

#: Sub-tables of ``[dynamics]``: the table's own (plant.table_dynamics) and the mounting's
#: (lab.dynamics_file); a new group adds its names here.
DYNAMICS_SECTIONS = (*TABLE_DYNAMICS_SECTIONS, *DYNAMICS_PARSERS)

#: Sections of the report's setup file that are not the lab's (read by report_config).
_EXPERIMENT_SECTIONS = ("design", "motion", "motions", "vs", "frf", "tuning")

#: Interlock keys of ``[limits]`` (internal unit, check); None-valued keys of SafetyLimits stay None.
LIMIT_FIELDS = {
    "stroke": Field("inch", default=0.0, help="measured displacement limit"),
    "velocity": Field("inch / second", default=0.0, help="table velocity limit"),
    "acceleration": Field("inch / second ** 2", default=0.0, help="measured acceleration limit"),
    "actuator_force": Field("force_pound", default=0.0, help="A_p |dP| limit"),
    "pressure": Field("psi", default=0.0, help="measured |dP| limit"),
    "valve_command": Field("volt", default=0.0, help="valve command clamp"),
    "valve_current": Field("milliampere", default=0.0, help="rms valve current limit"),
    "valve_duty": Field("dimensionless", default=0.0, help="saturated fraction of the window"),
    "valve_saturation_time": Field("second", default=0.0, help="longest continuous saturation"),
    "command_slew": Field("volt / second", default=0.0, help="rms slew of the valve command"),
    "interlock_window": Field("second", default=0.0, help="averaging time of the valve interlocks"),
    "divergence": Field("inch", default=0.0, help="displacement declared divergent"),
    "hf_cutoff": Field("hertz", default=0.0, help='band of the instability detector ("none": off)'),
    "hf_window": Field("second", default=0.0, help="rms window of the instability detector"),
    "hf_growth": Field("dimensionless", default=0.0, help="window-to-window rms ratio counted as growth"),
    "hf_windows": Field(
        "dimensionless", default=0.0, integer=True, help="growing windows in a row that trip"
    ),
    "hf_floor": Field("inch / second ** 2", default=0.0, help="rms the growth must start from"),
}

#: Keys of ``[limits]`` that may be ``"none"`` (the interlock off).
_LIMITS_OFF = ("hf_cutoff",)

#: Keys of ``[controller]`` read as quantities.
CONTROLLER_FIELDS = {
    "loop_time": Field("second", default=0.0, help="controller loop time"),
    "adc_bits": Field("dimensionless", default=0.0, integer=True, help="analog-input resolution"),
    "adc_range": Field("volt", default=0.0, help="+- analog-input range"),
    "dac_range": Field("volt", default=0.0, help="+- analog-output range"),
}
_CONTROLLER_TEXT = ("precision", "feedback", "substeps", "output_delay", "io_units")

#: Specimen keys.
_SPECIMEN_KEYS = ("kind", "water_depth", "article_weight")

#: The generic value of each key a lab file leaves out (documented in docs/your-lab.md).
GENERIC_DEFAULTS = {
    "limits.stroke": "the table's mid-stroke",
    "limits.velocity": "the valve's no-load velocity at the supply pressure",
    "limits.divergence": "the larger of 20 in and 4 strokes",
    "limits.valve_command": "the table's valve_command_limit",
    "limits.(others)": "as impedance_mil.lab.setup.SafetyLimits documents (none for acceleration, pressure)",
    "limits.hf_cutoff": "15 Hz (report Figures 9.33-9.34); hf_window 0.2 s, hf_growth 2, hf_windows 3, "
    "hf_floor 10 x the default accelerometer noise (impedance_mil.lab.oscillation)",
    "sensors": "one channel per quantity sized from the table (lab.labsensors.generic_sensors)",
    "controller.loop_time": "the table's loop_time",
    "controller.output_delay": "1 loop",
    "controller.precision": "single",
    "controller.feedback": "lc",
    "controller.substeps": "auto",
    "controller.adc_bits": "16",
    "controller.adc_range": "10 V",
    "controller.dac_range": "the valve command",
    "controller.io_units": "us (the exported code reads in/s^2 and lbf, writes in)",
    "specimen.kind": "none (the bare table)",
}

#: Precision and feedback names the controller accepts.
PRECISIONS = ("single", "double")
FEEDBACKS = ("lc", "fe", "none")


@dataclass(frozen=True)
class ControllerSetup:
    """Loop time [s], output delay [loops], precision, feedback, substeps, converters, I/O units.

    ``io_units`` are the units the exported controller reads and writes
    (:class:`~impedance_mil.implement.io_units.IOUnits`; ``imil export --lab``).
    """

    loop_time: float
    output_delay: int
    precision: str
    feedback: str
    substeps: int | str
    adc: Converter
    dac_range_v: float
    io_units: IOUnits = field(default_factory=IOUnits.internal)


@dataclass(frozen=True)
class SpecimenSetup:
    """Default article: ``kind`` (vessel, rigid, none or a file), water depth [in], weight [lbf]."""

    kind: str
    water_depth: Any = None
    article_weight: Any = None


@dataclass(frozen=True)
class LabSetup:
    """One laboratory setup, validated; internal units.

    Attributes
    ----------
    name : str
        ``report`` or the file's name.
    path : Path
        The file read.
    table : TableParameters or LTITable
        The table (its loop time, output delay in loops and valve command
        limit as the lab sets them: the linear models of
        :mod:`impedance_mil.plant` built from it are delayed as the lab's runs),
        or a table given as a linear model (only with ``load_lab(accept_lti=True)``;
        its loop time as the lab sets it).
    limits : SafetyLimits
        The interlocks.
    sensors : SensorSetup
        The channels and the clipping policy.
    controller : ControllerSetup
    specimen : SpecimenSetup
    sources : mapping of str to str
        Where each value came from: ``file``, ``default`` or ``--set``.
    units : UnitSystem
        The units of what the lab's commands print (``units = "us" | "si"``, default us).
    uncertainty : UncertaintySet or None
        The ranges of the table's uncertain parameters (``[uncertainty]``; None: none given).
    calibration : CalibrationRecord or None
        What the lab was calibrated on (``[calibration]``, written by ``imil lab calibrate``).
    dynamics : DynamicsSetup
        The optional additions of ``[dynamics]`` (the mounting of the article, ...).
    """

    name: str
    path: Path
    table: TableDefinition
    limits: SafetyLimits
    sensors: SensorSetup
    controller: ControllerSetup
    specimen: SpecimenSetup
    sources: Mapping[str, str] = field(default_factory=dict)
    units: UnitSystem = UnitSystem.US
    uncertainty: UncertaintySet | None = None
    calibration: CalibrationRecord | None = None
    dynamics: DynamicsSetup = field(default_factory=DynamicsSetup)

    @property
    def defaults(self) -> tuple[str, ...]:
        """Keys that took a generic default (what a run says it assumed)."""
        return tuple(k for k, v in self.sources.items() if v == "default")

    @property
    def is_report(self) -> bool:
        return self.name == REPORT_LAB

    def physical_table(self) -> TableParameters:
        """The table's physical parameters (a lab loaded without ``accept_lti`` always has them).

        Raises
        ------
        ConfigError
            The table is an LTI one (named ``table.file``).
        """
        if not isinstance(self.table, TableParameters):
            raise ConfigError("table.file", "a physical table file: an LTI table ([model]) has no parameters")
        return self.table

    def _hf_limits(self) -> dict[str, Any]:
        """The instability detector's keys as the lab file writes them (``hf_cutoff`` None: off)."""
        off = self.limits.hf_cutoff is None
        floor = self.limits.hf_values(self.controller.loop_time, accelerometer_noise(self.sensors.suite))[
            "hf_floor"
        ]
        return {
            "hf_cutoff": self.limits.hf_cutoff,
            "hf_window": None if off else self.limits.hf_window,
            "hf_growth": None if off else self.limits.hf_growth,
            "hf_windows": None if off else self.limits.hf_windows,
            "hf_floor": None if off else floor,
        }

    def to_dict(self) -> dict[str, Any]:
        """The effective setup with the source of each value (``imil lab show --json``)."""
        if isinstance(self.table, TableParameters):
            limits = self.limits.kernel_values(NonlinearTable.from_linear(self.table))._asdict()
            command = self.table.valve_command_limit
        else:  # an LTI table
            limits = lti_plant.lti_limits(
                self.limits, lti_plant.virtual_table_for(self.table)
            ).values._asdict()
            command = None  # no valve
        return {
            "lab": self.name,
            "file": str(self.path),
            "table": self.table.to_dict(),
            "limits": {
                k: (None if math.isinf(v) else v) for k, v in limits.items() if not k.startswith("hf_")
            }
            | {"valve_command": command}
            | self._hf_limits(),
            "sensors": {
                "clipping": self.sensors.clipping,
                "channels": [
                    {
                        "name": s.name,
                        "quantity": s.quantity,
                        "unit": s.unit,
                        "range": list(s.value_range),
                        "resolution": abs(s.scale) * s.lsb_v,
                        "noise_rms": abs(s.scale) * s.noise_rms_v,
                        "share": s.gain,
                        "bandwidth": s.bandwidth_hz,
                        "filter_order": s.filter_order if s.bandwidth_hz is not None else None,
                    }
                    | channel_dynamics(s)
                    for s in self.sensors.suite.sensors
                ],
            },
            "controller": {
                "loop_time": self.controller.loop_time,
                "output_delay": self.controller.output_delay,
                "precision": self.controller.precision,
                "feedback": self.controller.feedback,
                "substeps": self.controller.substeps,
                "adc_bits": self.controller.adc.bits,
                "adc_range": self.controller.adc.range_v,
                "dac_range": self.controller.dac_range_v,
                "io_units": self.controller.io_units.spec,
            },
            "specimen": {
                "kind": self.specimen.kind,
                "water_depth": self.specimen.water_depth,
                "article_weight": self.specimen.article_weight,
            },
            "uncertainty": None if self.uncertainty is None else self.uncertainty.to_dict(),
            "dynamics": _dynamics_dict(self.table, self.dynamics),
            "calibration": None if self.calibration is None else self.calibration.to_dict(),
            "sources": dict(self.sources),
            "output_units": self.units.value,
        }


def _dynamics_dict(table: TableDefinition, setup: DynamicsSetup) -> dict[str, Any]:
    """The optional dynamics: the mounting's sub-tables (``platen``, ``load_cells``: None when not
    given) and the table's values (:meth:`TableDynamics.to_dict`, flat, when any is given)."""
    mounting = {k: v for k, v in setup.to_dict().items() if k in DYNAMICS_PARSERS}
    table_dynamics = getattr(table, "dynamics", None)
    return mounting | ({} if table_dynamics is None else table_dynamics.to_dict())


def lab_path(name: str | Path) -> Path:
    """The file of ``--lab NAME|FILE`` (``report``: the report's setup file)."""
    if str(name) == REPORT_LAB:
        return REPORT_CONFIG_PATH
    path = Path(name)
    if not path.is_file():
        raise ConfigError("--lab", f"{REPORT_LAB} or a lab file (TOML)", str(name))
    return path


def load_lab(
    name: str | Path | None = None,
    *,
    table: Path | None = None,
    overrides: Mapping[str, Any] | None = None,
    accept_lti: bool = False,
) -> LabSetup:
    """Read and validate a lab (``name``: ``report``, the default, or a file), or a bare ``table`` file.

    ``overrides`` are ``--set`` values of the table.  Nothing of the report is
    taken for a lab that is not the report's: missing keys take
    :data:`GENERIC_DEFAULTS`.  ``accept_lti``: the caller takes a table given
    as a linear model (:class:`~impedance_mil.plant.lti_table.LTITable`, a
    ``[model]`` file; the virtual lab runs it); otherwise such a table is
    refused naming ``--table`` or ``table.file`` (the caller needs the
    physical parameters).  An LTI table's lab takes no generic default it
    cannot size (:data:`impedance_mil.lab.lti_lab.LTI_DEFAULTS`).

    Raises
    ------
    ConfigError
        Naming the section and key (``mylab.toml: limits.stroke: ...``).
    DataFileError
        A file is missing or not TOML.
    """
    if name is not None and table is not None:
        raise ConfigError("--lab", "either --lab or --table (a table file is a lab with only a table)")
    lti_file = table is not None and is_lti_table_file(table)
    if lti_file and not accept_lti:
        raise ConfigError(
            "--table",
            "a physical table file ([table] keys): this command needs the physical parameters, "
            "an LTI table ([model]) has none",
            str(table),
        )
    if table is not None and (lti_file or not _has_sections(read_toml(table))):
        path, data, label = Path(table), {"table": {"file": str(table)}}, Path(table).name
        base = Path.cwd()
    else:
        # A "table file" with [limits], [sensors] ... is a lab file: its sections are not ignored.
        name = table if table is not None else name
        path = lab_path(name or REPORT_LAB)
        label = REPORT_LAB if path == REPORT_CONFIG_PATH else path.name
        raw = read_toml(path)
        data = {k: v for k, v in raw.items() if k not in _EXPERIMENT_SECTIONS or path != REPORT_CONFIG_PATH}
        base = path.parent
    where = f"{label}: "
    units_given = "units" in data
    raw_units: Any = data.get("units")
    units = unit_system(raw_units, f"{where}units") if units_given else UnitSystem.US
    data = {k: v for k, v in data.items() if k != "units"}
    unknown = sorted(set(data) - set(LAB_SECTIONS))
    if unknown:
        raise ConfigError(f"{where}[{unknown[0]}]", "one of the sections " + ", ".join(LAB_SECTIONS))
    sources: dict[str, str] = {}
    params = _table(data.get("table"), base, overrides or {}, where, sources, accept_lti)
    controller = _controller(data.get("controller"), params, where, sources)
    if not isinstance(params, TableParameters):  # an LTI table
        params = replace(params, loop_time=controller.loop_time)
        limits = lti_lab.lti_lab_limits(
            _mapping(data.get("limits"), "limits", where), params, where, sources, LIMIT_FIELDS
        )
    else:
        params = params.replace(loop_time=controller.loop_time, output_delay_loops=controller.output_delay)
        limits, command = _limits(data.get("limits"), params, controller, where, sources)
        params = params.replace(valve_command_limit=command)
    params = _dynamics(data.get("dynamics"), params, where, sources)
    generic = None
    if not isinstance(params, TableParameters) and data.get("sensors") is None:
        generic = lti_lab.lti_sensor_ranges(params, where)
    sensors = sensor_setup(data.get("sensors"), params, controller.adc, where, generic, base)
    sources["sensors"] = sensors.source
    specimen = _specimen(data.get("specimen"), base, where, sources)
    sources["units"] = "file" if units_given else "default"
    uncertainty = _uncertainty(data.get("uncertainty"), params, where)
    calibration = parse_calibration(data.get("calibration"), where)
    dynamics = parse_dynamics(
        data.get("dynamics"), params.mass if isinstance(params, TableParameters) else None, where
    )
    if "dynamics" in data:  # no section adds nothing: not a default a run must declare
        sources["dynamics"] = "file"
    return LabSetup(
        label,
        path,
        params,
        limits,
        sensors,
        controller,
        specimen,
        sources,
        units,
        uncertainty,
        calibration,
        dynamics,
    )


def _uncertainty(section: Any, params: TableDefinition, where: str) -> UncertaintySet | None:
    """The ``[uncertainty]`` ranges (None without the section); an LTI table has no parameters to vary."""
    if section is None:
        return None
    if not isinstance(params, TableParameters):
        raise ConfigError(
            f"{where}uncertainty",
            "no [uncertainty] with an LTI table (it has no physical parameters to vary)",
        )
    return uncertainty_ranges.parse_uncertainty(section, params, where)


def _dynamics(section: Any, params: TableDefinition, where: str, sources: dict) -> TableDefinition:
    """The table with the ``[dynamics]`` sub-tables it takes (:data:`DYNAMICS_SECTIONS`)."""
    dynamics = _mapping(section, "dynamics", where)
    unknown = sorted(set(dynamics) - set(DYNAMICS_SECTIONS))
    if unknown:
        raise ConfigError(
            f"{where}dynamics.{unknown[0]}", "one of the sub-tables " + ", ".join(DYNAMICS_SECTIONS)
        )
    for name in dynamics:  # one left out is off (the report's model), not a generic default
        sources[f"dynamics.{name}"] = "file"
    own = {k: v for k, v in dynamics.items() if k in TABLE_DYNAMICS_SECTIONS}
    if not own:
        return params
    if not isinstance(params, TableParameters):
        raise ConfigError(
            f"{where}dynamics.{next(iter(own))}",
            "no table dynamics with an LTI table (its model is the table)",
        )
    return params.replace(dynamics=parse_table_dynamics(own, params.rated_current, where))


def _has_sections(data: Mapping[str, Any]) -> bool:
    """Whether a parsed table file has sections beside ``[table]`` (then it is read as a lab file)."""
    return any(isinstance(v, Mapping) and k != "table" for k, v in data.items())


def _mapping(section: Any, name: str, where: str) -> Mapping[str, Any]:
    if section is None:
        return {}
    if not isinstance(section, Mapping):
        raise ConfigError(f"{where}{name}", "a TOML table", section)
    return section


def _table(
    section: Any, base: Path, overrides: Mapping[str, Any], where: str, sources: dict, accept_lti: bool
) -> TableDefinition:
    table = dict(_mapping(section, "table", where))
    if not table:
        raise ConfigError(f"{where}table", 'a [table] section (file = "TABLE.toml" or the table keys)')
    keys: dict[str, Any] = {}
    if "file" in table:
        file = base / str(table.pop("file"))
        if is_lti_table_file(file):
            if not accept_lti:
                raise ConfigError(
                    f"{where}table.file",
                    "a physical table file: this command needs the physical parameters, "
                    "an LTI table ([model]) has none",
                    file.name,
                )
            if table:
                raise ConfigError(
                    f"{where}table.{next(iter(table))}",
                    f"no table keys beside the LTI table file {file.name} (its model is the table)",
                )
            sources["table"] = f"file {file.name}"
            return table_files.read_table_file(file, overrides)
        keys.update(table_mapping(read_toml(file), file))
        sources["table"] = f"file {file.name}"
    else:
        sources["table"] = "file"
    keys.update(table)
    for key in overrides:
        sources[f"table.{key}"] = "--set"
    for key in ratings_from_report({**keys, **overrides}):
        sources[f"table.{key}"] = "report"  # a valve or pressure rating the table file leaves out
    return TableParameters.from_mapping(merge_overrides(keys, overrides), where=f"{where}table.")


def _given(section: Mapping[str, Any], fields: Mapping[str, Field], where: str) -> dict[str, float]:
    """The keys of ``section`` that ``fields`` knows, converted (unknown keys refused)."""
    parsed = parse_fields(fields, section, where=where)
    return {k: v for k, v in parsed.items() if k in section}


def _controller(section: Any, table: TableDefinition, where: str, sources: dict) -> ControllerSetup:
    raw = dict(_mapping(section, "controller", where))
    text = {k: raw.pop(k) for k in _CONTROLLER_TEXT if k in raw}
    given = _given(raw, CONTROLLER_FIELDS, f"{where}controller.")
    for key in CONTROLLER_FIELDS | dict.fromkeys(_CONTROLLER_TEXT):
        sources[f"controller.{key}"] = "file" if key in given or key in text else "default"
    loop = given.get("loop_time", table.loop_time)
    loops = _output_delay(text.get("output_delay", 1), loop, f"{where}controller.output_delay")
    precision = text.get("precision", "single")
    if precision not in PRECISIONS:
        raise ConfigError(f"{where}controller.precision", " or ".join(PRECISIONS), precision)
    feedback = text.get("feedback", "lc")
    if feedback not in FEEDBACKS:
        raise ConfigError(f"{where}controller.feedback", " or ".join(FEEDBACKS), feedback)
    substeps = text.get("substeps", SUBSTEP_POLICIES[0])
    if substeps not in SUBSTEP_POLICIES and not (
        isinstance(substeps, int) and not isinstance(substeps, bool) and substeps > 0
    ):
        raise ConfigError(f"{where}controller.substeps", "a positive integer or auto", substeps)
    bits = int(given.get("adc_bits", 16))
    if not 2 <= bits <= 32:
        raise ConfigError(f"{where}controller.adc_bits", "a whole number of bits from 2 to 32", bits)
    adc = Converter(bits, given.get("adc_range", 10.0))
    # an LTI table has no valve: its command is a position, and the DAC range is the converters'
    dac = given.get(
        "dac_range", table.valve_command_limit if isinstance(table, TableParameters) else adc.range_v
    )
    io_units = IOUnits.parse(text.get("io_units", "us"), f"{where}controller.io_units")
    return ControllerSetup(loop, round(loops), precision, feedback, substeps, adc, dac, io_units)


def _output_delay(value: Any, loop: float, key: str) -> int:
    """The output delay in loops: a whole number (``2``, ``"2 loops"``), or a time that is a whole number of ``loop`` [s]."""
    if isinstance(value, str) and value.split()[-1:] in (["loop"], ["loops"]):
        value = value.split()[0] if len(value.split()) == 2 else value
    if isinstance(value, str) and any(c.isalpha() for c in value):
        loops = quantity(key, value, "second", "positive") / loop
    else:
        loops = quantity(key, value, "dimensionless", "positive")
    if abs(loops - round(loops)) > 1e-9 or not 1 <= round(loops) <= MAX_OUTPUT_DELAY:
        raise ConfigError(
            key, f"a whole number of loops of {loop * 1e6:g} us (1 to {MAX_OUTPUT_DELAY})", value
        )
    return round(loops)


def _limits(
    section: Any, table: TableParameters, controller: ControllerSetup, where: str, sources: dict
) -> tuple[SafetyLimits, float]:
    raw = dict(_mapping(section, "limits", where))
    off = {k: None for k in _LIMITS_OFF if isinstance(raw.get(k), str) and raw[k].strip().lower() == "none"}
    given = _given({k: v for k, v in raw.items() if k not in off}, LIMIT_FIELDS, f"{where}limits.")
    for key in LIMIT_FIELDS:
        sources[f"limits.{key}"] = "file" if key in given or key in off else "default"
    for key, value in given.items():
        if not value > 0:
            raise ConfigError(f"{where}limits.{key}", "a positive value", value)
    stroke = given.pop("stroke", table.mid_stroke)
    if stroke > table.mid_stroke:
        raise ConfigError(
            f"{where}limits.stroke",
            f"at most the table's mid-stroke ({table.mid_stroke:g} in)",
            f"{stroke:g} in",
        )
    dp = table.supply_pressure - table.return_pressure
    no_load = table.rated_flow * math.sqrt(dp / table.rated_pressure_drop) / table.piston_area
    velocity = given.pop("velocity", no_load)
    command = given.pop("valve_command", table.valve_command_limit)
    if command > controller.dac_range_v:
        raise ConfigError(
            f"{where}limits.valve_command",
            f"at most the controller's dac_range ({controller.dac_range_v:g} V)",
            f"{command:g} V",
        )
    divergence = given.pop("divergence", max(20.0, 4.0 * stroke))
    if divergence <= stroke:
        raise ConfigError(f"{where}limits.divergence", f"more than the stroke ({stroke:g} in)", divergence)
    if "valve_duty" in given and given["valve_duty"] > 1:
        raise ConfigError(f"{where}limits.valve_duty", "a fraction in (0, 1]", given["valve_duty"])
    try:
        keys: dict[str, Any] = {**given, **off}
        if "hf_windows" in keys:
            keys["hf_windows"] = int(keys["hf_windows"])  # a whole number (the field is read as one)
        limits = SafetyLimits(stroke=stroke, velocity=velocity, divergence=divergence, **keys)
        if controller.loop_time > 0:  # an analog table (loop time 0) has no loop to run the detector in
            limits.hf_detector(controller.loop_time)  # a cutoff above Nyquist is refused, naming the key
    except ConfigError as exc:
        raise ConfigError(f"{where}{exc.key}", exc.expected, exc.got) from None
    return limits, command


def _specimen(section: Any, base: Path, where: str, sources: dict) -> SpecimenSetup:
    spec = dict(_mapping(section, "specimen", where))
    unknown = sorted(set(spec) - set(_SPECIMEN_KEYS))
    if unknown:
        raise ConfigError(f"{where}specimen.{unknown[0]}", "one of the keys " + ", ".join(_SPECIMEN_KEYS))
    for key in _SPECIMEN_KEYS:
        sources[f"specimen.{key}"] = "file" if key in spec else "default"
    kind = spec.get("kind", "none")
    if not isinstance(kind, str) or not kind.strip():
        raise ConfigError(f"{where}specimen.kind", "vessel, rigid, none or a specimen file", kind)
    if kind not in ("vessel", "rigid", "none"):
        file = base / kind
        if not file.is_file():
            raise ConfigError(f"{where}specimen.kind", "vessel, rigid, none or a specimen file", kind)
        kind = str(file)
    depth = spec.get("water_depth")
    weight = spec.get("article_weight")
    if depth is not None:
        quantity(f"{where}specimen.water_depth", depth, "inch", "nonnegative")
    if weight is not None:
        weight = article_weight(weight, f"{where}specimen.article_weight")
    return SpecimenSetup(kind, depth, weight)


def article_weight(value: Any, key: str) -> float:
    """A weight [lbf], given as a force or as a mass (its weight under standard gravity: 1 lb -> 1 lbf)."""
    try:
        return quantity(key, value, "force_pound", "positive")
    except ConfigError:
        try:
            return quantity(key, value, "pound", "positive")
        except ConfigError:
            raise ConfigError(key, "a weight (a force, or a mass such as '2000 kg')", value) from None
