"""The campaign engine: run every pending run of a campaign, resumably, on any executor.

:func:`run_campaign` locks the output folder (a second session on it is
refused), removes the temporary files a killed session left, writes the
expanded campaign (``campaign.json``), skips the runs already done in the
folder (record ok or aborted, output verified by its checksum), submits the
others to a :class:`~impedance_mil.campaign.executors.RunExecutor`, and at
the end writes the summary table (CSV and Parquet).  Each run's record is
written by the process that ran it, atomically and *before* its output is
renamed into place, so no output ever exists without its record.  A run
that fails is recorded with its reason and the campaign goes on.  On an
interrupt (Ctrl-C, or a progress callback that raises
:class:`KeyboardInterrupt`), runs not yet started are cancelled, runs
already executing end (a local pool waits for them; Ctrl-C interrupts them
too) and are recorded, the summary is written and the interrupt propagates,
all while the folder is still locked; running the campaign again resumes it.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
import socket
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import LimitTripped
from ..fileio import atomic_path, file_sha256
from ..lab.trips import TRIP_LIMIT_KEY
from .executors import RunExecutor, make_executor
from .kinds import get_kind
from .spec import CampaignSpec, RunSpec
from .store import CampaignStore, RunRecord
from .summary import SummaryPaths, write_summary


@dataclass(frozen=True)
class ProgressEvent:
    """One run finished.

    Attributes
    ----------
    done : int
        Runs finished so far in this session.
    total : int
        Runs this session has to execute (skipped runs excluded).
    record : RunRecord
        The run that just finished.
    """

    done: int
    total: int
    record: RunRecord


@dataclass(frozen=True)
class CampaignResult:
    """What a campaign session did.

    Attributes
    ----------
    root : Path
        The campaign folder.
    records : tuple of RunRecord
        The record of every finished run of the campaign, in campaign order
        (runs still pending after an interrupt have none).
    executed : tuple of str
        Run ids executed in this session.
    skipped : tuple of str
        Run ids already done before this session.
    summary : SummaryPaths
        The summary files written.
    """

    root: Path
    records: tuple[RunRecord, ...]
    executed: tuple[str, ...]
    skipped: tuple[str, ...]
    summary: SummaryPaths

    def count(self, status: str) -> int:
        """Number of finished runs with this status (``ok``, ``aborted``, ``failed``)."""
        return sum(1 for record in self.records if record.status == status)


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _scalar_metrics(metrics: Mapping[str, Any]) -> dict[str, Any]:
    """Keep the scalar metrics (numbers, booleans, strings) as plain Python values."""
    out: dict[str, Any] = {}
    for key, value in metrics.items():
        if hasattr(value, "item") and getattr(value, "ndim", 1) == 0:
            value = value.item()
        if isinstance(value, (bool, int, float, str)):
            out[str(key)] = value
    return out


def execute_run(
    kind_name: str,
    config: dict[str, Any],
    root: str,
    run_id: str,
    studies: tuple[str, ...] = (),
    settings: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """Execute one run in a worker, write its record, and report its outcome (never raises for a run's own error).

    The run function writes to a temporary name; when it returns, the
    output's SHA-256 is taken and the run's record written (atomically), and
    only then is the output renamed to ``runs/<run_id>/<kind.output>``
    (:func:`impedance_mil.fileio.atomic_path`).  So an interrupt at any point
    leaves either nothing, a record without its output (the run is redone on
    resume), or both; never an output without a record.

    Parameters
    ----------
    kind_name : str
        The campaign kind.
    config : dict
        The full run configuration.
    root : str
        The campaign folder.
    run_id : str
        The run name.
    studies : tuple of str
        The studies that asked for the run (for its record).
    settings : mapping, optional
        The run's parameter values (for its record).

    Returns
    -------
    dict
        ``status``, ``metrics``, ``error``, ``hdf5`` (relative path or ""),
        ``sha256``, ``elapsed_s``, ``worker`` and ``recorded`` (whether the
        record was written).
    """
    start = time.perf_counter()
    store = CampaignStore(root)
    outcome: dict[str, Any] = {"status": "ok", "metrics": {}, "error": "", "hdf5": "", "sha256": ""}
    identity: dict[str, Any] = {
        "run_id": run_id,
        "kind": kind_name,
        "studies": tuple(studies),
        "settings": dict(settings or {}),
    }
    recorded: dict[str, Any] | None = None
    try:
        kind = get_kind(kind_name)
        final = store.output_path(run_id, kind.output)
        final.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(final) as partial:
            metrics = _scalar_metrics(kind.run(config, partial))
            outcome.update(hdf5=final.relative_to(store.root).as_posix(), sha256=file_sha256(partial))
            if metrics.get("aborted"):
                outcome["status"] = "aborted"
                outcome["error"] = str(metrics.get("abort_reason", "a safety limit tripped"))
            outcome["metrics"] = metrics
            _stamp(outcome, start)
            store.write_record(RunRecord(**identity, **outcome))  # the record first, then the output
            recorded = dict(outcome)
    except LimitTripped as exc:
        outcome.update(
            status="aborted",
            error=_one_line(exc),
            metrics={"aborted": True, "abort_time_s": exc.time_s, TRIP_LIMIT_KEY: exc.limit},
            hdf5="",
            sha256="",
        )
    except Exception as exc:  # any error of a run is recorded, the campaign goes on
        outcome.update(status="failed", error=_one_line(exc), metrics={}, hdf5="", sha256="")
    if outcome != recorded:  # no output, or its rename failed after the record was written
        _stamp(outcome, start)
        try:
            store.write_record(RunRecord(**identity, **outcome))
            recorded = outcome
        except (OSError, ValueError):  # the records folder is not writable: the engine tries again
            recorded = None
    return {**outcome, "recorded": recorded is not None}


def _stamp(outcome: dict[str, Any], start: float) -> None:
    outcome["elapsed_s"] = time.perf_counter() - start
    outcome["worker"] = f"{socket.gethostname()}:{os.getpid()}"


def _record(run: RunSpec, future: Any) -> tuple[RunRecord, bool]:
    """The record of a finished future, and whether it is already written (by the worker)."""
    try:
        outcome = dict(future.result())
    except cf.CancelledError:
        raise
    except Exception as exc:  # the worker itself died (e.g. BrokenProcessPool) or Dask lost it
        outcome = {"status": "failed", "error": "worker lost: " + _one_line(exc)}
    written = bool(outcome.pop("recorded", False))
    record = RunRecord(
        run_id=run.run_id, kind=run.kind, studies=run.studies, settings=dict(run.settings), **outcome
    )
    return record, written


def _store_record(store: CampaignStore, run: RunSpec, future: Any) -> RunRecord:
    record, written = _record(run, future)
    if not written:
        store.write_record(record)
    return record


def manifest(spec: CampaignSpec) -> dict[str, Any]:
    """The expanded campaign as plain data (written to ``campaign.json``)."""
    return {
        "name": spec.name,
        "kind": spec.kind,
        "title": spec.title,
        "section": spec.section,
        "source": spec.source,
        "reduced": spec.reduced,
        "parameters": list(spec.parameters),
        "runs": [
            {
                "run_id": r.run_id,
                "kind": r.kind,
                "studies": list(r.studies),
                "settings": r.settings,
                "config": r.config,
            }
            for r in spec.runs
        ],
    }


def run_campaign(
    spec: CampaignSpec,
    out_dir: str | Path,
    executor: RunExecutor | None = None,
    on_progress: Callable[[ProgressEvent], None] | None = None,
) -> CampaignResult:
    """Run the pending runs of a campaign and write its records and summary.

    Parameters
    ----------
    spec : CampaignSpec
        From :func:`~impedance_mil.campaign.spec.load_campaign`.
    out_dir : str or Path
        The campaign folder (created; reused to resume).
    executor : RunExecutor, optional
        Where runs execute; default: a local process pool, one worker per core.
        An executor passed in stays the caller's to shut down, except that an
        interrupt cancels its pending runs.
    on_progress : callable, optional
        Called in this process with a :class:`ProgressEvent` after every run.

    Returns
    -------
    CampaignResult

    Raises
    ------
    FolderLockedError
        Another session runs a campaign in ``out_dir`` (nothing is written).
    KeyboardInterrupt
        After cancelling pending runs and writing the summary of what finished.
    OSError
        The campaign folder itself cannot be written.
    """
    store = CampaignStore(out_dir)
    store.create()
    with store.lock():
        store.remove_stale_temporaries()
        store.write_json("campaign.json", manifest(spec))
        skipped = tuple(run.run_id for run in spec.runs if store.is_done(run.run_id))
        todo = [run for run in spec.runs if run.run_id not in set(skipped)]
        own = executor is None
        pool: RunExecutor = make_executor() if executor is None else executor
        try:
            executed = _execute(store, spec, todo, pool, on_progress)
        finally:
            if own:
                pool.shutdown()
        records = tuple(r for r in (store.load_record(run.run_id) for run in spec.runs) if r)
        return CampaignResult(
            root=store.root,
            records=records,
            executed=tuple(executed),
            skipped=skipped,
            summary=write_summary(store, spec),
        )


def _execute(
    store: CampaignStore,
    spec: CampaignSpec,
    todo: list[RunSpec],
    pool: RunExecutor,
    on_progress: Callable[[ProgressEvent], None] | None,
) -> list[str]:
    """Submit the pending runs and record them as they finish; on an interrupt, see :func:`run_campaign`."""
    executed: list[str] = []
    futures: dict[Any, RunSpec] = {}
    try:
        futures = {
            pool.submit(
                execute_run, run.kind, run.config, str(store.root), run.run_id, run.studies, run.settings
            ): run
            for run in todo
        }
        for future in pool.as_completed(futures):
            record = _store_record(store, futures.pop(future), future)
            executed.append(record.run_id)
            if on_progress is not None:
                on_progress(ProgressEvent(len(executed), len(todo), record))
    except KeyboardInterrupt:
        pool.shutdown(cancel=True)
        for future, run in futures.items():
            if (
                future.done()
                and not future.cancelled()
                and not isinstance(future.exception(), KeyboardInterrupt)
            ):
                _store_record(store, run, future)
        write_summary(store, spec)
        raise
    return executed
