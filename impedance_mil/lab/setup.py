"""Configuration of a virtual-lab run: sensors and safety limits.

Sensors are a :class:`~impedance_mil.specimens.sensors.SensorSuite` (report
Table 7.1 calibration, 16-bit analog inputs over +-10 V).  Noise levels are
not reported; the lab's default, :data:`DEFAULT_NOISE_V` = 1 mV rms per
channel (about 3 LSB), is an assumption of this tool.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from ..errors import ConfigError
from ..specimens.sensors import QUANTITIES, SensorSuite
from .structures import LimitValues, SensorArrays

#: Default sensor noise of the virtual lab [V rms per channel].
DEFAULT_NOISE_V = 1.0e-3

#: Quantities the loop must read, in the order of the channel-index array.
_REQUIRED = ("table_acceleration", "table_displacement", "differential_pressure")


#: Quantities the loop reads (the actuator load cells of Table 7.1 are not used).
LOOP_QUANTITIES = _REQUIRED + ("interface_force",)

#: LSB [V] standing for "no quantization" (exact to double precision within +-10 V).
UNQUANTIZED_LSB_V = 1.0e-14


def default_sensors(noise_rms_v: float = DEFAULT_NOISE_V) -> SensorSuite:
    """The Table 7.1 channels the loop reads, with ``noise_rms_v`` [V rms] of noise each.

    Accelerometer, string potentiometer, dP cell and the four reaction load
    cells; the actuator load cells are left out (nothing in the loop reads them).
    """
    suite = SensorSuite.report_default(noise_rms_v=noise_rms_v)
    return SensorSuite(tuple(s for s in suite.sensors if s.quantity in LOOP_QUANTITIES))


def ideal_sensors() -> SensorSuite:
    """:func:`default_sensors` without noise (pass ``quantize=False`` to drop the 16 bits too)."""
    return default_sensors(0.0)


def draw_noise(rng: np.random.Generator, suite: SensorSuite, n_loops: int | None = None):
    """Standard-normal draws for the sensor kernel, float32, ``(n_loops, n_channels)``.

    One row per loop; drawing row by row (``n_loops=None``) gives the same
    numbers as drawing the block, so the plant interface and the compiled
    loop agree.
    """
    shape = (suite.n_channels,) if n_loops is None else (n_loops, suite.n_channels)
    return rng.standard_normal(shape, dtype=np.float32)


def sensor_arrays(suite: SensorSuite, feedback: str = "lc", quantize: bool = True) -> SensorArrays:
    """The :class:`~impedance_mil.lab.structures.SensorArrays` the sensing kernel reads.

    The suite's channel arrays, the first channel measuring z, x and dP, and a
    quantity buffer.  ``quantize=False`` replaces the 16-bit LSB by
    :data:`UNQUANTIZED_LSB_V` (model studies only).
    """
    qi = np.asarray(suite.quantity_index)
    idx = []
    for name in _REQUIRED:
        hits = np.nonzero(qi == QUANTITIES.index(name))[0]
        if hits.size == 0:
            raise ConfigError("sensors", f"a channel measuring {name}", suite.names)
        idx.append(int(hits[0]))
    if feedback == "lc" and not np.any(suite.load_cell_weights != 0):
        raise ConfigError(
            "sensors", "reaction load cells (interface_force channels) for feedback 'lc'", suite.names
        )
    z_channel, x_channel, dp_channel = idx
    return SensorArrays(
        quantity_index=np.ascontiguousarray(qi, dtype=np.int64),
        gain=np.array(suite.gain),
        scale=np.array(suite.scale),
        offset=np.array(suite.offset),
        noise_rms=np.array(suite.noise_rms),
        lsb=np.array(suite.lsb) if quantize else np.full(suite.n_channels, UNQUANTIZED_LSB_V),
        v_low=np.array(suite.v_low),
        v_high=np.array(suite.v_high),
        load_cell_weights=np.array(suite.load_cell_weights),
        z_channel=z_channel,
        x_channel=x_channel,
        dp_channel=dp_channel,
        quantities=np.zeros(len(QUANTITIES)),
    )


@dataclass(frozen=True)
class SafetyLimits:
    """Interlocks of the virtual controller; a run that crosses one stops cleanly.

    Parameters
    ----------
    stroke : float
        Measured displacement limit [in] (report Section 8.2: +-3 in).
    velocity : float
        Table velocity limit [in/s] (the valve's rated flow over A_p is 27.5 in/s;
        default 40 in/s).
    actuator_force : float, optional
        |A_p dP| limit [lbf]; default 95 % of the stall force A_p (P_s - P_R).
    valve_saturation_time : float
        Longest time the valve command may sit at its limit [s].
    divergence : float
        Displacement beyond which the simulation is declared divergent [in].
    """

    stroke: float = 3.0
    velocity: float = 40.0
    actuator_force: float | None = None
    valve_saturation_time: float = 0.25
    divergence: float = 20.0

    def __post_init__(self):
        for key in ("stroke", "velocity", "valve_saturation_time", "divergence"):
            value = getattr(self, key)
            if not (np.isfinite(value) and value > 0):
                raise ConfigError(f"limits.{key}", "a positive finite number", value)
        if self.actuator_force is not None and not self.actuator_force > 0:
            raise ConfigError("limits.actuator_force", "a positive force [lbf]", self.actuator_force)

    @classmethod
    def disabled(cls) -> SafetyLimits:
        """Only NaN and divergence checks remain (for studies beyond the rig's limits)."""
        return cls(stroke=1e9, velocity=1e9, actuator_force=1e12, valve_saturation_time=1e9, divergence=1e3)

    def kernel_values(self, table) -> LimitValues:
        """The thresholds for ``table`` (a NonlinearTable; it sets the default actuator force)."""
        force = 0.95 * table.max_force if self.actuator_force is None else self.actuator_force
        return LimitValues(
            stroke=float(self.stroke),
            velocity=float(self.velocity),
            actuator_force=float(force),
            valve_saturation_time=float(self.valve_saturation_time),
            divergence=float(self.divergence),
        )

    def to_dict(self) -> dict:
        return asdict(self)
