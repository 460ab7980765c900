"""Recording files by format: the column readers and writers behind :mod:`impedance_mil.signals.recordings`.

Each reader returns the named columns, as float vectors in the file's units, and
the sample rate when the file states one (an HDF5 ``rate_hz`` attribute, a TDMS
``wf_increment``); the checks and the unit conversion are the caller's.
"""

from __future__ import annotations

import io
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import scipy.io

from ..bounds import MAX_RECORDING_FILE_BYTES
from ..errors import ConfigError, DataFileError, MissingDependencyError
from ..fileio import read_text

#: Formats written by :func:`write_columns`.
WRITTEN = ("csv", "mat", "hdf5")
#: Suffixes of each format.
FORMATS = {
    ".csv": "csv",
    ".txt": "csv",
    ".h5": "hdf5",
    ".hdf5": "hdf5",
    ".hdf": "hdf5",
    ".mat": "mat",
    ".tdms": "tdms",
}
_DELIMITERS = (",", ";", "\t")


def recording_format(path: str | Path) -> str:
    """The format of a recording from its suffix (:data:`FORMATS`)."""
    fmt = FORMATS.get(Path(path).suffix.lower())
    if fmt is None:
        raise DataFileError(path, "unknown recording format: expected " + ", ".join(sorted(FORMATS)))
    return fmt


def _csv_columns(path: Path) -> dict[str, np.ndarray]:
    """Columns of a CSV with one header line of names (``#`` comment lines before it are skipped)."""
    text = read_text(path, "a CSV recording", max_bytes=MAX_RECORDING_FILE_BYTES)
    lines = text.split("\n")
    start = next((i for i, ln in enumerate(lines) if ln.strip() and not ln.lstrip().startswith("#")), None)
    if start is None:
        raise DataFileError(path, "empty file: expected a header line of column names, then data")
    header = lines[start]
    delimiter = next((d for d in _DELIMITERS if d in header), None)
    names = [n.strip().strip('"') for n in (header.split(delimiter) if delimiter else header.split())]
    if len(set(names)) != len(names) or not all(names):
        raise DataFileError(path, f"line {start + 1}: expected a header of distinct column names")
    body = "\n".join(ln for ln in lines[start + 1 :] if ln.strip() and not ln.lstrip().startswith("#"))
    if not body:  # before numpy, which would warn "input contained no data" (a second stderr line)
        raise DataFileError(path, "no data rows after the header")
    try:
        data = np.loadtxt(io.StringIO(body), delimiter=delimiter, ndmin=2, dtype=float)
    except ValueError:
        raise DataFileError(path, _first_bad_row(lines, start, delimiter, len(names))) from None
    if data.shape[0] == 0:
        raise DataFileError(path, "no data rows after the header")
    if data.shape[1] != len(names):
        raise DataFileError(path, f"{data.shape[1]} columns of data under a header of {len(names)} names")
    return {name: data[:, i] for i, name in enumerate(names)}


def _first_bad_row(lines: list[str], start: int, delimiter: str | None, n_columns: int) -> str:
    for number in range(start + 1, len(lines)):
        line = lines[number].strip()
        if not line or line.startswith("#"):
            continue
        cells = [c.strip() for c in (line.split(delimiter) if delimiter else line.split())]
        if len(cells) != n_columns:
            return f"line {number + 1}: {len(cells)} values, expected {n_columns} (one per header name)"
        for cell in cells:
            try:
                float(cell)
            except ValueError:
                return f"line {number + 1}: non-numeric value {cell!r}"
    return "unreadable data rows"


def _vector(path: Path, column: str, value: Any) -> np.ndarray:
    array = np.asarray(value)
    if array.dtype.kind not in "biuf" or array.ndim > 2 or (array.ndim == 2 and min(array.shape) != 1):
        raise DataFileError(path, f"{column!r} is not a numeric vector (shape {array.shape})")
    return array.astype(float).ravel()


def _hdf5_columns(path: Path, columns: Sequence[str]) -> tuple[dict[str, np.ndarray], float | None]:
    """Datasets of an HDF5 file (MATLAB v7.3 included: variables at the root, struct fields as groups)."""
    out, rate = {}, None
    try:
        with h5py.File(path, "r") as fh:
            for column in columns:
                key = column.replace(".", "/")
                node = fh.get(key)
                if not isinstance(node, h5py.Dataset):
                    raise DataFileError(path, f"no dataset {column!r} (has: {', '.join(_hdf5_names(fh))})")
                out[column] = _vector(path, column, node[()])
                for attr in ("rate_hz", "sample_rate_hz"):
                    if attr in node.attrs and rate is None:
                        rate = float(node.attrs[attr])
    except OSError as exc:
        raise DataFileError(path, f"cannot read as HDF5 ({exc})") from None
    return out, rate


def _hdf5_names(fh: h5py.File, limit: int = 20) -> list[str]:
    names: list[str] = []
    fh.visititems(lambda name, node: names.append(name) if isinstance(node, h5py.Dataset) else None)
    return [n for n in names if not n.startswith("#")][:limit]


def _is_mat73(path: Path) -> bool:
    with open(path, "rb") as fh:
        head = fh.read(128)
    return head.startswith(b"MATLAB 7.3") or (h5py.is_hdf5(path) and not head.startswith(b"MATLAB 5.0"))


def _mat_columns(path: Path, columns: Sequence[str]) -> dict[str, np.ndarray]:
    """Variables (``acc``) or struct fields (``rec.acc``) of a MATLAB v5 or v7.3 file."""
    if _is_mat73(path):
        return _hdf5_columns(path, columns)[0]
    try:
        data = scipy.io.loadmat(path, squeeze_me=True, struct_as_record=False)
    except (ValueError, TypeError, OSError, NotImplementedError) as exc:
        raise DataFileError(path, f"not a readable MATLAB file ({exc})") from None
    names = [k for k in data if not k.startswith("__")]
    out = {}
    for column in columns:
        node: Any = data
        for part in re.split(r"[./]", column):
            node = node.get(part) if isinstance(node, dict) else getattr(node, part, None)
            if node is None:
                raise DataFileError(path, f"no variable {column!r} (has: {', '.join(names)})")
        out[column] = _vector(path, column, node)
    return out


def _tdms_columns(path: Path, columns: Sequence[str]) -> tuple[dict[str, np.ndarray], float | None]:
    """Channels of an NI TDMS file (``group/channel`` or a unique channel name); rate from ``wf_increment``."""
    try:
        from nptdms import TdmsFile  # an optional extra: imported only when a TDMS file is read
    except ImportError:
        raise MissingDependencyError(
            f"{path}: reading TDMS needs the optional package npTDMS (pip install impedance-mil[recordings])"
        ) from None
    try:
        tdms = TdmsFile.read(path)
    except Exception as exc:  # npTDMS raises many types for a bad file
        raise DataFileError(path, f"not a readable TDMS file ({exc})") from None
    found = {f"{g.name}/{c.name}": c for g in tdms.groups() for c in g.channels()}
    out, rate = {}, None
    for column in columns:
        matches = [c for key, c in found.items() if key == column or key.split("/", 1)[1] == column]
        if len(matches) != 1:
            problem = "no channel" if not matches else "more than one channel named"
            raise DataFileError(path, f"{problem} {column!r} (has: {', '.join(found)})")
        channel = matches[0]
        out[column] = _vector(path, column, channel[:])
        increment = channel.properties.get("wf_increment")
        if increment and rate is None:
            rate = 1.0 / float(increment)
    return out, rate


def read_columns(path: Path, fmt: str, columns: Sequence[str]) -> tuple[dict[str, np.ndarray], float | None]:
    """The named columns of a recording of format ``fmt`` [the file's units], and the rate the file states."""
    if fmt == "csv":
        table = _csv_columns(path)
        missing = [c for c in columns if c not in table]
        if missing:
            raise DataFileError(path, f"no column {missing[0]!r} (columns: {', '.join(table)})")
        return {c: table[c] for c in columns}, None
    if fmt == "hdf5":
        return _hdf5_columns(path, columns)
    if fmt == "mat":
        return _mat_columns(path, columns), None
    return _tdms_columns(path, columns)


def write_columns(path: Path, fmt: str, columns: Mapping[str, np.ndarray]) -> None:
    """Write named columns [the file's units] to ``path`` in format ``fmt`` (``.csv``, ``.mat``, ``.h5``)."""
    if fmt == "csv":
        with open(path, "w", encoding="utf-8") as fh:
            np.savetxt(
                fh,
                np.column_stack(list(columns.values())),
                delimiter=",",
                fmt="%.17g",
                header=",".join(columns),
                comments="",
            )
    elif fmt == "mat":
        with open(path, "wb") as fh:  # a file object: savemat would append ".mat" to the name
            scipy.io.savemat(fh, {name: a.reshape(-1, 1) for name, a in columns.items()}, format="5")
    elif fmt == "hdf5":
        with h5py.File(path, "w") as fh:
            for name, a in columns.items():
                fh.create_dataset(name, data=a)
    else:
        raise ConfigError("-o", "a .csv, .mat or .h5 file (TDMS is read, not written)", fmt)
