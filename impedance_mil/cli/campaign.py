"""`imil campaign` commands: run parameter sweeps, list them, and report on them.

``imil campaign run FILE.toml|NAME`` expands and validates the campaign,
refuses bad input before anything runs, then runs the pending runs on local
processes (or a Dask cluster with ``--scheduler``) with a live progress bar,
and prints a summary.  ``imil campaign report DIR -o report.html`` writes the
reproduction report of the campaign folders given.  ``imil campaign calibrate
PROTOCOL -o DIR`` calibrates a lab on one report observation
(:mod:`impedance_mil.campaign.calibration`).
"""

from __future__ import annotations

import sys
from pathlib import Path

import typer
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from ..campaign import (
    DEFAULT_MAX_RUNS,
    KINDS,
    ProgressEvent,
    builtin_campaigns,
    get_kind,
    load_campaign,
    make_executor,
    run_campaign,
)
from ..campaign.calibration import Evaluation, calibrate, load_protocol
from ..campaign.executors import DEFAULT_CONNECT_TIMEOUT_S
from ..config import parse_overrides
from ..report.reproduction import write_reproduction_report
from .common import UnitsOpt, console, output_units, print_json
from .runopts import EXIT_INTERRUPTED

app = typer.Typer(
    help="Parameter sweeps (campaigns) and the report-reproduction suite.", no_args_is_help=True
)


def _load(campaign: str, reduced: bool, max_runs: int, overrides: list[str] | None):
    return load_campaign(campaign, reduced=reduced, max_runs=max_runs, overrides=parse_overrides(overrides))


@app.command("run")
def run(
    campaign: str = typer.Argument(
        ..., help="Campaign file (TOML) or built-in name (see `imil campaign list`)."
    ),
    out: Path | None = typer.Option(None, "-o", "--out", help="Campaign folder (default: campaign-NAME)."),
    workers: int | None = typer.Option(
        None, "--workers", help="Local worker processes (default: one per core; 0: run inline)."
    ),
    scheduler: str | None = typer.Option(
        None, "--scheduler", help="Dask scheduler address, e.g. tcp://host:8786."
    ),
    connect_timeout: float = typer.Option(
        DEFAULT_CONNECT_TIMEOUT_S, "--connect-timeout", help="Seconds to reach the scheduler."
    ),
    max_runs: int = typer.Option(DEFAULT_MAX_RUNS, "--max-runs", help="Refuse campaigns with more runs."),
    reduced: bool = typer.Option(False, "--reduced", help="Run the reduced (CI) version of the campaign."),
    overrides: list[str] | None = typer.Option(None, "--set", help="Base setting KEY=VALUE (repeatable)."),
    as_json: bool = typer.Option(False, "--json", help="Print the result as JSON, no progress bar."),
    units: str | None = UnitsOpt,
) -> None:
    """Run a campaign; runs already done in the folder are skipped (resume)."""
    shown = output_units(units)
    spec = _load(campaign, reduced, max_runs, overrides)
    folder = out or Path(f"campaign-{spec.name}{'-reduced' if reduced else ''}")
    executor = make_executor(workers, scheduler, connect_timeout)
    try:
        with executor:
            result = _run_with_progress(spec, folder, executor, quiet=as_json)
    except KeyboardInterrupt:
        print(
            f"imil: interrupted; finished runs are kept in {folder}; run the same command to resume",
            file=sys.stderr,
        )
        raise typer.Exit(EXIT_INTERRUPTED) from None
    counts = {s: result.count(s) for s in ("ok", "aborted", "failed")}
    if as_json:
        print_json(
            {
                "campaign": spec.name,
                "folder": str(folder),
                "runs": len(spec.runs),
                "executed": len(result.executed),
                "skipped": len(result.skipped),
                **counts,
                "summary_csv": str(result.summary.csv),
                "summary_parquet": str(result.summary.parquet or ""),
            },
            shown,
        )
        return
    console.print(
        f"{spec.name}: {len(spec.runs)} runs, {len(result.executed)} executed, "
        f"{len(result.skipped)} already done; ok {counts['ok']}, aborted {counts['aborted']}, "
        f"failed {counts['failed']}"
    )
    for record in result.records:
        if record.status == "failed":
            console.print(f"  failed {record.run_id}: {record.error}")
    console.print(
        f"summary: {result.summary.csv}" + (f", {result.summary.parquet}" if result.summary.parquet else "")
    )


def _run_with_progress(spec, folder: Path, executor, quiet: bool):
    if quiet:
        return run_campaign(spec, folder, executor)
    columns = (
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("{task.fields[status]}"),
        TimeElapsedColumn(),
    )
    with Progress(*columns, console=console, transient=False) as progress:
        task = progress.add_task(f"{spec.name} ({executor.description})", total=None, status="")

        def on_progress(event: ProgressEvent) -> None:
            tally = progress.tasks[0].fields.get("tally", {})
            tally[event.record.status] = tally.get(event.record.status, 0) + 1
            status = ", ".join(f"{k} {v}" for k, v in sorted(tally.items()))
            progress.update(task, completed=event.done, total=event.total, status=status, tally=tally)

        return run_campaign(spec, folder, executor, on_progress=on_progress)


@app.command("plan")
def plan(
    campaign: str = typer.Argument(..., help="Campaign file or built-in name."),
    max_runs: int = typer.Option(DEFAULT_MAX_RUNS, "--max-runs", help="Refuse campaigns with more runs."),
    reduced: bool = typer.Option(False, "--reduced", help="Expand the reduced (CI) version."),
    overrides: list[str] | None = typer.Option(None, "--set", help="Base setting KEY=VALUE (repeatable)."),
    as_json: bool = typer.Option(False, "--json", help="Print the runs as JSON."),
    units: str | None = UnitsOpt,
) -> None:
    """Validate and expand a campaign without running it."""
    shown = output_units(units)
    spec = _load(campaign, reduced, max_runs, overrides)
    if as_json:
        # The internal unit of each setting, from its kind's parameters, for the units block.
        given = {
            f"runs[{i}].settings.{key}": get_kind(r.kind).params[key].unit
            for i, r in enumerate(spec.runs)
            for key in r.settings
            if key in get_kind(r.kind).params and get_kind(r.kind).params[key].type == "quantity"
        }
        print_json(
            {
                "campaign": spec.name,
                "kind": spec.kind,
                "runs": [
                    {"run_id": r.run_id, "kind": r.kind, "studies": list(r.studies), "settings": r.settings}
                    for r in spec.runs
                ],
                "units": given,
            },
            shown,
        )
        return
    table = Table(title=f"{spec.name} ({spec.kind}): {len(spec.runs)} runs")
    for column in ("run_id", "study", *spec.parameters):
        table.add_column(column)
    for r in spec.runs:
        table.add_row(r.run_id, ";".join(r.studies), *(_fmt(r.settings.get(p)) for p in spec.parameters))
    console.print(table)


def _fmt(value) -> str:
    if value is None:
        return ""
    return f"{value:.6g}" if isinstance(value, float) else str(value)


@app.command("list")
def list_campaigns() -> None:
    """List the built-in campaigns and the campaign kinds."""
    for name, path in builtin_campaigns().items():
        spec = load_campaign(path)
        reduced = load_campaign(path, reduced=True)
        console.print(
            f"{name:16s} {spec.kind:9s} {len(spec.runs):4d} runs ({len(reduced.runs)} reduced)  {spec.title}"
        )
    console.print("kinds: " + ", ".join(f"{k} ({v.description})" for k, v in KINDS.items()))


@app.command("params")
def params(kind: str = typer.Argument(..., help="Campaign kind.")) -> None:
    """List the parameters a campaign kind accepts, with units."""
    for name, spec in get_kind(kind).params.items():
        console.print(f"{name:14s} {spec.describe():40s} {spec.help}")


@app.command("report")
def report(
    folders: list[Path] = typer.Argument(..., help="Campaign folders (e.g. of report-sec4, -sec8, -sec9)."),
    out: Path = typer.Option(Path("reproduction.html"), "-o", "--out", help="HTML file to write."),
) -> None:
    """Write the self-contained reproduction report (the report's claims against the campaigns)."""
    result = write_reproduction_report(folders, out)
    console.print(
        f"{out}: {len(result.outcomes)} claims: {result.agree} agree, "
        f"{result.disagree} disagree, {result.not_run} not run"
    )
    for record in result.calibrations:
        console.print(
            f"calibrated lab: {record.parameter} = {record.value}, calibrated on {record.claim} "
            f"(does not count); predicted claims that agree: {result.predicted_agree}",
            markup=False,
        )


@app.command("calibrate")
def calibrate_cmd(
    protocol: Path = typer.Argument(
        ..., help="Calibration protocol (TOML): the claim, the parameter, its range."
    ),
    out: Path = typer.Option(..., "-o", "--out", help="Folder for calibrated-lab.toml and calibration.json."),
    as_json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
) -> None:
    """Calibrate one lab parameter on one report observation named in advance (issue 17)."""
    spec = load_protocol(protocol)
    par = spec.parameter

    def say(e: Evaluation) -> None:
        if not as_json:
            console.print(
                f"  {par.name} {e.value:.4g} {par.unit}, {spec.observation.vary} {e.setting:g}: {e.verdict}"
                + (f" (hf_ratio {e.hf_ratio:.3g})" if e.hf_ratio is not None else "")
                + (f", trip {e.trip}" if e.trip else ""),
                markup=False,
            )

    result = calibrate(spec, out, on_run=say)
    if as_json:
        print_json(result.to_dict())
        return
    console.print(
        f"{out}: calibrated on {spec.claim}: {par.name} = {result.value:.4g} {par.unit} "
        f"({'reproduced' if result.reproduced else 'NOT reproduced'} within {par.low:g}-{par.high:g} {par.unit})",
        markup=False,
    )
    console.print(result.note, markup=False)
