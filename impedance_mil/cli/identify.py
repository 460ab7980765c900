"""`imil identify RECORDING`: identify the table from a recorded drive and response.

With ``--drive DIR/multisine.json`` (written by ``imil drive multisine``) the FRF
is the synchronous average over the multisine's periods at its lines; without
it, a random drive's Welch H1 (``--segment``).  Both the physical model (the
report's, ``--delay``, ``--free``) and a rational transfer function (``--order N``
or automatic) are fitted, with 95 % confidence intervals; ``-o`` receives the
table file of ``--model`` (``physical``: a table file ``--table`` reads;
``tf``: a transfer-function table in issue 13's layout).  ``--plot`` draws
data against both fits (magnitude, phase, coherence).

Several recordings of the same multisine (``imil identify BARE.csv MASS.csv
--drive ... --channel w=load_cell[kN]``), each with the article force ``w``,
whose ``w`` differ (the bare table and the table with a mass): the command path
``y/u`` and the force path ``y/w`` are separated line by line, and the
transfer-function table holds both (``H_zu`` and ``H_zw``: what a MIL design
needs).

The known parts of the table (gains, loop time, area, mass, stroke) and the
starting values come from ``--table`` or ``--lab``.

Exit status: 0; 2 for bad input (one line naming the file, channel or key; nothing written).
"""

from __future__ import annotations

from pathlib import Path

import typer

from ..display import human_name
from ..errors import ConfigError
from ..fileio import atomic_write_text
from ..lab.identification import IDENTIFIABLE
from ..lab.identify import MODELS, OUTPUT_ZEROS, identify_recording
from ..lab.recorded import read_lab_recording
from ..plant.linear import DELAYS
from ..report.documents import express
from ..report.identification_plots import save_identification_plot
from ..report.motion_plots import check_figure_path
from ..signals.drive import check_recording, read_drive
from .common import (
    LabOpt,
    UnitsOpt,
    console,
    lab_setup,
    output_units,
    positive_numbers,
    print_json,
)
from .recording import AllowClippedOpt, ChannelOpt, ChannelsFileOpt, RateOpt, channel_map
from .runopts import output_path


def _order(text: str | None) -> int | None:
    if text is None or text.strip().lower() == "auto":
        return None
    try:
        value = int(text)
    except ValueError:
        raise ConfigError("--order", "a number of poles or auto", text) from None
    if value < 1:
        raise ConfigError("--order", "a number of poles >= 1 or auto", text)
    return value


def _print(doc: dict, model: str) -> None:
    say = lambda text: console.print(text, markup=False)  # noqa: E731
    frf = doc["frf"]
    say(
        f"identify: {doc['recording']['file']}, {doc['output']}/u, {frf['estimator']}, {frf['n_lines']} lines "
        f"{frf['f_min_hz']:.4g}-{frf['f_max_hz']:.4g} Hz, coherence min {frf['coherence_min']:.3f} "
        f"(median {frf['coherence_median']:.4f})"
    )
    phys = doc["physical"]
    say(f"physical model ({phys['delay']} delay): fit error {phys['fit_error']:.4f}")
    for name, value in phys["parameters"].items():
        lo, hi = phys["ci95"].get(name, (float("nan"), float("nan")))
        unit = human_name(doc["units"].get(f"physical.parameters.{name}", ""))
        unit = "" if unit in ("1", "unknown") else unit
        say(f"  {name:16s} {value:12.6g} {unit:12s} 95 % interval {lo:.6g} .. {hi:.6g}")
    tf = doc["tf"]
    say(
        f"rational model: order {tf['order']}, numerator degree {tf['num_order']} "
        f"(+{tf['zeros_at_origin']} zeros at 0), fit error {tf['fit_error']:.4f}, DC gain {tf['dc_gain']:.5g} "
        f"(95 % {tf['ci95_dc_gain'][0]:.5g} .. {tf['ci95_dc_gain'][1]:.5g})"
    )
    for pole in tf["poles"]:
        kind = f"pair, damping {pole['damping']:.4f}" if pole["complex_pair"] else "real"
        lo, hi = pole["ci95_frequency_hz"]
        say(f"  pole {pole['frequency_hz']:10.4f} Hz ({kind}); 95 % {lo:.4f} .. {hi:.4f} Hz")
    bands = [k for k in phys if k.startswith("fit_error_")]
    for key in bands:
        p, r = phys[key], tf[key]
        if p is not None:
            say(f"  {key:22s} physical {p:.4f}   rational {r:.4f}")
    force = doc.get("force_path")
    if force is not None:
        say(
            f"force path {force['path']} from {len(doc['recordings'])} tests (input condition number "
            f"<= {force['condition_max']:.3g}): order {force['order']}, fit error {force['fit_error']:.4f}"
        )
        for pole in force["poles"]:
            kind = f"pair, damping {pole['damping']:.4f}" if pole["complex_pair"] else "real"
            say(f"  pole {pole['frequency_hz']:10.4f} Hz ({kind})")
    for path in (doc["file"], doc.get("plot")):
        if path:
            say(f"wrote {path}")
    say(f"(the table file holds the {model} model)")


def identify(
    recordings: list[Path] = typer.Argument(
        ...,
        metavar="RECORDING...",
        help="Recording of the drive and the response (.csv, .h5, .mat, .tdms); several recordings "
        "of one multisine with different article forces w separate the force path.",
    ),
    drive: Path | None = typer.Option(
        None, "--drive", help="Metadata of the multisine played (DIR/multisine.json)."
    ),
    channels: list[str] | None = ChannelOpt,
    channels_file: Path | None = ChannelsFileOpt,
    rate: str | None = RateOpt,
    table: Path | None = typer.Option(
        None, "--table", help="Table file: known parameters and starting values (default the report's)."
    ),
    lab: str | None = LabOpt,
    response: str = typer.Option(
        "z", "--response", help="Response identified against u: " + ", ".join(OUTPUT_ZEROS)
    ),
    model: str = typer.Option("physical", "--model", help="Model written to -o: " + ", ".join(MODELS) + "."),
    order: str | None = typer.Option(None, "--order", help="Poles of the rational model, or auto (default)."),
    num_order: int | None = typer.Option(None, "--num-order", help="Numerator degree of the rational model."),
    zeros: int | None = typer.Option(
        None, "--zeros-at-origin", help="Known zeros at s = 0 (default 2 for z, dp)."
    ),
    delay: str = typer.Option(
        "first-order", "--delay", help="Delay model of the physical fit: " + ", ".join(DELAYS)
    ),
    free: str = typer.Option(
        "f_oil_hz,zeta_oil,d", "--free", help="Physical parameters fitted, from " + ", ".join(IDENTIFIABLE)
    ),
    band: str = typer.Option("0.25,100", "--band", help="Band of the fits [Hz], LOW,HIGH."),
    segment: int | None = typer.Option(None, "--segment", help="Welch segment [samples] for a random drive."),
    output: Path = typer.Option(..., "-o", "--output", help="Table file to write (TOML)."),
    plot: Path | None = typer.Option(None, "--plot", help="Also plot data against the fits (png, pdf, svg)."),
    allow_clipped: bool = AllowClippedOpt,
    as_json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace existing output files."),
    units: str | None = UnitsOpt,
) -> None:
    """Identify the table (physical and rational models, with confidence intervals) from a recording."""
    shown = output_units(units, lab, table)
    out = output_path("-o", output, overwrite)
    if plot is not None:
        check_figure_path(plot, "--plot")
        output_path("--plot", plot, overwrite)
    if model not in MODELS:
        raise ConfigError("--model", "one of " + ", ".join(MODELS), model)
    low, high = positive_numbers("--band", band, "LOW,HIGH in Hz", "two increasing frequencies in Hz", 2)
    if not low < high:
        raise ConfigError("--band", "LOW < HIGH", band)
    setup = lab_setup(table, None, lab)  # the table, and the sensors clipping is judged against
    params = setup.physical_table()
    drv = read_drive(drive) if drive is not None else None
    expected = drv.sample_rate_hz if drv is not None else 1.0 / params.loop_time
    source = (
        f"the drive file {drive}" if drv is not None else f"the table's loop time ({params.loop_time:g} s)"
    )
    cmap = channel_map(channels, channels_file, rate)
    recs = []
    for recording in recordings:
        rec = read_lab_recording(
            recording,
            cmap,
            expected_rate_hz=expected,
            rate_source=source,
            sensors=setup.sensors.suite,
            allow_clipped=allow_clipped,
        )
        if drv is not None:
            check_recording(drv, str(drive), rec.path, rec.sample_rate_hz, rec.channels.get("u"))
        recs.append(rec)
    ident = identify_recording(
        recs,
        params,
        output=response,
        drive=drv,
        segment_points=segment,
        order=_order(order),
        num_order=num_order,
        zeros_at_origin=zeros,
        delay=delay,
        free=[name.strip() for name in free.split(",") if name.strip()],
        f_range_hz=(low, high),
    )
    doc = ident.summary(model)
    atomic_write_text(out, ident.table_text(model, ", ".join(path.name for path in recordings)))
    if plot is not None:
        save_identification_plot(ident, plot)
    doc = {**doc, "file": str(out), "plot": None if plot is None else str(plot)}
    if as_json:
        print_json(doc, shown)
    else:
        _print(express(doc, shown), model)
