"""Recorded lab data in: one reader for CSV, HDF5, MATLAB .mat (v5 and v7.3) and NI TDMS.

A *recording* is a file of sampled channels written by the lab's controller or
data-acquisition system.  A *channel map* says which column holds which of the
toolkit's channels, and in which unit::

    u=cmd[mm]  z=table_accel[g]  x=lvdt[mm]  w=force[kN]  a_g=ag[g]  t=time[s]

on the command line (``--channel``, repeatable), or as a small TOML file::

    [channels]
    u = "cmd[mm]"
    z = "table_accel[g]"
    [recording]
    rate = "2000 Hz"        # needed only when no time channel is mapped

Units are converted at the edge, by dimension (pint, :func:`impedance_mil.config.quantity`),
into the internal units of :data:`CHANNELS`; ``g`` on an acceleration channel is
standard gravity (``g0``).  A column is a CSV header name, an HDF5 dataset path
(``run/acc``), a MATLAB variable or struct field (``rec.acc``), or a TDMS
``group/channel`` (or a channel name that is unique in the file).

:func:`read_recording` checks, and refuses with one line naming the file and
channel (:class:`~impedance_mil.errors.DataFileError`) or the map entry
(:class:`~impedance_mil.errors.ConfigError`):

* a mapped column that the file does not have;
* an unknown unit, or a unit of the wrong dimension;
* channels of unequal length;
* a time channel with a gap or non-uniform steps, or a sample rate other than
  the expected one (the drive file's, the loop rate);
* NaN or infinite samples;
* a clipped channel (samples at the reading limit of the lab's sensor for that
  quantity, ``ranges``), unless ``allow_clipped``: the clipped channels are then
  listed in :attr:`Recording.clipped`.

The sensor ranges come from the caller (``impedance_mil.lab.recorded.sensor_ranges``
turns a :class:`~impedance_mil.specimens.sensors.SensorSuite` into them), so the
lab's own sensors decide what "clipped" means.

TDMS needs the optional package ``npTDMS`` (``pip install impedance-mil[recordings]``);
MATLAB v7.3 files are HDF5 and are read with h5py.
The formats themselves are read and written by
:mod:`impedance_mil.signals.recording_files`.
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..bounds import MAX_RECORD_SAMPLES, MAX_RECORDING_FILE_BYTES
from ..config import quantity, read_toml
from ..errors import ConfigError, DataFileError
from ..fileio import atomic_path
from .recording_files import WRITTEN, read_columns, recording_format, write_columns

#: Channels of a recording: internal unit and meaning.
CHANNELS: dict[str, tuple[str, str]] = {
    "t": ("second", "time [s]"),
    "u": ("inch", "position command u [in]"),
    "a_g": ("inch / second**2", "ground acceleration a_g [in/s^2]"),
    "z": ("inch / second**2", "measured table acceleration z [in/s^2]"),
    "x": ("inch", "measured table displacement x [in]"),
    "dp": ("psi", "measured differential pressure dP [psi]"),
    "w": ("force_pound", "measured test-article force w [lbf]"),
    "z_vs": ("inch / second**2", "target acceleration the controller computed z_vs [in/s^2]"),
}
#: Name of each dimension in messages.
_DIMENSION = {
    "second": "time (s, ms)",
    "inch": "length (in, mm, m)",
    "inch / second**2": "acceleration (g, m/s**2, in/s**2)",
    "psi": "pressure (psi, bar, MPa)",
    "force_pound": "force (lbf, kip, N, kN)",
}
#: Largest deviation of a time sample from the uniform grid, as a fraction of the step.
UNIFORM_RTOL = 0.01
#: Largest relative difference between the recording's rate and the expected one.
RATE_RTOL = 1e-6

_SPEC_RE = re.compile(r"^\s*([A-Za-z_][A-Za-z_0-9]*)\s*=\s*(.+?)\s*\[([^\[\]]+)\]\s*$")


@dataclass(frozen=True)
class ChannelSpec:
    """One entry of a channel map: toolkit channel, the file's column, the file's unit.

    Attributes
    ----------
    channel : str
        A key of :data:`CHANNELS` (``"z"``).
    column : str
        Column, dataset, variable or ``group/channel`` in the file.
    unit : str
        Unit of the column (pint; ``g`` is standard gravity on an acceleration).
    """

    channel: str
    column: str
    unit: str

    @property
    def text(self) -> str:
        """The entry as written on the command line, ``z=acc[g]``."""
        return f"{self.channel}={self.column}[{self.unit}]"

    @property
    def factor(self) -> float:
        """Factor from the file's unit to the internal unit of the channel."""
        internal = CHANNELS[self.channel][0]
        unit = self.unit.strip()
        if internal == "inch / second**2" and unit.lower() == "g":
            unit = "g0"  # pint's g is the gram
        try:
            return quantity(self.text, f"1 {unit}", internal, "positive")
        except ConfigError:
            raise ConfigError(
                f"channel {self.text}", f"a unit of {_DIMENSION[internal]}", self.unit
            ) from None


def parse_channel(text: str, key: str = "--channel") -> ChannelSpec:
    """``"z=table_accel[g]"`` -> :class:`ChannelSpec` (the unit is checked here).

    Raises
    ------
    ConfigError
        Not ``NAME=COLUMN[UNIT]``, an unknown channel name, or a unit of the wrong dimension.
    """
    match = _SPEC_RE.match(str(text))
    if match is None:
        raise ConfigError(key, "NAME=COLUMN[UNIT], e.g. z=table_accel[g]", text)
    name, column, unit = match.groups()
    if name not in CHANNELS:
        raise ConfigError(f"{key} {text}", "a channel among " + ", ".join(CHANNELS), name)
    spec = ChannelSpec(name, column.strip(), unit.strip())
    _ = spec.factor
    return spec


@dataclass(frozen=True)
class ChannelMap:
    """Which column is which channel, and the sample rate when there is no time channel.

    Attributes
    ----------
    specs : tuple of ChannelSpec
    rate_hz : float or None
        Sample rate [Hz] (None: from the time channel or the file).
    source : str
        Where the map came from (``--channel`` or a file name).
    """

    specs: tuple[ChannelSpec, ...]
    rate_hz: float | None = None
    source: str = "--channel"

    def __post_init__(self):
        names = [s.channel for s in self.specs]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ConfigError(f"{self.source} {dup[0]}", "each channel mapped once")

    @classmethod
    def parse(cls, items: Sequence[str], rate: Any = None, key: str = "--channel") -> ChannelMap:
        """From ``--channel`` items and an optional rate (``"2000 Hz"`` or a number in Hz)."""
        rate_hz = None if rate is None else quantity("--rate", rate, "hertz", "positive")
        return cls(tuple(parse_channel(item, key) for item in items), rate_hz, key)

    @classmethod
    def from_toml(cls, path: str | Path) -> ChannelMap:
        """From a TOML file with a ``[channels]`` table (``z = "acc[g]"``) and an optional ``[recording] rate``."""
        data = read_toml(path)
        name = Path(path).name
        table = data.get("channels")
        if not isinstance(table, Mapping) or not table:
            raise DataFileError(path, 'expected a [channels] table, e.g. z = "table_accel[g]"')
        unknown = sorted(set(data) - {"channels", "recording"})
        if unknown:
            raise ConfigError(f"{name}: {unknown[0]}", "the sections [channels] and [recording]")
        specs = tuple(parse_channel(f"{k}={v}", f"{name}: channels.{k}") for k, v in table.items())
        rec = data.get("recording", {})
        extra = sorted(set(rec) - {"rate"}) if isinstance(rec, Mapping) else ["recording"]
        if extra:
            raise ConfigError(f"{name}: recording.{extra[0]}", "the key rate (sample rate, e.g. '2000 Hz')")
        rate = rec.get("rate")
        rate_hz = None if rate is None else quantity(f"{name}: recording.rate", rate, "hertz", "positive")
        return cls(specs, rate_hz, name)

    def merged(self, other: ChannelMap) -> ChannelMap:
        """This map with ``other``'s entries added (a channel in both is refused)."""
        return ChannelMap(self.specs + other.specs, other.rate_hz or self.rate_hz, self.source)

    def spec(self, channel: str) -> ChannelSpec | None:
        return next((s for s in self.specs if s.channel == channel), None)

    def require(self, channels: Sequence[str], why: str) -> None:
        """Refuse a map without one of ``channels`` (needed for ``why``)."""
        missing = [c for c in channels if self.spec(c) is None]
        if missing:
            raise ConfigError(
                "--channel",
                f"a map of {', '.join(channels)} for {why} (e.g. {missing[0]}=COLUMN[UNIT])",
                ", ".join(s.text for s in self.specs) or "no channel",
            )


@dataclass(frozen=True)
class SensorRange:
    """Reading limits of the lab's sensor for one channel, internal units.

    Attributes
    ----------
    low, high : float
        Lowest and highest value the sensor can read.
    resolution : float
        One quantization step (samples within half a step of a limit are clipped).
    sensor : str
        The sensor's name, for messages.
    """

    low: float
    high: float
    resolution: float
    sensor: str


@dataclass(frozen=True)
class ClippedChannel:
    """A channel with samples at its sensor's reading limit."""

    channel: str
    column: str
    sensor: str
    n_samples: int
    first_time_s: float
    limit: float

    def text(self) -> str:
        return (
            f"channel {self.channel} (column {self.column!r}) is clipped: {self.n_samples} samples at the "
            f"{self.sensor} limit {self.limit:.6g} from t = {self.first_time_s:.4f} s"
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "channel": self.channel,
            "column": self.column,
            "sensor": self.sensor,
            "n_samples": self.n_samples,
            "first_time_s": self.first_time_s,
            "limit": self.limit,
        }


@dataclass(frozen=True, eq=False)
class Recording:
    """A checked recording, every channel in internal units (:data:`CHANNELS`).

    Attributes
    ----------
    path : Path
    format : str
        ``csv``, ``hdf5``, ``mat`` or ``tdms``.
    sample_rate_hz : float
        [Hz].
    channels : dict of str to ndarray
        Mapped channels (no ``t``: see :attr:`time`).
    specs : tuple of ChannelSpec
        The map it was read with.
    clipped : tuple of ClippedChannel
        Channels accepted although clipped (``allow_clipped``).
    """

    path: Path
    format: str
    sample_rate_hz: float
    channels: dict
    specs: tuple
    clipped: tuple = field(default=())

    @property
    def n_samples(self) -> int:
        return int(next(iter(self.channels.values())).size)

    @property
    def time_step(self) -> float:
        """Sample interval [s]."""
        return 1.0 / self.sample_rate_hz

    @property
    def time(self) -> np.ndarray:
        """Sample times from 0 [s]."""
        return np.arange(self.n_samples) / self.sample_rate_hz

    @property
    def duration_s(self) -> float:
        return self.n_samples / self.sample_rate_hz

    def provenance(self) -> dict[str, Any]:
        """What was read, from where and how (for run files and identification reports)."""
        return {
            "file": str(self.path),
            "format": self.format,
            "sample_rate_hz": self.sample_rate_hz,
            "n_samples": self.n_samples,
            "channels": {s.channel: {"column": s.column, "unit": s.unit} for s in self.specs},
            "clipped": [c.to_dict() for c in self.clipped],
        }


# ------------------------------------------------------------------ checks
def _check_time(path: Path, spec: ChannelSpec, t: np.ndarray) -> float:
    """The sample rate [Hz] of a uniform time channel; a gap or jitter is refused naming the sample."""
    where = f"channel t (column {spec.column!r})"
    if t.size < 2:
        raise DataFileError(path, f"{where}: fewer than 2 samples")
    steps = np.diff(t)
    dt = (t[-1] - t[0]) / (t.size - 1)
    if not dt > 0 or np.any(steps <= 0):
        k = int(np.flatnonzero(steps <= 0)[0]) if np.any(steps <= 0) else 0
        raise DataFileError(path, f"{where}: time does not increase at sample {k + 1} (t = {t[k + 1]:.9g} s)")
    median = float(np.median(steps))
    gaps = np.flatnonzero(steps > 1.5 * median)
    if gaps.size:
        k = int(gaps[0])
        raise DataFileError(
            path,
            f"{where}: a gap of {steps[k]:.6g} s after t = {t[k]:.9g} s (sample {k}; the step is "
            f"{median:.6g} s); {gaps.size} gap(s) in all",
        )
    deviation = np.abs(t - (t[0] + dt * np.arange(t.size)))
    worst = int(np.argmax(deviation))
    if deviation[worst] > UNIFORM_RTOL * dt:
        raise DataFileError(
            path,
            f"{where}: non-uniform sampling: sample {worst} at t = {t[worst]:.9g} s is {deviation[worst]:.3g} s "
            f"off the grid of dt = {dt:.9g} s (tolerance {UNIFORM_RTOL:g} dt)",
        )
    return 1.0 / dt


def _check_finite(path: Path, specs: Sequence[ChannelSpec], data: Mapping[str, np.ndarray], rate: float):
    for spec in specs:
        bad = np.flatnonzero(~np.isfinite(data[spec.channel]))
        if bad.size:
            k = int(bad[0])
            raise DataFileError(
                path,
                f"channel {spec.channel} (column {spec.column!r}): {bad.size} NaN or infinite sample(s), "
                f"the first at sample {k} (t = {k / rate:.6g} s)",
            )


def clipped_channels(
    recording_channels: Mapping[str, np.ndarray],
    specs: Sequence[ChannelSpec],
    ranges: Mapping[str, SensorRange],
    sample_rate_hz: float,
) -> list[ClippedChannel]:
    """Channels with samples within half a resolution step of their sensor's reading limits."""
    found = []
    for spec in specs:
        sensor = ranges.get(spec.channel)
        if sensor is None:
            continue
        values = recording_channels[spec.channel]
        margin = 0.5 * sensor.resolution
        for limit, hit in (
            (sensor.high, values >= sensor.high - margin),
            (sensor.low, values <= sensor.low + margin),
        ):
            if np.any(hit):
                first = int(np.argmax(hit))
                found.append(
                    ClippedChannel(
                        spec.channel,
                        spec.column,
                        sensor.sensor,
                        int(np.count_nonzero(hit)),
                        first / sample_rate_hz,
                        limit,
                    )
                )
    return found


def read_recording(
    path: str | Path,
    channel_map: ChannelMap,
    *,
    expected_rate_hz: float | None = None,
    rate_source: str = "",
    ranges: Mapping[str, SensorRange] | None = None,
    allow_clipped: bool = False,
) -> Recording:
    """Read and check a recording (see the module docstring for every check).

    Parameters
    ----------
    path : str or Path
        The file (``.csv``, ``.h5``, ``.mat``, ``.tdms``).
    channel_map : ChannelMap
        Which column is which channel, and its unit.
    expected_rate_hz : float, optional
        The rate the recording must have [Hz] (the drive file's, or the loop rate);
        also the rate when neither a time channel nor the map nor the file gives one.
    rate_source : str
        What ``expected_rate_hz`` is, for the message (``"the drive file d.json"``).
    ranges : mapping of str to SensorRange, optional
        Reading limits of the lab's sensors, by channel (no clipping check without).
    allow_clipped : bool
        Accept clipped channels (listed in :attr:`Recording.clipped`) instead of refusing the file.

    Returns
    -------
    Recording
    """
    p = Path(path)
    fmt = recording_format(p)
    if not p.is_file():
        raise DataFileError(p, "file not found" if not p.exists() else "not a file")
    if os.path.getsize(p) > MAX_RECORDING_FILE_BYTES:
        raise DataFileError(
            p, f"larger than a recording may be ({MAX_RECORDING_FILE_BYTES} bytes, docs/limits.md)"
        )
    specs = channel_map.specs
    if not specs:
        raise ConfigError("--channel", "at least one channel, NAME=COLUMN[UNIT]")
    columns, file_rate = read_columns(p, fmt, [s.column for s in specs])
    raw = {s.channel: columns[s.column] for s in specs}
    lengths = {name: a.size for name, a in raw.items()}
    if len(set(lengths.values())) != 1:
        shown = ", ".join(f"{n} {k}" for n, k in lengths.items())
        raise DataFileError(p, f"channels of unequal length: {shown} samples")
    n = next(iter(lengths.values()))
    if n > MAX_RECORD_SAMPLES:
        raise DataFileError(p, f"{n} samples, more than {MAX_RECORD_SAMPLES} (docs/limits.md)")
    data = {s.channel: raw[s.channel] * s.factor for s in specs}
    rate = _rate(p, channel_map, data, file_rate, expected_rate_hz, rate_source)
    data.pop("t", None)
    kept = tuple(s for s in specs if s.channel != "t")
    if not kept:
        raise ConfigError("--channel", "a channel other than t")
    _check_finite(p, kept, data, rate)
    clipped = clipped_channels(data, kept, ranges or {}, rate)
    if clipped and not allow_clipped:
        raise DataFileError(
            p, clipped[0].text() + " (--allow-clipped to evaluate it anyway, recorded in the result)"
        )
    return Recording(p, fmt, rate, data, specs, tuple(clipped))


def _rate(
    path: Path,
    channel_map: ChannelMap,
    data: Mapping[str, np.ndarray],
    file_rate: float | None,
    expected: float | None,
    expected_source: str,
) -> float:
    """The recording's sample rate [Hz]: time channel, else the map's, else the file's, else the expected one."""
    t_spec = channel_map.spec("t")
    if t_spec is not None:
        if not np.all(np.isfinite(data["t"])):
            raise DataFileError(path, f"channel t (column {t_spec.column!r}): NaN or infinite time")
        rate, source = _check_time(path, t_spec, data["t"]), f"the time channel {t_spec.column!r}"
    elif channel_map.rate_hz is not None:
        rate, source = channel_map.rate_hz, f"the rate of {channel_map.source}"
    elif file_rate is not None:
        rate, source = file_rate, "the file's metadata"
    elif expected is not None:
        return float(expected)
    else:
        raise ConfigError("--channel", "a time channel t=COLUMN[s] or --rate, for the sample rate", path.name)
    if expected is not None and abs(rate - expected) > RATE_RTOL * expected:
        raise DataFileError(
            path,
            f"sample rate {rate:.9g} Hz (from {source}) is not {expected:.9g} Hz, the rate of "
            f"{expected_source or 'the test'}",
        )
    return float(rate)


# ------------------------------------------------------------------ writing
def write_recording(path: str | Path, channels: Mapping[str, np.ndarray], channel_map: ChannelMap) -> Path:
    """Write channels [internal units] as a recording in the map's columns and units, atomically.

    The format follows the suffix: ``.csv`` (a header of column names, 17 significant
    digits, so that a float64 reads back exactly), ``.mat`` (MATLAB v5, one variable
    per column), ``.h5`` (one dataset per column).  Every mapped channel must be in
    ``channels``; ``t`` may be mapped and is then written from ``channels["t"]``.

    Raises
    ------
    ConfigError
        A mapped channel is not among ``channels``, or channels of unequal length.
    """
    p = Path(path)
    fmt = recording_format(p)
    missing = [s.channel for s in channel_map.specs if s.channel not in channels]
    if missing:
        raise ConfigError(f"--channel {missing[0]}", "a channel the run recorded: " + ", ".join(channels))
    columns = {s.column: np.asarray(channels[s.channel], dtype=float) / s.factor for s in channel_map.specs}
    if len({a.size for a in columns.values()}) != 1:
        raise ConfigError("--channel", "channels of equal length")
    if fmt not in WRITTEN:
        raise ConfigError("-o", "a .csv, .mat or .h5 file (TDMS is read, not written)", p.name)
    with atomic_path(p) as tmp:
        write_columns(tmp, fmt, columns)
    return p
