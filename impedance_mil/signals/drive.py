"""Drive files out: what the lab's controller plays, and the metadata that reads the response back.

A drive is one signal at the controller's loop rate, in the lab's unit: the
position command ``u`` of a multisine test (report Section 4.5.2), or the ground
acceleration ``a_g`` of a tracking or MIL test (Section 8.2, the motion the RMC
program reads from a curve, Figure 7.9).  :func:`write_drive` writes two files
into a folder:

* ``DIR/<kind>.csv``, the samples, in one of :data:`FILE_FORMATS`:

  - ``csv``: a header ``time_s,<channel>_<unit>`` then one row per loop;
  - ``rmc75e``: the layout of a data curve for the RMC75E's curve tool
    (report Section 7.3, Figure 7.7: ``Curve Start Advanced`` with the curve's X
    in seconds, ``CRV_INTERP_Y(id, deltat*count, 0)`` in Figure 7.9): two columns,
    X = time [s] and Y = value, comma-separated, no header.  This layout follows
    the report's use of curves; check it against your RMCTools version's curve
    import before the test.

* ``DIR/<kind>.json``, the metadata (:class:`DriveFile`): the kind, the rate,
  the number of samples, the channel and its unit, the scale, the multisine's
  excited lines and periods (or the motion's scaling and pre-test check), the
  SHA-256 of the data file, and the provenance (software version, table, the
  values taken from the report's setup).

:func:`read_drive` reads the metadata back and :func:`check_recording` checks a
recording against it (rate, length, excited lines) before an identification.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ..config import quantity
from ..errors import ConfigError, DataFileError
from ..fileio import atomic_write_text, file_sha256, json_safe, read_text
from .multisine import Multisine

#: Format tag of a drive metadata file.
DRIVE_FORMAT = "impedance-mil drive 1"
#: Layouts of the data file.
FILE_FORMATS = ("csv", "rmc75e")
#: Kinds of drive and the channel each plays (signals.recordings.CHANNELS).
KINDS = {"multisine": "u", "motion": "a_g"}
#: Internal unit of each played channel.
CHANNEL_UNITS = {"u": "inch", "a_g": "inch / second**2"}
#: Smallest share of the recorded command's power at the drive's lines (after the transient period).
MIN_LINE_POWER = 0.9
#: Relative tolerance on the rate of a recording against its drive.
RATE_RTOL = 1e-6


def unit_factor(channel: str, unit: str, key: str = "--units") -> float:
    """Factor from the lab's ``unit`` to the internal unit of ``channel`` (``g`` is standard gravity)."""
    internal = CHANNEL_UNITS[channel]
    text = "g0" if internal.startswith("inch / second") and unit.strip().lower() == "g" else unit
    try:
        return quantity(key, f"1 {text}", internal, "positive")
    except ConfigError:
        raise ConfigError(key, f"a unit of the same dimension as {internal}", unit) from None


@dataclass(frozen=True)
class DriveFile:
    """The metadata of a drive (``DIR/<kind>.json``).

    Attributes
    ----------
    kind : str
        ``"multisine"`` or ``"motion"``.
    channel : str
        The channel played (``u`` [in] or ``a_g`` [in/s^2]).
    unit : str
        Unit of the values in the data file (the lab's).
    factor : float
        Internal units per file unit (value_internal = factor * value_file).
    sample_rate_hz : float
        Controller loop rate [Hz].
    n_samples : int
        Samples in the data file.
    data_file : str
        Name of the data file, beside the metadata.
    file_format : str
        One of :data:`FILE_FORMATS`.
    sha256 : str
        Checksum of the data file.
    multisine : mapping
        For a multisine: ``lines`` (FFT bins of one period), ``n_points``,
        ``n_periods``, ``discard_periods``, ``f_min_hz``, ``f_max_hz``, ``peak``
        (internal unit), ``crest_factor``, ``phases``.
    motion : mapping
        For a motion: its name, source, scaling, rate and pre-test check.
    provenance : mapping
        Software version, table, the values taken from the report's setup.
    """

    kind: str
    channel: str
    unit: str
    factor: float
    sample_rate_hz: float
    n_samples: int
    data_file: str
    file_format: str
    sha256: str
    multisine: Mapping[str, Any] = field(default_factory=dict)
    motion: Mapping[str, Any] = field(default_factory=dict)
    provenance: Mapping[str, Any] = field(default_factory=dict)

    @property
    def lines(self) -> np.ndarray:
        """Excited FFT bins of one multisine period."""
        return np.asarray(self.multisine.get("lines", ()), dtype=int)

    @property
    def n_points(self) -> int:
        return int(self.multisine["n_points"])

    @property
    def n_periods(self) -> int:
        return int(self.multisine["n_periods"])

    @property
    def discard_periods(self) -> int:
        return int(self.multisine.get("discard_periods", 1))

    def to_dict(self) -> dict[str, Any]:
        return json_safe(
            {
                "format": DRIVE_FORMAT,
                "kind": self.kind,
                "channel": self.channel,
                "unit": self.unit,
                "factor_to_internal": self.factor,
                "sample_rate_hz": self.sample_rate_hz,
                "n_samples": self.n_samples,
                "duration_s": self.n_samples / self.sample_rate_hz,
                "data_file": self.data_file,
                "file_format": self.file_format,
                "sha256": self.sha256,
                "multisine": dict(self.multisine),
                "motion": dict(self.motion),
                "provenance": dict(self.provenance),
            }
        )


def multisine_metadata(ms: Multisine, phases: str) -> dict[str, Any]:
    """What a multisine drive's metadata records of the signal (lines, periods, band, peak, crest factor)."""
    f = ms.frequencies_hz
    return {
        "lines": ms.lines.tolist(),
        "n_points": ms.n_points,
        "n_periods": ms.n_periods,
        "discard_periods": 1,
        "period_s": ms.n_points / ms.sample_rate_hz,
        "f_min_hz": float(f.min()),
        "f_max_hz": float(f.max()),
        "n_lines": int(ms.lines.size),
        "peak": float(np.max(np.abs(ms.period))),
        "crest_factor": ms.crest_factor,
        "phases": phases,
    }


def _data_text(values: np.ndarray, rate_hz: float, header: str | None) -> str:
    t = np.arange(values.size) / rate_hz
    rows = "\n".join(f"{ti:.9g},{vi:.12g}" for ti, vi in zip(t, values))
    return (header + "\n" if header else "") + rows + "\n"


def write_drive(
    directory: str | Path,
    kind: str,
    values: np.ndarray,
    *,
    sample_rate_hz: float,
    unit: str,
    file_format: str = "csv",
    multisine: Mapping[str, Any] | None = None,
    motion: Mapping[str, Any] | None = None,
    provenance: Mapping[str, Any] | None = None,
    overwrite: bool = False,
) -> DriveFile:
    """Write ``DIR/<kind>.csv`` and ``DIR/<kind>.json`` (data first, metadata last, each atomically).

    Parameters
    ----------
    directory : str or Path
        The folder to write into: an existing one, or a new one in an existing
        folder (created here, and removed again if the write fails).
    kind : {"multisine", "motion"}
    values : ndarray
        The signal at the loop rate, internal units (``u`` [in] or ``a_g`` [in/s^2]).
    sample_rate_hz : float
        Loop rate [Hz].
    unit : str
        The lab's unit for the data file (``"mm"``, ``"g"`` ...).
    file_format : {"csv", "rmc75e"}
    multisine, motion, provenance : mapping, optional
        What the metadata records (see :class:`DriveFile`).
    overwrite : bool
        Replace existing drive files of this kind.

    Raises
    ------
    ConfigError
        Unknown kind or format, a unit of the wrong dimension, a missing folder,
        or existing files without ``overwrite``.
    """
    if kind not in KINDS:
        raise ConfigError("kind", "one of " + ", ".join(KINDS), kind)
    if file_format not in FILE_FORMATS:
        raise ConfigError("--format", "one of " + ", ".join(FILE_FORMATS), file_format)
    folder = Path(directory)
    check_drive_folder(folder)
    channel = KINDS[kind]
    factor = unit_factor(channel, unit)
    data_path, meta_path = folder / f"{kind}.csv", folder / f"{kind}.json"
    for path in (data_path, meta_path):
        if path.exists() and not overwrite:
            raise ConfigError(
                "-o", f"a folder without {path.name} (or --overwrite to replace it)", str(folder)
            )
    created = not folder.exists()
    if created:
        folder.mkdir()
    try:
        return _write_drive_files(
            folder,
            kind,
            channel,
            values,
            sample_rate_hz,
            unit,
            factor,
            file_format,
            multisine,
            motion,
            provenance,
        )
    except BaseException:
        if created:  # nothing half-written: the folder this call made goes with its files
            for path in (data_path, meta_path):
                path.unlink(missing_ok=True)
            folder.rmdir()
        raise


def check_drive_folder(folder: Path) -> None:
    """Refuse an output path that is neither a folder nor a new name in an existing folder.

    Raises
    ------
    ConfigError
        Naming ``-o``.
    """
    if folder.is_dir() or (not folder.exists() and folder.parent.is_dir()):
        return
    raise ConfigError("-o", "a folder, or a new folder's name in an existing folder", str(folder))


def _write_drive_files(
    folder: Path,
    kind: str,
    channel: str,
    values: Any,
    sample_rate_hz: float,
    unit: str,
    factor: float,
    file_format: str,
    multisine: Mapping[str, Any] | None,
    motion: Mapping[str, Any] | None,
    provenance: Mapping[str, Any] | None,
) -> DriveFile:
    """Write the data file, then the metadata (the data file removed if the metadata fails)."""
    data_path, meta_path = folder / f"{kind}.csv", folder / f"{kind}.json"
    header = None if file_format == "rmc75e" else f"time_s,{channel}_{unit.replace(' ', '')}"
    atomic_write_text(data_path, _data_text(np.asarray(values, float) / factor, sample_rate_hz, header))
    drive = DriveFile(
        kind,
        channel,
        unit,
        factor,
        float(sample_rate_hz),
        int(np.asarray(values).size),
        data_path.name,
        file_format,
        file_sha256(data_path),
        dict(multisine or {}),
        dict(motion or {}),
        {"software_version": __version__, **dict(provenance or {})},
    )
    try:
        atomic_write_text(meta_path, json.dumps(drive.to_dict(), indent=2) + "\n")
    except BaseException:
        data_path.unlink(missing_ok=True)
        raise
    return drive


def read_drive(path: str | Path) -> DriveFile:
    """Read and check a drive's metadata file (``DIR/<kind>.json``).

    Raises
    ------
    DataFileError
        Not JSON, not a drive file, a missing or inconsistent entry (lines
        outside the period, a data file whose checksum changed).
    """
    p = Path(path)
    try:
        doc = json.loads(read_text(p, "a drive metadata file (JSON)", max_bytes=1 << 24))
    except json.JSONDecodeError as exc:
        raise DataFileError(p, f"not JSON ({exc})") from None
    if not isinstance(doc, dict) or doc.get("format") != DRIVE_FORMAT:
        raise DataFileError(p, f"not an impedance-mil drive file (format {DRIVE_FORMAT!r})")
    try:
        drive = DriveFile(
            kind=str(doc["kind"]),
            channel=str(doc["channel"]),
            unit=str(doc["unit"]),
            factor=float(doc["factor_to_internal"]),
            sample_rate_hz=float(doc["sample_rate_hz"]),
            n_samples=int(doc["n_samples"]),
            data_file=str(doc["data_file"]),
            file_format=str(doc["file_format"]),
            sha256=str(doc["sha256"]),
            multisine=doc.get("multisine") or {},
            motion=doc.get("motion") or {},
            provenance=doc.get("provenance") or {},
        )
    except (KeyError, TypeError, ValueError) as exc:
        raise DataFileError(p, f"missing or malformed entry {exc}") from None
    if drive.kind not in KINDS or not (drive.sample_rate_hz > 0 and drive.n_samples > 0):
        raise DataFileError(p, "kind, sample_rate_hz or n_samples out of range")
    if drive.kind == "multisine":
        _check_multisine(p, drive)
    data = p.parent / drive.data_file
    if data.is_file() and file_sha256(data) != drive.sha256:
        raise DataFileError(data, f"changed since {p.name} was written (SHA-256 differs)")
    return drive


def _check_multisine(path: Path, drive: DriveFile) -> None:
    try:
        n_points, n_periods, lines = drive.n_points, drive.n_periods, drive.lines
    except (KeyError, TypeError, ValueError):
        raise DataFileError(path, "multisine: expected lines, n_points and n_periods") from None
    if n_points < 4 or n_periods < 1 or n_points * n_periods != drive.n_samples:
        raise DataFileError(path, f"multisine: n_points x n_periods is not n_samples ({drive.n_samples})")
    if lines.size == 0 or lines.min() < 1 or lines.max() >= n_points // 2:
        raise DataFileError(path, f"multisine: lines must lie in 1 .. {n_points // 2 - 1}")
    if not 0 <= drive.discard_periods < n_periods:
        raise DataFileError(path, "multisine: discard_periods must be fewer than n_periods")


def check_recording(
    drive: DriveFile, drive_name: str, recording_path: Path, rate_hz: float, command=None
) -> None:
    """Refuse a recording that does not match its drive: rate, length, and the lines the command excites.

    Parameters
    ----------
    drive : DriveFile
    drive_name : str
        The metadata file, for messages.
    recording_path : Path
        The recording, for messages.
    rate_hz : float
        The recording's sample rate [Hz].
    command : array_like, optional
        The recorded command (``u``, internal units); its power must lie at the
        drive's lines (at least :data:`MIN_LINE_POWER` of it, after the first period).

    Raises
    ------
    DataFileError
        Naming the recording and the drive file.
    """
    if abs(rate_hz - drive.sample_rate_hz) > RATE_RTOL * drive.sample_rate_hz:
        raise DataFileError(
            recording_path,
            f"sample rate {rate_hz:.9g} Hz, but {drive_name} was played at {drive.sample_rate_hz:.9g} Hz",
        )
    if command is None:
        return
    u = np.asarray(command, dtype=float)
    if u.size != drive.n_samples:
        raise DataFileError(
            recording_path,
            f"{u.size} samples, but {drive_name} has {drive.n_samples} (drive and recording must match)",
        )
    if drive.kind != "multisine":
        return
    n = drive.n_points
    periods = u[drive.discard_periods * n :].reshape(-1, n)
    spectrum = np.mean(np.abs(np.fft.rfft(periods, axis=1)) ** 2, axis=0)
    total = float(np.sum(spectrum[1:]))
    share = float(np.sum(spectrum[drive.lines]) / total) if total > 0 else 0.0
    if share < MIN_LINE_POWER:
        raise DataFileError(
            recording_path,
            f"the recorded command has {100 * share:.1f} % of its power at the {drive.lines.size} lines of "
            f"{drive_name} (expected at least {100 * MIN_LINE_POWER:g} %): not the drive that was played",
        )


def read_drive_values(drive: DriveFile, folder: Path) -> np.ndarray:
    """The drive's samples in internal units, from its data file (beside the metadata)."""
    path = folder / drive.data_file
    text = read_text(path, "a drive data file", max_bytes=1 << 30)
    lines = [ln for ln in text.split("\n") if ln.strip()]
    if drive.file_format == "csv":
        lines = lines[1:]
    try:
        values = np.array([float(ln.split(",")[1]) for ln in lines])
    except (IndexError, ValueError):
        raise DataFileError(path, "expected rows of time, value") from None
    if values.size != drive.n_samples:
        raise DataFileError(path, f"{values.size} samples, the metadata says {drive.n_samples}")
    return values * drive.factor
