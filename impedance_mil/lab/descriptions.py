"""Experiment descriptions: one named, validated value per kind of test (tracking, MIL, FRF).

A description holds everything a run needs (the table, the specimen, the
motion or the multisine, the controller settings, the feedback source, the
precision, the noise seed, the interlocks and the plant substeps) and runs it:

* :class:`TrackingTest` (Section 8) and :class:`MilTest` (Section 9) run
  :func:`~impedance_mil.lab.experiments.run_tracking` /
  :func:`~impedance_mil.lab.experiments.run_mil` and return a
  :class:`~impedance_mil.lab.experiments.ControlledRun`;
  :meth:`TrackingTest.summary` states the test and its metrics under the
  shared names of :mod:`impedance_mil.lab.runfile`;
* :class:`FrfTest` (Section 4.5) runs the multisine test (and the K_p study)
  and returns an :class:`FrfOutcome`; :meth:`FrfTest.summary` and
  :meth:`FrfTest.arrays` are what its run file stores.

``imil simulate``/``track``/``frf`` and the campaign kinds ``mil``/
``tracking``/``frf`` build these descriptions and call the same methods.
:mod:`impedance_mil.lab.choices` turns a user's partial choices into a
description, taking every value the user did not choose from the report's
setup (:mod:`impedance_mil.report_config`) and listing it in
``from_report``.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from ..design import ControllerDesign
from ..errors import ConfigError, DesignRefused
from ..plant import TableParameters
from ..plant.lti_table import LTITable
from ..plant.uncertainty import UncertaintySet
from ..signals import GroundMotion
from ..signals.multisine import report_multisine
from ..specimens import FluidVessel
from ..virtual.files import VSSpec
from .chunks import RecordSink
from .clipping import clipped_channels
from .design_file import table_differences
from .experiments import (
    ControlledRun,
    FrfExperiment,
    kp_study,
    mil_design,
    run_frf,
    run_mil,
    run_tracking,
    tracking_design,
)
from .feedback import Feedback
from .pretest import Pretest, pretest
from .runfile import FRF_GROUP, MODEL_LOOP, model_loop, run_summary, trip_summary, trip_text
from .setup import SafetyLimits, default_sensors

#: Controller arithmetic of the runtime.
PRECISIONS = ("single", "double")
#: Bands of the FRF model error [Hz]: the identification band, and the oil-column band (Figure 4.16).
FRF_BANDS_HZ = {"model_error_0p25_100hz": (0.25, 100.0), "model_error_10_50hz": (10.0, 50.0)}
#: Delay treatments of the linear model an FRF is compared with (plant.LinearTable).
FRF_DELAYS = ("none", "first-order", "pade", "sampled")


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

    @classmethod
    def bare(cls) -> SpecimenChoice:
        """The bare table."""
        return cls(None, "bare table", 0.0)

    @classmethod
    def vessel(cls, water_depth_in: float) -> SpecimenChoice:
        """The report's vessel (Section 3.2) with ``water_depth_in`` [in] of water."""
        vessel = FluidVessel(water_depth_in=water_depth_in)
        label = f"vessel with {water_depth_in:g} in of water ({vessel.total_weight:.0f} lb)"
        return cls(vessel, label, vessel.total_weight)


@dataclass(frozen=True)
class MotionChoice:
    """The input motion of a run, as it will be run (before resampling to the loop time).

    Attributes
    ----------
    motion : GroundMotion
        Scaled (and trimmed) motion [in/s^2].
    argument : str
        What the user named (built-in name, FEMA source, file, or a motion of Table 8.1).
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
class ControllerChoice:
    """Controller settings of a controlled test: cut-off f_c [Hz], feedback source, arithmetic."""

    fc_hz: float
    feedback: Feedback
    precision: str

    def __post_init__(self):
        if not (np.isfinite(self.fc_hz) and self.fc_hz > 0):
            raise ConfigError("fc", "a positive cut-off frequency in Hz", self.fc_hz)
        if self.precision not in PRECISIONS:
            raise ConfigError("precision", "one of " + ", ".join(PRECISIONS), self.precision)


#: Constraints a design must satisfy before ``simulate`` or ``track`` runs it
#: (``--require``): III (passivity) -- a design that violates it is the one
#: the report found unstable on the real table.
REQUIRED_CONSTRAINTS: tuple[str, ...] = ("III",)
CONSTRAINTS = ("I", "II", "III")


def parse_required(text: str) -> tuple[str, ...]:
    """``"III"``, ``"I,II,III"``, ``"all"`` or ``"none"`` as a tuple of constraint names.

    Raises
    ------
    ConfigError
        An unknown constraint name.
    """
    key = text.strip().lower()
    if key == "none":
        return ()
    if key == "all":
        return CONSTRAINTS
    names = tuple(part.strip().upper() for part in text.split(",") if part.strip())
    bad = [n for n in names if n not in CONSTRAINTS]
    if bad or not names:
        raise ConfigError(
            "--require", "constraints among I, II, III (comma-separated), 'all' or 'none'", text
        )
    return names


def design_violations(design: ControllerDesign, required: tuple[str, ...]) -> list[str]:
    """Sentences of the violated constraints of ``design`` at its f_c that are in ``required``."""
    verdict = design.constraint_at(design.fc_hz)
    failed = [name for name in CONSTRAINTS if not getattr(verdict, name)]
    sentence = dict(zip(failed, verdict.violations(), strict=True))  # violations() follows I, II, III
    return [sentence[name] for name in failed if name in required]


@dataclass(frozen=True)
class LabChoice:
    """The virtual lab of a run: interlocks, sensors (None: the lab's Table 7.1 suite), plant substeps, seed,
    what a clipped channel does (``clipping``: warn or fail), the lab's name and the controller's
    output delay [loops]; ``uncertainty``: the lab's ``[uncertainty]`` set (None: none given)."""

    limits: SafetyLimits
    sensors: Any
    substeps: int | str
    seed: int
    clipping: str = "warn"
    name: str = "report"
    output_delay: int = 1
    uncertainty: UncertaintySet | None = field(default=None, compare=False)

    def __post_init__(self):
        if isinstance(self.seed, bool) or not isinstance(self.seed, (int, np.integer)) or self.seed < 0:
            raise ConfigError("seed", "a non-negative integer", self.seed)


@dataclass(frozen=True)
class TrackingTest:
    """Acceleration tracking of a ground motion under a specimen (report Section 8, ``z_vs = a_g``).

    Attributes
    ----------
    table : TableParameters or LTITable
        Table model (the virtual table is derived from it, or is it: an LTI table).
    specimen : SpecimenChoice
    motion : MotionChoice
    controller : ControllerChoice
    lab : LabChoice
    from_report : mapping
        The values taken from the report's setup because nobody chose them
        (key of ``data/report/config.toml`` -> value, internal units).
    """

    table: TableParameters | LTITable
    specimen: SpecimenChoice
    motion: MotionChoice
    controller: ControllerChoice
    lab: LabChoice
    from_report: Mapping[str, Any] = field(compare=False)
    #: A design file's controller to run as designed (``--design``, :mod:`impedance_mil.lab.design_file`);
    #: None: the test designs its own at ``controller.fc_hz``.
    given_design: ControllerDesign | None = field(default=None, kw_only=True, compare=False)
    #: Where ``given_design`` was read from (the JSON's ``design_file``).
    design_file: str | None = field(default=None, kw_only=True, compare=False)

    #: ``kind`` in the JSON and the run file; also the lab's run mode.
    kind: ClassVar[str] = "track"
    #: Constraints that can refuse this kind of test.  Not III for tracking: its target
    #: is the rigid ground (z_vs = a_g), the article's force does not enter it, and the
    #: phase of the near-zero H_vw it is judged on is numerical (-89.9 deg at 0.01 Hz
    #: for the report's own tracking design, which ran on the real table).
    gated: ClassVar[tuple[str, ...]] = ("I", "II")

    @property
    def vs(self):
        """The virtual system (None for tracking)."""
        return None

    @property
    def vs_name(self) -> str | None:
        return None

    def pretest(self) -> Pretest:
        """The motion (and, for MIL, the predicted basemat motion) against the table's limits."""
        return pretest(self.table, self.specimen.weight_lbf, self.motion.motion, self.lab.limits, self.vs)

    @functools.cached_property
    def design(self) -> ControllerDesign:
        """The controller this test runs (designed once; its verdicts are checked before the run)."""
        if self.given_design is not None:
            return self.given_design
        return tracking_design(self.table, self.controller.fc_hz)

    def design_violations(self, required: tuple[str, ...] = REQUIRED_CONSTRAINTS) -> list[str]:
        """One sentence per constraint of ``required`` (``"I"``, ``"II"``, ``"III"``) the design
        violates, among those that can refuse this kind of test (:attr:`gated`)."""
        return design_violations(self.design, tuple(r for r in required if r in self.gated))

    def check_design(
        self, required: tuple[str, ...] = REQUIRED_CONSTRAINTS, force: bool = False
    ) -> list[str]:
        """Refuse a design that violates a ``required`` constraint, unless ``force``; the warnings.

        Raises
        ------
        DesignRefused
            The design violates a required constraint and ``force`` is False.
        """
        other_table = [] if self.given_design is None else table_differences(self.given_design, self.table)
        if other_table and not force:
            raise DesignRefused(
                "--design: the design was made for another table ("
                + "; ".join(other_table)
                + ") -- use --force to run it on this one anyway"
            )
        found = self.design_violations(required)
        if found and not force:
            raise DesignRefused(
                "; ".join(found)
                + " -- a real table would go unstable or wear its valve; use --force to run it anyway "
                "(the interlocks will stop it), or --require to choose the constraints"
            )
        return [f"{text}; running anyway (--force)" for text in other_table + found]

    def _common(self) -> dict[str, Any]:
        return dict(
            specimen=self.specimen.specimen,
            fc_hz=self.controller.fc_hz,
            feedback=self.controller.feedback.channel,
            precision=self.controller.precision,
            sensors=self.lab.sensors,
            seed=self.lab.seed,
            substeps=self.lab.substeps,
            limits=self.lab.limits,
            output_delay=self.lab.output_delay,
        )

    def run(self, sink: RecordSink | None = None) -> ControlledRun:
        """Design the tracking controller and run the loop (``lab.experiments.run_tracking``).

        ``sink`` receives the records as the run goes (the run file, :class:`~impedance_mil.lab.run_stream.RunFileStream`).
        """
        return run_tracking(
            self.table,
            self.motion.motion,
            compensate=self.controller.feedback.compensates,
            design=self.design,
            sink=sink,
            **self._common(),
        )

    def describe(self) -> dict[str, Any]:
        """The test as plain data (JSON output, run file summary)."""
        return {
            "kind": self.kind,
            "vs": self.vs_name,
            "specimen": self.specimen.label,
            "specimen_weight_lbf": self.specimen.weight_lbf,
            "motion": self.motion.to_dict(),
            "fc_hz": self.controller.fc_hz,
            "feedback": self.controller.feedback.value,
            "precision": self.controller.precision,
            "seed": self.lab.seed,
            "design_file": self.design_file,
            "design_method": "filter" if self.design.optimization is None else "optimized",
            "from_report": dict(self.from_report),
        }

    def arrays(self, result: ControlledRun) -> dict[str, dict[str, np.ndarray]]:
        """Arrays stored with the run: the VS model's own isolator loop of a MIL run (none for tracking)."""
        return {} if self.vs is None else {MODEL_LOOP: model_loop(result.run, self.vs, result.vs_force)}

    def summary(
        self, result: ControlledRun, pre: Pretest | None = None, warnings: tuple[str, ...] = ()
    ) -> dict[str, Any]:
        """The test, its metrics (shared names), the pre-test check and the design verdicts."""
        design = result.design
        doc = {**self.describe(), **run_summary(result.run, result.metrics)}
        if pre is not None:
            doc["pretest"] = pre.to_dict()
        clipped = clipped_channels(self.lab.sensors or default_sensors(), result.run.channels)
        doc["lab"] = self.lab.name
        doc["sensor_clipping"] = [c.to_dict() for c in clipped]
        doc["sensor_clipping_fails"] = bool(clipped) and self.lab.clipping == "fail"
        doc["warnings"] = list(warnings) + [c.sentence for c in clipped]
        doc["design"] = {
            "form": design.form,
            "fc_hz": design.fc_hz,
            "constraints": design.constraint_at(design.fc_hz).to_dict(),
            "notes": list(design.warnings),
        }
        return doc


@dataclass(frozen=True)
class MilTest(TrackingTest):
    """A MIL test: the table imitates a virtual isolation system (report Section 9).

    Attributes
    ----------
    vs_spec : VSSpec
        The virtual system and where it came from (plus those of :class:`TrackingTest`).
    """

    vs_spec: VSSpec = field(kw_only=True)

    kind: ClassVar[str] = "mil"
    gated: ClassVar[tuple[str, ...]] = CONSTRAINTS

    def __post_init__(self):
        if not self.controller.feedback.compensates:
            raise ConfigError("feedback", "lc or fe (a MIL run feeds the measured force to the VS)", "none")

    @property
    def vs(self):
        return self.vs_spec.vs

    @property
    def vs_name(self) -> str | None:
        return self.vs_spec.name

    def run(self, sink: RecordSink | None = None) -> ControlledRun:
        """Design the standardized controller and run the MIL loop (``lab.experiments.run_mil``; ``sink`` as for tracking)."""
        return run_mil(
            self.table, self.vs, self.motion.motion, design=self.design, sink=sink, **self._common()
        )

    @functools.cached_property
    def design(self) -> ControllerDesign:
        """The standardized controller of this test (open-f_h verdicts, see ``lab.experiments.mil_design``)."""
        if self.given_design is not None:
            return self.given_design
        return mil_design(self.table, self.vs, self.controller.fc_hz)


@dataclass(frozen=True, eq=False)
class FrfOutcome:
    """Outcome of :meth:`FrfTest.run`: the multisine experiment and the K_p study (empty after a trip)."""

    experiment: FrfExperiment
    kp_values: tuple[float, ...]
    study: tuple[FrfExperiment, ...]


def identified(exp: FrfExperiment) -> dict[str, float]:
    """omega_oil [rad/s], f_oil [Hz], zeta_oil, d and the misfit identified from z/u (empty without)."""
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


def _kp_row(kp: float, exp: FrfExperiment) -> dict[str, Any]:
    ident = identified(exp)
    return {
        "Kp": kp,
        **{key: ident.get(key) for key in ("omega_oil_rad_s", "f_oil_hz", "zeta_oil", "d")},
        "misfit": ident.get("identification_error"),
        "abort_reason": trip_text(exp.run),
    }


def _table_file(table: TableParameters | LTITable) -> dict[str, Any]:
    """What the FRF run states of the table it compares with: the oil column and K_p, or the LTI model's kind."""
    if isinstance(table, LTITable):
        return {"kind": table.kind, "delay": table.delay, "outputs": list(table.outputs)}
    return {
        "omega_oil_rad_s": table.omega_oil,
        "f_oil_hz": table.f_oil_hz,
        "zeta_oil": table.zeta_oil,
        "d": table.d,
        "Kp": table.Kp,
    }


@dataclass(frozen=True)
class FrfTest:
    """The multisine test of Section 4.5 and the identification of omega_oil, zeta_oil and d.

    Attributes
    ----------
    table : TableParameters
    specimen : SpecimenChoice
        Identification needs the bare table (``specimen.specimen`` None).
    peak_in : float
        Peak of the multisine position command [in].
    delay : str
        Delay model of the linear model compared and identified (:data:`FRF_DELAYS`).
    kp_values : tuple of float
        K_p [V/psi] of the study repeated after the test (empty: none; bare table only).
    lab : LabChoice
    from_report : mapping
        Values taken from the report's setup (as :class:`TrackingTest`).
    """

    table: TableParameters | LTITable
    specimen: SpecimenChoice
    peak_in: float
    delay: str
    kp_values: tuple[float, ...]
    lab: LabChoice
    from_report: Mapping[str, Any] = field(compare=False)

    kind: ClassVar[str] = "frf"

    def __post_init__(self):
        if not (np.isfinite(self.peak_in) and self.peak_in > 0):
            raise ConfigError("peak", "a positive command peak in in", self.peak_in)
        if self.delay not in FRF_DELAYS:
            raise ConfigError("delay", "one of " + ", ".join(FRF_DELAYS), self.delay)
        if self.kp_values and self.specimen.specimen is not None:
            raise ConfigError(
                "kp_study", "the bare table (the identification is of the bare table, Section 4.5.3)"
            )

    def _options(self) -> dict[str, Any]:
        return dict(
            multisine=report_multisine(self.table.loop_time, peak=self.peak_in),
            delay=self.delay,
            sensors=self.lab.sensors,
            seed=self.lab.seed,
            substeps=self.lab.substeps,
            limits=self.lab.limits,
            output_delay=self.lab.output_delay,
        )

    def run(self, on_step: Callable[[str], None] | None = None) -> FrfOutcome:
        """Run the test, then (if it completed) the K_p study; ``on_step(text)`` is told of each K_p."""
        options = self._options()
        # an LTI table has no physical parameters to identify: its FRFs are measured against its model
        bare = self.specimen.specimen is None and not isinstance(self.table, LTITable)
        exp = run_frf(self.table, specimen=self.specimen.specimen, identify=bare, **options)
        kps = self.kp_values if exp.completed else ()
        study = []
        for kp in kps:
            if on_step is not None:
                on_step(f"K_p study: K_p = {kp:g} V/psi")
            study.append(kp_study(self.table, (kp,), **options).experiments[0])
        return FrfOutcome(exp, tuple(kps), tuple(study))

    def summary(self, outcome: FrfOutcome) -> dict[str, Any]:
        """What the run file and the JSON state: the multisine, the identification, the model error."""
        exp = outcome.experiment
        ms = exp.multisine
        f = ms.frequencies_hz
        errors = (
            {name: exp.model_error("z", band) for name, band in FRF_BANDS_HZ.items()} if exp.completed else {}
        )
        p = self.table
        return {
            "kind": self.kind,
            "specimen": self.specimen.label,
            "specimen_weight_lbf": self.specimen.weight_lbf,
            **trip_summary(exp.run),
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
            "table_file": _table_file(p),
            "kp_study": [_kp_row(kp, e) for kp, e in zip(outcome.kp_values, outcome.study)],
            "from_report": dict(self.from_report),
        }

    @staticmethod
    def arrays(outcome: FrfOutcome, summary: Mapping[str, Any]) -> dict[str, dict[str, np.ndarray]]:
        """Arrays stored with the run: the z/u FRF and its model (none after a trip), and the K_p study.

        In ``kp_study`` a run stopped by an interlock has NaN parameters and misfit.
        """
        exp = outcome.experiment
        arrays = {}
        if exp.completed:
            z = exp.frf["z"]
            arrays[FRF_GROUP] = {
                "f_hz": z.frequency_hz,
                "H_zu_measured": z.response,
                "H_zu_model": exp.model["z"],
                "coherence_zu": z.coherence,
            }
        if summary["kp_study"]:
            arrays["kp_study"] = {
                key: np.array([row[key] for row in summary["kp_study"]], dtype=float)
                for key in ("Kp", "f_oil_hz", "zeta_oil", "d", "misfit")
            }
        return arrays
