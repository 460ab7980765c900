"""`imil simulate`, `imil track`, `imil frf`: the report's experiments in the virtual lab.

* ``imil simulate``: a MIL run (Section 9): the table imitates a virtual
  isolation system (``--vs``) under a ground motion, with the standardized
  controller (Section 6).
* ``imil track``: acceleration tracking (Section 8, Eq 1-6): the table
  reproduces the ground motion under the test article.
* ``imil frf``: the multisine test of Section 4.5 and the identification of
  omega_oil, zeta_oil and d; ``--kp-study`` repeats it for several K_p.

Defaults are the report's configuration (see :mod:`impedance_mil.cli.runopts`).
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

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import typer

from ..config import parse_overrides, quantity
from ..errors import ConfigError
from ..lab import ControlledRun, FrfExperiment, kp_study, run_frf, run_mil, run_tracking
from ..plant import TableParameters
from ..signals.multisine import report_multisine
from ..virtual import presets
from ..virtual.files import VSSpec, resolve
from .common import console, positive_numbers, print_json, table_parameters
from .motion import SOURCE_HELP, UNITS_HELP
from .report_cmd import MODEL_LOOP, model_loop, write_report
from .runopts import (
    DEFAULT_FC_HZ,
    DEFAULT_MOTION,
    DEFAULT_TIME_SCALE,
    EXIT_ABORTED,
    EXIT_INTERRUPTED,
    SPECIMEN_HELP,
    MotionChoice,
    Pretest,
    SpecimenChoice,
    Written,
    activity,
    check_choice,
    design_lines,
    enforce_pretest,
    err_console,
    feedback_choice,
    motion_choice,
    output_path,
    percent,
    pretest,
    run_summary,
    specimen_choice,
    trip_text,
    write_run_file,
)

TableOpt = typer.Option(None, "--table", help="Table file (TOML with units); default report Table 4.1.")
SetOpt = typer.Option(None, "--set", help="Table value KEY=VALUE (repeatable), e.g. Kp=0.0006.")
SpecimenOpt = typer.Option("vessel", "--specimen", help=SPECIMEN_HELP)
WaterOpt = typer.Option(None, "--water-depth", help="Water in the vessel [in] (default 36; '0.9 m' works).")
WeightOpt = typer.Option(None, "--specimen-weight", help="Weight of --specimen rigid [lbf] (default 3600).")
MotionOpt = typer.Option(DEFAULT_MOTION, "--motion", help=SOURCE_HELP)
UnitsOpt = typer.Option("g", "--units", help=UNITS_HELP)
TimeScaleOpt = typer.Option(
    DEFAULT_TIME_SCALE, "--time-scale", help="Compress time by this factor (t' = t/F; report Section 8.2: 2)."
)
PgaOpt = typer.Option(
    None,
    "--pga",
    help="Scale to this PGA [g]; default for elcentro: 0.8 (Table 8.1, GM1); other motions: as recorded.",
)
DurationOpt = typer.Option(None, "--duration", help="Run only the first S seconds of the scaled motion [s].")
FcOpt = typer.Option(DEFAULT_FC_HZ, "--fc", help="Filter cut-off [Hz] (report: 80).")
PrecisionOpt = typer.Option("single", "--precision", help="Controller arithmetic: single (RMC75E) or double.")
SeedOpt = typer.Option(0, "--seed", help="Sensor-noise seed (non-negative integer).")
OutOpt = typer.Option(..., "-o", "--output", help="Run file to write (HDF5).")
ReportOpt = typer.Option(None, "--report", help="Also write the HTML report of the run.")
JsonOpt = typer.Option(False, "--json", help="Print the result as JSON (no progress display).")
ForceOpt = typer.Option(
    False, "--force", help="Run a motion that exceeds the table's limits (the interlocks will stop it)."
)
OverwriteOpt = typer.Option(False, "--overwrite", help="Replace existing output files.")

#: Bands of the FRF model error [Hz]: the identification band, and the oil-column band (Figure 4.16).
FRF_BANDS_HZ = {"model_error_0p25_100hz": (0.25, 100.0), "model_error_10_50hz": (10.0, 50.0)}
#: K_p values of Sections 4.5.3.1 and 8.3.3 [V/psi].
REPORT_KP_VALUES = "0.0002,0.0006,0.001,0.0014"
#: Delay treatments of the linear model (plant.LinearTable).
DELAYS = ("none", "first-order", "pade", "sampled")


@dataclass(frozen=True)
class ControlledRequest:
    """A tracking or MIL run, resolved from the command line.

    Attributes
    ----------
    params : TableParameters
        Table model (the virtual table is derived from it).
    specimen : SpecimenChoice
    motion : MotionChoice
    vs_spec : VSSpec or None
        The virtual system; None for tracking.
    fc_hz : float
        Filter cut-off [Hz].
    feedback : str
        ``lc``, ``fe`` or ``none`` (tracking without u_w).
    precision : str
        ``single`` or ``double``.
    seed : int
        Sensor-noise seed.
    """

    params: TableParameters
    specimen: SpecimenChoice
    motion: MotionChoice
    vs_spec: VSSpec | None
    fc_hz: float
    feedback: str
    precision: str
    seed: int

    @property
    def kind(self) -> str:
        return "track" if self.vs_spec is None else "mil"

    def describe(self) -> dict:
        """The request as plain data (for the JSON output and the run file's summary)."""
        return {
            "kind": self.kind,
            "vs": None if self.vs_spec is None else self.vs_spec.name,
            "specimen": self.specimen.label,
            "specimen_weight_lbf": self.specimen.weight_lbf,
            "motion": self.motion.to_dict(),
            "fc_hz": self.fc_hz,
            "feedback": self.feedback,
            "precision": self.precision,
            "seed": self.seed,
        }


@dataclass
class Outcome:
    """What a controlled run produced: the lab result, the pre-test check, warnings and files."""

    request: ControlledRequest
    pre: Pretest | None = None
    warnings: list[str] = field(default_factory=list)
    result: ControlledRun | None = None
    document: dict = field(default_factory=dict)
    written: Written = field(default_factory=Written)
    elapsed_s: float = 0.0


def build_request(
    *,
    vs: str | None,
    table,
    sets,
    specimen,
    water_depth,
    specimen_weight,
    sets_vs,
    motion,
    units,
    time_scale,
    pga,
    duration,
    fc,
    feedback,
    precision,
    seed,
) -> ControlledRequest:
    """Resolve and validate every option (raises ImilError naming the option)."""
    params = table_parameters(table, sets)
    feedback_choice(feedback, allow_none=vs is None)
    check_choice("--precision", precision, ("single", "double"))
    if seed < 0:
        raise ConfigError("--seed", "a non-negative integer", seed)
    vs_spec = resolve(vs, parse_overrides(sets_vs, option="--set-vs")) if vs is not None else None
    return ControlledRequest(
        params,
        specimen_choice(specimen, water_depth, specimen_weight),
        motion_choice(motion, units, time_scale, pga, duration),
        vs_spec,
        quantity("--fc", fc, "hertz", "positive"),
        feedback,
        precision,
        seed,
    )


def execute(request: ControlledRequest) -> ControlledRun:
    """Design the controller and run the loop (``lab.experiments.run_tracking`` / ``run_mil``)."""
    channel, compensate = feedback_choice(request.feedback, allow_none=request.vs_spec is None)
    common = dict(
        specimen=request.specimen.specimen,
        fc_hz=request.fc_hz,
        feedback=channel,
        precision=request.precision,
        seed=request.seed,
    )
    if request.vs_spec is None:
        return run_tracking(request.params, request.motion.motion, compensate=compensate, **common)
    return run_mil(request.params, request.vs_spec.vs, request.motion.motion, **common)


def check(outcome: Outcome, *, force: bool) -> None:
    """Pre-test check of ``outcome.request`` (refuses a motion over the limits unless ``force``)."""
    request = outcome.request
    vs = None if request.vs_spec is None else request.vs_spec.vs
    outcome.pre = pretest(request.params, request.specimen, request.motion.motion, vs)
    outcome.warnings = enforce_pretest(outcome.pre, request.motion, force)


def perform(outcome: Outcome, out: Path, report: Path | None, *, quiet: bool) -> Outcome:
    """Run the checked ``outcome.request``, then write the run file (and the report).

    ``outcome`` is filled in as the work proceeds, so that after an interrupt
    it says which files were already written.
    """
    request = outcome.request
    loops = int(round(request.motion.motion.duration / request.params.loop_time))
    start = time.perf_counter()
    with activity(
        not quiet,
        f"{request.kind}: designing and running {request.motion.motion.duration:.2f} s (about {loops} loops)",
    ) as step:
        result = execute(request)
        outcome.elapsed_s = time.perf_counter() - start
        outcome.result = result
        doc = {
            **request.describe(),
            **run_summary(result.run, result.metrics),
            "pretest": outcome.pre.to_dict(),
            "warnings": outcome.warnings,
            "design": {
                "form": result.design.form,
                "fc_hz": result.design.fc_hz,
                "constraints": result.design.constraint_at(result.design.fc_hz).to_dict(),
                "notes": list(result.design.warnings),
            },
        }
        loop = {} if request.vs_spec is None else model_loop(result.run, request.vs_spec.vs)
        step(f"writing {out}")
        outcome.written.paths.append(
            write_run_file(result.run, out, doc, {MODEL_LOOP: loop} if loop else None)
        )
        if report is not None:
            step(f"writing {report}")
            outcome.written.paths.append(write_report(result.run, doc, report, loop=loop))
    outcome.document = {**doc, "file": str(out), "report": None if report is None else str(report)}
    return outcome


def print_outcome(outcome: Outcome) -> None:
    """The run on the terminal: configuration, pre-test check, design verdicts, status, metrics, files."""
    say = lambda text: console.print(text, markup=False)  # noqa: E731  (units like [g] stay literal)
    req, doc, pre = outcome.request, outcome.document, outcome.pre
    gm = req.motion.motion
    head = "MIL run, VS " + req.vs_spec.name if req.vs_spec is not None else "tracking run"
    say(
        f"{head}: {gm.name}, time-compressed x{req.motion.time_scale:g}, PGA {gm.pga_g:.3f} g, "
        f"{gm.duration:.2f} s"
    )
    say(
        f"  specimen: {req.specimen.label}; feedback: {req.feedback}; f_c {req.fc_hz:g} Hz; "
        f"{req.precision} precision; seed {req.seed}"
    )
    checks = ", ".join(f"{c.name} {c.peak:.4g}/{c.limit:.4g} {c.unit}" for c in pre.input.checks)
    say(f"pre-test check of the input motion: {checks}: {'fits' if pre.input.ok else 'EXCEEDS'}")
    if pre.basemat is not None:
        checks = ", ".join(f"{c.name} {c.peak:.4g}/{c.limit:.4g} {c.unit}" for c in pre.basemat.checks)
        say(
            f"predicted VS basemat motion against the interlocks: {checks}: "
            f"{'fits' if pre.basemat.ok else 'EXCEEDS'}"
        )
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
    if doc["spectral_error_0p25_15hz"] is None:
        say("  no metrics (the run stopped before 1 s)")
    else:
        say(
            f"  spectral error (5% PSA, table vs target): 0.25-15 Hz {percent(doc['spectral_error_0p25_15hz'])}, "
            f"15-50 Hz {percent(doc['spectral_error_15_50hz'])}"
        )
        energy = "" if doc["energy_error"] is None else f", energy error {percent(doc['energy_error'])}"
        say(f"  NRMS error {percent(doc['nrms_error'])}, peak error {percent(doc['peak_error'])}{energy}")
    if doc["peak_table_accel_g"] is not None:
        say(
            f"  peak table acceleration {doc['peak_table_accel_g']:.3f} g (target "
            f"{doc['peak_target_accel_g']:.3f} g), peak table displacement {doc['peak_table_disp_in']:.3f} in"
        )
    for path in outcome.written.paths:
        say(f"wrote {path}")


def warn(lines: list[str]) -> None:
    """Warnings on stderr, one line each."""
    for line in lines:
        err_console.print(f"imil: warning: {line}", markup=False)


def run_command(
    request: ControlledRequest,
    output: Path,
    report: Path | None,
    *,
    force: bool,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Shared body of ``simulate`` and ``track``: check outputs, perform, print, exit status."""
    out = output_path("-o", output, overwrite)
    page = output_path("--report", report, overwrite)
    if page is not None and page.resolve() == out.resolve():
        raise ConfigError("--report", "a path other than the run file (-o)", str(report))
    outcome = Outcome(request)
    check(outcome, force=force)
    warn(outcome.warnings)
    try:
        perform(outcome, out, page, quiet=as_json)
    except KeyboardInterrupt:
        kept = ", ".join(str(p) for p in outcome.written.paths) or "nothing written"
        err_console.print(f"imil: interrupted ({kept})", markup=False)
        raise typer.Exit(EXIT_INTERRUPTED) from None
    if as_json:
        print_json(outcome.document)
    else:
        print_outcome(outcome)
    if outcome.document["aborted"]:
        raise typer.Exit(EXIT_ABORTED)


def simulate(
    table: Path | None = TableOpt,
    specimen: str = SpecimenOpt,
    water_depth: str | None = WaterOpt,
    specimen_weight: str | None = WeightOpt,
    vs: str = typer.Option(
        "SD2", "--vs", help="VS preset (" + ", ".join(presets.names()) + ") or VS file (TOML)."
    ),
    sets: list[str] | None = SetOpt,
    sets_vs: list[str] | None = typer.Option(None, "--set-vs", help="VS value KEY=VALUE (repeatable)."),
    motion: str = MotionOpt,
    units: str = UnitsOpt,
    time_scale: float = TimeScaleOpt,
    pga: float | None = PgaOpt,
    duration: float | None = DurationOpt,
    fc: float = FcOpt,
    feedback: str = typer.Option(
        "lc", "--feedback", help="Source of w: lc (load cells) or fe (force equilibrium, Section 8.3.2)."
    ),
    precision: str = PrecisionOpt,
    seed: int = SeedOpt,
    output: Path = OutOpt,
    report: Path | None = ReportOpt,
    as_json: bool = JsonOpt,
    force: bool = ForceOpt,
    overwrite: bool = OverwriteOpt,
) -> None:
    """MIL run: the table imitates a virtual isolation system under a ground motion (Section 9)."""
    request = build_request(
        vs=vs,
        table=table,
        sets=sets,
        specimen=specimen,
        water_depth=water_depth,
        specimen_weight=specimen_weight,
        sets_vs=sets_vs,
        motion=motion,
        units=units,
        time_scale=time_scale,
        pga=pga,
        duration=duration,
        fc=fc,
        feedback=feedback,
        precision=precision,
        seed=seed,
    )
    run_command(request, output, report, force=force, overwrite=overwrite, as_json=as_json)


def track(
    table: Path | None = TableOpt,
    specimen: str = SpecimenOpt,
    water_depth: str | None = WaterOpt,
    specimen_weight: str | None = WeightOpt,
    sets: list[str] | None = SetOpt,
    motion: str = MotionOpt,
    units: str = UnitsOpt,
    time_scale: float = TimeScaleOpt,
    pga: float | None = PgaOpt,
    duration: float | None = DurationOpt,
    fc: float = FcOpt,
    feedback: str = typer.Option(
        "lc",
        "--feedback",
        help="Source of w: lc (load cells), fe (force equilibrium) or none (u_w = 0); Section 8.3.2.",
    ),
    precision: str = PrecisionOpt,
    seed: int = SeedOpt,
    output: Path = OutOpt,
    report: Path | None = ReportOpt,
    as_json: bool = JsonOpt,
    force: bool = ForceOpt,
    overwrite: bool = OverwriteOpt,
) -> None:
    """Acceleration tracking: the table reproduces the ground motion under the specimen (Section 8)."""
    request = build_request(
        vs=None,
        table=table,
        sets=sets,
        specimen=specimen,
        water_depth=water_depth,
        specimen_weight=specimen_weight,
        sets_vs=None,
        motion=motion,
        units=units,
        time_scale=time_scale,
        pga=pga,
        duration=duration,
        fc=fc,
        feedback=feedback,
        precision=precision,
        seed=seed,
    )
    run_command(request, output, report, force=force, overwrite=overwrite, as_json=as_json)


def kp_list(text: str) -> list[float]:
    """``"0.0002,0.001"`` -> positive K_p values [V/psi]."""
    return positive_numbers(
        "--kp-values", text, "comma-separated K_p values in V/psi", "positive K_p values in V/psi"
    )


def identified(exp: FrfExperiment) -> dict:
    """omega_oil [rad/s], f_oil [Hz], zeta_oil, d and the misfit identified from z/u (bare table)."""
    if exp.identification is None:
        return {}
    p = exp.identification.parameters
    return {
        "omega_oil_rad_s": p.omega_oil,
        "f_oil_hz": p.f_oil_hz,
        "zeta_oil": p.zeta_oil,
        "d": p.d,
        "identification_error": exp.identification.rms_log_error,
    }


def kp_row(kp: float, exp: FrfExperiment) -> dict:
    """One row of the K_p study: identified parameters and misfit (None after a trip, with the reason)."""
    ident = identified(exp)
    return {
        "Kp": kp,
        **{key: ident.get(key) for key in ("omega_oil_rad_s", "f_oil_hz", "zeta_oil", "d")},
        "misfit": ident.get("identification_error"),
        "abort_reason": trip_text(exp.run),
    }


def frf_document(exp: FrfExperiment, spec: SpecimenChoice, params: TableParameters, kps, study) -> dict:
    """The JSON / stored summary of an FRF experiment (no FRF figures after a trip)."""
    ms = exp.multisine
    f = ms.frequencies_hz
    errors = (
        {name: exp.model_error("z", band) for name, band in FRF_BANDS_HZ.items()} if exp.completed else {}
    )
    return {
        "kind": "frf",
        "specimen": spec.label,
        "specimen_weight_lbf": spec.weight_lbf,
        "simulated_s": exp.run.n_samples * exp.run.loop_time,
        "aborted": not exp.completed,
        "abort_reason": trip_text(exp.run),
        "multisine": {
            "peak_in": float(np.max(np.abs(ms.period))),
            "lines": int(ms.lines.size),
            "f_min_hz": float(f.min()),
            "f_max_hz": float(f.max()),
            "period_s": ms.n_points / ms.sample_rate_hz,
            "n_periods": ms.n_periods,
            "crest_factor": ms.crest_factor,
        },
        "delay": exp.delay,
        "seed": exp.run.config.get("seed"),
        **identified(exp),
        **errors,
        "table_file": {
            "omega_oil_rad_s": params.omega_oil,
            "f_oil_hz": params.f_oil_hz,
            "zeta_oil": params.zeta_oil,
            "d": params.d,
            "Kp": params.Kp,
        },
        "kp_study": [kp_row(kp, e) for kp, e in zip(kps, study)],
    }


def frf_arrays(exp: FrfExperiment, doc: dict) -> dict:
    """Arrays stored with an FRF run: the z/u FRF and the model (none after a trip), and the K_p study.

    In ``kp_study`` a run stopped by an interlock has NaN parameters and misfit.
    """
    arrays = {}
    if exp.completed:
        z = exp.frf["z"]
        arrays["frf"] = {
            "f_hz": z.frequency_hz,
            "H_zu_measured": z.response,
            "H_zu_model": exp.model["z"],
            "coherence_zu": z.coherence,
        }
    if doc["kp_study"]:
        arrays["kp_study"] = {
            key: np.array([row[key] for row in doc["kp_study"]], dtype=float)
            for key in ("Kp", "f_oil_hz", "zeta_oil", "d", "misfit")
        }
    return arrays


def print_frf(doc: dict, path: Path) -> None:
    """The FRF experiment on the terminal."""
    say = lambda text: console.print(text, markup=False)  # noqa: E731
    ms, ref = doc["multisine"], doc["table_file"]
    say(
        f"frf: multisine of {ms['lines']} lines {ms['f_min_hz']:.3g}-{ms['f_max_hz']:.4g} Hz, "
        f"{ms['peak_in']:.3g} in peak, {ms['n_periods']} x {ms['period_s']:.4g} s; {doc['specimen']}"
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
    specimen: str = typer.Option("none", "--specimen", help=SPECIMEN_HELP + " Identification needs none."),
    water_depth: str | None = WaterOpt,
    specimen_weight: str | None = WeightOpt,
    sets: list[str] | None = SetOpt,
    peak: str = typer.Option(
        "0.1", "--peak", help="Peak of the multisine position command [in] (Section 4.5.2)."
    ),
    delay: str = typer.Option(
        "first-order",
        "--delay",
        help="Delay model of the linear model compared and identified: " + ", ".join(DELAYS) + ".",
    ),
    seed: int = SeedOpt,
    kp_study_flag: bool = typer.Option(
        False, "--kp-study", help="Repeat the test and identification for each --kp-values (bare table)."
    ),
    kp_values: str = typer.Option(REPORT_KP_VALUES, "--kp-values", help="K_p values of the study [V/psi]."),
    output: Path = OutOpt,
    as_json: bool = JsonOpt,
    overwrite: bool = OverwriteOpt,
) -> None:
    """Multisine test of the table (Section 4.5): FRFs, identified omega_oil, zeta_oil, d, model error.

    A run stopped by a safety interlock is written up to the trip (no FRF, no K_p study) and exits 3.
    """
    params = table_parameters(table, sets)
    spec = specimen_choice(specimen, water_depth, specimen_weight)
    amplitude = quantity("--peak", peak, "inch", "positive")
    check_choice("--delay", delay, DELAYS)
    if seed < 0:
        raise ConfigError("--seed", "a non-negative integer", seed)
    kps = kp_list(kp_values) if kp_study_flag else []
    if kps and spec.specimen is not None:
        raise ConfigError(
            "--kp-study", "--specimen none (the identification is of the bare table, Section 4.5.3)", specimen
        )
    out = output_path("-o", output, overwrite)
    multisine = report_multisine(params.loop_time, peak=amplitude)
    try:
        with activity(not as_json, "frf: multisine test and identification", total=1 + len(kps)) as step:
            exp = run_frf(
                params,
                multisine=multisine,
                specimen=spec.specimen,
                delay=delay,
                identify=spec.specimen is None,
                seed=seed,
            )
            if not exp.completed:
                kps = []
            study = []
            for kp in kps:
                step(f"K_p study: K_p = {kp:g} V/psi", advance=1)
                study.append(
                    kp_study(params, (kp,), multisine=multisine, delay=delay, seed=seed).experiments[0]
                )
            step(f"writing {out}", advance=1)
            doc = frf_document(exp, spec, params, kps, study)
            write_run_file(exp.run, out, doc, frf_arrays(exp, doc))
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
        print_json({**doc, "file": str(out)})
    else:
        print_frf(doc, out)
    if doc["aborted"]:
        raise typer.Exit(EXIT_ABORTED)
