"""Virtual-lab campaign kinds: ``frf`` (Section 4.5), ``tracking`` (Section 8), ``mil`` (Section 9).

Each adapter turns a run configuration (plain data, internal units) into a
call of :mod:`impedance_mil.lab.experiments`, writes the run's HDF5 file with
:func:`impedance_mil.lab.results.save_run` and returns its metrics: those of
:func:`impedance_mil.lab.metrics.evaluate_run` (``spectral_error_low``,
``spectral_error_high``, ``nrms_error``, ``peak_error``, ``energy_error``)
plus ``spectral_agreement_hz`` and ``hf_ratio`` of
:mod:`impedance_mil.campaign.runmetrics`.  A run that trips a safety limit
returns ``aborted = True`` with the trip as ``abort_reason`` (its data up to
the trip are kept).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..lab.experiments import ControlledRun, run_frf, run_mil, run_tracking
from ..lab.results import save_run
from ..signals.multisine import report_multisine
from ..specimens.vessel import FluidVessel
from ..units import INTERNAL_UNITS
from .modelkinds import CONTROLLER_PARAMS, TABLE_PARAMS, VS_PARAMS, table_parameters, virtual_system
from .motions import REPORT_MOTIONS, motion_source, report_motion
from .params import Param
from .runmetrics import tracking_metrics

#: Feedback sources of Section 8.3.2: name -> (lab feedback channel, compensate with u_w).
FEEDBACK_SOURCES = {"load_cells": ("lc", True), "force_equilibrium": ("fe", True), "none": ("lc", False)}

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
        choices=tuple(FEEDBACK_SOURCES),
        help="source of w (Section 8.3.2): load_cells, force_equilibrium, none (u_w = 0)",
    ),
    "precision": Param(
        "controller.precision",
        type="choice",
        choices=("single", "double"),
        help="controller arithmetic (the RMC75E computes in single precision)",
    ),
    "seed": Param("seed", type="integer", check="nonnegative", help="sensor-noise seed"),
}

FRF_PARAMS: dict[str, Param] = {**TABLE_PARAMS, **SPECIMEN_PARAMS, "seed": RUN_PARAMS["seed"]}
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
        choices=("load_cells", "force_equilibrium"),
        help="source of w (Appendix C): load_cells or force_equilibrium",
    ),
    "m_vs": Param(
        "vs.m_vs",
        unit=INTERNAL_UNITS["mass"],
        check="positive",
        help="basemat mass m_vs (instead of m_vs_ratio) [lbf*s^2/in]",
    ),
}

_MOTION_DEFAULTS = {"name": "GM1", "motions_dir": None, "scale": 1.0, "duration": None}
_CONTROLLER_DEFAULTS = {"fc_hz": 80.0, "feedback": "load_cells", "precision": "single"}
FRF_DEFAULTS: dict[str, Any] = {"table": {}, "specimen": {"kind": "bare", "water_depth": 36.0}, "seed": 0}
TRACKING_DEFAULTS: dict[str, Any] = {
    "table": {},
    "specimen": {"kind": "vessel", "water_depth": 0.0},
    "motion": _MOTION_DEFAULTS,
    "controller": _CONTROLLER_DEFAULTS,
    "seed": 0,
}
MIL_DEFAULTS: dict[str, Any] = {
    **TRACKING_DEFAULTS,
    "specimen": {"kind": "vessel", "water_depth": 36.0},
    "vs": {"preset": "SD2", "m_vs_ratio": None, "m_vs": None},
}

#: Bands of the FRF model error [Hz]: the whole multisine band, and the oil-column band of Figure 4.16.
FRF_BANDS_HZ = {"model_error": (0.25, 100.0), "model_error_10_50hz": (10.0, 50.0)}


def _specimen(config: dict[str, Any]) -> FluidVessel | None:
    spec = config["specimen"]
    return FluidVessel(water_depth_in=float(spec["water_depth"])) if spec["kind"] == "vessel" else None


def run_frf_kind(config: dict[str, Any], out_path: Path) -> dict[str, Any]:
    """Multisine identification of the virtual table (report Section 4.5); see the module docstring.

    The multisine is the report's (512 lines from 0.25 to 125 Hz, 0.1 in peak)
    with its 4.096 s period kept at every loop time.

    Returns
    -------
    dict
        ``model_error`` (0.25-100 Hz) and ``model_error_10_50hz``: rms ``|log(H_model/H_meas)|``
        of ``z/u`` (0.01 is about 1 %); for the bare table also the identified
        ``f_oil_hz`` [Hz], ``zeta_oil`` and ``identification_error``; after a
        trip, ``aborted`` and ``abort_reason`` (the run's data are kept).
    """
    params = table_parameters(config)
    specimen = _specimen(config)
    multisine = report_multisine(params.loop_time)
    exp = run_frf(
        params, multisine=multisine, specimen=specimen, identify=specimen is None, seed=int(config["seed"])
    )
    if not exp.completed:
        save_run(exp.run, out_path)
        return _aborted(exp.run)
    z = exp.frf["z"]
    save_run(
        exp.run,
        out_path,
        extra_groups={
            "frf": {"f_hz": z.frequency_hz, "H_zu_measured": z.response, "H_zu_model": exp.model["z"]}
        },
    )
    metrics = {name: exp.model_error("z", band) for name, band in FRF_BANDS_HZ.items()}
    if exp.identification is not None:
        ident = exp.identification.summary()
        metrics.update(
            f_oil_hz=ident["f_oil_hz"],
            zeta_oil=ident["zeta_oil"],
            identification_error=ident["rms_log_error"],
        )
    return metrics


def resolve_motion(config: dict[str, Any]) -> dict[str, Any]:
    """Record in ``motion.source`` which record the run will use (hashed into the run name)."""
    motion = config["motion"]
    motion["source"] = motion_source(motion["name"], motion.get("motions_dir"))
    return config


def _motion(config: dict[str, Any]):
    m = config["motion"]
    return report_motion(m["name"], m.get("motions_dir"), float(m.get("scale", 1.0)), m.get("duration"))


def _controlled_metrics(result: ControlledRun, source: str, out_path: Path) -> dict[str, Any]:
    run = result.run
    save_run(run, out_path)
    metrics: dict[str, Any] = {"motion_source": source, "duration_s": run.n_samples * run.loop_time}
    if run.n_samples > 1:
        metrics["peak_table_disp_in"] = float(np.max(np.abs(run.x)))
    if result.metrics is not None:
        metrics.update({k: v for k, v in result.metrics.to_dict().items() if v is not None})
        metrics.update(tracking_metrics(run.z_meas, run.z_vs, run.loop_time))
    if run.trip is not None:
        metrics.update(_aborted(run))
    return metrics


def _aborted(run) -> dict[str, Any]:
    return {"aborted": True, "abort_reason": str(run.trip.as_exception())}


def run_tracking_kind(config: dict[str, Any], out_path: Path) -> dict[str, Any]:
    """Acceleration tracking of a report motion (Section 8); see the module docstring."""
    params = table_parameters(config)
    motion, source = _motion(config)
    ctrl = config["controller"]
    feedback, compensate = FEEDBACK_SOURCES[ctrl["feedback"]]
    result = run_tracking(
        params,
        motion,
        specimen=_specimen(config),
        fc_hz=float(ctrl["fc_hz"]),
        feedback=feedback,
        compensate=compensate,
        precision=ctrl["precision"],
        seed=int(config["seed"]),
    )
    return _controlled_metrics(result, source, out_path)


def run_mil_kind(config: dict[str, Any], out_path: Path) -> dict[str, Any]:
    """MIL imitating a virtual isolation system (Section 9); see the module docstring."""
    params = table_parameters(config)
    motion, source = _motion(config)
    ctrl = config["controller"]
    feedback, _ = FEEDBACK_SOURCES[ctrl["feedback"]]
    vs = virtual_system(config, params.mass)
    result = run_mil(
        params,
        vs,
        motion,
        specimen=_specimen(config),
        fc_hz=float(ctrl["fc_hz"]),
        feedback=feedback,
        precision=ctrl["precision"],
        seed=int(config["seed"]),
    )
    metrics = _controlled_metrics(result, source, out_path)
    metrics["m_vs_over_m_st"] = vs.m_vs / params.mass
    return metrics
