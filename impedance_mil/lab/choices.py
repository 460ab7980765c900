"""From a user's partial choices to an experiment description, the rest from the report's setup.

A :class:`Choices` holds what a user chose for a run, as text or numbers
with units (``None``: not chosen).  :func:`tracking_test`, :func:`mil_test`
and :func:`frf_test` resolve and validate every choice and take each value
nobody chose from the report's setup (:func:`impedance_mil.report_config.report_config`):
the table of Table 4.1, the vessel with 36 in of water (or the 3600 lbf
article for a rigid mass), GM1 time-compressed by 2 at 0.8 g (a chosen
motion runs as recorded: time scale 1), f_c = 80 Hz,
load-cell feedback, single precision, the interlocks and the substep policy.
Each value so taken is listed in the description's ``from_report`` under its
key in ``data/report/config.toml``.

Errors name the choice as the caller calls it: ``Choices.keys`` maps a
choice (``water_depth``) to its name in messages (``--water-depth`` for the
CLI).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, cast

from ..config import quantity, read_toml
from ..design import ControllerDesign
from ..errors import ConfigError, DataFileError
from ..implement.export import designed_vs
from ..plant import TableParameters
from ..plant.lti_table import LTITable
from ..plant.parameters import ratings_from_report, table_mapping
from ..plausibility import check_specimen_weight
from ..report_config import ReportConfig, report_config
from ..signals.sources import scaled_motion
from ..specimens import FluidVessel, RigidMass, specimen_from_config
from ..specimens.mounting import mount
from ..virtual.files import VSSpec, resolve
from .descriptions import (
    ControllerChoice,
    FrfTest,
    LabChoice,
    MilTest,
    MotionChoice,
    SpecimenChoice,
    TrackingTest,
)
from .design_file import check_loop_time, read_design
from .feedback import Feedback
from .labfile import LabSetup, load_lab
from .setup import SafetyLimits

#: Names of the specimens a user may choose (or a specimen file).
SPECIMEN_KINDS = ("vessel", "rigid", "none")


@dataclass(frozen=True)
class Choices:
    """What a user chose for a run; ``None`` (or empty) means "not chosen: the report's".

    Attributes
    ----------
    table : Path or None
        Table file (a lab with only a table: the rest takes generic defaults).
    lab : str or None
        Lab file or ``report`` (:func:`impedance_mil.lab.labfile.load_lab`).
    table_overrides : mapping
        ``--set`` values of the table (with units or in the report's unit).
    specimen : str or None
        ``vessel``, ``rigid``, ``none`` or a specimen file (TOML).
    water_depth, specimen_weight : str or float or None
        Water in the vessel [in]; weight of the rigid mass [lbf].
    motion : str or None
        Motion source (:mod:`impedance_mil.signals.sources`).
    motion_units : str or None
        Unit of the accelerations of a column file that states none (required for such a file).
    time_scale : float or None
        Time compression (t' = t / factor).
    pga_g : float or None
        PGA to scale to [g].
    duration : str or float or None
        Run only the first seconds [s].
    fc_hz : str or float or None
        Filter cut-off [Hz].
    feedback, precision : str or None
        Source of w (:class:`~impedance_mil.lab.feedback.Feedback`), controller arithmetic.
    seed : int
        Sensor-noise seed.
    vs : str or None
        VS preset or file (MIL).
    vs_overrides : mapping
        Values of the VS.
    design : Path or None
        A design file to run as designed (:mod:`impedance_mil.lab.design_file`): its controller,
        cut-off and (MIL) virtual system; ``fc_hz`` must then be left out.
    keys : mapping of str to str
        Name of each choice in error messages (default: the attribute name).
    """

    table: Path | None = None
    lab: str | None = None
    table_overrides: Mapping[str, Any] = field(default_factory=dict)
    specimen: str | None = None
    water_depth: Any = None
    specimen_weight: Any = None
    motion: str | None = None
    motion_units: str | None = None
    time_scale: float | None = None
    pga_g: float | None = None
    duration: Any = None
    fc_hz: Any = None
    feedback: str | None = None
    precision: str | None = None
    seed: int = 0
    vs: str | None = None
    vs_overrides: Mapping[str, Any] = field(default_factory=dict)
    design: Path | None = None
    keys: Mapping[str, str] = field(default_factory=dict)

    def key(self, name: str) -> str:
        """The name of a choice in error messages."""
        return self.keys.get(name, name)


def _pick(value: Any, default: Any, key: str, used: dict[str, Any]) -> Any:
    """``value``, or the report's ``default`` (recorded in ``used`` under ``key``) when it is None."""
    if value is None:
        used[key] = default
        return default
    return value


def choose_table(
    path: Path | None, overrides: Mapping[str, Any], cfg: ReportConfig, used: dict
) -> TableParameters:
    """The table file (default the report's, Table 4.1) with overrides; ratings it leaves out are the report's."""
    if path is None:
        used["table.file"] = cfg.table_file.name
        path = cfg.table_file
    params = TableParameters.from_toml(path, overrides)
    given = {**table_mapping(read_toml(path), path), **overrides}
    for key in ratings_from_report(given):
        used[f"table.{key}"] = getattr(params, key)
    return params


def choose_specimen(
    choices: Choices, cfg: ReportConfig, used: dict, default_kind: str | None = None
) -> SpecimenChoice:
    """Resolve the specimen with its water depth [in] or weight [lbf] (``default_kind``: the report's)."""
    text = choices.specimen
    if text is None:
        text = (
            default_kind
            if default_kind is not None
            else _pick(None, cfg.specimen.kind, "specimen.kind", used)
        )
    key = text.strip().lower()
    if choices.water_depth is not None and key != "vessel":
        raise ConfigError(
            choices.key("water_depth"),
            f"{choices.key('specimen')} vessel (it sets the vessel's water depth)",
            text,
        )
    if choices.specimen_weight is not None and key != "rigid":
        raise ConfigError(
            choices.key("specimen_weight"),
            f"{choices.key('specimen')} rigid (it sets the rigid mass's weight)",
            text,
        )
    if key == "none":
        return SpecimenChoice.bare()
    if key == "vessel":
        raw = _pick(choices.water_depth, cfg.specimen.water_depth_in, "specimen.water_depth", used)
        return SpecimenChoice.vessel(quantity(choices.key("water_depth"), raw, "inch", "nonnegative"))
    if key == "rigid":
        raw = _pick(choices.specimen_weight, cfg.specimen.article_weight_lbf, "specimen.article_weight", used)
        lbf = quantity(choices.key("specimen_weight"), raw, "force_pound", "positive")
        check_specimen_weight(choices.key("specimen_weight"), lbf)
        return SpecimenChoice(RigidMass(lbf), f"rigid mass of {lbf:.0f} lb", lbf)
    return _specimen_file(Path(text), choices.key("specimen"))


def mounted_choice(specimen: SpecimenChoice, setup: LabSetup | None) -> SpecimenChoice:
    """``specimen`` on the lab's mounting (``[dynamics.platen]``, ``[dynamics.load_cells]``), if it has one.

    The article is composed with the mounting by
    :func:`impedance_mil.specimens.mounting.mount` for the lab's table mass
    m_st, so the virtual table and the linear checks see the same model.
    Without a mounting (or without a lab file) ``specimen`` is returned as it is.
    """
    if setup is None or isinstance(setup.table, LTITable):  # an LTI table's lab has no mounting (load_lab)
        return specimen
    mounting = setup.dynamics.mounting
    if not mounting:
        return specimen
    composed = mount(specimen.specimen, mounting, setup.table.mass)
    parts = [
        name for name, part in (("platen mode", mounting.platen), ("load cells", mounting.load_cells)) if part
    ]
    return SpecimenChoice(
        composed, f"{specimen.label} on {' and '.join(parts)}", float(composed.total_weight)
    )


def article_weight(specimen: SpecimenChoice, cfg: ReportConfig, used: dict) -> float:
    """The weight [lbf] of the article a VS preset carries: the specimen's.

    The report's own article (its vessel at its water depth) weighs what the
    report says (``specimen.article_weight``, Tables 9.1-9.3: listed in
    ``used``), so that the report's runs are unchanged; any other specimen
    weighs what its model weighs (0 for the bare table).
    """
    report_vessel = cfg.specimen.kind == "vessel" and specimen.specimen == FluidVessel(
        cfg.specimen.water_depth_in
    )
    if report_vessel:
        used["specimen.article_weight"] = cfg.specimen.article_weight_lbf
        return cfg.specimen.article_weight_lbf
    return float(specimen.weight_lbf)


def _specimen_file(path: Path, key: str) -> SpecimenChoice:
    if not path.is_file():
        raise ConfigError(
            key, ", ".join(SPECIMEN_KINDS[:-1]) + " or none, or a specimen file (TOML)", str(path)
        )
    data = read_toml(path)
    table = data.get("specimen", data)
    if not isinstance(table, Mapping):
        raise DataFileError(path, "expected a [specimen] table")
    specimen = specimen_from_config(table, where=f"{path.name}: specimen.")
    return SpecimenChoice(
        specimen,
        f"{type(specimen).__name__} from {path.name} ({specimen.total_weight:.0f} lb)",
        float(specimen.total_weight),
    )


def choose_motion(choices: Choices, cfg: ReportConfig, used: dict) -> MotionChoice:
    """Resolve the motion: the report's (GM1, built in) unless chosen; time compression, PGA and length.

    Only the report's own default motion (no motion chosen) takes the report's
    time compression (``motion.time_scale``, listed in ``from_report``); a
    chosen motion runs as recorded (time scale 1) unless ``time_scale`` is
    given.  The PGA of Table 8.1 applies to the default motion's record when no
    PGA is chosen; any other motion runs at its recorded PGA unless ``pga_g``
    is given.
    A ``duration`` [s] keeps the motion's first seconds; one longer than the
    (scaled) motion by more than a time step is refused, not silently cut to it.
    """
    default = cfg.default_motion
    argument = choices.motion
    time_scale = choices.time_scale
    if argument is None:
        used["motion.record"] = default.name
        argument = default.builtin_substitute
        time_scale = _pick(time_scale, cfg.motion.time_scale, "motion.time_scale", used)
    pga = choices.pga_g
    if pga is None and argument.strip().lower() == default.builtin_substitute:
        pga = _pick(None, default.pga_scaled_g, f"motions.{default.name}.pga", used)
    time_scale = float(1.0 if time_scale is None else time_scale)
    motion = scaled_motion(
        argument, choices.motion_units, time_scale, pga, choices.key("motion"), choices.key("motion_units")
    )
    if choices.duration is not None:
        length = quantity(choices.key("duration"), choices.duration, "second", "positive")
        if length > motion.duration + motion.time_step:
            raise ConfigError(
                choices.key("duration"),
                f"at most the motion's length, {motion.duration:.6g} s (leave it out to run the whole motion)",
                length,
            )
        if length < motion.duration:
            motion = motion.trimmed(0.0, length)
    return MotionChoice(motion, argument, time_scale, pga, choices.duration)


def choose_controller(
    choices: Choices, cfg: ReportConfig, used: dict, *, allow_none: bool
) -> ControllerChoice:
    """f_c [Hz], feedback source and precision, the report's where not chosen."""
    fc = quantity(
        choices.key("fc_hz"), _pick(choices.fc_hz, cfg.design.fc_hz, "design.fc", used), "hertz", "positive"
    )
    name = _pick(choices.feedback, cfg.controller.feedback, "controller.feedback", used)
    feedback = Feedback.parse(name, choices.key("feedback"), allow_none=allow_none)
    precision = _pick(choices.precision, cfg.controller.precision, "controller.precision", used)
    try:
        return ControllerChoice(fc, feedback, precision)
    except ConfigError as exc:
        raise ConfigError(choices.key(exc.key), exc.expected, exc.got) from None


def report_lab(cfg: ReportConfig, seed: int, used: dict, key: str = "seed") -> LabChoice:
    """The report's interlocks and substep policy, the lab's sensors, and ``seed``."""
    used["limits.stroke"] = cfg.limits.stroke_in
    used["limits.velocity"] = cfg.limits.velocity_in_s
    used["controller.substeps"] = cfg.controller.substeps
    limits = SafetyLimits(stroke=cfg.limits.stroke_in, velocity=cfg.limits.velocity_in_s)
    try:
        return LabChoice(limits, None, cfg.controller.substeps, seed)
    except ConfigError as exc:
        raise ConfigError(key, exc.expected, exc.got) from None


def lab_choice(setup: LabSetup, seed: int, used: dict, key: str = "seed") -> LabChoice:
    """The interlocks, sensors and substeps of a lab file; its generic defaults listed in ``used``.

    Raises
    ------
    ConfigError
        The table is analog (``loop_time`` 0, accepted by ``imil table`` and
        ``imil design``): a virtual-lab run needs the controller's loop time,
        named ``controller.loop_time`` of the lab.
    """
    if not setup.controller.loop_time > 0:
        raise ConfigError(
            f"{setup.name}: controller.loop_time",
            "a positive loop time for a run in the virtual lab (the table is analog: give "
            "[controller] loop_time in a lab file)",
            setup.controller.loop_time,
        )
    for name in setup.defaults:
        used[f"lab.{name}"] = "generic default"
    for name, source in setup.sources.items():
        if source == "report":
            used[name] = getattr(setup.table, name.removeprefix("table."))
    try:
        return LabChoice(
            setup.limits,
            setup.sensors.suite,
            setup.controller.substeps,
            seed,
            setup.sensors.clipping,
            setup.name,
            setup.controller.output_delay,
            setup.uncertainty,
        )
    except ConfigError as exc:
        raise ConfigError(key, exc.expected, exc.got) from None


def with_lab_defaults(choices: Choices, setup: LabSetup) -> Choices:
    """``choices`` with the lab's specimen, feedback and precision where the user chose none."""
    spec = setup.specimen
    chosen: dict[str, Any] = {}
    if choices.specimen is None:
        chosen["specimen"] = spec.kind
        if spec.kind == "vessel" and choices.water_depth is None:
            chosen["water_depth"] = spec.water_depth
        if spec.kind == "rigid" and choices.specimen_weight is None:
            chosen["specimen_weight"] = spec.article_weight
    if choices.feedback is None:
        chosen["feedback"] = setup.controller.feedback
    if choices.precision is None:
        chosen["precision"] = setup.controller.precision
    return replace(choices, **chosen)


def uses_lab_file(choices: Choices) -> bool:
    """Whether the run names a lab or a table (else it is the report's setup, read from ``cfg``)."""
    return choices.lab is not None or choices.table is not None


def _controlled(choices: Choices, cfg: ReportConfig, mil: bool) -> dict[str, Any]:
    used: dict[str, Any] = {}
    setup = None
    if uses_lab_file(choices):
        setup = load_lab(choices.lab, table=choices.table, overrides=choices.table_overrides, accept_lti=True)
        if choices.lab is not None and setup.is_report:
            used["lab"] = setup.name
        choices = with_lab_defaults(choices, setup)
        table = setup.table
        lab = lab_choice(setup, choices.seed, used, choices.key("seed"))
    else:
        table = choose_table(None, choices.table_overrides, cfg, used)
        lab = report_lab(cfg, choices.seed, used, choices.key("seed"))
    design = None
    if choices.design is not None:
        design = read_design(choices.design, "mil" if mil else "track", choices.key("design"))
        check_loop_time(design, table, choices.key("design"))
        if choices.fc_hz is not None:
            raise ConfigError(
                choices.key("fc_hz"), f"no cut-off with {choices.key('design')} (the design holds its own)"
            )
        choices = replace(choices, fc_hz=design.fc_hz)
    parts: dict[str, Any] = dict(
        table=table,
        controller=choose_controller(choices, cfg, used, allow_none=not mil),
        lab=lab,
        specimen=choose_specimen(choices, cfg, used),
        motion=choose_motion(choices, cfg, used),
        from_report=used,
    )
    if mil:
        if design is not None and design.vs is not None and choices.vs is None:
            # the designed VS as it is: no preset is fitted to the article, nothing taken from the report
            parts["vs_spec"] = vs_of_design(design, choices)
        else:
            name = _pick(choices.vs, cfg.vs_preset, "vs.preset", used)
            weight = article_weight(cast(SpecimenChoice, parts["specimen"]), cfg, used)
            spec = resolve(name, choices.vs_overrides, weight)
            if design is not None:  # a VS asked for must be the designed one
                vs_of_design(design, choices, spec)
            parts["vs_spec"] = spec
    # the VS preset is fitted to the article's weight (above); the plant runs the article on its mounting
    parts["specimen"] = mounted_choice(cast(SpecimenChoice, parts["specimen"]), setup)
    if design is not None:
        parts["given_design"] = design
        parts["design_file"] = str(choices.design)
    return parts


def vs_of_design(design: ControllerDesign, choices: Choices, requested: VSSpec | None = None) -> VSSpec:
    """The designed virtual system, rebuilt from the design file (``requested`` must equal it).

    Raises
    ------
    ConfigError
        ``--set-vs`` with a design file (its VS is the designed one), or ``requested`` differs.
    """
    if choices.vs_overrides:
        raise ConfigError(
            choices.key("vs_overrides"),
            f"no VS values with {choices.key('design')} (its VS is the designed one)",
        )
    if requested is None:
        chosen = designed_vs(design)
        return VSSpec(chosen.name, chosen.vs)
    try:
        designed_vs(design, requested.vs, requested.name)
    except ConfigError:
        name = (design.vs or {}).get("name") or (design.vs or {}).get("kind")
        raise ConfigError(
            choices.key("vs"),
            f"the VS of {choices.key('design')}, {name} with its designed parameters (or leave --vs out)",
            requested.name,
        ) from None
    return requested


def tracking_test(choices: Choices, cfg: ReportConfig | None = None) -> TrackingTest:
    """A :class:`TrackingTest` from ``choices``, the rest from the report's setup (``cfg``)."""
    return TrackingTest(**_controlled(choices, cfg or report_config(), mil=False))


def mil_test(choices: Choices, cfg: ReportConfig | None = None) -> MilTest:
    """A :class:`MilTest` from ``choices`` (``vs``: default the report's SD2), the rest from the report's setup."""
    return MilTest(**_controlled(choices, cfg or report_config(), mil=True))


def frf_test(
    choices: Choices,
    *,
    peak: Any = None,
    delay: str | None = None,
    kp_values: tuple[float, ...] | None = None,
    kp_study: bool = False,
    cfg: ReportConfig | None = None,
) -> FrfTest:
    """An :class:`FrfTest`: the bare table unless ``choices.specimen``; peak [in], delay, K_p study.

    ``kp_values`` [V/psi] matter only with ``kp_study`` (default the report's values).
    """
    cfg = cfg or report_config()
    used: dict[str, Any] = {}
    setup = None
    if uses_lab_file(choices):
        setup = load_lab(choices.lab, table=choices.table, overrides=choices.table_overrides, accept_lti=True)
        table = setup.table
    else:
        table = choose_table(None, choices.table_overrides, cfg, used)
    specimen = mounted_choice(choose_specimen(choices, cfg, used, default_kind="none"), setup)
    peak_in = quantity(
        choices.key("peak"), _pick(peak, cfg.frf.peak_in, "frf.peak", used), "inch", "positive"
    )
    delay = _pick(delay, cfg.frf.delay, "frf.delay", used)
    kps: tuple[float, ...] = ()
    if kp_study and isinstance(table, LTITable):
        raise ConfigError(
            choices.key("kp_study"),
            "a physical table (an LTI table's hydraulic loop, K_p in it, is inside its model)",
        )
    if kp_study:
        kps = tuple(_pick(kp_values, cfg.frf.kp_values, "frf.kp_values", used))
        if specimen.specimen is not None:
            raise ConfigError(
                choices.key("kp_study"),
                f"{choices.key('specimen')} none (the identification is of the bare table, Section 4.5.3)",
                choices.specimen,
            )
    if setup is None:
        lab = report_lab(cfg, choices.seed, used, choices.key("seed"))
    else:
        lab = lab_choice(setup, choices.seed, used, choices.key("seed"))
    try:
        return FrfTest(table, specimen, peak_in, delay, kps, lab, used)
    except ConfigError as exc:
        raise ConfigError(choices.key(exc.key), exc.expected, exc.got) from None
