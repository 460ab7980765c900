"""Virtual-lab campaign kinds: ``frf`` (Section 4.5), ``tracking`` (Section 8), ``mil`` (Section 9).

Each adapter turns a run configuration (plain data, internal units) into the
experiment description of :mod:`impedance_mil.lab.descriptions` that
``imil frf``/``track``/``simulate`` build too, runs it, writes the run file
with :func:`impedance_mil.lab.runfile.write_run_file` (the same summary
attribute and ``imil/frf`` group as the CLI's) and returns its metrics under
the shared names of :mod:`impedance_mil.lab.runfile`
(``spectral_error_0p25_15hz``, ``spectral_error_15_50hz``, ``nrms_error``,
``peak_error``, ``energy_error``, ``simulated_s``, ``aborted``,
``abort_reason``, ``trip_limit``/``trip_time_s``/``trip_value``) plus
``spectral_agreement_hz`` and ``hf_ratio`` of
:mod:`impedance_mil.campaign.runmetrics`, and for ``mil`` the design's
``passivity_margin_deg`` and ``passivity_index`` (:func:`design_passivity`).  A run that trips a safety limit
returns ``aborted = True`` with the trip as ``abort_reason`` (its data up to
the trip are kept).

The kinds' defaults are the report's setup (:mod:`impedance_mil.report_config`).
The feedback names are those of :class:`impedance_mil.lab.feedback.Feedback`
(``lc``, ``fe``, ``none``); campaign files with the older ``load_cells`` and
``force_equilibrium`` are still read.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..design import ControllerDesign, virtual_model
from ..design.constraints import DesignCriteria
from ..design.optimized.indices import passivity_index
from ..lab.choices import lab_choice, mounted_choice, report_lab
from ..lab.descriptions import (
    FRF_BANDS_HZ,
    ControllerChoice,
    FrfTest,
    LabChoice,
    MilTest,
    MotionChoice,
    SpecimenChoice,
    TrackingTest,
)
from ..lab.experiments import ControlledRun
from ..lab.feedback import LEGACY_NAMES, Feedback
from ..lab.labfile import LabSetup, load_lab
from ..lab.runfile import TRIP_KEYS, flat_summary, run_summary, write_run_file
from ..plant import TableParameters
from ..report_config import report_config
from ..units import INTERNAL_UNITS
from ..virtual.files import VSSpec
from .modelkinds import CONTROLLER_PARAMS, TABLE_PARAMS, VS_PARAMS, table_parameters, virtual_system
from .motions import REPORT_MOTIONS, TIME_SCALE, motion_source, report_motion
from .params import Param
from .runmetrics import tracking_metrics

#: Feedback names a campaign accepts (the older spellings are read as the shared names).
FEEDBACK_NAMES = tuple(f.value for f in Feedback)
#: Metrics of an FRF run: its end, the identified parameters and the model errors.
FRF_METRICS = (
    *TRIP_KEYS,
    "omega_oil_rad_s",
    "f_oil_hz",
    "zeta_oil",
    "d",
    "identification_error",
    *FRF_BANDS_HZ,
)

SPECIMEN_PARAMS: dict[str, Param] = {
    "specimen": Param(
        "specimen.kind",
        type="choice",
        choices=("vessel", "bare"),
        help="test article: the water-filled vessel of Section 3.2, or the bare table",
    ),
    "water_depth": Param(
        "specimen.water_depth",
        unit="inch",
        check="nonnegative",
        help="water depth in the vessel d_w [in] (Section 8.2: 0, 18, 30, 42)",
    ),
}

MOTION_PARAMS: dict[str, Param] = {
    "motion": Param(
        "motion.name",
        type="choice",
        choices=tuple(REPORT_MOTIONS),
        help="input motion of Table 8.1 (GM1, GM2, GM3)",
    ),
    "motions_dir": Param(
        "motion.motions_dir",
        type="text",
        help="folder with the PEER RSN*.AT2 seeds (else documented substitutes)",
    ),
    "motion_scale": Param(
        "motion.scale",
        unit="dimensionless",
        check="positive",
        help="factor on the PGA of Table 8.1 (1 = the report's motion)",
    ),
    "duration": Param(
        "motion.duration",
        unit="second",
        check="positive",
        help="keep only the first seconds of the (time-scaled) motion [s]",
    ),
}

RUN_PARAMS: dict[str, Param] = {
    "feedback": Param(
        "controller.feedback",
        type="choice",
        choices=FEEDBACK_NAMES,
        aliases=LEGACY_NAMES,
        help="source of w (Section 8.3.2): lc (load cells), fe (force equilibrium), none (u_w = 0)",
    ),
    "precision": Param(
        "controller.precision",
        type="choice",
        choices=("single", "double"),
        help="controller arithmetic (the RMC75E computes in single precision)",
    ),
    "seed": Param("seed", type="integer", check="nonnegative", help="sensor-noise seed"),
    "lab": Param(
        "lab",
        type="text",
        help="lab file (or a shipped lab's name) whose table, sensors, interlocks and dynamics the runs "
        "use; default: the report's setup",
    ),
}

FRF_PARAMS: dict[str, Param] = {
    **TABLE_PARAMS,
    **SPECIMEN_PARAMS,
    "seed": RUN_PARAMS["seed"],
    "lab": RUN_PARAMS["lab"],
}
TRACKING_PARAMS: dict[str, Param] = {
    **TABLE_PARAMS,
    **SPECIMEN_PARAMS,
    **MOTION_PARAMS,
    **CONTROLLER_PARAMS,
    **RUN_PARAMS,
}
MIL_PARAMS: dict[str, Param] = {
    **TRACKING_PARAMS,
    **VS_PARAMS,
    "feedback": Param(
        "controller.feedback",
        type="choice",
        choices=tuple(n for n in FEEDBACK_NAMES if Feedback(n).compensates),
        aliases=LEGACY_NAMES,
        help="source of w (Appendix C): lc (load cells) or fe (force equilibrium)",
    ),
    "m_vs": Param(
        "vs.m_vs",
        unit=INTERNAL_UNITS["mass"],
        check="positive",
        help="basemat mass m_vs (instead of m_vs_ratio) [lbf*s^2/in]",
    ),
}

_REPORT = report_config()
_MOTION_DEFAULTS = {"name": _REPORT.motion.record, "motions_dir": None, "scale": 1.0, "duration": None}
_CONTROLLER_DEFAULTS = {
    "fc_hz": _REPORT.design.fc_hz,
    "feedback": _REPORT.controller.feedback,
    "precision": _REPORT.controller.precision,
}
FRF_DEFAULTS: dict[str, Any] = {
    "table": {},
    "specimen": {"kind": "bare", "water_depth": _REPORT.specimen.water_depth_in},
    "seed": 0,
    "lab": None,
}
#: Tracking runs default to the empty vessel (the first depth of Section 8.2's study, 0 in).
TRACKING_DEFAULTS: dict[str, Any] = {
    "table": {},
    "specimen": {"kind": "vessel", "water_depth": 0.0},
    "motion": _MOTION_DEFAULTS,
    "controller": _CONTROLLER_DEFAULTS,
    "seed": 0,
    "lab": None,
}
MIL_DEFAULTS: dict[str, Any] = {
    **TRACKING_DEFAULTS,
    "specimen": {"kind": "vessel", "water_depth": _REPORT.specimen.water_depth_in},
    "vs": {"preset": _REPORT.vs_preset, "m_vs_ratio": None, "m_vs": None},
}


def _specimen(config: dict[str, Any]) -> SpecimenChoice:
    """The run's article, on the lab file's mounting (``[dynamics.platen]``, ``[dynamics.load_cells]``) if any."""
    spec = config["specimen"]
    if spec["kind"] != "vessel":
        article = SpecimenChoice.bare()
    else:
        article = SpecimenChoice.vessel(float(spec["water_depth"]))
    return mounted_choice(article, _lab_setup(config))


def _lab_setup(config: dict[str, Any]) -> LabSetup | None:
    """The run's lab file (``lab``), or None for the report's setup."""
    name = config.get("lab")
    return None if name is None else load_lab(name)


def _lab(config: dict[str, Any], used: dict[str, Any]) -> LabChoice:
    """The lab of ``config["lab"]`` (its interlocks, sensors, substeps), else the report's; the run's seed."""
    setup = _lab_setup(config)
    if setup is None:
        return report_lab(_REPORT, int(config["seed"]), used)
    used["lab"] = setup.name
    return lab_choice(setup, int(config["seed"]), used)


def _table(config: dict[str, Any]) -> TableParameters:
    """The run's table: the lab file's physical table (``lab``) or Table 4.1, with the ``table`` entries set."""
    setup = _lab_setup(config)
    if setup is None:
        return table_parameters(config)
    changes = {k: v for k, v in config.get("table", {}).items() if v is not None}
    return setup.physical_table().replace(**changes)


def run_frf_kind(config: dict[str, Any], out_path: Path) -> dict[str, Any]:
    """Multisine identification of the virtual table (report Section 4.5); see the module docstring.

    The multisine is the report's (512 lines from 0.25 to 125 Hz, 0.1 in peak)
    with its 4.096 s period kept at every loop time.

    Returns
    -------
    dict
        ``model_error_0p25_100hz`` and ``model_error_10_50hz``: rms
        ``|log(H_model/H_meas)|`` of ``z/u`` (0.01 is about 1 %); for the bare
        table also the identified ``omega_oil_rad_s``, ``f_oil_hz`` [Hz],
        ``zeta_oil``, ``d`` and ``identification_error``; ``simulated_s``;
        after a trip, ``aborted`` and ``abort_reason`` (the run's data are kept).
    """
    used: dict[str, Any] = {"frf.peak": _REPORT.frf.peak_in, "frf.delay": _REPORT.frf.delay}
    lab = _lab(config, used)
    test = FrfTest(_table(config), _specimen(config), _REPORT.frf.peak_in, _REPORT.frf.delay, (), lab, used)
    outcome = test.run()
    summary = test.summary(outcome)
    write_run_file(outcome.experiment.run, out_path, summary, test.arrays(outcome, summary))
    return {k: v for k, v in flat_summary(summary).items() if k in FRF_METRICS or k.startswith("trip_")}


def resolve_motion(config: dict[str, Any]) -> dict[str, Any]:
    """Record in ``motion.source`` which record the run will use (hashed into the run name)."""
    motion = config["motion"]
    motion["source"] = motion_source(motion["name"], motion.get("motions_dir"))
    return config


def _motion(config: dict[str, Any]) -> tuple[MotionChoice, str]:
    m = config["motion"]
    scale = float(m.get("scale", 1.0))
    motion, source = report_motion(m["name"], m.get("motions_dir"), scale, m.get("duration"))
    pga = REPORT_MOTIONS[m["name"]].pga_scaled_g * scale
    return MotionChoice(motion, m["name"], TIME_SCALE, pga, m.get("duration")), source


def _controller(config: dict[str, Any]) -> ControllerChoice:
    ctrl = config["controller"]
    return ControllerChoice(float(ctrl["fc_hz"]), Feedback.parse(ctrl["feedback"]), ctrl["precision"])


def controlled_metrics(
    test: TrackingTest, result: ControlledRun, source: str, out_path: Path
) -> dict[str, Any]:
    run = result.run
    write_run_file(run, out_path, test.summary(result), test.arrays(result))
    metrics: dict[str, Any] = {"motion_source": source}
    metrics.update({k: v for k, v in flat_summary(run_summary(run, result.metrics)).items() if k != "mode"})
    if result.metrics is not None:
        metrics.update(tracking_metrics(run.z_meas, run.z_vs, run.loop_time))
    return metrics


def tracking_test_of(config: dict[str, Any]) -> tuple[TrackingTest, str]:
    """The :class:`TrackingTest` a ``tracking`` run configuration describes, and its motion's source."""
    motion, source = _motion(config)
    used: dict[str, Any] = {}
    lab = _lab(config, used)
    return TrackingTest(_table(config), _specimen(config), motion, _controller(config), lab, used), source


def run_tracking_kind(config: dict[str, Any], out_path: Path) -> dict[str, Any]:
    """Acceleration tracking of a report motion (Section 8); see the module docstring."""
    test, source = tracking_test_of(config)
    return controlled_metrics(test, test.run(), source, out_path)


def run_mil_kind(config: dict[str, Any], out_path: Path) -> dict[str, Any]:
    """MIL imitating a virtual isolation system (Section 9); see the module docstring."""
    params = _table(config)
    motion, source = _motion(config)
    vs = virtual_system(config, params.mass)
    used: dict[str, Any] = {}
    lab = _lab(config, used)
    test = MilTest(
        params,
        _specimen(config),
        motion,
        _controller(config),
        lab,
        used,
        vs_spec=VSSpec(config["vs"]["preset"], vs),
    )
    result = test.run()
    metrics = controlled_metrics(test, result, source, out_path)
    metrics["m_vs_over_m_st"] = vs.m_vs / params.mass
    metrics.update(design_passivity(result.design, params, vs))
    return metrics


def design_passivity(design: ControllerDesign, params: TableParameters, vs) -> dict[str, float]:
    """``passivity_margin_deg`` [deg] and ``passivity_index`` [lbf*s/in] of a MIL run's controller.

    The margin is the design's constraint-III margin at its cut-off; the index
    is ``min Re(1/H_vw)``, the smallest equivalent damping the controlled
    table presents to the article over the passivity band up to the loop's
    Nyquist frequency (:func:`impedance_mil.design.optimized.passivity_index`),
    on the same VS model as the run's design (``open-fh``, see
    :func:`impedance_mil.lab.experiments.mil_design`).  Together with
    ``hf_ratio`` they answer the report's question of Section 10.4, "does less
    passive mean more oscillatory?" (claim ``sec10-passive-oscillatory``).
    """
    criteria = DesignCriteria()
    band = (criteria.passivity_low_hz, 0.5 / params.loop_time)
    index, _ = passivity_index(design, params, virtual_model(vs, linearization="open-fh"), band)
    return {
        "passivity_margin_deg": float(design.constraint_at(design.fc_hz).passivity_margin_deg),
        "passivity_index": index,
    }
