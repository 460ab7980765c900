"""`imil drive multisine` and `imil drive motion`: what the lab's controller plays, at its loop rate.

Each writes ``DIR/<kind>.csv`` (``--format csv`` or ``rmc75e``, in ``--drive-units``)
and ``DIR/<kind>.json``, the metadata that ``imil identify --drive`` reads back
(:mod:`impedance_mil.signals.drive`).

* ``multisine``: the report's Section 4.5.2 design (equal-amplitude lines,
  crest-factor minimization, periods) at the table's loop rate; the position command u.
* ``motion``: a ground motion time-compressed and scaled, resampled to the loop
  rate and baseline-corrected, checked against the table's limits with the
  specimen on it (refused unless ``--force``, as ``imil simulate``); the ground
  acceleration a_g the MIL program reads (report Figure 7.9).

The loop rate and the limits come from ``--lab`` (default the report's lab) or
``--table`` (a lab with only a table: its generic interlocks).  Exit status: 0; 2 for bad input or a refused
motion (one line, nothing written).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from ..config import quantity
from ..display import UnitSystem
from ..lab.pretest import pretest
from ..report_config import report_config
from ..signals.drive import FILE_FORMATS, check_drive_folder, multisine_metadata, write_drive
from ..signals.multisine import REPORT_PERIOD_S, design_multisine
from ..signals.sources import scaled_motion
from ..virtual.files import resolve
from .common import (
    LabOpt,
    UnitsOpt,
    WeightOpt,
    console,
    lab_setup,
    output_units,
    print_json,
    table_parameters,
    weight_option,
)
from .motion import PGA_HELP, SOURCE_HELP, TIME_SCALE_HELP, UNITS_HELP
from .runopts import refuse_or_warn
from .simulate import check_text, warn

_REPORT = report_config()

app = typer.Typer(
    help="Drive files for the lab's controller (multisine, ground motion).", no_args_is_help=True
)

TableOpt = typer.Option(
    None, "--table", help="Table file: loop rate and limits (default the report's Table 4.1)."
)
SetOpt = typer.Option(None, "--set", help="Table value KEY=VALUE (repeatable).")
FormatOpt = typer.Option("csv", "--format", help="Data-file layout: " + ", ".join(FILE_FORMATS) + ".")
DirOpt = typer.Option(..., "-o", "--output", help="Folder to write the drive into (created if new).")
OverwriteOpt = typer.Option(False, "--overwrite", help="Replace existing drive files of this kind.")
JsonOpt = typer.Option(False, "--json", help="Print the metadata as JSON.")


def _folder(path: Path) -> Path:
    check_drive_folder(path)
    return path


def _report(drive, folder: Path, as_json: bool, lines: list[str], shown: UnitSystem) -> None:
    if as_json:
        print_json(
            {**drive.to_dict(), "files": [str(folder / drive.data_file), str(folder / f"{drive.kind}.json")]},
            shown,
        )
        return
    for line in lines:
        console.print(line, markup=False)
    console.print(f"wrote {folder / drive.data_file} and {folder / (drive.kind + '.json')}", markup=False)


@app.command("multisine")
def multisine(
    table: Path | None = TableOpt,
    lab: str | None = LabOpt,
    sets: list[str] | None = SetOpt,
    peak: str | None = typer.Option(
        None,
        "--peak",
        help=f"Peak of the position command [in] (default the report's {_REPORT.frf.peak_in:g}; '2 mm').",
    ),
    f_min: float | None = typer.Option(None, "--f-min", help="Lowest line [Hz] (default the report's 0.25)."),
    f_max: float | None = typer.Option(None, "--f-max", help="Highest line [Hz] (default the report's 125)."),
    lines: int | None = typer.Option(None, "--lines", help="Number of lines (default the report's 512)."),
    periods: int | None = typer.Option(None, "--periods", help="Periods, the first a transient (default 3)."),
    period: float | None = typer.Option(
        None, "--period", help=f"Length of one period [s] (default the report's {REPORT_PERIOD_S:g})."
    ),
    phases: str = typer.Option("min-crest", "--phases", help="min-crest (report), schroeder or random."),
    seed: int = typer.Option(0, "--seed", help="Seed of random phases."),
    drive_units: str = typer.Option("in", "--drive-units", help="Unit of the written command (in, mm ...)."),
    file_format: str = FormatOpt,
    output: Path = DirOpt,
    overwrite: bool = OverwriteOpt,
    as_json: bool = JsonOpt,
    units: str | None = UnitsOpt,
) -> None:
    """The report's multisine (Section 4.5.2) at the table's loop rate, with the metadata identify reads."""
    shown = output_units(units, lab, table)
    folder = _folder(output)
    params = table_parameters(table, sets, lab)
    peak_in = quantity("--peak", _REPORT.frf.peak_in if peak is None else peak, "inch", "positive")
    length = REPORT_PERIOD_S if period is None else quantity("--period", period, "second", "positive")
    chosen: dict[str, Any] = {"f_min_hz": f_min, "f_max_hz": f_max, "n_lines": lines, "n_periods": periods}
    ms = design_multisine(
        peak=peak_in,
        sample_rate_hz=1.0 / params.loop_time,
        n_points=int(round(length / params.loop_time)),
        phases=phases,
        seed=seed,
        **{k: v for k, v in chosen.items() if v is not None},
    )
    from_report = {"frf.peak": _REPORT.frf.peak_in} if peak is None else {}
    drive = write_drive(
        folder,
        "multisine",
        ms.signal,
        sample_rate_hz=ms.sample_rate_hz,
        unit=drive_units,
        file_format=file_format,
        multisine=multisine_metadata(ms, phases),
        provenance={"table": params.to_dict(), "from_report": from_report},
        overwrite=overwrite,
    )
    meta = drive.multisine
    _report(
        drive,
        folder,
        as_json,
        [
            f"multisine: {meta['n_lines']} lines {meta['f_min_hz']:.4g}-{meta['f_max_hz']:.4g} Hz, "
            f"{meta['n_periods']} periods of {meta['period_s']:.4g} s at {drive.sample_rate_hz:g} Hz "
            f"({drive.n_samples} samples), peak {peak_in:.4g} in = {peak_in / drive.factor:.4g} {drive_units}, "
            f"crest factor {meta['crest_factor']:.3f}"
        ],
        shown,
    )


@app.command("motion")
def motion(
    source: str = typer.Argument(..., help=SOURCE_HELP),
    motion_units: str | None = typer.Option(None, "--motion-units", help=UNITS_HELP),
    time_scale: float | None = typer.Option(None, "--time-scale", help=TIME_SCALE_HELP),
    pga: float | None = typer.Option(None, "--pga", help=PGA_HELP),
    table: Path | None = TableOpt,
    lab: str | None = LabOpt,
    sets: list[str] | None = SetOpt,
    specimen_weight: str | None = WeightOpt,
    vs: str | None = typer.Option(None, "--vs", help="VS of a MIL test: also check the basemat motion."),
    drive_units: str = typer.Option(
        "g", "--drive-units", help="Unit of the written acceleration (g, m/s**2 ...)."
    ),
    file_format: str = FormatOpt,
    output: Path = DirOpt,
    force: bool = typer.Option(False, "--force", help="Write a motion that exceeds the table's limits."),
    overwrite: bool = OverwriteOpt,
    as_json: bool = JsonOpt,
    units: str | None = UnitsOpt,
) -> None:
    """A ground motion as played: scaled, resampled to the loop rate, baseline-corrected, checked."""
    shown = output_units(units, lab, table)
    folder = _folder(output)
    setup = lab_setup(table, sets, lab)
    params, interlocks = setup.physical_table(), setup.limits
    weight = weight_option("--specimen-weight", specimen_weight, setup)
    record = scaled_motion(source, motion_units, time_scale, pga, "SOURCE", "--motion-units")
    played = record.resampled(params.loop_time).baseline_corrected()
    spec = None if vs is None else resolve(vs, article_weight_lbf=weight or None)
    pre = pretest(params, weight, played, interlocks, None if spec is None else spec.vs)
    warnings = refuse_or_warn(pre.findings(played, time_scale or 1.0), force)
    warn(warnings)
    drive = write_drive(
        folder,
        "motion",
        played.accel,
        sample_rate_hz=1.0 / params.loop_time,
        unit=drive_units,
        file_format=file_format,
        motion={
            "name": played.name,
            "source": played.source,
            "argument": source,
            "time_scale": time_scale,
            "pga_g": played.pga_g,
            "baseline_corrected": True,
            "pretest": pre.to_dict(),
            "warnings": warnings,
        },
        provenance={"table": params.to_dict(), "interlocks": interlocks.to_dict()},
        overwrite=overwrite,
    )
    checks = ", ".join(check_text(c, shown) for c in pre.input.checks)
    _report(
        drive,
        folder,
        as_json,
        [
            f"motion: {played.name}, PGA {played.pga_g:.3f} g, {played.duration:.2f} s at {drive.sample_rate_hz:g} Hz "
            f"({drive.n_samples} samples), baseline-corrected, in {drive_units}",
            f"pre-test check: {checks}: {'fits' if pre.input.ok else 'EXCEEDS (--force)'}",
        ],
        shown,
    )
