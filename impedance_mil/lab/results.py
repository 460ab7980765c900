"""Results of a virtual-lab run and their HDF5 files.

A :class:`RunResult` holds every recorded channel (``CHANNELS`` of
:mod:`impedance_mil.lab.structures`), the VS states, how the run ended (a
:class:`~impedance_mil.lab.trips.Trip` when a safety limit stopped it; the
data up to the trip are kept) and the full configuration.  The file stores a
trip's cause by name and code (``trip_json``); files written before the code
was stored carry the name only and load the same.  :func:`save_run` writes one HDF5 file per
run (with any extra attributes and groups of the caller), to a temporary name
renamed into place; :func:`load_run` reads it back.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Mapping
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import h5py
import numpy as np

from .. import __version__
from ..errors import ConfigError, DataFileError
from ..fileio import atomic_path, json_safe, parse_json
from .structures import CHANNELS
from .trips import Trip, TripCause

#: Format tag written in every run file.
FILE_FORMAT = "impedance-mil run 1"
#: Root attributes and groups of a run file (``save_run``'s extras may not replace them).
RUN_ATTRS = ("format", "software_version", "mode", "loop_time_s", "config_json", "trip_json", "data_sha256")
RUN_GROUPS = ("channels", "vs_states")
#: How channels are stored: contiguous, uncompressed (issue 16).  Measured on a 600 s MIL run
#: (22 channels and the VS states, 1.2 million float64 samples each, 230 MB; the table is in
#: docs/lab.md, "Run files"): gzip level 4 took 8.6 s of CPU to save 41 %, shuffle+lzf 3.1 s
#: to save 44 %, uncompressed 0.1 s.  Full-precision channels compress little, so a run file
#: is written at disk speed; h5py reads compressed and uncompressed datasets alike, so files
#: written before (gzip channels) read as they did.
CHANNEL_STORAGE: Mapping[str, Any] = MappingProxyType({})
#: Suffixes of a run file (HDF5); ``imil simulate -o r.xyz`` is refused, not written as HDF5 under another name.
RUN_FILE_SUFFIXES = (".h5", ".hdf5")


@dataclass(frozen=True, eq=False)
class RunResult:
    """Every channel of one run, named (``result.x``, ``result.u_w`` ...).

    Attributes
    ----------
    channels : dict of str to ndarray
        One array per entry of ``CHANNELS`` (units: s, in/s^2, in, V, mA,
        in/s, psi, lbf), one sample per loop.
    vs_states : ndarray (n, n_vs)
        VS state at the start of each loop (empty without a VS).
    vs_state_names : tuple of str
        Names of the VS states.
    mode : str
        ``"open"``, ``"track"`` or ``"mil"``.
    loop_time : float
        Loop time [s].
    trip : Trip or None
        Safety trip that ended the run, if any.
    config : dict
        Full configuration (JSON-serializable).
    software_version : str
        impedance-mil version that produced the run.
    """

    channels: dict
    vs_states: np.ndarray
    vs_state_names: tuple
    mode: str
    loop_time: float
    trip: Trip | None = None
    config: dict = field(default_factory=dict)
    software_version: str = __version__

    def __getattr__(self, name):
        channels = self.__dict__.get("channels", {})
        if name in channels:
            return channels[name]
        raise AttributeError(f"RunResult has no channel or attribute {name!r}")

    @property
    def completed(self) -> bool:
        """True when no safety limit tripped."""
        return self.trip is None

    @property
    def n_samples(self) -> int:
        return int(self.channels["t"].size)

    def raise_if_tripped(self) -> RunResult:
        """Raise :class:`LimitTripped` if a limit stopped the run; else return self."""
        if self.trip is not None:
            raise self.trip.as_exception()
        return self


def save_run(
    result: RunResult,
    path: str | Path,
    extra_attrs: Mapping[str, Any] | None = None,
    extra_groups: Mapping[str, Mapping[str, Any]] | None = None,
) -> Path:
    """Write ``result`` to an HDF5 file atomically (temporary name, then rename); return the path.

    Parameters
    ----------
    result : RunResult
        The run.
    path : str or Path
        Target file (its folder is created when needed).
    extra_attrs : mapping of str to str or number, optional
        Further attributes of the file's root (e.g. a caller's JSON summary).
    extra_groups : mapping of str to mapping, optional
        Further groups, ``{group: {dataset: array}}``; a nested mapping in
        place of an array becomes a subgroup.

    Everything, extras included, is written under the temporary name, so an
    interrupted write leaves nothing under ``path``.

    Raises
    ------
    ConfigError
        An extra attribute or group would replace one of the run file's own (a ValueError).
    """
    extra_attrs, extra_groups = checked_extras(extra_attrs, extra_groups)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    # The checksum is computed beside the write (hashlib releases the GIL): on a 600 s run
    # (230 MB) SHA-256 takes about 0.13 s, half of what HDF5 and the fsync take (docs/lab.md).
    with (
        ThreadPoolExecutor(max_workers=1, thread_name_prefix="imil-run-digest") as digests,
        atomic_path(path) as tmp,
        h5py.File(tmp, "w") as f,
    ):
        digest = digests.submit(data_digest, result.channels, result.vs_states)
        write_records(f, result.channels, result.vs_states)
        write_run_attrs(f, result, digest.result(), extra_attrs, extra_groups)
    return path


def checked_extras(
    extra_attrs: Mapping[str, Any] | None, extra_groups: Mapping[str, Mapping[str, Any]] | None
) -> tuple[dict[str, Any], dict[str, Mapping[str, Any]]]:
    """``save_run``'s extras as dicts; ConfigError (a ValueError) if one would replace a run file's own entry."""
    extra_attrs, extra_groups = dict(extra_attrs or {}), dict(extra_groups or {})
    clash = sorted(set(extra_attrs) & set(RUN_ATTRS)) + sorted(set(extra_groups) & set(RUN_GROUPS))
    if clash:
        raise ConfigError(f"extra entry {clash[0]!r}", "a name other than the run file's own entries")
    return extra_attrs, extra_groups


def write_records(
    f: h5py.File,
    channels: Mapping[str, np.ndarray] | None,
    vs_states: np.ndarray,
    *,
    shape_only: bool = False,
) -> dict[str, h5py.Dataset]:
    """Create the run file's records (:data:`RUN_GROUPS`): the channels, then the VS states.

    ``shape_only``: the datasets are made at their full size and left for the
    caller to fill (a run file written as the run goes,
    :class:`impedance_mil.lab.run_stream.RunFileStream`).  Returns them by name.
    """
    grp = f.create_group("channels")
    made = {}
    for name, arr in (channels or {}).items():
        if shape_only:
            made[name] = grp.create_dataset(name, shape=arr.shape, dtype=arr.dtype, **CHANNEL_STORAGE)
        else:
            made[name] = grp.create_dataset(name, data=arr, **CHANNEL_STORAGE)
    if shape_only:
        made["vs_states"] = f.create_dataset("vs_states", shape=vs_states.shape, dtype=vs_states.dtype)
    else:
        made["vs_states"] = f.create_dataset("vs_states", data=vs_states)
    return made


def write_run_attrs(
    f: h5py.File,
    result: RunResult,
    digest: str,
    extra_attrs: Mapping[str, Any],
    extra_groups: Mapping[str, Mapping[str, Any]],
) -> None:
    """The run file's attributes (``digest``: :func:`data_digest` of the records), then the extras."""
    f.attrs["format"] = FILE_FORMAT
    f.attrs["software_version"] = result.software_version
    f.attrs["mode"] = result.mode
    f.attrs["loop_time_s"] = result.loop_time
    f.attrs["config_json"] = json.dumps(json_safe(result.config), default=repr)
    f.attrs["trip_json"] = json.dumps(json_safe(_trip_record(result.trip)))
    f["vs_states"].attrs["names"] = json.dumps(list(result.vs_state_names))
    f.attrs["data_sha256"] = digest
    f.attrs.update(extra_attrs)
    _write_groups(f, extra_groups)


def data_digest(channels: Mapping[str, np.ndarray], vs_states: np.ndarray) -> str:
    """SHA-256 of a run's records: every channel (name, dtype, shape, bytes) in name order, then the VS states.

    Stored at write time as ``data_sha256`` and checked by :func:`load_run`, so a
    file damaged after it was written (a truncated copy, zeroed blocks that still
    decompress) is refused instead of plotted.
    """
    h = hashlib.sha256()
    for name in sorted(channels):
        arr = np.ascontiguousarray(channels[name])
        h.update(f"{name}:{arr.dtype.str}:{arr.shape}".encode())
        h.update(_raw_bytes(arr))
    states = np.ascontiguousarray(vs_states)
    h.update(f"vs_states:{states.dtype.str}:{states.shape}".encode())
    h.update(_raw_bytes(states))
    return h.hexdigest()


def _raw_bytes(arr: np.ndarray) -> memoryview:
    """The bytes of a C-contiguous array, as ``arr.tobytes()`` gives them, without copying them."""
    return arr.reshape(-1).view(np.uint8).data


def _check_records(
    path: Path, channels: Mapping[str, np.ndarray], vs_states: np.ndarray, stored: Any
) -> None:
    """Shapes (one length for every record) and, when the file has one, the stored checksum."""
    lengths = {name: arr.shape for name, arr in channels.items()}
    n = vs_states.shape[0] if vs_states.ndim == 2 else None
    bad = [name for name, shape in lengths.items() if len(shape) != 1 or shape[0] != n]
    if n is None or bad:
        where = bad[0] if bad else "vs_states"
        raise DataFileError(path, f"{where}: records of unequal length (the file is damaged)")
    if stored is not None and str(stored) != data_digest(channels, vs_states):
        raise DataFileError(
            path, "data_sha256: the records do not match the checksum written with them (the file is damaged)"
        )


def _trip_record(trip: Trip | None) -> dict | None:
    """The ``trip_json`` entry: the cause by name (``limit``) and code (``cause``)."""
    if trip is None:
        return None
    return {"limit": trip.limit, "cause": int(trip.cause), "time_s": trip.time_s, "value": trip.value}


def _trip_from_record(path: Path, record: Mapping[str, Any]) -> Trip:
    """The :class:`Trip` of a ``trip_json`` entry (the name decides; a stored code must agree)."""
    try:
        cause = TripCause.from_label(record["limit"])
    except ValueError as exc:
        raise DataFileError(path, f"trip_json: {exc}") from exc
    if "cause" in record and record["cause"] != int(cause):
        raise DataFileError(
            path, f"trip_json: cause code {record['cause']!r} does not match limit {record['limit']!r}"
        )
    value = record["value"]  # None: a non-finite value (JSON has no NaN)
    return Trip(cause, float(record["time_s"]), math.nan if value is None else float(value))


def attr_json(path: str | Path, attrs: Mapping[str, Any], key: str) -> Any:
    """The JSON text of HDF5 attribute ``key``, parsed with the caps of :func:`impedance_mil.fileio.parse_json`.

    Raises
    ------
    DataFileError
        Not JSON, nested too deep, or a number that is not a finite double
        (the message names the file and the attribute).
    KeyError
        No such attribute.
    """
    raw = attrs[key]
    text = raw.decode("utf-8", "replace") if isinstance(raw, bytes) else str(raw)
    return parse_json(text, f"{path}: {key}")


def _write_groups(parent: h5py.Group, groups: Mapping[str, Mapping[str, Any]]) -> None:
    for name, entries in groups.items():
        group = parent.create_group(name)
        for key, value in entries.items():
            if isinstance(value, Mapping):
                _write_groups(group, {key: value})
            else:
                group.create_dataset(key, data=np.asarray(value))


def load_run(path: str | Path) -> RunResult:
    """Read a run file written by :func:`save_run`."""
    path = Path(path)
    try:
        with h5py.File(path, "r") as f:
            if f.attrs.get("format") != FILE_FORMAT:
                raise DataFileError(path, f"not an impedance-mil run file (format {FILE_FORMAT!r})")
            stored = {name: np.asarray(f["channels"][name]) for name in f["channels"]}
            vs_states = np.asarray(f["vs_states"])
            # Files written before checksums (software 0.1.0 before issue 18) have none: shapes only.
            _check_records(path, stored, vs_states, f.attrs.get("data_sha256"))
            channels = {name: stored[name] for name in CHANNELS if name in stored}
            trip = attr_json(path, f.attrs, "trip_json")
            return RunResult(
                channels=channels,
                vs_states=vs_states,
                vs_state_names=tuple(attr_json(path, f["vs_states"].attrs, "names")),
                mode=str(f.attrs["mode"]),
                loop_time=float(f.attrs["loop_time_s"]),
                trip=None if trip is None else _trip_from_record(path, trip),
                config=attr_json(path, f.attrs, "config_json"),
                software_version=str(f.attrs["software_version"]),
            )
    except OSError as exc:
        raise DataFileError(path, f"cannot read HDF5 run file ({exc})") from exc
    except KeyError as exc:
        raise DataFileError(path, f"missing entry {exc}") from exc
