"""The summary table of a campaign: one row per run, as CSV and Parquet.

Columns, in order: ``run_id``, ``study`` (studies joined with ``;``),
``status`` (``ok``, ``aborted``, ``failed`` or ``not run``), ``error``,
``hdf5`` (path relative to the campaign folder), ``elapsed_s``, then every
parameter of the campaign (internal units, named as in the campaign file),
then every metric the runs returned.  A metric whose name clashes with an
earlier column is written as ``metric:<name>``.

The Parquet file needs :mod:`pyarrow`; without it only the CSV is written.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import DataFileError, MissingDependencyError
from ..fileio import atomic_write_bytes, atomic_write_text, read_text
from .spec import CampaignSpec
from .store import CampaignStore

try:  # pyarrow writes the Parquet copy of the summary
    import pyarrow
    import pyarrow.parquet as parquet
except ImportError:  # pragma: no cover - depends on the environment
    pyarrow = None
    parquet = None

#: The fixed leading columns of a summary table.
FIXED_COLUMNS = ("run_id", "study", "status", "error", "hdf5", "elapsed_s")

#: Status of a run of the campaign that has no record yet.
NOT_RUN = "not run"


@dataclass(frozen=True)
class SummaryPaths:
    """The summary files written (``parquet`` is None without pyarrow)."""

    csv: Path
    parquet: Path | None


@dataclass(frozen=True)
class SummaryTable:
    """Rows of a campaign summary, with typed values.

    Attributes
    ----------
    columns : tuple of str
        Column names in order.
    rows : tuple of dict
        One mapping per run (missing values are None).
    parameters : tuple of str
        The parameter columns.
    metrics : tuple of str
        The metric columns.
    """

    columns: tuple[str, ...]
    rows: tuple[dict[str, Any], ...]
    parameters: tuple[str, ...] = ()
    metrics: tuple[str, ...] = ()

    def __len__(self) -> int:
        return len(self.rows)

    def where(self, **criteria: Any) -> SummaryTable:
        """Rows whose columns equal the given values (numbers to 1e-9 relative).

        ``study=NAME`` matches rows that belong to that study among others.
        """
        kept = tuple(row for row in self.rows if all(_matches(row, k, v) for k, v in criteria.items()))
        return SummaryTable(self.columns, kept, self.parameters, self.metrics)

    def column(self, name: str) -> list[Any]:
        """All values of one column (None where missing)."""
        return [row.get(name) for row in self.rows]

    def values(self, name: str) -> list[float]:
        """The finite numeric values of one column."""
        out = []
        for value in self.column(name):
            if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value):
                out.append(float(value))
        return out


def _matches(row: Mapping[str, Any], key: str, wanted: Any) -> bool:
    value = row.get(key)
    if key == "study" and isinstance(value, str):
        return wanted in value.split(";")
    if isinstance(wanted, float) and isinstance(value, (int, float)) and not isinstance(value, bool):
        return math.isclose(value, wanted, rel_tol=1e-9)
    return value == wanted


def summary_table(store: CampaignStore, spec_or_manifest: CampaignSpec | Mapping[str, Any]) -> SummaryTable:
    """Build the summary of a campaign from its store (records and the expanded campaign).

    Parameters
    ----------
    store : CampaignStore
        The campaign folder.
    spec_or_manifest : CampaignSpec or mapping
        The campaign, or the content of its ``campaign.json``.
    """
    if isinstance(spec_or_manifest, CampaignSpec):
        params = list(spec_or_manifest.parameters)
        runs = [(r.run_id, r.studies, r.settings) for r in spec_or_manifest.runs]
    else:
        params = list(spec_or_manifest.get("parameters", []))
        runs = [
            (r["run_id"], tuple(r.get("studies", ())), r.get("settings", {}))
            for r in spec_or_manifest.get("runs", [])
        ]
    rows, metric_names = [], {}
    taken = set(FIXED_COLUMNS) | set(params)
    for run_id, studies, settings in runs:
        record = store.load_record(run_id)
        row: dict[str, Any] = {
            "run_id": run_id,
            "study": ";".join(studies),
            "status": NOT_RUN,
            "error": "",
            "hdf5": "",
            "elapsed_s": None,
        }
        row.update({p: settings.get(p) for p in params})
        if record is not None:
            row.update(status=record.status, error=record.error, hdf5=record.hdf5, elapsed_s=record.elapsed_s)
            for name, value in record.metrics.items():
                column = f"metric:{name}" if name in taken else name
                metric_names[column] = None
                row[column] = value
        rows.append(row)
    metrics = tuple(metric_names)
    columns = FIXED_COLUMNS + tuple(params) + metrics
    full = tuple({c: row.get(c) for c in columns} for row in rows)
    return SummaryTable(columns, full, tuple(params), metrics)


def write_summary(store: CampaignStore, spec: CampaignSpec) -> SummaryPaths:
    """Write ``summary.csv`` (and ``summary.parquet`` with pyarrow) atomically."""
    table = summary_table(store, spec)
    csv_path = store.root / "summary.csv"
    atomic_write_text(csv_path, to_csv(table))
    parquet_path = None
    if parquet is not None:
        parquet_path = store.root / "summary.parquet"
        atomic_write_bytes(parquet_path, to_parquet_bytes(table))
    return SummaryPaths(csv_path, parquet_path)


def _verify_outputs(store: CampaignStore, run_ids: list[str]) -> None:
    for run_id in run_ids:
        record = store.load_record(run_id)
        problem = store.output_problem(record) if record is not None and record.done else ""
        if problem:
            raise DataFileError(
                store.root, f"run {run_id}: {problem}; run the campaign again on this folder to redo it"
            )


def to_csv(table: SummaryTable) -> str:
    """The table as CSV text (floats at full precision, missing values empty)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(table.columns)
    for row in table.rows:
        writer.writerow(["" if row.get(c) is None else _cell(row.get(c)) for c in table.columns])
    return buffer.getvalue()


def _cell(value: Any) -> str:
    return repr(value) if isinstance(value, float) else str(value)


def _arrow_column(values: list[Any]) -> Any:
    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present):
        return pyarrow.array(values, type=pyarrow.bool_())
    if present and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in present):
        return pyarrow.array([None if v is None else float(v) for v in values], type=pyarrow.float64())
    return pyarrow.array([None if v is None else str(v) for v in values], type=pyarrow.string())


def to_parquet_bytes(table: SummaryTable) -> bytes:
    """The table as a Parquet file (bool, float64 or string columns).

    Raises
    ------
    MissingDependencyError
        pyarrow is not installed (a RuntimeError).
    """
    if parquet is None:
        raise MissingDependencyError("writing Parquet needs pyarrow")
    arrow = pyarrow.table({c: _arrow_column(table.column(c)) for c in table.columns})
    sink = pyarrow.BufferOutputStream()
    parquet.write_table(arrow, sink)
    return sink.getvalue().to_pybytes()


def _parse_cell(text: str) -> Any:
    if text == "":
        return None
    if text in ("True", "False"):
        return text == "True"
    try:
        return float(text)
    except ValueError:
        return text


def read_csv_summary(path: Path) -> SummaryTable:
    """Read a ``summary.csv`` written by :func:`write_summary` (numbers parsed as floats).

    Raises
    ------
    DataFileError
        The file is missing or lacks the fixed columns.
    """
    text = read_text(path, "a campaign summary (CSV)")
    reader = csv.reader(io.StringIO(text))
    header = next(reader, [])
    if tuple(header[: len(FIXED_COLUMNS)]) != FIXED_COLUMNS:
        raise DataFileError(
            path, "not a campaign summary (columns " + ", ".join(FIXED_COLUMNS) + " expected)"
        )
    rows = []
    for cells in reader:
        row = {c: _parse_cell(v) for c, v in zip(header, cells)}
        for key in ("run_id", "study", "status", "error", "hdf5"):
            row[key] = "" if row.get(key) is None else str(row[key])
        rows.append(row)
    return SummaryTable(tuple(header), tuple(rows))


def load_summary(folder: str | Path) -> SummaryTable:
    """The summary of a campaign folder: from its records when present, else its ``summary.csv``.

    With records, every done run's output is verified first
    (:meth:`CampaignStore.output_problem`: inside the folder, present, its
    checksum the recorded one, opens), so that nothing is reported over a
    truncated or altered file.

    Raises
    ------
    DataFileError
        The folder holds neither ``campaign.json`` nor ``summary.csv``, or a
        done run's output does not verify (running the campaign again redoes it).
    """
    store = CampaignStore(folder)
    if (store.root / "campaign.json").is_file():
        try:
            manifest = store.read_json("campaign.json")
            table = summary_table(store, manifest)
        except (ValueError, KeyError, TypeError):
            raise DataFileError(store.root / "campaign.json", "not a campaign manifest") from None
        _verify_outputs(store, [row["run_id"] for row in table.rows])
        return table
    if (store.root / "summary.csv").is_file():
        return read_csv_summary(store.root / "summary.csv")
    raise DataFileError(folder, "not a campaign folder (no campaign.json or summary.csv)")
