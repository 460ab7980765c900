"""`imil simulate`, `imil track`, `imil frf`: the report's experiments in the virtual lab.

* ``imil simulate``: a MIL run (Section 9): the table imitates a virtual
  isolation system (``--vs``) under a ground motion, with the standardized
  controller (Section 6).
* ``imil track``: acceleration tracking (Section 8, Eq 1-6): the table
  reproduces the ground motion under the test article.
* ``imil frf``: the multisine test of Section 4.5 and the identification of
  omega_oil, zeta_oil and d; ``--kp-study`` repeats it for several K_p.

An option left out takes the report's value from the report's setup file
(``impedance_mil/data/report/config.toml``, read by
:mod:`impedance_mil.lab.choices`); the JSON lists each such value under
``from_report``.  The experiment is the library's
(:mod:`impedance_mil.lab.descriptions`): this module parses, calls and prints.
Before a controlled run the motion is checked against the table's limits
with the specimen on it (Section 8.2); a motion over a limit is refused
unless ``--force``.  For a MIL run the VS basemat motion the table will
have to follow is predicted too (specimen taken as rigid) and a warning
says when it exceeds a limit.

Exit status: 0 for a completed run; 3 when a safety interlock stopped the
run (its data up to the trip are written, and the trip is stated on the
terminal, in the JSON and in the file); 2 for bad input or a refused motion
(one line on stderr, nothing written); 130 after Ctrl-C.
"""

from __future__ import annotations

import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..config import parse_overrides
from ..design.robust import RobustMargins
from ..display import UnitSystem, display_unit, format_value
from ..errors import ConfigError
from ..lab.choices import Choices, frf_test, mil_test, tracking_test
from ..lab.compile_aside import kernels_compiled_aside
from ..lab.descriptions import (
    FRF_DELAYS,
    REQUIRED_CONSTRAINTS,
    FrfTest,
    MilTest,
    TrackingTest,
    parse_required,
)
from ..lab.experiments import ControlledRun
from ..lab.first_run import COMPILING_NOTICE, compile_progress, kernels_need_compiling
from ..lab.pretest import Pretest
from ..lab.results import RUN_FILE_SUFFIXES
from ..lab.robust import require_uncertainty, test_robustness
from ..lab.run_stream import RunFileStream
from ..lab.runfile import MODEL_LOOP, finish_run_file, trip_text, write_run_file
from ..lazy import LazyModule
from ..report_config import report_config
from ..virtual import presets
from .common import UnitsOpt, console, output_units, positive_numbers, print_json
from .motion import SOURCE_HELP, UNITS_HELP
from .runopts import (
    CHOICE_OPTIONS,
    EXIT_ABORTED,
    EXIT_INTERRUPTED,
    SPECIMEN_HELP,
    Written,
    activity,
    design_lines,
    err_console,
    metric_lines,
    output_path,
    refuse_or_warn,
    report_defaults_line,
)

if TYPE_CHECKING:
    from ..campaign.engine import ProgressEvent

#: The robust campaign (``simulate --robust``), imported when used: the campaign engine brings
#: its executors and summaries, which a plain run does not need (issue 16).
robust_campaigns = LazyModule("impedance_mil.campaign.robust")
#: The HTML page of a run (``--report``), imported when asked for: it brings matplotlib (0.3 s).
run_pages = LazyModule("impedance_mil.report.runpage")

_REPORT = report_config()
_GM = _REPORT.default_motion
_KP_TEXT = ",".join(f"{kp:g}" for kp in _REPORT.frf.kp_values)

TableOpt = typer.Option(
    None,
    "--table",
    help="Table file (TOML with units): a lab with only a table (generic defaults for the rest).",
)
LabOpt = typer.Option(
    None,
    "--lab",
    help="Lab file (TOML: table, limits, sensors, controller, specimen) or 'report' (the default).",
)
SetOpt = typer.Option(None, "--set", help="Table value KEY=VALUE (repeatable), e.g. Kp=0.0006.")
SpecimenOpt = typer.Option(
    None, "--specimen", help=SPECIMEN_HELP + f" Default the report's: {_REPORT.specimen.kind}."
)
WaterOpt = typer.Option(
    None,
    "--water-depth",
    help=f"Water in the vessel [in] (default the report's {_REPORT.specimen.water_depth_in:g}; '0.9 m' works).",
)
WeightOpt = typer.Option(
    None,
    "--specimen-weight",
    help=f"Weight of --specimen rigid [lbf] (default the report's article, {_REPORT.specimen.article_weight_lbf:g}).",
)
MotionOpt = typer.Option(
    None,
    "--motion",
    help=SOURCE_HELP + f" Default the report's {_GM.name}: {_GM.builtin_substitute} (RSN {_GM.rsn}).",
)
MotionUnitsOpt = typer.Option(None, "--motion-units", help=UNITS_HELP)
TimeScaleOpt = typer.Option(
    None,
    "--time-scale",
    help=f"Compress time by this factor (t' = t/F); default the report's {_REPORT.motion.time_scale:g} "
    f"for the report's {_GM.name} (no --motion, Section 8.2), else 1 (the motion as recorded).",
)
PgaOpt = typer.Option(
    None,
    "--pga",
    help=f"Scale to this PGA [g]; default for {_GM.builtin_substitute}: {_GM.pga_scaled_g:g} (Table 8.1, {_GM.name}); "
    "other motions: as recorded.",
)
DurationOpt = typer.Option(None, "--duration", help="Run only the first S seconds of the scaled motion [s].")
FcOpt = typer.Option(
    None, "--fc", help=f"Filter cut-off [Hz] (default the report's {_REPORT.design.fc_hz:g})."
)
PrecisionOpt = typer.Option(
    None,
    "--precision",
    help=f"Controller arithmetic: single (RMC75E) or double (default the report's {_REPORT.controller.precision}).",
)
SeedOpt = typer.Option(0, "--seed", help="Sensor-noise seed (non-negative integer).")
OutOpt = typer.Option(..., "-o", "--output", help="Run file to write (HDF5).")
ReportOpt = typer.Option(None, "--report", help="Also write the HTML report of the run.")
JsonOpt = typer.Option(False, "--json", help="Print the result as JSON (no progress display).")
ForceOpt = typer.Option(
    False,
    "--force",
    help="Run a motion that exceeds the table's limits, or a design that violates a required "
    "constraint (the interlocks will stop it).",
)
RequireOpt = typer.Option(
    ",".join(REQUIRED_CONSTRAINTS),
    "--require",
    help="Constraints the design must satisfy before it runs: I, II, III (comma-separated), all or none.",
)
OverwriteOpt = typer.Option(False, "--overwrite", help="Replace existing output files.")
DesignOpt = typer.Option(
    None,
    "--design",
    help="Design file (JSON, imil design -o) to run as designed: its controller, cut-off and VS "
    "(refused for another table unless --force).",
)


def choices(**options) -> Choices:
    """The run choices of the options (``--set``/``--set-vs`` parsed; None: not chosen)."""
    sets, sets_vs = options.pop("sets", None), options.pop("sets_vs", None)
    return Choices(
        table_overrides=parse_overrides(sets),
        vs_overrides=parse_overrides(sets_vs, option="--set-vs"),
        keys=CHOICE_OPTIONS,
        **options,
    )


@dataclass
class Outcome:
    """What a controlled run produced: the test, its pre-test check, warnings, result and files."""

    test: TrackingTest
    pre: Pretest | None = None
    warnings: list[str] = field(default_factory=list)
    result: ControlledRun | None = None
    document: dict = field(default_factory=dict)
    written: Written = field(default_factory=Written)
    elapsed_s: float = 0.0
    robust: RobustMargins | None = None


def check(outcome: Outcome, *, force: bool, required: tuple[str, ...] = REQUIRED_CONSTRAINTS) -> None:
    """Pre-test check of ``outcome.test``: refuses a motion over the limits, or a design that
    violates a ``required`` constraint, unless ``force``."""
    test = outcome.test
    outcome.pre = test.pretest()
    outcome.warnings = refuse_or_warn(outcome.pre.findings(test.motion.motion, test.motion.time_scale), force)
    outcome.warnings += test.check_design(required, force)
    if isinstance(test, MilTest):
        outcome.warnings += list(test.vs_spec.notes)
    outcome.robust = test_robustness(test, seed=test.lab.seed)  # None: the lab has no [uncertainty]


def perform(
    outcome: Outcome, out: Path, report: Path | None, *, quiet: bool, units: UnitSystem = UnitSystem.US
) -> Outcome:
    """Run the checked ``outcome.test``, then write the run file (and the report, in ``units``).

    The run file keeps internal units; ``outcome.document`` says why a run stopped in ``units``.

    ``outcome`` is filled in as the work proceeds, so that after an interrupt
    it says which files were already written.
    """
    test = outcome.test
    gm = test.motion.motion
    loops = int(round(gm.duration / test.table.loop_time))
    start = time.perf_counter()
    with (
        activity(
            not quiet, f"{test.kind}: designing and running {gm.duration:.2f} s (about {loops} loops)"
        ) as step,
        RunFileStream(out) as stream,  # the records are written as the run goes; in place at finish
    ):
        result = test.run(sink=stream)
        outcome.elapsed_s = time.perf_counter() - start
        outcome.result = result
        doc = test.summary(result, outcome.pre, tuple(outcome.warnings))
        if outcome.robust is not None:
            doc["pretest"]["robust"] = outcome.robust.to_dict()
        arrays = test.arrays(result)
        step(f"writing {out}")
        outcome.written.paths.append(finish_run_file(stream, result.run, doc, arrays))
        if report is not None:
            step(f"writing {report}")
            outcome.written.paths.append(
                run_pages.write_run_page(result.run, doc, report, loop=arrays.get(MODEL_LOOP), units=units)
            )
    reason = trip_text(result.run, units)
    outcome.document = {
        **doc,
        "abort_reason": reason,
        "file": str(out),
        "report": None if report is None else str(report),
    }
    return outcome


def print_outcome(outcome: Outcome, units: UnitSystem = UnitSystem.US) -> None:
    """The run on the terminal (in ``units``): configuration, pre-test check, design verdicts, status, metrics, files."""
    say = lambda text: console.print(text, markup=False)  # noqa: E731  (units like [g] stay literal)
    test, doc, pre = outcome.test, outcome.document, outcome.pre
    gm = test.motion.motion
    head = "MIL run, VS " + test.vs_name if test.vs_name is not None else "tracking run"
    say(
        f"{head}: {gm.name}, time-compressed x{test.motion.time_scale:g}, PGA {gm.pga_g:.3f} g, "
        f"{gm.duration:.2f} s"
    )
    say(
        f"  specimen: {test.specimen.label}; feedback: {test.controller.feedback.value}; "
        f"f_c {test.controller.fc_hz:g} Hz; {test.controller.precision} precision; seed {test.lab.seed}"
    )
    if test.design_file is not None:
        say(f"  controller: {doc['design_method']} design of {test.design_file}, run as designed")
    say(report_defaults_line(dict(test.from_report)))
    checks = ", ".join(check_text(c, units) for c in pre.input.checks)
    say(f"pre-test check of the input motion: {checks}: {'fits' if pre.input.ok else 'EXCEEDS'}")
    if pre.basemat is not None:
        checks = ", ".join(check_text(c, units) for c in pre.basemat.checks)
        say(
            f"predicted VS basemat motion against the interlocks: {checks}: "
            f"{'fits' if pre.basemat.ok else 'EXCEEDS'}"
        )
    if outcome.robust is not None:
        say("robust stability: " + outcome.robust.line())
    for line in design_lines(outcome.result.design):
        say(line)
    if doc["aborted"]:
        say(
            f"STOPPED by a safety interlock: {doc['abort_reason']}; {doc['simulated_s']:.3f} s of "
            f"{gm.duration:.2f} s simulated, the data up to the trip are kept"
        )
    else:
        say(
            f"completed: {doc['simulated_s']:.2f} s simulated (designed and run in {outcome.elapsed_s:.1f} s)"
        )
    for line in metric_lines(doc, "the run stopped before 1 s"):
        say(line)
    if doc["peak_table_accel_g"] is not None:
        say(
            f"  peak table acceleration {doc['peak_table_accel_g']:.3f} g (target "
            f"{doc['peak_target_accel_g']:.3f} g), peak table displacement "
            f"{format_value(doc['peak_table_disp_in'], 'in', units)}"
        )
    for path in outcome.written.paths:
        say(f"wrote {path}")


def check_text(check, units: UnitSystem) -> str:
    """``stroke 60.5/81.28 mm``: one pre-test check, its peak against its limit, in ``units``."""
    unit = display_unit(check.unit.replace("^", "**"), units)
    return f"{check.name} {unit(check.peak):.4g}/{unit(check.limit):.4g} {unit.name}"


def warn(lines: list[str]) -> None:
    """Warnings on stderr, one line each."""
    for line in lines:
        err_console.print(f"imil: warning: {line}", markup=False)


def run_command(
    test: TrackingTest,
    output: Path,
    report: Path | None,
    *,
    force: bool,
    overwrite: bool,
    as_json: bool,
    require: str = ",".join(REQUIRED_CONSTRAINTS),
    units: UnitSystem = UnitSystem.US,
) -> None:
    """Shared body of ``simulate`` and ``track``: check outputs, perform, print (in ``units``), exit status."""
    out = output_path("-o", output, overwrite, RUN_FILE_SUFFIXES)
    page = output_path("--report", report, overwrite)
    if page is not None and page.resolve() == out.resolve():
        raise ConfigError("--report", "a path other than the run file (-o)", str(report))
    required = parse_required(require)
    outcome = Outcome(test)
    try:
        with notice_compiling():
            check(outcome, force=force, required=required)
            warn(outcome.warnings)
            perform(outcome, out, page, quiet=as_json, units=units)
    except KeyboardInterrupt:
        kept = ", ".join(str(p) for p in outcome.written.paths) or "nothing written"
        err_console.print(f"imil: interrupted ({kept})", markup=False)
        raise typer.Exit(EXIT_INTERRUPTED) from None
    if as_json:
        print_json(outcome.document, units)
    else:
        print_outcome(outcome, units)
    if outcome.document["sensor_clipping_fails"]:
        err_console.print(
            f"imil: error: a sensor clipped and the lab's [sensors] clipping is 'fail' "
            f"({outcome.document['sensor_clipping'][0]['channel']}); the data are kept",
            markup=False,
        )
    if outcome.document["aborted"] or outcome.document["sensor_clipping_fails"]:
        raise typer.Exit(EXIT_ABORTED)


def simulate(
    table: Path | None = TableOpt,
    lab: str | None = LabOpt,
    specimen: str | None = SpecimenOpt,
    water_depth: str | None = WaterOpt,
    specimen_weight: str | None = WeightOpt,
    vs: str | None = typer.Option(
        None,
        "--vs",
        help="VS preset ("
        + ", ".join(presets.names())
        + f") or VS file (TOML); default the report's {_REPORT.vs_preset}.",
    ),
    sets: list[str] | None = SetOpt,
    sets_vs: list[str] | None = typer.Option(None, "--set-vs", help="VS value KEY=VALUE (repeatable)."),
    motion: str | None = MotionOpt,
    motion_units: str | None = MotionUnitsOpt,
    time_scale: float | None = TimeScaleOpt,
    pga: float | None = PgaOpt,
    duration: float | None = DurationOpt,
    fc: float | None = FcOpt,
    design: Path | None = DesignOpt,
    feedback: str | None = typer.Option(
        None,
        "--feedback",
        help="Source of w: lc (load cells) or fe (force equilibrium, Section 8.3.2); "
        f"default the report's {_REPORT.controller.feedback}.",
    ),
    precision: str | None = PrecisionOpt,
    seed: int = SeedOpt,
    output: Path = OutOpt,
    report: Path | None = ReportOpt,
    as_json: bool = JsonOpt,
    force: bool = ForceOpt,
    require: str = RequireOpt,
    overwrite: bool = OverwriteOpt,
    units: str | None = UnitsOpt,
    robust: int | None = typer.Option(
        None,
        "--robust",
        help="Run N labs sampled (Latin hypercube, --seed) from the lab's [uncertainty] set with the "
        "nominal design, as a campaign; report the fraction unstable and save the worst run to -o.",
    ),
) -> None:
    """MIL run: the table imitates a virtual isolation system under a ground motion (Section 9)."""
    chosen = choices(
        vs=vs,
        table=table,
        lab=lab,
        sets=sets,
        specimen=specimen,
        water_depth=water_depth,
        specimen_weight=specimen_weight,
        sets_vs=sets_vs,
        motion=motion,
        motion_units=motion_units,
        time_scale=time_scale,
        pga_g=pga,
        duration=duration,
        fc_hz=fc,
        design=design,
        feedback=feedback,
        precision=precision,
        seed=seed,
    )
    test = mil_test(chosen)
    shown = output_units(units, lab, table)
    if robust is not None:
        run_robust(
            chosen,
            test,
            robust,
            output,
            report,
            force=force,
            overwrite=overwrite,
            as_json=as_json,
            require=require,
            units=shown,
        )
        return
    run_command(
        test, output, report, force=force, overwrite=overwrite, as_json=as_json, require=require, units=shown
    )


def run_robust(
    chosen: Choices,
    test: MilTest,
    n: int,
    output: Path,
    report: Path | None,
    *,
    force: bool,
    overwrite: bool,
    as_json: bool,
    require: str,
    units: UnitSystem,
) -> None:
    """``simulate --robust N``: the pre-test check, then N sampled labs as a campaign; the worst run to ``output``."""
    if n < 1:
        raise ConfigError("--robust", "a positive number of sampled runs", n)
    if report is not None:
        raise ConfigError(
            "--report", "no --report with --robust (imil report draws the worst run's file, -o)"
        )
    require_uncertainty(test.lab.uncertainty, "--robust")
    out = output_path("-o", output, overwrite, RUN_FILE_SUFFIXES)
    outcome = Outcome(test)
    with notice_compiling():
        check(outcome, force=force, required=parse_required(require))
    warn(outcome.warnings)

    def progress(event: ProgressEvent) -> None:
        if not as_json:
            err_console.print(
                f"imil: robust run {event.done}/{event.total}: {event.record.status}", markup=False
            )

    try:
        with tempfile.TemporaryDirectory(prefix="imil-robust-") as folder:
            campaign = robust_campaigns.run_robust_campaign(
                chosen, test, n, test.lab.seed, Path(folder), out, on_progress=progress
            )
    except KeyboardInterrupt:
        err_console.print("imil: interrupted (nothing written)", markup=False)
        raise typer.Exit(EXIT_INTERRUPTED) from None
    pre = outcome.pre.to_dict() if outcome.pre is not None else {}
    if outcome.robust is not None:
        pre["robust"] = outcome.robust.to_dict()
    doc = {**test.describe(), "lab": test.lab.name, "pretest": pre, "warnings": outcome.warnings}
    doc["robust"] = campaign.to_dict()
    if as_json:
        print_json(doc, units)
        return
    say = lambda text: console.print(text, markup=False)  # noqa: E731
    if outcome.robust is not None:
        say("robust stability: " + outcome.robust.line())
    say(
        f"robust campaign: {len(campaign.runs)} labs sampled from the uncertainty set (seed {campaign.seed}), "
        f"nominal design: {campaign.unstable_fraction:.0%} unstable; by cause: "
        + ", ".join(f"{k} {v}" for k, v in campaign.causes().items())
    )
    for run in campaign.runs:
        if run.status == "failed":
            say(f"  {run.run_id}: failed: {run.error}")
    if campaign.worst is not None:
        trip = f"tripped ({campaign.worst.cause.label})" if campaign.worst.unstable else "completed"
        say(f"  worst: {trip} at {', '.join(f'{k} = {v:.4g}' for k, v in campaign.worst.point.items())}")
    if campaign.worst_file is not None:
        say(f"wrote {campaign.worst_file}")


def track(
    table: Path | None = TableOpt,
    lab: str | None = LabOpt,
    specimen: str | None = SpecimenOpt,
    water_depth: str | None = WaterOpt,
    specimen_weight: str | None = WeightOpt,
    sets: list[str] | None = SetOpt,
    motion: str | None = MotionOpt,
    motion_units: str | None = MotionUnitsOpt,
    time_scale: float | None = TimeScaleOpt,
    pga: float | None = PgaOpt,
    duration: float | None = DurationOpt,
    fc: float | None = FcOpt,
    design: Path | None = DesignOpt,
    feedback: str | None = typer.Option(
        None,
        "--feedback",
        help="Source of w: lc (load cells), fe (force equilibrium) or none (u_w = 0); Section 8.3.2; "
        f"default the report's {_REPORT.controller.feedback}.",
    ),
    precision: str | None = PrecisionOpt,
    seed: int = SeedOpt,
    output: Path = OutOpt,
    report: Path | None = ReportOpt,
    as_json: bool = JsonOpt,
    force: bool = ForceOpt,
    require: str = RequireOpt,
    overwrite: bool = OverwriteOpt,
    units: str | None = UnitsOpt,
) -> None:
    """Acceleration tracking: the table reproduces the ground motion under the specimen (Section 8)."""
    test = tracking_test(
        choices(
            table=table,
            lab=lab,
            sets=sets,
            specimen=specimen,
            water_depth=water_depth,
            specimen_weight=specimen_weight,
            motion=motion,
            motion_units=motion_units,
            time_scale=time_scale,
            pga_g=pga,
            duration=duration,
            fc_hz=fc,
            design=design,
            feedback=feedback,
            precision=precision,
            seed=seed,
        )
    )
    shown = output_units(units, lab, table)
    run_command(
        test, output, report, force=force, overwrite=overwrite, as_json=as_json, require=require, units=shown
    )


def kp_list(text: str) -> list[float]:
    """``"0.0002,0.001"`` -> positive K_p values [V/psi]."""
    return positive_numbers(
        "--kp-values", text, "comma-separated K_p values in V/psi", "positive K_p values in V/psi"
    )


def print_frf(doc: dict, path: Path, units: UnitSystem = UnitSystem.US) -> None:
    """The FRF experiment on the terminal (the multisine's peak in ``units``)."""
    say = lambda text: console.print(text, markup=False)  # noqa: E731
    ms, ref = doc["multisine"], doc["table_file"]
    say(
        f"frf: multisine of {ms['lines']} lines {ms['f_min_hz']:.3g}-{ms['f_max_hz']:.4g} Hz, "
        f"{format_value(ms['peak_in'], 'in', units, 3)} peak, {ms['n_periods']} x {ms['period_s']:.4g} s; {doc['specimen']}"
    )
    if "omega_oil_rad_s" in doc:
        say(f"identified from z/u (0.25-100 Hz, {doc['delay']} delay model; report Section 4.3.5):")
        say(
            f"  omega_oil {doc['omega_oil_rad_s']:10.2f} rad/s (f_oil {doc['f_oil_hz']:.3f} Hz)   "
            f"table file: {ref['omega_oil_rad_s']:.2f} rad/s ({ref['f_oil_hz']:g} Hz)"
        )
        say(f"  zeta_oil  {doc['zeta_oil']:10.4f}                        table file: {ref['zeta_oil']:g}")
        say(f"  d         {doc['d']:10.4g}                        table file: {ref['d']:g}")
        say(
            f"  misfit of the identified model {doc['identification_error']:.4f} "
            "(rms |log(H_model/H_meas)|; 0.01 is about 1 % or 0.6 deg)"
        )
    if doc["aborted"]:
        say(
            f"STOPPED by a safety interlock: {doc['abort_reason']}; {doc['simulated_s']:.3f} s of "
            f"{ms['n_periods'] * ms['period_s']:.4g} s simulated, the data up to the trip are kept (no FRF)"
        )
    else:
        say(
            f"model error of the table file's linear model: 0.25-100 Hz {doc['model_error_0p25_100hz']:.4f}, "
            f"10-50 Hz {doc['model_error_10_50hz']:.4f}"
        )
    if doc["kp_study"]:
        say("K_p study (Sections 4.5.3.1, 8.3.3): misfit of the identified model")
        for row in doc["kp_study"]:
            if row["misfit"] is None:
                say(f"  K_p {row['Kp']:8.4g} V/psi: stopped, {row['abort_reason']}")
                continue
            say(
                f"  K_p {row['Kp']:8.4g} V/psi: misfit {row['misfit']:.4f}, f_oil {row['f_oil_hz']:.2f} Hz, "
                f"zeta_oil {row['zeta_oil']:.4f}, d {row['d']:.4g}"
            )
    say(f"wrote {path}")


def frf(
    table: Path | None = TableOpt,
    lab: str | None = LabOpt,
    specimen: str | None = typer.Option(
        None, "--specimen", help=SPECIMEN_HELP + " Default none: identification needs the bare table."
    ),
    water_depth: str | None = WaterOpt,
    specimen_weight: str | None = WeightOpt,
    sets: list[str] | None = SetOpt,
    peak: str | None = typer.Option(
        None,
        "--peak",
        help=f"Peak of the multisine position command [in] (default the report's {_REPORT.frf.peak_in:g}, "
        "Section 4.5.2).",
    ),
    delay: str | None = typer.Option(
        None,
        "--delay",
        help="Delay model of the linear model compared and identified: "
        + ", ".join(FRF_DELAYS)
        + f" (default the report's {_REPORT.frf.delay}).",
    ),
    seed: int = SeedOpt,
    kp_study_flag: bool = typer.Option(
        False, "--kp-study", help="Repeat the test and identification for each --kp-values (bare table)."
    ),
    kp_values: str | None = typer.Option(
        None,
        "--kp-values",
        help="K_p values of the study [V/psi] (default the report's " + _KP_TEXT + ").",
    ),
    output: Path = OutOpt,
    as_json: bool = JsonOpt,
    overwrite: bool = OverwriteOpt,
    units: str | None = UnitsOpt,
) -> None:
    """Multisine test of the table (Section 4.5): FRFs, identified omega_oil, zeta_oil, d, model error.

    A run stopped by a safety interlock is written up to the trip (no FRF, no K_p study) and exits 3.
    """
    test = frf_test(
        choices(
            table=table,
            lab=lab,
            sets=sets,
            specimen=specimen,
            water_depth=water_depth,
            specimen_weight=specimen_weight,
            seed=seed,
        ),
        peak=peak,
        delay=delay,
        kp_values=None if kp_values is None else tuple(kp_list(kp_values)),
        kp_study=kp_study_flag,
    )
    out = output_path("-o", output, overwrite, RUN_FILE_SUFFIXES)
    shown = output_units(units, lab, table)
    try:
        doc = run_frf_test(test, out, quiet=as_json)
    except KeyboardInterrupt:
        err_console.print("imil: interrupted (nothing written)", markup=False)
        raise typer.Exit(EXIT_INTERRUPTED) from None
    if doc["aborted"]:
        err_console.print(
            f"imil: the multisine run was stopped by a safety interlock: {doc['abort_reason']}; "
            f"the data up to the trip are in {out}",
            markup=False,
        )
    if as_json:
        print_json({**doc, "file": str(out)}, shown)
    else:
        print_frf(doc, out, shown)
    if doc["aborted"]:
        raise typer.Exit(EXIT_ABORTED)


@contextmanager
def notice_compiling() -> Iterator[None]:
    """Say on stderr, before a run that compiles the lab's kernels, that it will (first run only), then its progress."""
    if not kernels_need_compiling():
        yield
        return
    err_console.print(f"imil: {COMPILING_NOTICE}", markup=False)
    with (
        compile_progress(lambda line: err_console.print(f"imil: {line}", markup=False)) as progress,
        kernels_compiled_aside(),
    ):
        yield
    if progress.announced:
        err_console.print(
            f"imil: kernels compiled in {progress.seconds:.0f} s (cached: later runs load them)", markup=False
        )


def run_frf_test(test: FrfTest, out: Path, *, quiet: bool) -> dict:
    """Run the FRF test with progress on stderr and write its run file; return its summary."""
    with (
        notice_compiling(),
        activity(not quiet, "frf: multisine test and identification", total=1 + len(test.kp_values)) as step,
    ):
        outcome = test.run(on_step=lambda text: step(text, advance=1))
        step(f"writing {out}", advance=1)
        doc = test.summary(outcome)
        write_run_file(outcome.experiment.run, out, doc, test.arrays(outcome, doc))
    return doc
