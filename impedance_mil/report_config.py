"""The report's setup, read from the one data file that holds it (``data/report/config.toml``).

Every value a run takes from the report when the user does not choose it
lives in that file: the table of Table 4.1 (by reference to its table file,
which also holds the loop time), the interlocks, the controller's precision,
feedback source and plant-substep policy, the vessel with 36 in of water and
the 3600 lbf article, the controller form and f_c = 80 Hz, the default motion
(GM1 of Table 8.1, time-compressed by 2, at 0.8 g), the default virtual
system and the multisine test.  No function signature or dataclass field
repeats these numbers: library functions take the value or a configuration
object, and the edges (the CLI, the campaign kinds, the convenience functions
of :mod:`impedance_mil.lab.experiments`) read this module.

:func:`report_config` parses the file once (it is immutable, so the cached
object is shared, not global mutable state).  :func:`load_config` reads any
file of the same layout; a lab file (issue 12) extends it.

>>> cfg = report_config()
>>> cfg.design.fc_hz, cfg.specimen.water_depth_in, cfg.motion.time_scale
(80.0, 36.0, 2.0)
>>> cfg.motions["GM1"].pga_scaled_g, cfg.motions["GM1"].builtin_substitute
(0.8, 'elcentro')
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any

from .config import quantity, read_toml
from .errors import ConfigError

#: The shipped file with the report's setup.
REPORT_CONFIG_PATH = Path(__file__).resolve().parent / "data" / "report" / "config.toml"

#: Sections of the file, in order.
SECTIONS = (
    "table",
    "limits",
    "sensors",
    "controller",
    "specimen",
    "design",
    "motion",
    "motions",
    "vs",
    "frf",
    "tuning",
)

#: Values of ``[controller] substeps`` other than a positive integer.
SUBSTEP_POLICIES = ("auto",)


@dataclass(frozen=True)
class LimitSettings:
    """Interlocks of the virtual controller: ``stroke`` [in], ``velocity`` [in/s]."""

    stroke_in: float
    velocity_in_s: float


@dataclass(frozen=True)
class ControllerSettings:
    """Controller arithmetic (``single``/``double``), feedback source name, plant substeps (int or ``auto``)."""

    precision: str
    feedback: str
    substeps: int | str


@dataclass(frozen=True)
class SpecimenSettings:
    """Default test article: ``kind``, water depth of the vessel [in], article weight [lbf]."""

    kind: str
    water_depth_in: float
    article_weight_lbf: float


@dataclass(frozen=True)
class DesignSettings:
    """Controller form, cut-off f_c [Hz], filter family, vessel depths of the coupled check [in]."""

    form: str
    fc_hz: float
    filter: str
    coupled_water_depths_in: tuple[float, ...]


@dataclass(frozen=True)
class ReportMotion:
    """One motion of report Table 8.1 (sections ``[motions.*]``).

    Attributes
    ----------
    name : str
        ``GM1``, ``GM2`` or ``GM3``.
    rsn : int
        PEER record sequence number of the seed.
    earthquake : str
        Event and component.
    pga_original_g, pga_scaled_g : float
        PGA of the seed and of the scaled motion [g].
    fema_substitute : str or None
        FEMA P695 record used without the PEER file, ``"SET:RECORDCOMPONENT"``
        (``"farfield:14a"``, see :mod:`impedance_mil.signals.sources`).
    builtin_substitute : str
        Built-in record used otherwise.
    """

    name: str
    rsn: int
    earthquake: str
    pga_original_g: float
    pga_scaled_g: float
    fema_substitute: str | None
    builtin_substitute: str


@dataclass(frozen=True)
class MotionSettings:
    """Default input: a motion of ``motions`` and the time compression (t' = t / ``time_scale``)."""

    record: str
    time_scale: float


@dataclass(frozen=True)
class FrfSettings:
    """Multisine test: command peak [in], delay model compared, K_p values of the study [V/psi]."""

    peak_in: float
    delay: str
    kp_values: tuple[float, ...]


@dataclass(frozen=True)
class TuningFigures:
    """The report's printed tuning figures (Section 4.4), shown beside a report table's own.

    ``ke_limit`` [V/in] (stability, K_p = 0, analog), ``kp_limit`` [V/psi]
    (stability, K_e = 5 V/in), ``breakaway_ke`` [V/in], ``breakaway_kp`` [V/psi],
    ``chosen_kp`` [V/psi] (the K_p the report runs with).
    """

    ke_limit: float
    kp_limit: float
    breakaway_ke: float
    breakaway_kp: float
    chosen_kp: float


@dataclass(frozen=True)
class ReportConfig:
    """The report's setup (see the module docstring); internal units.

    Attributes
    ----------
    source : Path
        The file it was read from.
    table_file : Path
        Table file of the report's table (Table 4.1).
    limits, controller, specimen, design, motion, vs_preset, frf, tuning
        The sections.
    motions : mapping of str to ReportMotion
        Table 8.1, by name.
    """

    source: Path
    table_file: Path
    limits: LimitSettings
    controller: ControllerSettings
    specimen: SpecimenSettings
    design: DesignSettings
    motion: MotionSettings
    motions: Mapping[str, ReportMotion]
    vs_preset: str
    frf: FrfSettings
    tuning: TuningFigures

    @property
    def default_motion(self) -> ReportMotion:
        """The motion of Table 8.1 that runs when none is chosen (GM1)."""
        return self.motions[self.motion.record]


def _section(
    data: Mapping[str, Any], name: str, keys: tuple[str, ...], where: str, optional: tuple[str, ...] = ()
) -> Mapping[str, Any]:
    """The table ``data[name]`` with exactly ``keys`` (plus any of ``optional``)."""
    table = data.get(name)
    if not isinstance(table, Mapping):
        raise ConfigError(f"{where}[{name}]", "a table with " + ", ".join(keys))
    unknown = sorted(set(table) - set(keys) - set(optional))
    missing = [k for k in keys if k not in table]
    if unknown or missing:
        key = (unknown or missing)[0]
        raise ConfigError(
            f"{where}{name}.{key}", "the keys " + ", ".join(keys + optional) + " (and no other)"
        )
    return table


def _text(value: Any, key: str) -> str:
    if not isinstance(value, str) or not value.strip():
        raise ConfigError(key, "a non-empty string", value)
    return value


def _substeps(value: Any, key: str) -> int | str:
    if value in SUBSTEP_POLICIES:
        return str(value)
    if isinstance(value, int) and not isinstance(value, bool) and value > 0:
        return value
    raise ConfigError(key, "a positive integer or " + " or ".join(SUBSTEP_POLICIES), value)


def _motions(data: Mapping[str, Any], where: str) -> dict[str, ReportMotion]:
    table = data.get("motions")
    if not isinstance(table, Mapping) or not table:
        raise ConfigError(f"{where}[motions]", "one [motions.NAME] table per motion of Table 8.1")
    out = {}
    for name in table:
        keys = ("rsn", "earthquake", "pga_original", "pga", "builtin")
        entry = _section(table, name, keys, f"{where}motions.", optional=("fema",))
        key = f"{where}motions.{name}."
        rsn = entry["rsn"]
        if isinstance(rsn, bool) or not isinstance(rsn, int) or rsn <= 0:
            raise ConfigError(f"{key}rsn", "a positive PEER record sequence number", rsn)
        out[name] = ReportMotion(
            name,
            rsn,
            _text(entry["earthquake"], f"{key}earthquake"),
            quantity(f"{key}pga_original", entry["pga_original"], "g0", "positive"),
            quantity(f"{key}pga", entry["pga"], "g0", "positive"),
            None if entry.get("fema") is None else _text(entry["fema"], f"{key}fema"),
            _text(entry["builtin"], f"{key}builtin"),
        )
    return out


def load_config(path: str | Path) -> ReportConfig:
    """Read a file laid out like ``data/report/config.toml``.

    Raises
    ------
    DataFileError
        The file is missing or not TOML.
    ConfigError
        A section or key is missing, unknown or invalid (the message names it).
    """
    path = Path(path)
    data = read_toml(path)
    where = f"{path.name}: "
    unknown = sorted(set(data) - set(SECTIONS))
    if unknown:
        raise ConfigError(f"{where}[{unknown[0]}]", "one of the sections " + ", ".join(SECTIONS))
    table = _section(data, "table", ("file",), where)
    limits = _section(data, "limits", ("stroke", "velocity"), where)
    ctrl = _section(data, "controller", ("precision", "feedback", "substeps"), where)
    spec = _section(data, "specimen", ("kind", "water_depth", "article_weight"), where)
    design = _section(data, "design", ("form", "fc", "filter", "coupled_water_depths"), where)
    motion = _section(data, "motion", ("record", "time_scale"), where)
    vs = _section(data, "vs", ("preset",), where)
    frf = _section(data, "frf", ("peak", "delay", "kp_values"), where)
    tuning = _section(data, "tuning", TUNING_KEYS, where)
    motions = _motions(data, where)
    record = _text(motion["record"], f"{where}motion.record")
    if record not in motions:
        raise ConfigError(
            f"{where}motion.record", "one of the [motions.*] tables " + ", ".join(motions), record
        )
    return ReportConfig(
        source=path,
        table_file=(path.parent / _text(table["file"], f"{where}table.file")).resolve(),
        limits=LimitSettings(
            quantity(f"{where}limits.stroke", limits["stroke"], "inch", "positive"),
            quantity(f"{where}limits.velocity", limits["velocity"], "inch / second", "positive"),
        ),
        controller=ControllerSettings(
            _text(ctrl["precision"], f"{where}controller.precision"),
            _text(ctrl["feedback"], f"{where}controller.feedback"),
            _substeps(ctrl["substeps"], f"{where}controller.substeps"),
        ),
        specimen=SpecimenSettings(
            _text(spec["kind"], f"{where}specimen.kind"),
            quantity(f"{where}specimen.water_depth", spec["water_depth"], "inch", "nonnegative"),
            quantity(f"{where}specimen.article_weight", spec["article_weight"], "force_pound", "positive"),
        ),
        design=DesignSettings(
            _text(design["form"], f"{where}design.form"),
            quantity(f"{where}design.fc", design["fc"], "hertz", "positive"),
            _text(design["filter"], f"{where}design.filter"),
            _quantities(design["coupled_water_depths"], f"{where}design.coupled_water_depths", "inch"),
        ),
        motion=MotionSettings(
            record, quantity(f"{where}motion.time_scale", motion["time_scale"], "dimensionless", "positive")
        ),
        motions=MappingProxyType(motions),
        vs_preset=_text(vs["preset"], f"{where}vs.preset"),
        frf=FrfSettings(
            quantity(f"{where}frf.peak", frf["peak"], "inch", "positive"),
            _text(frf["delay"], f"{where}frf.delay"),
            _quantities(frf["kp_values"], f"{where}frf.kp_values", "volt / psi", "positive"),
        ),
        tuning=TuningFigures(
            *(
                quantity(f"{where}tuning.{key}", tuning[key], "volt / inch" if "ke" in key else "volt / psi")
                for key in TUNING_KEYS
            )
        ),
    )


#: Keys of ``[tuning]``, in :class:`TuningFigures` order.
TUNING_KEYS = ("ke_limit", "kp_limit", "breakaway_ke", "breakaway_kp", "chosen_kp")


def _quantities(values: Any, key: str, unit: str, check: str = "nonnegative") -> tuple[float, ...]:
    if not isinstance(values, list) or not values:
        raise ConfigError(key, f"a list of quantities in {unit}", values)
    return tuple(quantity(key, v, unit, check) for v in values)


@functools.cache
def report_config() -> ReportConfig:
    """The report's setup, parsed once from :data:`REPORT_CONFIG_PATH`."""
    return load_config(REPORT_CONFIG_PATH)
