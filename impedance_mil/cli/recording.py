"""`imil recording export` and the channel-map options shared by `identify` and `evaluate`.

``imil recording export RUN.h5 --channel z=acc[g] ... -o rec.csv`` writes a
virtual-lab run as the lab would have recorded it: the sensor readings and the
controller's signals, in the lab's column names and units (CSV, MATLAB .mat or
HDF5).  It stands for the real table in ``docs/measured-data.md`` and in the
round-trip tests; the reader is :mod:`impedance_mil.signals.recordings`.
"""

from __future__ import annotations

from pathlib import Path

import typer

from ..lab.recorded import run_as_recording
from ..lab.results import load_run
from ..signals.recordings import CHANNELS, ChannelMap
from .common import console
from .runopts import output_path

app = typer.Typer(help="Recordings: write a virtual run as the lab's recording.", no_args_is_help=True)

ChannelOpt = typer.Option(
    None,
    "--channel",
    help="NAME=COLUMN[UNIT], repeatable; NAME one of " + ", ".join(CHANNELS) + " (e.g. z=table_accel[g]).",
)
ChannelsFileOpt = typer.Option(
    None, "--channels", help='Channel map file (TOML: [channels] z = "table_accel[g]"; [recording] rate).'
)
RateOpt = typer.Option(None, "--rate", help="Sample rate [Hz] of a recording without a time channel.")
AllowClippedOpt = typer.Option(
    False, "--allow-clipped", help="Accept clipped channels (recorded in the result) instead of refusing."
)


def channel_map(channels: list[str] | None, channels_file: Path | None, rate: str | None) -> ChannelMap:
    """The channel map of ``--channel`` items and a ``--channels`` file (a channel in both is refused)."""
    given = ChannelMap.parse(channels or [], rate)
    if channels_file is None:
        return given
    return ChannelMap.from_toml(channels_file).merged(given)


@app.command("export")
def export(
    run_file: Path = typer.Argument(..., help="Run file of imil simulate, track or frf (HDF5)."),
    channels: list[str] | None = ChannelOpt,
    channels_file: Path | None = ChannelsFileOpt,
    output: Path = typer.Option(..., "-o", "--output", help="Recording to write (.csv, .mat or .h5)."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace an existing file."),
) -> None:
    """Write a virtual run as a recording: measured channels in the lab's names and units."""
    out = output_path("-o", output, overwrite)
    cmap = channel_map(channels, channels_file, None)
    run = load_run(run_file)
    run_as_recording(run, out, cmap)
    console.print(
        f"wrote {out}: {run.n_samples} samples at {1.0 / run.loop_time:g} Hz, "
        + ", ".join(s.text for s in cmap.specs),
        markup=False,
    )
