"""Sensor channels driven beyond their range during a run (``[sensors] clipping`` of a lab file).

A channel clips when the true value it sees (its share of the quantity, with
its mounting sign) lies outside what its converter can read
(:attr:`~impedance_mil.specimens.sensors.Sensor.value_range`): the reading
then sits at a rail and the controller acts on a wrong value.  The run's
recorded true channels (``z``, ``x``, ``dp``, ``w``) are checked after the
run, sample by sample; the summary lists every clipped channel, and a lab
whose policy is ``fail`` makes the command fail (exit status 3, the data
kept).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..specimens.sensors import SensorSuite

#: Recorded true channel of each quantity a lab channel may measure.
TRUE_CHANNELS = {
    "table_acceleration": "z",
    "table_displacement": "x",
    "differential_pressure": "dp",
    "interface_force": "w",
}


@dataclass(frozen=True)
class ClippedChannel:
    """A channel beyond its range: ``samples`` clipped, the first at ``first_time_s`` [s],
    the largest true value ``peak`` [unit] against the channel's ``range`` [unit]."""

    name: str
    quantity: str
    unit: str
    samples: int
    first_time_s: float
    peak: float
    range: tuple[float, float]

    def to_dict(self) -> dict:
        return {
            "channel": self.name,
            "quantity": self.quantity,
            "unit": self.unit,
            "samples": self.samples,
            "first_time_s": self.first_time_s,
            "peak": self.peak,
            "range": list(self.range),
        }

    @property
    def sentence(self) -> str:
        low, high = self.range
        return (
            f"sensor {self.name} ({self.quantity}) clipped in {self.samples} samples from t = "
            f"{self.first_time_s:.3f} s: true value up to {self.peak:.6g} {self.unit}, range "
            f"{low:.6g} to {high:.6g} {self.unit}"
        )


def clipped_channels(suite: SensorSuite, channels: dict[str, np.ndarray]) -> list[ClippedChannel]:
    """Every channel of ``suite`` whose true value left its range in the recorded ``channels``."""
    out = []
    t = channels["t"]
    for sensor in suite.sensors:
        name = TRUE_CHANNELS.get(sensor.quantity)
        if name is None or name not in channels or t.size == 0:
            continue
        seen = sensor.gain * np.asarray(channels[name], dtype=float)
        low, high = sensor.value_range
        outside = (seen < low) | (seen > high)
        count = int(np.count_nonzero(outside))
        if count:
            first = int(np.argmax(outside))
            out.append(
                ClippedChannel(
                    sensor.name,
                    sensor.quantity,
                    sensor.unit,
                    count,
                    float(t[first]),
                    float(seen[np.argmax(np.abs(seen))]),
                    (low, high),
                )
            )
    return out
