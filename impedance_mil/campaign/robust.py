"""``imil simulate --robust N``: N labs sampled from the uncertainty set, run as a campaign (issue 17, item 3).

Each run is the user's MIL test (the same choices: lab, VS, motion, article,
controller) on the table of one point of a seeded Latin-hypercube sample of
the lab's ``[uncertainty]`` set, with the controller designed for the
*nominal* table (:func:`impedance_mil.lab.robust.sampled_test`): what a real
table whose parameters are off by that much would do with the design.  The
runs go through the campaign engine (:func:`~impedance_mil.campaign.engine.run_campaign`,
kind ``robust-mil``, any :class:`~impedance_mil.campaign.executors.RunExecutor`);
a run's configuration is the user's choices as plain data and its point.

A run is *unstable* when its record's trip cause (:class:`~impedance_mil.lab.trips.TripCause`,
read from the ``trip_limit`` metric, never from a message) is any cause: a
divergence, a NaN, or an interlock the oscillation reached first.  The worst
run is the unstable one that tripped earliest, else the one with the largest
high-frequency ratio ``hf_ratio`` (:mod:`impedance_mil.campaign.runmetrics`).
"""

from __future__ import annotations

import math
import shutil
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import ConfigError
from ..fileio import atomic_path
from ..lab.choices import Choices
from ..lab.descriptions import TrackingTest
from ..lab.robust import require_uncertainty
from ..lab.trips import TRIP_LIMIT_KEY, TripCause
from .engine import ProgressEvent, run_campaign
from .executors import RunExecutor
from .robustkind import KIND, choices_config
from .spec import CampaignSpec, RunSpec
from .store import RunRecord, run_id_for


@dataclass(frozen=True)
class SampledRun:
    """One run of the robust campaign.

    Attributes
    ----------
    run_id : str
    point : mapping of str to float
        The point of the set (internal units; ``extra_delay`` in loops).
    status : str
        ``ok``, ``aborted`` (tripped) or ``failed`` (an error, see ``error``).
    cause : TripCause
        Why it stopped (``NONE``: it completed).
    trip_time_s : float or None
        When [s].
    hf_ratio : float or None
        High-frequency rms ratio of the run (None without metrics).
    error : str
    """

    run_id: str
    point: Mapping[str, float]
    status: str
    cause: TripCause
    trip_time_s: float | None
    hf_ratio: float | None
    error: str

    @property
    def unstable(self) -> bool:
        return self.cause is not TripCause.NONE

    def severity(self) -> tuple[float, float]:
        """Sort key, largest worst: a trip (earlier worse), then the high-frequency ratio."""
        if self.unstable:
            return (1.0, -(self.trip_time_s if self.trip_time_s is not None else math.inf))
        return (0.0, self.hf_ratio if self.hf_ratio is not None else -math.inf)

    def to_dict(self) -> dict[str, Any]:
        names = {"extra_delay": "extra_delay_loops", "valve_poles_hz": "valve_poles_factor"}
        return {
            "run_id": self.run_id,
            "parameters": {names.get(k, k): float(v) for k, v in self.point.items()},
            "status": self.status,
            "trip": None if not self.unstable else {"limit": self.cause.label, "time_s": self.trip_time_s},
            "hf_ratio": self.hf_ratio,
            "error": self.error or None,
        }


@dataclass(frozen=True)
class RobustCampaign:
    """What ``simulate --robust N`` found.

    Attributes
    ----------
    runs : tuple of SampledRun
        In sample order.
    seed : int
        Seed of the Latin-hypercube sample.
    worst : SampledRun or None
        The worst run (None: every run failed).
    worst_file : Path or None
        Where its run file was saved.
    """

    runs: tuple[SampledRun, ...]
    seed: int
    worst: SampledRun | None
    worst_file: Path | None

    @property
    def unstable_fraction(self) -> float:
        """Fraction of the runs that tripped or diverged (failed runs count in the total)."""
        return sum(r.unstable for r in self.runs) / len(self.runs) if self.runs else 0.0

    def causes(self) -> dict[str, int]:
        """Number of runs per trip cause (``none``: completed)."""
        out: dict[str, int] = {}
        for r in self.runs:
            if r.status != "failed":
                out[r.cause.label] = out.get(r.cause.label, 0) + 1
        return out

    def to_dict(self) -> dict[str, Any]:
        return {
            "runs_count": len(self.runs),
            "seed": self.seed,
            "sample": "Latin hypercube of the lab's [uncertainty] box, nominal design on each table",
            "unstable_fraction": self.unstable_fraction,
            "failed_count": sum(r.status == "failed" for r in self.runs),
            "causes": {f"{k}_count": v for k, v in self.causes().items()},
            "worst": None if self.worst is None else self.worst.to_dict(),
            "worst_file": None if self.worst_file is None else str(self.worst_file),
            "runs": [r.to_dict() for r in self.runs],
        }


def _sampled(record: RunRecord, point: Mapping[str, float]) -> SampledRun:
    metrics = record.metrics
    label = metrics.get(TRIP_LIMIT_KEY)
    cause = TripCause.from_label(label) if label else TripCause.NONE
    time_s = metrics.get("trip_time_s", metrics.get("abort_time_s"))
    hf = metrics.get("hf_ratio")
    return SampledRun(
        record.run_id,
        dict(point),
        record.status,
        cause,
        None if time_s is None else float(time_s),
        None if hf is None else float(hf),
        record.error,
    )


def run_robust_campaign(
    choices: Choices,
    test: TrackingTest,
    n: int,
    seed: int,
    folder: Path,
    output: Path,
    executor: RunExecutor | None = None,
    on_progress: Callable[[ProgressEvent], None] | None = None,
) -> RobustCampaign:
    """Run ``n`` MIL tests sampled from ``test``'s uncertainty set in ``folder``; save the worst to ``output``.

    Parameters
    ----------
    choices : Choices
        The user's choices of the MIL test (``test`` was made from them).
    test : TrackingTest
        The nominal test (its lab's ``uncertainty`` is sampled).
    n : int
        Number of runs (Latin-hypercube points).
    seed : int
        Seed of the sample.
    folder : Path
        The campaign folder (records, run files).
    output : Path
        Where the worst run's file is copied.
    executor : RunExecutor, optional
        Default a local process pool (:func:`~impedance_mil.campaign.executors.make_executor`).
    on_progress : callable, optional
        Called after every run (:class:`~impedance_mil.campaign.engine.ProgressEvent`).
    """
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ConfigError("--robust", "a positive number of sampled runs", n)
    uncertainty = require_uncertainty(test.lab.uncertainty, "--robust")
    points = uncertainty.latin_hypercube(n, seed)
    base = choices_config(choices)
    runs = []
    for i, point in enumerate(points):
        config = {"choices": base, "point": point, "index": i}
        runs.append(RunSpec(run_id_for(KIND, config), KIND, ("robust",), dict(point), config))
    spec = CampaignSpec(
        "robust",
        KIND,
        "imil simulate --robust",
        "",
        "imil simulate --robust",
        False,
        tuple(runs),
        uncertainty.keys,
    )
    result = run_campaign(spec, folder, executor, on_progress)
    by_id = {r.run_id: r for r in result.records}
    sampled = tuple(
        _sampled(by_id[r.run_id], r.settings)
        if r.run_id in by_id
        else SampledRun(r.run_id, r.settings, "failed", TripCause.NONE, None, None, "not run")
        for r in runs
    )
    candidates = [r for r in sampled if r.status != "failed"]
    worst = max(candidates, key=SampledRun.severity) if candidates else None
    saved = None
    if worst is not None and by_id[worst.run_id].hdf5:
        with atomic_path(output) as partial:
            shutil.copyfile(Path(result.root) / by_id[worst.run_id].hdf5, partial)
        saved = output
    return RobustCampaign(sampled, seed, worst, saved)
