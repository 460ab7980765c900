"""`imil evaluate RECORDING`: judge a recorded tracking or MIL test like a virtual run.

The recording's channels are mapped with ``--channel NAME=COLUMN[UNIT]`` (or a
``--channels`` file): ``a_g`` and ``z`` always, ``w`` for a MIL test (``--vs``), ``x``
for the energy error and the loops.  The target is recomputed from the recorded
``a_g`` and ``w`` as the controller did (``--precision``); the metrics have the
names of ``imil simulate --json``; the run file (``-o``) has the layout of a
virtual run, so ``imil report`` and the campaigns read it.  ``--compare RUN.h5``
sets a virtual-lab prediction of the same test against the measurement.

The sample rate must be the loop rate of ``--table`` (the lab file's, once
``--lab`` exists: issue 12); the clipping check uses the lab's sensors (Table 7.1).

Exit status: 0; 2 for bad input (one line naming the file, channel or key; nothing written).
"""

from __future__ import annotations

from pathlib import Path

import typer

from ..config import parse_overrides
from ..errors import ConfigError
from ..lab.evaluation import compare_summaries, evaluate_recording
from ..lab.recorded import read_lab_recording
from ..lab.results import RUN_FILE_SUFFIXES, load_run
from ..lab.runfile import MODEL_LOOP, read_summary, recomputed_summary, write_run_file
from ..report.documents import express
from ..report.evaluation_page import write_evaluation_page
from ..report_config import report_config
from ..virtual import presets
from ..virtual.files import resolve
from .common import LabOpt, UnitsOpt, console, lab_setup, output_units, print_json
from .recording import AllowClippedOpt, ChannelOpt, ChannelsFileOpt, RateOpt, channel_map
from .runopts import metric_lines, output_path

_REPORT = report_config()


def _print(doc: dict) -> None:
    say = lambda text: console.print(text, markup=False)  # noqa: E731
    rec = doc["recording"]
    head = f"MIL test, VS {doc['vs']}" if doc["mode"] == "mil" else "tracking test"
    say(
        f"{head}: {rec['file']} ({rec['format']}), {rec['n_samples']} samples at {rec['sample_rate_hz']:g} Hz, "
        f"{doc['simulated_s']:.2f} s; target recomputed in {doc['precision']} precision"
    )
    for clip in doc["clipped"]:
        say(
            f"  clipped (accepted): channel {clip['channel']} at {clip['limit']:.6g}, {clip['n_samples']} samples"
        )
    for line in metric_lines(doc, "the recording is shorter than 1 s"):
        say(line)
    if doc.get("comparison"):
        say(f"prediction {doc['prediction']} against the measurement (measured - predicted):")
        for key, row in doc["comparison"].items():
            if row["measured"] is not None and row["predicted"] is not None:
                say(
                    f"  {key:26s} {row['measured']:10.4g} {row['predicted']:10.4g} {row['difference']:+10.4g}"
                )
    for path in (doc["file"], doc["report"]):
        if path:
            say(f"wrote {path}")


def evaluate(
    recording: Path = typer.Argument(..., help="Recording (.csv, .h5, .mat, .tdms)."),
    vs: str | None = typer.Option(
        None,
        "--vs",
        help="VS preset (" + ", ".join(presets.names()) + ") or VS file: a MIL test; none: tracking.",
    ),
    sets_vs: list[str] | None = typer.Option(None, "--set-vs", help="VS value KEY=VALUE (repeatable)."),
    channels: list[str] | None = ChannelOpt,
    channels_file: Path | None = ChannelsFileOpt,
    rate: str | None = RateOpt,
    table: Path | None = typer.Option(
        None, "--table", help="Table file: its loop time is the recording's rate (default the report's)."
    ),
    lab: str | None = LabOpt,
    precision: str | None = typer.Option(
        None,
        "--precision",
        help=f"Controller arithmetic (default the report's {_REPORT.controller.precision}).",
    ),
    compare: Path | None = typer.Option(
        None, "--compare", help="Run file of a virtual-lab prediction to compare."
    ),
    output: Path = typer.Option(..., "-o", "--output", help="Run file to write (HDF5)."),
    report: Path | None = typer.Option(None, "--report", help="Also write the HTML page."),
    allow_clipped: bool = AllowClippedOpt,
    as_json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace existing output files."),
    units: str | None = UnitsOpt,
) -> None:
    """Judge a recorded tracking or MIL test with the metrics, run file and page of a virtual run."""
    shown = output_units(units, lab, table)
    out = output_path("-o", output, overwrite, RUN_FILE_SUFFIXES)
    page = output_path("--report", report, overwrite)
    if page is not None and page.resolve() == out.resolve():
        raise ConfigError("--report", "a path other than the run file (-o)", str(report))
    setup = lab_setup(table, None, lab)  # the table, and the sensors clipping is judged against
    params = setup.physical_table()
    cmap = channel_map(channels, channels_file, rate)
    rec = read_lab_recording(
        recording,
        cmap,
        expected_rate_hz=1.0 / params.loop_time,
        rate_source=f"the table's loop time ({params.loop_time:g} s)",
        sensors=setup.sensors.suite,
        allow_clipped=allow_clipped,
    )
    precision = precision or _REPORT.controller.precision
    spec = None if vs is None else resolve(vs, parse_overrides(sets_vs, option="--set-vs"))
    evaluation = evaluate_recording(rec, vs_spec=spec, precision=precision)
    doc = evaluation.summary()
    prediction = None
    if compare is not None:
        prediction = load_run(compare)
        stored, _ = read_summary(compare)
        doc["prediction"] = str(compare)
        doc["comparison"] = compare_summaries(doc, stored or recomputed_summary(prediction))
    arrays = evaluation.arrays()
    write_run_file(evaluation.run, out, doc, arrays)
    if page is not None:
        write_evaluation_page(
            evaluation.run,
            doc,
            page,
            loop=arrays.get(MODEL_LOOP),
            prediction=prediction,
            comparison=doc.get("comparison"),
            units=shown,
        )
    doc = {**doc, "file": str(out), "report": None if page is None else str(page)}
    if as_json:
        print_json(doc, shown)
    else:
        _print(express(doc, shown))
