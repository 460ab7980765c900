"""The resumable on-disk store of a campaign: run names, records, atomic writes.

Layout of a campaign folder::

    DIR/campaign.json          the expanded campaign (name, kind, runs and their settings)
    DIR/runs/<run_id>/<file>   what each run wrote: run.h5 (a lab run file: frf, tracking,
                               mil), design.json (a design file), poles.h5, selftest.h5
    DIR/records/<run_id>.json  one record per finished run: status, metrics, error
    DIR/summary.csv, DIR/summary.parquet   one row per run (written at the end)

``run_id`` is the first :data:`RUN_ID_LENGTH` hex digits of the sha256 of the
canonical JSON (sorted keys, no spaces) of ``{"kind": ..., "config": ...}``:
the same configuration always lands in the same place, so a campaign that is
interrupted and started again skips every run whose record says ``ok`` or
``aborted`` (and whose output file is there); failed runs are tried again.
Every file is written under a temporary name and renamed, so a crash never
leaves a half-written record or output file under its final name.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from ..errors import DataFileError
from ..fileio import atomic_write_text, json_safe

#: Number of hex digits of the sha256 kept in a run name (48 bits).
RUN_ID_LENGTH = 12

#: Statuses of a finished run.  ``ok`` and ``aborted`` count as done.
STATUSES = ("ok", "aborted", "failed")
DONE_STATUSES = ("ok", "aborted")


def canonical_json(obj: Any) -> str:
    """JSON with sorted keys and no whitespace; NaN and infinity are refused.

    Raises
    ------
    ValueError
        The object holds NaN or infinity (they have no canonical JSON form).
    """
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), ensure_ascii=True, allow_nan=False)


def run_id_for(kind: str, config: Mapping[str, Any]) -> str:
    """The run name of a configuration: a short sha256 prefix of its canonical JSON.

    Examples
    --------
    >>> run_id_for("selftest", {"a": 1.0}) == run_id_for("selftest", {"a": 1.0})
    True
    >>> len(run_id_for("selftest", {"a": 1.0}))
    12
    """
    text = canonical_json({"kind": kind, "config": config})
    return hashlib.sha256(text.encode("ascii")).hexdigest()[:RUN_ID_LENGTH]


@dataclass(frozen=True)
class RunRecord:
    """What is known about one finished run.

    Attributes
    ----------
    run_id : str
        The run name (hash of its configuration).
    kind : str
        The campaign kind.
    studies : tuple of str
        Studies that asked for the run.
    settings : dict
        Parameter values (internal units).
    status : str
        ``"ok"``, ``"aborted"`` (a safety limit tripped, a legitimate outcome) or ``"failed"``.
    metrics : dict
        Metric name -> number returned by the run function (empty when failed).
    error : str
        Why the run failed or aborted, one line; empty when ok.
    hdf5 : str
        Path of the run's output file (see the module docstring; the name is
        historical) relative to the campaign folder; empty if none.
    elapsed_s : float
        Wall-clock time of the run [s].
    worker : str
        ``host:pid`` of the process that ran it.
    """

    run_id: str
    kind: str
    studies: tuple[str, ...]
    settings: dict[str, Any]
    status: str
    metrics: dict[str, Any] = field(default_factory=dict)
    error: str = ""
    hdf5: str = ""
    elapsed_s: float = 0.0
    worker: str = ""

    @property
    def done(self) -> bool:
        """Whether the run counts as completed (``ok`` or ``aborted``)."""
        return self.status in DONE_STATUSES

    def to_json(self) -> str:
        """The record as JSON (NaN and infinity become null)."""
        return json.dumps(json_safe(asdict(self)), indent=1, sort_keys=True)

    @classmethod
    def from_json(cls, text: str) -> RunRecord:
        """Parse a record written by :meth:`to_json`.

        Raises
        ------
        ValueError
            Not a record: bad JSON (json.JSONDecodeError), or missing fields or an
            unknown status (DataFileError).
        """
        data = json.loads(text)
        if not isinstance(data, dict) or data.get("status") not in STATUSES:
            raise DataFileError("run record", "not a run record (a JSON object with a known status)")
        data["studies"] = tuple(data.get("studies", ()))
        return cls(**data)


class CampaignStore:
    """The files of one campaign folder (see the module docstring for the layout).

    Parameters
    ----------
    root : Path
        The campaign output folder (created when needed).
    """

    def __init__(self, root: str | Path):
        self.root = Path(root)
        self.runs_dir = self.root / "runs"
        self.records_dir = self.root / "records"

    def create(self) -> None:
        """Create the folder layout (idempotent)."""
        self.runs_dir.mkdir(parents=True, exist_ok=True)
        self.records_dir.mkdir(parents=True, exist_ok=True)

    def run_dir(self, run_id: str) -> Path:
        """Folder of one run's data."""
        return self.runs_dir / run_id

    def output_path(self, run_id: str, name: str) -> Path:
        """Final path of one run's output file ``name`` (e.g. ``run.h5``, the kind's ``output``)."""
        return self.run_dir(run_id) / name

    def record_path(self, run_id: str) -> Path:
        """Path of one run's record."""
        return self.records_dir / f"{run_id}.json"

    def load_record(self, run_id: str) -> RunRecord | None:
        """The record of a run, or None when absent or unreadable (the run is then redone)."""
        try:
            return RunRecord.from_json(self.record_path(run_id).read_text(encoding="utf-8"))
        except (OSError, ValueError, TypeError):
            return None

    def is_done(self, run_id: str) -> bool:
        """Whether a run finished (ok or aborted) and its output file, if any, is present."""
        record = self.load_record(run_id)
        if record is None or not record.done:
            return False
        return not record.hdf5 or (self.root / record.hdf5).is_file()

    def write_record(self, record: RunRecord) -> None:
        """Write a run's record atomically."""
        atomic_write_text(self.record_path(record.run_id), record.to_json())

    def write_json(self, name: str, data: Any) -> None:
        """Write a JSON file at the top of the campaign folder atomically."""
        atomic_write_text(self.root / name, json.dumps(json_safe(data), indent=1))

    def read_json(self, name: str) -> Any:
        """Read a JSON file at the top of the campaign folder (OSError/ValueError on failure)."""
        return json.loads((self.root / name).read_text(encoding="utf-8"))
