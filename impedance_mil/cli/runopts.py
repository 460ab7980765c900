"""Options and helpers shared by the run commands (``imil simulate``, ``track``, ``frf``, ``report``, ``demo``).

Everything here resolves command-line text into the library's value objects
(table parameters, specimen, motion), checks the output paths *before* a run
starts, and writes a run's HDF5 file atomically with the command's summary
next to the lab's channels.  Bad input raises :class:`~impedance_mil.errors.ImilError`
subclasses, which ``imil`` prints as one line with exit status 2.

Defaults are the report's configuration: the table of Table 4.1, the vessel
with 36 in of water (Sections 8.3.2 and 9.2), El Centro (RSN 6, GM1 of
Table 8.1) time-compressed by 2 and scaled to 0.8 g, f_c = 80 Hz, load-cell
feedback (Sections 8.3 and 9.3).
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import h5py
import numpy as np
from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    SpinnerColumn,
    TextColumn,
    TimeElapsedColumn,
)

from ..campaign.motions import REPORT_MOTIONS, TIME_SCALE
from ..config import quantity, read_toml
from ..design.constraints import DesignCriteria
from ..errors import ConfigError, DataFileError, ImilError
from ..fileio import json_safe
from ..lab.results import RunResult, save_run
from ..lab.setup import SafetyLimits
from ..plant import TableParameters
from ..signals import GroundMotion, MotionCheck, TableLimits, check_motion
from ..specimens import FluidVessel, RigidMass, specimen_from_config
from ..units import G0, in_s2_to_g, weight_to_mass
from ..virtual import TEST_ARTICLE_WEIGHT
from ..virtual.excitation import rigid_article_response
from .motion import load_motion

#: Exit status of a run stopped by a safety interlock (its data up to the trip are written).
EXIT_ABORTED = 3
#: Exit status after Ctrl-C (like a shell after SIGINT).
EXIT_INTERRUPTED = 130

#: Built-in motion whose default PGA is Table 8.1's: GM1 is El Centro, RSN 6.
DEFAULT_MOTION = "elcentro"
#: Table 8.1: GM1 (RSN 6) scaled to 0.8 g.
DEFAULT_PGA_G = REPORT_MOTIONS["GM1"].pga_scaled_g
#: Section 8.2: the seeds are time-compressed by 2.
DEFAULT_TIME_SCALE = TIME_SCALE
#: Filter cut-off of Sections 8.3 and 9.3 [Hz].
DEFAULT_FC_HZ = 80.0
#: Water depth of the MIL experiments (Section 9.2, Table 9.1) and of Figure 8.7 [in].
DEFAULT_WATER_DEPTH_IN = 36.0

#: ``--feedback`` -> (lab feedback channel, compensate with u_w); Section 8.3.2.
FEEDBACK = {"lc": ("lc", True), "fe": ("fe", True), "none": ("lc", False)}

#: Unit of the value a trip reports, by limit (lab.results.Trip).
TRIP_UNITS = {
    "stroke": "in",
    "velocity": "in/s",
    "actuator_force": "lbf",
    "valve_saturation": "V",
    "divergence": "in",
    "nan": "",
}

#: Root attribute of a run file holding the command's summary (JSON).
SUMMARY_ATTR = "imil_summary_json"
#: HDF5 group holding the command's extra arrays.
SUMMARY_GROUP = "imil"

SPECIMEN_HELP = (
    "vessel (Section 3.2), rigid (a rigid mass of --specimen-weight), none (bare table) "
    "or a specimen file (TOML, [specimen] table as in docs/specimens.md)."
)


class MotionRefused(ImilError, ValueError):
    """The motion exceeds the table's limits and ``--force`` was not given."""


@dataclass(frozen=True)
class SpecimenChoice:
    """The test article of a run.

    Attributes
    ----------
    specimen : Specimen or None
        ``None`` for the bare table.
    label : str
        Description for the terminal and the report.
    weight_lbf : float
        Total weight [lbf] (0 for the bare table).
    """

    specimen: Any
    label: str
    weight_lbf: float


@dataclass(frozen=True)
class MotionChoice:
    """The input motion of a run, as it will be run (before resampling to the loop time).

    Attributes
    ----------
    motion : GroundMotion
        Scaled (and trimmed) motion [in/s^2].
    argument : str
        What the user named (built-in name or file).
    time_scale : float
        Time compression applied (t' = t / factor).
    pga_g : float or None
        PGA it was scaled to [g] (None: as recorded).
    duration_s : float or None
        Length it was trimmed to [s] (None: the whole record).
    """

    motion: GroundMotion
    argument: str
    time_scale: float
    pga_g: float | None
    duration_s: float | None

    def to_dict(self) -> dict:
        return {
            "argument": self.argument,
            "name": self.motion.name,
            "source": self.motion.source,
            "time_scale": self.time_scale,
            "pga_g": self.motion.pga_g,
            "duration_s": self.motion.duration,
            "trimmed_to_s": self.duration_s,
            "time_step_s": self.motion.time_step,
        }


@dataclass(frozen=True)
class Pretest:
    """Pre-test check of a motion against the table's limits (report Section 8.2).

    Attributes
    ----------
    limits : TableLimits
        Capacity of the table with the specimen.
    input : MotionCheck
        The input motion (what the table follows when tracking).
    basemat : MotionCheck or None
        MIL only: stroke and velocity of the VS basemat motion the table must
        follow, predicted with the specimen as a rigid mass (:func:`basemat_check`).
    """

    limits: TableLimits
    input: MotionCheck
    basemat: MotionCheck | None = None

    def to_dict(self) -> dict:
        out = {"moving_weight_lbf": self.limits.moving_mass * G0, "input": check_dict(self.input)}
        if self.basemat is not None:
            out["basemat_predicted"] = check_dict(self.basemat)
        return out


@dataclass
class Written:
    """Files a command wrote (in order), for the closing message."""

    paths: list[Path] = field(default_factory=list)


# ------------------------------------------------------------------ parsing
def specimen_choice(text: str, water_depth: str | None, weight: str | None) -> SpecimenChoice:
    """Resolve ``--specimen`` with ``--water-depth`` [in] or ``--specimen-weight`` [lbf]."""
    key = text.strip().lower()
    if water_depth is not None and key != "vessel":
        raise ConfigError("--water-depth", "--specimen vessel (it sets the vessel's water depth)", text)
    if weight is not None and key != "rigid":
        raise ConfigError("--specimen-weight", "--specimen rigid (it sets the rigid mass's weight)", text)
    if key == "none":
        return SpecimenChoice(None, "bare table", 0.0)
    if key == "vessel":
        depth = quantity(
            "--water-depth",
            DEFAULT_WATER_DEPTH_IN if water_depth is None else water_depth,
            "inch",
            "nonnegative",
        )
        vessel = FluidVessel(water_depth_in=depth)
        return SpecimenChoice(
            vessel, f"vessel with {depth:g} in of water ({vessel.total_weight:.0f} lb)", vessel.total_weight
        )
    if key == "rigid":
        lbf = quantity(
            "--specimen-weight", TEST_ARTICLE_WEIGHT if weight is None else weight, "force_pound", "positive"
        )
        return SpecimenChoice(RigidMass(lbf), f"rigid mass of {lbf:.0f} lb", lbf)
    path = Path(text)
    if not path.is_file():
        raise ConfigError("--specimen", "vessel, rigid, none or a specimen file (TOML)", text)
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


def motion_choice(
    argument: str, units: str, time_scale: float, pga: float | None, duration: float | None
) -> MotionChoice:
    """Resolve ``--motion`` with its scaling; the default PGA is Table 8.1's for El Centro (GM1)."""
    if pga is None and argument.strip().lower() == DEFAULT_MOTION:
        pga = DEFAULT_PGA_G
    motion = load_motion(argument, units, time_scale, pga)
    if duration is not None:
        length = quantity("--duration", duration, "second", "positive")
        if length < motion.duration:
            motion = motion.trimmed(0.0, length)
    return MotionChoice(motion, argument, float(time_scale), pga, duration)


def feedback_choice(text: str, allow_none: bool) -> tuple[str, bool]:
    """``--feedback lc|fe|none`` -> (lab feedback channel, compensate with u_w)."""
    key = text.strip().lower()
    if key not in FEEDBACK or (key == "none" and not allow_none):
        choices = (
            "lc, fe or none"
            if allow_none
            else "lc or fe (a MIL run feeds the measured force to the VS; 'none' is for imil track)"
        )
        raise ConfigError("--feedback", choices, text)
    return FEEDBACK[key]


def check_choice(option: str, value: str, choices: tuple[str, ...]) -> str:
    """``value`` if it is one of ``choices`` (else ConfigError naming the option)."""
    if value not in choices:
        raise ConfigError(option, "one of " + ", ".join(choices), value)
    return value


def output_path(option: str, path: Path | None, overwrite: bool) -> Path | None:
    """Check an output path before anything runs: its folder exists, and it is new or ``--overwrite``."""
    if path is None:
        return None
    if not path.parent.is_dir():
        raise ConfigError(option, "a path in an existing folder", str(path))
    if path.is_dir():
        raise ConfigError(option, "a file path, not a folder", str(path))
    if path.exists() and not overwrite:
        raise ConfigError(option, "a file that does not exist yet (or --overwrite to replace it)", str(path))
    if not os.access(path.parent, os.W_OK):
        raise ConfigError(option, "a path in a writable folder", str(path))
    return path


# ------------------------------------------------------------------ pre-test check
def check_dict(check: MotionCheck) -> dict:
    """JSON form of a :class:`MotionCheck`."""
    return {
        "ok": check.ok,
        "exceeded": check.exceeded,
        "checks": [
            {"name": c.name, "peak": c.peak, "limit": c.limit, "unit": c.unit, "ok": c.ok, "time_s": c.time_s}
            for c in check.checks
        ],
        "suggested_time_scale": check.suggested_time_scale,
        "max_pga_g": check.max_pga_g,
    }


def overruns(check: MotionCheck) -> str:
    """``"stroke 9.70 in > 3.2 in at t = 5.10 s, ..."`` for the exceeded limits."""
    return ", ".join(
        f"{c.name} {c.peak:.3g} {c.unit} > {c.limit:.3g} {c.unit} at t = {c.time_s:.2f} s"
        for c in check.checks
        if not c.ok
    )


def basemat_check(
    vs, motion: GroundMotion, params: TableParameters, limits: TableLimits, specimen: SpecimenChoice
) -> MotionCheck:
    """Stroke and velocity the table needs to follow the VS basemat in a MIL run (a prediction).

    The basemat's absolute acceleration comes from the VS model carrying the
    specimen as a rigid mass (``virtual.excitation.rigid_article_response``),
    at the loop time; it is checked *without* baseline correction
    (``check_motion(..., baseline_correct=False)``), as the loop integrates it
    from rest (a correction misjudges an excerpt that ends mid-shaking).  The
    limits are the lab's interlocks where they are tighter than the table's
    capacity (stroke 3 in, Section 8.2).
    """
    gm = motion.resampled(params.loop_time)
    response = rigid_article_response(vs, gm.accel, gm.time_step, weight_to_mass(specimen.weight_lbf))
    basemat = GroundMotion(gm.time_step, response.z_vs, "VS basemat")
    interlocks = SafetyLimits()
    lab = replace(
        limits,
        stroke_in=min(limits.stroke_in, interlocks.stroke),
        velocity_in_s=min(limits.velocity_in_s, interlocks.velocity),
    )
    full = check_motion(basemat, lab, baseline_correct=False)
    checks = [full.check("stroke"), full.check("velocity")]
    return MotionCheck(all(c.ok for c in checks), checks, None, full.max_pga_g)


def pretest(params: TableParameters, specimen: SpecimenChoice, motion: GroundMotion, vs=None) -> Pretest:
    """Check the input motion (and, with a VS, the predicted basemat motion) against the table."""
    limits = TableLimits.from_table(params, specimen_weight=specimen.weight_lbf)
    basemat = None if vs is None else basemat_check(vs, motion, params, limits, specimen)
    return Pretest(limits, check_motion(motion, limits), basemat)


def enforce_pretest(pre: Pretest, motion: MotionChoice, force: bool) -> list[str]:
    """Refuse a motion over the limits unless ``force``; return the warnings to print."""
    warnings = []
    if not pre.input.ok:
        text = f"the motion exceeds the table's limits: {overruns(pre.input)}"
        hint = []
        if pre.input.suggested_time_scale is not None:
            hint.append(f"--time-scale {motion.time_scale * pre.input.suggested_time_scale:.2f}")
        if not pre.input.check("force").ok:
            hint.append(f"--pga <= {pre.input.max_pga_g:.3f}")
        if not force:
            raise MotionRefused(
                f"{text}; try {' or '.join(hint) or 'a smaller --pga'}, "
                "or --force to run it anyway (the interlocks will stop it)"
            )
        warnings.append(f"{text}; running anyway (--force)")
    if pre.basemat is not None and not pre.basemat.ok:
        stroke = pre.basemat.check("stroke")
        fit = ""
        if not stroke.ok:
            fit = f"; at about {motion.motion.pga_g * stroke.limit / stroke.peak:.2f} g it would fit"
        warnings.append(
            "the VS basemat motion the table must follow (specimen taken as rigid) "
            f"exceeds the lab's interlocks: {overruns(pre.basemat)}; the run will "
            f"probably be stopped{fit}"
        )
    return warnings


# ------------------------------------------------------------------ results
def trip_text(run: RunResult) -> str | None:
    """``"limit 'stroke' tripped at t = 2.6500 s (value -3.001 in)"`` or None."""
    if run.trip is None:
        return None
    unit = TRIP_UNITS.get(run.trip.limit, "")
    return (
        f"limit '{run.trip.limit}' tripped at t = {run.trip.time_s:.4f} s "
        f"(value {run.trip.value:.4g}{' ' + unit if unit else ''})"
    )


def run_summary(run: RunResult, metrics) -> dict:
    """The run's figures of merit under stable names (lab.metrics mapped; fractions, g, in, s).

    ``spectral_error_*``: mean absolute relative error of the 5 %-damped PSA of
    the measured table acceleration against the target (lab.metrics.spectral_error).
    """
    m = metrics.to_dict() if metrics is not None else {}
    n = run.n_samples
    peak = lambda name: float(np.max(np.abs(run.channels[name]))) if n else None
    return {
        "mode": run.mode,
        "simulated_s": n * run.loop_time,
        "aborted": run.trip is not None,
        "abort_reason": trip_text(run),
        "trip": None
        if run.trip is None
        else {"limit": run.trip.limit, "time_s": run.trip.time_s, "value": run.trip.value},
        "spectral_error_0p25_15hz": m.get("spectral_error_low"),
        "spectral_error_15_50hz": m.get("spectral_error_high"),
        "nrms_error": m.get("nrms_error"),
        "peak_error": m.get("peak_error"),
        "energy_error": m.get("energy_error"),
        "peak_table_accel_g": None if not n else in_s2_to_g(peak("z_meas")),
        "peak_target_accel_g": None if not n else in_s2_to_g(peak("z_vs")),
        "peak_table_disp_in": peak("x") if n else None,
    }


def write_run_file(
    run: RunResult,
    path: Path,
    summary: Mapping[str, Any],
    arrays: Mapping[str, Mapping[str, np.ndarray]] | None = None,
) -> Path:
    """Write the lab's run file plus the command's summary, atomically (``lab.results.save_run``).

    The summary is the root attribute :data:`SUMMARY_ATTR` (JSON, NaN as
    null); ``arrays`` are subgroups of the group :data:`SUMMARY_GROUP`.
    """
    groups = {SUMMARY_GROUP: dict(arrays)} if arrays else None
    return save_run(
        run, path, extra_attrs={SUMMARY_ATTR: json.dumps(json_safe(summary))}, extra_groups=groups
    )


def read_summary(path: Path) -> tuple[dict | None, dict]:
    """The summary and arrays an ``imil`` command stored in a run file (``(None, {})`` for others)."""
    try:
        with h5py.File(path, "r") as fh:
            if SUMMARY_ATTR not in fh.attrs:
                return None, {}
            group = fh.get(SUMMARY_GROUP, {})
            arrays = {
                name: {key: np.asarray(data) for key, data in sub.items()}
                for name, sub in group.items()
                if isinstance(sub, h5py.Group)
            }
            return json.loads(fh.attrs[SUMMARY_ATTR]), arrays
    except (OSError, ValueError) as exc:
        raise DataFileError(path, f"cannot read the run summary ({exc})") from None


# ------------------------------------------------------------------ printing
def design_lines(design) -> list[str]:
    """The design summary, the verdicts of constraints I, II, III at the design cut-off, and its notes.

    The design's notes that only repeat a violated verdict are left out.
    """
    criteria = DesignCriteria()
    c = design.constraint_at(design.fc_hz)
    mark = {True: "satisfied", False: "VIOLATED"}
    lo, hi = criteria.band_hz
    return [
        f"{design.form} controller (u = H_uz*{design.reference} + H_uw*w), f_c = {design.fc_hz:g} Hz, "
        f"{design.filter.family} filters of order {design.filter.order_z} (z) / {design.filter.order_w} (w), "
        f"loop time {design.loop_time_s * 1e6:g} us",
        f"  constraint I   performance: error {c.performance_error:.3f} over {lo:g}-{hi:g} Hz "
        f"(limit {criteria.performance_max:.3f})  {mark[bool(c.I)]}",
        f"  constraint II  effort: high/low-frequency gain ratio {c.effort_ratio:.3g} "
        f"(limit {criteria.effort_ratio_max:g})  {mark[bool(c.II)]}",
        f"  constraint III passivity: margin {c.passivity_margin_deg:.2f} deg, "
        f"{c.passivity_tolerant_margin_deg:.2f} deg with the delay-model tolerance  {mark[bool(c.III)]}",
    ] + [f"  note: {text}" for text in design.warnings if "violated at" not in text]


def percent(value: float | None) -> str:
    """A fraction as ``"5.36 %"`` (``"n/a"`` for None)."""
    return "n/a" if value is None else f"{100.0 * value:.2f} %"


#: Progress and warnings go to stderr, so that stdout stays machine-readable.
err_console = Console(stderr=True, highlight=False, soft_wrap=True)


@contextmanager
def activity(enabled: bool, text: str, total: int | None = None) -> Iterator:
    """A spinner (``total=None``) or a bar on stderr while the library works.

    Yields ``step(description, advance=0)``.  The compiled loop of the lab has
    no progress callback, so a single run shows an indeterminate spinner with
    the elapsed time; loops over several runs show a bar.
    """
    if not enabled:
        yield lambda description=None, advance=0: None
        return
    columns = [SpinnerColumn(), TextColumn("{task.description}")]
    if total is not None:
        columns += [BarColumn(), MofNCompleteColumn()]
    columns.append(TimeElapsedColumn())
    with Progress(*columns, console=err_console, transient=True) as progress:
        task = progress.add_task(text, total=total)

        def step(description: str | None = None, advance: int = 0) -> None:
            progress.update(task, description=description or progress.tasks[0].description, advance=advance)

        yield step
