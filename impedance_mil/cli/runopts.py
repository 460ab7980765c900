"""Options and helpers shared by the run commands (``imil simulate``, ``track``, ``frf``, ``report``, ``demo``).

Only command-line matters live here: the option names of the run choices
(:data:`CHOICE_OPTIONS`, so that the library's errors name ``--water-depth``),
the check of output paths *before* a run starts, the refusal of a motion over
the limits (which names ``--force``), progress on stderr and the printing of
a design's verdicts.  The run itself is described and run by the library:
:mod:`impedance_mil.lab.choices` (defaults from the report's setup file),
:mod:`impedance_mil.lab.descriptions`, :mod:`impedance_mil.lab.pretest` and
:mod:`impedance_mil.lab.runfile` (metric names and the run file's summary,
re-exported here for existing callers).
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import overload

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    SpinnerColumn,
    TextColumn,
    TimeElapsedColumn,
)

from ..design.constraints import DesignCriteria
from ..errors import ConfigError, MotionRefused
from ..lab.pretest import PretestFindings
from ..lab.runfile import SUMMARY_ATTR, read_summary
from ..report_config import report_config

__all__ = [
    "CHOICE_OPTIONS",
    "EXIT_ABORTED",
    "EXIT_INTERRUPTED",
    "SUMMARY_ATTR",
    "Written",
    "activity",
    "design_lines",
    "err_console",
    "output_path",
    "percent",
    "read_summary",
    "refuse_or_warn",
    "report_defaults_line",
]

#: Exit status of a run stopped by a safety interlock (its data up to the trip are written).
EXIT_ABORTED = 3
#: Exit status after Ctrl-C (like a shell after SIGINT).
EXIT_INTERRUPTED = 130

#: The option of each run choice (lab.choices.Choices), for the library's error messages.
CHOICE_OPTIONS = {
    "table": "--table",
    "lab": "--lab",
    "specimen": "--specimen",
    "water_depth": "--water-depth",
    "specimen_weight": "--specimen-weight",
    "motion": "--motion",
    "motion_units": "--motion-units",
    "duration": "--duration",
    "fc_hz": "--fc",
    "feedback": "--feedback",
    "precision": "--precision",
    "seed": "--seed",
    "vs": "--vs",
    "peak": "--peak",
    "delay": "--delay",
    "kp_study": "--kp-study",
    "design": "--design",
    "vs_overrides": "--set-vs",
}

_REPORT = report_config()
SPECIMEN_HELP = (
    "vessel (Section 3.2), rigid (a rigid mass of --specimen-weight), none (bare table) "
    "or a specimen file (TOML, [specimen] table as in docs/specimens.md)."
)


@dataclass
class Written:
    """Files a command wrote (in order), for the closing message."""

    paths: list[Path] = field(default_factory=list)


@overload
def output_path(option: str, path: Path, overwrite: bool, suffixes: tuple[str, ...] = ()) -> Path: ...
@overload
def output_path(
    option: str, path: Path | None, overwrite: bool, suffixes: tuple[str, ...] = ()
) -> Path | None: ...
def output_path(
    option: str, path: Path | None, overwrite: bool, suffixes: tuple[str, ...] = ()
) -> Path | None:
    """Check an output path before anything runs: its folder exists, and it is new or ``--overwrite``.

    ``suffixes``: the file's suffixes allowed (any letter case; none given: any suffix).
    """
    if path is None:
        return None
    if suffixes and path.suffix.lower() not in suffixes:
        raise ConfigError(option, "a file named " + " or ".join(f"*{s}" for s in suffixes), str(path))
    if not path.parent.is_dir():
        raise ConfigError(option, "a path in an existing folder", str(path))
    if path.is_dir():
        raise ConfigError(option, "a file path, not a folder", str(path))
    if path.exists() and not overwrite:
        raise ConfigError(option, "a file that does not exist yet (or --overwrite to replace it)", str(path))
    if not os.access(path.parent, os.W_OK):
        raise ConfigError(option, "a path in a writable folder", str(path))
    return path


def refuse_or_warn(found: PretestFindings, force: bool) -> list[str]:
    """Refuse a motion over the limits unless ``--force`` (naming the options that fix it); the warnings."""
    warnings = list(found.warnings)
    if found.refusal is not None:
        if not force:
            hint = []
            if found.time_scale is not None:
                hint.append(f"--time-scale {found.time_scale:.2f}")
            if found.pga_g is not None:
                hint.append(f"--pga <= {found.pga_g:.3f}")
            raise MotionRefused(
                f"{found.refusal}; try {' or '.join(hint) or 'a smaller --pga'}, "
                "or --force to run it anyway (the interlocks will stop it)"
            )
        warnings.insert(0, f"{found.refusal}; running anyway (--force)")
    return warnings


def report_defaults_line(from_report: dict) -> str:
    """``from the report's setup (data/report/config.toml): design.fc 80, ...`` for the terminal."""
    values = ", ".join(
        f"{key} {value:g}" if isinstance(value, float) else f"{key} {value}"
        for key, value in from_report.items()
    )
    return f"  from the report's setup ({_REPORT.source.name}): {values or 'nothing'}"


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


def metric_lines(doc: dict, why_none: str) -> list[str]:
    """The run metrics of a summary ``doc`` for the terminal (shared by simulate and evaluate);
    ``why_none`` says why there are none when the record was shorter than 1 s."""
    if doc["spectral_error_0p25_15hz"] is None:
        return [f"  no metrics ({why_none})"]
    energy = "" if doc["energy_error"] is None else f", energy error {percent(doc['energy_error'])}"
    return [
        f"  spectral error (5% PSA, table vs target): 0.25-15 Hz {percent(doc['spectral_error_0p25_15hz'])}, "
        f"15-50 Hz {percent(doc['spectral_error_15_50hz'])}",
        f"  NRMS error {percent(doc['nrms_error'])}, peak error {percent(doc['peak_error'])}{energy}",
    ]


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
