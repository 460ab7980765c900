"""The resumable on-disk store of a campaign: run names, records, atomic writes.

Layout of a campaign folder::

    DIR/campaign.json          the expanded campaign (name, kind, runs and their settings)
    DIR/runs/<run_id>/<file>   what each run wrote: run.h5 (a lab run file: frf, tracking,
                               mil), design.json (a design file), poles.h5, selftest.h5
    DIR/records/<run_id>.json  one record per finished run: status, metrics, error
    DIR/summary.csv, DIR/summary.parquet   one row per run (written at the end)

    DIR/.lock                  held by the one process running the campaign (see :meth:`CampaignStore.lock`)

``run_id`` is the first :data:`RUN_ID_LENGTH` hex digits of the sha256 of the
canonical JSON (sorted keys, no spaces) of ``{"kind": ..., "config": ...}``:
the same configuration always lands in the same place, so a campaign that is
interrupted and started again skips every run whose record says ``ok`` or
``aborted`` and whose output is verified: it is inside the folder, it opens,
and its SHA-256 is the one the record holds.  Failed runs, and runs whose
output is missing, truncated or altered, are done again.

Every file is written under a temporary name and renamed, so a crash never
leaves a half-written record or output file under its final name; a run's
record is written *before* its output is renamed into place, so an output
never exists without its record (an interrupt between the two leaves a
record whose output is missing, and the run is redone).  Temporary files a
killed process left are removed when the next session starts.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import h5py

from ..errors import ConfigError, DataFileError
from ..fileio import (
    atomic_write_text,
    file_sha256,
    folder_lock,
    json_safe,
    parse_json,
    read_text,
    remove_stale_temporaries,
)

#: Number of hex digits of the sha256 kept in a run name (48 bits).
RUN_ID_LENGTH = 12

#: Statuses of a finished run.  ``ok`` and ``aborted`` count as done.
STATUSES = ("ok", "aborted", "failed")
DONE_STATUSES = ("ok", "aborted")

#: What a run name may be made of: a single safe path component (the engine makes hex digests).
_RUN_ID_RE = re.compile(r"^[A-Za-z0-9_-]{1,64}$")


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
    sha256 : str
        Hex SHA-256 of the output file as written; empty if none (or a
        record of a version before checksums, whose run is then redone).
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
    sha256: str = ""

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
            Not a record: bad or oversized JSON (:func:`impedance_mil.fileio.parse_json`),
            or missing fields or an unknown status (DataFileError).
        """
        data = parse_json(text, "run record")
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
        """Folder of one run's data.

        Raises
        ------
        ConfigError
            ``run_id`` is not a single safe name (letters, digits, ``-``, ``_``), so
            that no run name read from a file can point outside the campaign folder.
        """
        return self.runs_dir / _checked_id(run_id)

    def output_path(self, run_id: str, name: str) -> Path:
        """Final path of one run's output file ``name`` (e.g. ``run.h5``, the kind's ``output``)."""
        return self.run_dir(run_id) / name

    def record_path(self, run_id: str) -> Path:
        """Path of one run's record."""
        return self.records_dir / f"{_checked_id(run_id)}.json"

    def load_record(self, run_id: str) -> RunRecord | None:
        """The record of a run, or None when absent or unreadable (the run is then redone)."""
        try:
            return RunRecord.from_json(self.record_path(run_id).read_text(encoding="utf-8"))
        except (OSError, ValueError, TypeError):
            return None

    def output_problem(self, record: RunRecord) -> str:
        """Why a done run's output cannot be trusted, or ``""`` when it is verified (or there is none).

        Verified means: the path stays inside the campaign folder, the file
        exists, its SHA-256 is the one the record holds, and it opens as what
        its suffix says (HDF5 for ``.h5``, JSON for ``.json``).
        """
        if not record.hdf5:
            return ""
        # Lexically, so that ".." and absolute paths are caught but a symlinked folder still works.
        root = os.path.normpath(os.path.abspath(self.root))
        path = Path(os.path.normpath(os.path.join(root, record.hdf5)))
        if os.path.commonpath([root, path]) != root or path == Path(root):
            return f"{record.hdf5}: outside the campaign folder"
        if not path.is_file():
            return f"{record.hdf5}: missing"
        if not record.sha256:
            return f"{record.hdf5}: its record holds no checksum (written before checksums were recorded)"
        try:
            if file_sha256(path) != record.sha256:
                return f"{record.hdf5}: checksum differs from its record's (truncated or altered)"
            _open(path)
        except (OSError, ValueError, RuntimeError, KeyError) as exc:  # h5py raises several kinds
            return f"{record.hdf5}: does not open ({' '.join(str(exc).split())[:120]})"
        return ""

    def is_done(self, run_id: str) -> bool:
        """Whether a run finished (ok or aborted) and its output, if any, is verified (:meth:`output_problem`)."""
        record = self.load_record(run_id)
        if record is None or not record.done:
            return False
        return not self.output_problem(record)

    @contextmanager
    def lock(self) -> Iterator[Path]:
        """Hold the folder's lock (``DIR/.lock``): a second campaign session on the folder is refused.

        Raises
        ------
        FolderLockedError
            Another process runs a campaign in this folder.
        """
        with folder_lock(self.root, holder="another imil campaign run") as path:
            yield path

    def remove_stale_temporaries(self) -> list[Path]:
        """Remove the temporary files a killed session left (call while holding :meth:`lock`)."""
        return remove_stale_temporaries(self.root)

    def write_record(self, record: RunRecord) -> None:
        """Write a run's record atomically."""
        atomic_write_text(self.record_path(record.run_id), record.to_json())

    def write_json(self, name: str, data: Any) -> None:
        """Write a JSON file at the top of the campaign folder atomically."""
        atomic_write_text(self.root / name, json.dumps(json_safe(data), indent=1))

    def read_json(self, name: str) -> Any:
        """Read a JSON file at the top of the campaign folder (OSError/ValueError on failure)."""
        path = self.root / name
        return parse_json(path.read_text(encoding="utf-8"), path)


def _checked_id(run_id: str) -> str:
    if not isinstance(run_id, str) or not _RUN_ID_RE.match(run_id):
        raise ConfigError("run_id", "a run name of letters, digits, '-' and '_'", run_id)
    return run_id


def _open(path: Path) -> None:
    """Open an output as what its suffix says (ValueError or OSError when it does not open)."""
    if path.suffix == ".h5":
        with h5py.File(path, "r") as fh:
            fh.visit(lambda name: None)  # walks every group and dataset header
    elif path.suffix == ".json":
        parse_json(read_text(path, "a JSON file"), path)
