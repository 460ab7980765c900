"""A recording read against the lab's sensors (the clipping check of ``imil identify``/``evaluate``).

:func:`sensor_ranges` turns a :class:`~impedance_mil.specimens.sensors.SensorSuite`
into the reading limits of each recorded channel (``z``, ``x``, ``dp``, ``w``);
:func:`read_lab_recording` reads a recording with them.  The suite defaults to
the lab's Table 7.1 channels (:func:`~impedance_mil.lab.setup.default_sensors`);
a lab file (issue 12) will pass its own ``[sensors.*]`` here.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from ..signals.recordings import ChannelMap, Recording, SensorRange, read_recording, write_recording
from ..specimens.sensors import SensorSuite
from .results import RunResult
from .setup import default_sensors

#: Sensor quantity measured by each recorded channel (specimens.sensors.QUANTITIES).
CHANNEL_QUANTITIES = {
    "z": "table_acceleration",
    "x": "table_displacement",
    "dp": "differential_pressure",
    "w": "interface_force",
}


def sensor_ranges(sensors: SensorSuite) -> dict[str, SensorRange]:
    """Reading limits of each recorded channel, internal units, from the lab's sensors.

    A channel read by several sensors (``w``: the four reaction load cells, each
    carrying a share ``gain`` of it) can read only what every one of them can:
    the limits are the intersection of each sensor's ``(scale * V_limit + offset) / gain``.
    """
    ranges: dict[str, SensorRange] = {}
    for channel, quantity in CHANNEL_QUANTITIES.items():
        lows, highs, steps, names = [], [], [], []
        for s in sensors.sensors:
            if s.quantity != quantity or s.gain == 0:
                continue
            ends = sorted((s.scale * v + s.offset) / s.gain for v in s.volts_range)
            lows.append(ends[0])
            highs.append(ends[1])
            steps.append(abs(s.scale * s.lsb_v / s.gain))
            names.append(s.name)
        if names:
            ranges[channel] = SensorRange(max(lows), min(highs), max(steps), "/".join(names))
    return ranges


def read_lab_recording(
    path: str | Path,
    channel_map: ChannelMap,
    *,
    sensors: SensorSuite | None = None,
    expected_rate_hz: float | None = None,
    rate_source: str = "",
    allow_clipped: bool = False,
) -> Recording:
    """:func:`~impedance_mil.signals.recordings.read_recording` with the clipping limits of ``sensors``.

    ``sensors`` None: the lab's Table 7.1 channels (:func:`default_sensors`).
    """
    ranges: Mapping[str, SensorRange] = sensor_ranges(sensors or default_sensors())
    return read_recording(
        path,
        channel_map,
        expected_rate_hz=expected_rate_hz,
        rate_source=rate_source,
        ranges=ranges,
        allow_clipped=allow_clipped,
    )


#: The run channel each recording channel is taken from when a virtual run is written as a recording.
RUN_CHANNELS = {
    "t": "t",
    "u": "u",
    "a_g": "a_g",
    "z": "z_meas",
    "x": "x_meas",
    "dp": "dp_meas",
    "w": "w_used",
    "z_vs": "z_vs",
}


def run_as_recording(run: RunResult, path: str | Path, channel_map: ChannelMap) -> Path:
    """Write a virtual run as the lab would have recorded it: the measured channels, in the map's units.

    ``z``, ``x``, ``dp`` and ``w`` are the sensor readings (``z_meas``, ``x_meas``,
    ``dp_meas``, ``w_used``); ``u``, ``a_g``, ``z_vs`` what the controller played
    or computed; ``t`` the loop times.
    """
    channels = {name: run.channels[source] for name, source in RUN_CHANNELS.items() if source in run.channels}
    return write_recording(path, channels, channel_map)
