"""Sensors of the shake table and the feedback force (report Table 7.1, Section 7.3.4, Appendix A).

Each sensor maps a physical value to volts with its calibration
(``value = scale * volts + offset``, Table 7.1), optionally passes it through
an analog anti-alias filter (:meth:`Sensor.anti_alias_filter`, a Butterworth
low-pass of ``bandwidth_hz``; the report's channels have none) and a
converter delay (``delay_s``), adds noise [V rms] (white, or shaped by a
:class:`~.sensor_noise.NoiseSpectrum`),
saturates at its conditioner limit (+-10 V) and is read by a 16-bit
analog input over +-10 V (Section 7.2.2: "All input/outputs are +-10 V
analog with 16-bit resolution"), then converted back to the physical value.

The analog input is modelled as a two's-complement converter: codes
-32768 ... +32767 of one LSB = 20 V / 2**16 = 0.305 mV, rounding to the
nearest code; so a saturated positive input reads +10 V - 1 LSB.

Feedback force ``w`` [lbf] (force the specimen applies on the table,
Eq 4-7b: ``m_st z = A_p dP + w``):

* ``w_LC`` from the four reaction load cells LC-03, LC-06, LC-08 and
  LC-14 (Section 3.5, 200 lb/V each), summed with the signs of the RMC user
  program (Figure 7.9): ``w := -(_AI[5] + _AI[6] + _AI[7] - _AI[8]) * 200``.
  The report does not say which cell is on which input; we take the order
  of Section 3.5 (LC-03 on ``_AI[5]`` ... LC-14 on ``_AI[8]``), so LC-14
  is the cell mounted the other way round.  In simulation the total force
  is shared equally, each cell carrying ``w / 4`` with its own sign.
* ``w_FE = m_st z - A_p dP`` from force equilibrium of the table
  (Section 8.3.2; Appendix C prints the opposite sign, see docs/errata.md).

The compiled loop uses :func:`measure_kernel` with the plain arrays of a
:class:`SensorSuite` and standard-normal draws that it takes from a seeded
``numpy.random.Generator`` (no global random state anywhere).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ConfigError
from ..lazy import LazyModule, lazy_attributes
from ..units import G0, TWO_PI
from .sensor_noise import NoiseSpectrum

if TYPE_CHECKING:
    from ..lti import StateSpace

#: The LTI core, read by :meth:`Sensor.anti_alias_filter` only: a channel without a filter, and a
#: lab that only lists its channels (``imil lab show``), do not need it (issue 16, start-up).
lti = LazyModule("impedance_mil.lti")

#: Resolution of the RMC75E analog inputs [bits] (Section 7.2.2).
ADC_BITS = 16
#: Full scale of the analog inputs, +- [V] (Section 7.2.2).
ADC_RANGE_V = 10.0

#: Physical quantities a channel can measure, in the order of the vector
#: passed to :func:`measure_kernel`: table acceleration z [in/s**2], table
#: displacement x_st [in], differential pressure dP [psi], actuator force
#: [lbf] and interface force w [lbf].
QUANTITIES = (
    "table_acceleration",
    "table_displacement",
    "differential_pressure",
    "actuator_force",
    "interface_force",
)

#: Orders of the Butterworth anti-alias filter a channel may have (:meth:`Sensor.anti_alias_filter`).
FILTER_ORDERS = (1, 2)

#: Reaction load cells in the order of Section 3.5 and their signs in the
#: RMC sum w := -(AI5 + AI6 + AI7 - AI8) * 200 (Figure 7.9).
REACTION_CELLS = ("LC-03", "LC-06", "LC-08", "LC-14")
REACTION_SIGNS = (-1.0, -1.0, -1.0, 1.0)


@dataclass(frozen=True)
class Sensor:
    """One calibrated channel: physical value -> volts -> 16-bit code -> physical value.

    Parameters
    ----------
    name : str
        Channel name (``"accelerometer"``, ``"LC-03"`` ...).
    quantity : str
        One of :data:`QUANTITIES`.
    unit : str
        Internal unit of the quantity (for display only).
    scale : float
        Calibration [unit/V], nonzero (Table 7.1).
    offset : float
        Calibration offset [unit]: ``value = scale * volts + offset``.
    gain : float
        Share of the quantity this channel sees, with its mounting sign
        (1 for most channels; +-1/4 for a reaction load cell).
    noise_rms_v : float
        White measurement noise [V rms], >= 0.
    saturation_v : float
        Conditioner output limit [V], > 0 (10).
    adc_bits : int
        Resolution of the analog input [bits] (16, Section 7.2.2).
    adc_range_v : float
        Full scale of the analog input, +- [V] (10).
    bandwidth_hz : float, optional
        -3 dB frequency [Hz] of the channel's analog anti-alias filter, a
        Butterworth low-pass of ``filter_order`` acting on the signal before
        noise, saturation and quantization; None (the report's channels): no filter.
    filter_order : int
        Order of that filter, 1 or 2 (default 2); only with ``bandwidth_hz``.
    delay_s : float
        Group delay [s] of the converter or signal conditioner (>= 0, default 0):
        the reading at t is of the (filtered) analog value at ``t - delay_s``,
        before noise and quantization (:meth:`transfer_function`).
    noise_spectrum : NoiseSpectrum, optional
        Shape of the noise (:mod:`.sensor_noise`); ``noise_rms_v`` stays its
        total rms over 0 ... the loop's Nyquist frequency.  None: white noise.
    """

    name: str
    quantity: str
    unit: str
    scale: float
    offset: float = 0.0
    gain: float = 1.0
    noise_rms_v: float = 0.0
    saturation_v: float = ADC_RANGE_V
    adc_bits: int = ADC_BITS
    adc_range_v: float = ADC_RANGE_V
    bandwidth_hz: float | None = None
    filter_order: int = 2
    delay_s: float = 0.0
    noise_spectrum: NoiseSpectrum | None = None

    def __post_init__(self):
        if self.quantity not in QUANTITIES:
            raise ConfigError(f"{self.name}.quantity", f"one of {', '.join(QUANTITIES)}", self.quantity)
        if not (math.isfinite(self.scale) and self.scale != 0):
            raise ConfigError(f"{self.name}.scale", "a finite nonzero scale [unit/V]", self.scale)
        if not (math.isfinite(self.noise_rms_v) and self.noise_rms_v >= 0):
            raise ConfigError(f"{self.name}.noise_rms_v", "a noise level >= 0 [V rms]", self.noise_rms_v)
        if not (math.isfinite(self.saturation_v) and self.saturation_v > 0):
            raise ConfigError(f"{self.name}.saturation_v", "a positive limit [V]", self.saturation_v)
        if not (isinstance(self.adc_bits, int) and 2 <= self.adc_bits <= 32):
            raise ConfigError(f"{self.name}.adc_bits", "a whole number of bits from 2 to 32", self.adc_bits)
        if not (math.isfinite(self.adc_range_v) and self.adc_range_v > 0):
            raise ConfigError(f"{self.name}.adc_range_v", "a positive input range [V]", self.adc_range_v)
        if not (math.isfinite(self.offset) and math.isfinite(self.gain)):
            raise ConfigError(f"{self.name}.offset", "finite offset and gain")
        if self.bandwidth_hz is not None and not (math.isfinite(self.bandwidth_hz) and self.bandwidth_hz > 0):
            raise ConfigError(
                f"{self.name}.bandwidth_hz", "a positive finite bandwidth [Hz]", self.bandwidth_hz
            )
        if self.filter_order not in FILTER_ORDERS or isinstance(self.filter_order, bool):
            raise ConfigError(f"{self.name}.filter_order", "1 or 2", self.filter_order)
        if not (math.isfinite(self.delay_s) and self.delay_s >= 0):
            raise ConfigError(f"{self.name}.delay", "a delay >= 0 [s]", self.delay_s)
        if self.noise_spectrum is not None and not isinstance(self.noise_spectrum, NoiseSpectrum):
            raise ConfigError(f"{self.name}.noise_spectrum", "a NoiseSpectrum", self.noise_spectrum)

    def anti_alias_filter(self) -> StateSpace | None:
        """The channel's analog anti-alias filter, a continuous Butterworth low-pass (None: no filter).

        Input the true channel value, output the filtered value (same unit,
        unit DC gain), ``omega_c = 2 pi bandwidth_hz`` [rad/s]:

        * order 1: ``H(s) = omega_c / (s + omega_c)``, state ``y``;
        * order 2: ``H(s) = omega_c^2 / (s^2 + sqrt(2) omega_c s + omega_c^2)``,
          states ``y`` and ``y' / omega_c`` (scaled so that both are of the
          signal's size).

        The output is the first state (``C = [1, 0]``, ``D = 0``) for both
        orders; this one definition gives the virtual lab's exact
        discretization (:func:`impedance_mil.lab.setup.sensor_arrays`).

        Examples
        --------
        >>> s = Sensor("x", "table_displacement", "in", 1.0, bandwidth_hz=100.0)
        >>> h = s.anti_alias_filter().frequency_response([100.0])[0]
        >>> round(float(abs(h)) ** 2, 6)  # -3 dB at the bandwidth
        0.5
        """
        if self.bandwidth_hz is None:
            return None
        wc = TWO_PI * self.bandwidth_hz
        if self.filter_order == 1:
            return lti.StateSpace([[-wc]], [[wc]], [[1.0]], 0.0, states=("y",))
        return lti.StateSpace(
            [[0.0, wc], [-wc, -math.sqrt(2.0) * wc]], [[0.0], [wc]], [[1.0, 0.0]], 0.0, states=("y", "dy/wc")
        )

    @property
    def lsb_v(self) -> float:
        """Quantization step [V]: the input range over the codes (20 V / 2**16 for the report's)."""
        return 2.0 * self.adc_range_v / 2**self.adc_bits

    @property
    def volts_range(self) -> tuple[float, float]:
        """Lowest and highest reading [V]: saturation, then the converter's codes."""
        lsb = self.lsb_v
        top = min(math.floor(self.saturation_v / lsb), 2 ** (self.adc_bits - 1) - 1)
        bottom = max(-math.floor(self.saturation_v / lsb), -(2 ** (self.adc_bits - 1)))
        return bottom * lsb, top * lsb

    def to_volts(self, value):
        """Ideal output [V] for a physical value (no noise, no limits)."""
        return (np.asarray(value, dtype=float) - self.offset) / self.scale

    @property
    def value_range(self) -> tuple[float, float]:
        """Lowest and highest value the channel can read [unit], whatever the sign of ``scale``."""
        a, b = (self.to_physical(v) for v in self.volts_range)
        return float(min(a, b)), float(max(a, b))

    def to_physical(self, volts):
        """Physical value for a reading [V] (Table 7.1 calibration)."""
        return self.scale * np.asarray(volts, dtype=float) + self.offset


@dataclass(frozen=True)
class SensorReadings:
    """Result of :meth:`SensorSuite.measure`.

    Attributes
    ----------
    volts : ndarray, (..., n_channels)
        Quantized readings [V].
    values : ndarray, (..., n_channels)
        Readings in physical units (each channel's ``unit``).
    """

    volts: np.ndarray
    values: np.ndarray


@dataclass(frozen=True, eq=False)
class SensorSuite:
    """An ordered set of channels with the plain arrays a compiled loop needs.

    Parameters
    ----------
    sensors : tuple of Sensor
        The channels, in order; names must be unique.

    Attributes (arrays, one entry per channel, float64 unless stated)
    -----------------------------------------------------------------
    scale [unit/V], offset [unit], gain [-], noise_rms [V], lsb [V],
    v_low, v_high [V] (reading limits), quantity_index (int64, index into
    :data:`QUANTITIES`), load_cell_weights [-] (``w_LC = load_cell_weights @ values``).
    """

    sensors: tuple[Sensor, ...]

    def __post_init__(self):
        sensors = tuple(self.sensors)
        names = [s.name for s in sensors]
        if not sensors or len(set(names)) != len(names):
            raise ConfigError("sensors", "at least one sensor, with unique names", names)
        object.__setattr__(self, "sensors", sensors)
        lows, highs = zip(*(s.volts_range for s in sensors))
        arrays = {
            "scale": [s.scale for s in sensors],
            "offset": [s.offset for s in sensors],
            "gain": [s.gain for s in sensors],
            "noise_rms": [s.noise_rms_v for s in sensors],
            "lsb": [s.lsb_v for s in sensors],
            "v_low": lows,
            "v_high": highs,
            "load_cell_weights": [
                np.sign(s.gain) if s.quantity == "interface_force" else 0.0 for s in sensors
            ],
        }
        for key, vals in arrays.items():
            arr = np.ascontiguousarray(vals, dtype=np.float64)
            arr.setflags(write=False)
            object.__setattr__(self, key, arr)
        qi = np.array([QUANTITIES.index(s.quantity) for s in sensors], dtype=np.int64)
        qi.setflags(write=False)
        object.__setattr__(self, "quantity_index", qi)

    # -------------------------------------------------------------- builders
    @classmethod
    def report_default(cls, noise_rms_v: float | Mapping[str, float] = 0.0) -> SensorSuite:
        """The nine channels of Table 7.1, in the order of :data:`REPORT_CHANNELS`.

        Parameters
        ----------
        noise_rms_v : float or mapping
            Noise [V rms] for every channel, or per channel name.
        """
        suite = cls(REPORT_CHANNELS)
        return suite.with_noise(noise_rms_v)

    def with_noise(self, noise_rms_v: float | Mapping[str, float]) -> SensorSuite:
        """A copy with noise [V rms] set for all channels or for the named ones."""
        if isinstance(noise_rms_v, Mapping):
            unknown = set(noise_rms_v) - set(self.names)
            if unknown:
                raise ConfigError(
                    "noise_rms_v", f"channel names among {', '.join(self.names)}", sorted(unknown)
                )
            levels = {n: noise_rms_v.get(n, s.noise_rms_v) for n, s in zip(self.names, self.sensors)}
        else:
            levels = dict.fromkeys(self.names, noise_rms_v)
        return SensorSuite(tuple(replace(s, noise_rms_v=float(levels[s.name])) for s in self.sensors))

    # ------------------------------------------------------------ properties
    @property
    def names(self) -> tuple[str, ...]:
        """Channel names, in order."""
        return tuple(s.name for s in self.sensors)

    @property
    def n_channels(self) -> int:
        """Number of channels."""
        return len(self.sensors)

    def index(self, name: str) -> int:
        """Position of the channel called ``name``."""
        try:
            return self.names.index(name)
        except ValueError:
            raise ConfigError("sensor", f"one of {', '.join(self.names)}", name) from None

    # ----------------------------------------------------------- measuring
    def channel_values(
        self,
        table_acceleration=0.0,
        table_displacement=0.0,
        differential_pressure=0.0,
        actuator_force=0.0,
        interface_force=0.0,
    ):
        """True physical value at every channel, shape ``(..., n_channels)``.

        Parameters
        ----------
        table_acceleration : float or array_like
            Absolute table acceleration z [in/s**2].
        table_displacement : float or array_like
            Table displacement x_st [in].
        differential_pressure : float or array_like
            dP = P1 - P2 [psi].
        actuator_force : float or array_like
            Force in the actuator [lbf].
        interface_force : float or array_like
            Force w that the specimen applies on the table [lbf].
        """
        q = np.stack(
            np.broadcast_arrays(
                *(
                    np.asarray(v, dtype=float)
                    for v in (
                        table_acceleration,
                        table_displacement,
                        differential_pressure,
                        actuator_force,
                        interface_force,
                    )
                )
            ),
            axis=-1,
        )
        return q[..., self.quantity_index] * self.gain

    def draw_noise(self, rng: np.random.Generator, n_samples: int | None = None) -> np.ndarray:
        """Standard-normal draws for the kernel, shape ``(n_samples, n_channels)`` or ``(n_channels,)``."""
        shape = (self.n_channels,) if n_samples is None else (n_samples, self.n_channels)
        return rng.standard_normal(shape)

    def measure(self, values, rng: np.random.Generator | None = None) -> SensorReadings:
        """Readings for true channel values (plain numpy; the reference for :func:`measure_kernel`).

        Static: the anti-alias filters, converter delays and noise spectra act
        over time, in the lab's loop (:mod:`impedance_mil.lab.setup`), not here.

        Parameters
        ----------
        values : array_like, (..., n_channels)
            True physical values, e.g. from :meth:`channel_values`.
        rng : numpy.random.Generator, optional
            Source of the noise; required when any channel has noise.  Draws
            ``rng.standard_normal(values.shape)``, the same numbers
            :meth:`draw_noise` would give the kernel.
        """
        values = np.asarray(values, dtype=float)
        if values.shape[-1:] != (self.n_channels,):
            raise ConfigError(
                "values", f"an array whose last axis has {self.n_channels} channels", values.shape
            )
        volts = (values - self.offset) / self.scale
        if np.any(self.noise_rms > 0):
            if rng is None:
                raise ConfigError("rng", "a numpy.random.Generator when a channel has noise")
            volts = volts + self.noise_rms * rng.standard_normal(values.shape)
        volts = np.clip(np.floor(volts / self.lsb + 0.5) * self.lsb, self.v_low, self.v_high)
        return SensorReadings(volts, self.scale * volts + self.offset)

    def load_cell_force(self, readings) -> np.ndarray:
        """``w_LC`` [lbf]: reaction-cell readings summed with the RMC signs (Figure 7.9)."""
        return np.asarray(readings, dtype=float) @ self.load_cell_weights

    def to_dict(self) -> dict:
        """Plain description of every channel."""
        return {"sensors": [_sensor_dict(s) for s in self.sensors]}


def _sensor_dict(sensor: Sensor) -> dict:
    """A channel's fields; the delay and the noise spectrum only when set (older records stay as they were)."""
    out = asdict(sensor)
    if sensor.delay_s == 0.0:
        del out["delay_s"]
    if sensor.noise_spectrum is None:
        del out["noise_spectrum"]
    return out


def _reaction_cell(name: str, sign: float) -> Sensor:
    # 0.2 kip/V (Section 3.5, Appendix A; Table 7.1: 200 lb/V); each carries w/4.
    return Sensor(name, "interface_force", "lbf", 200.0, 0.0, gain=0.25 * sign)


#: The channels of Table 7.1 (scale [unit/V], offset [unit]; g converted to in/s**2).
REPORT_CHANNELS: tuple[Sensor, ...] = (
    Sensor("accelerometer", "table_acceleration", "in/s**2", 0.6711 * G0, 0.067 * G0),
    Sensor("string_pot", "table_displacement", "in", -1.25, 6.0),
    Sensor("dp_cell", "differential_pressure", "psi", -400.0, 0.0),
    Sensor("ALC1", "actuator_force", "lbf", -1000.0, 0.0),
    Sensor("ALC2", "actuator_force", "lbf", -1000.0, 0.0),
) + tuple(_reaction_cell(n, s) for n, s in zip(REACTION_CELLS, REACTION_SIGNS))


#: The compiled measurement kernels (numba), read from :mod:`.sensor_kernels` on first use (PEP 562):
#: describing the sensors of a lab (``imil lab show``) does not import numba (issue 16, start-up).
KERNELS = (
    "measure_kernel",
    "read_channel",
    "load_cell_force_kernel",
    "force_from_equilibrium",
)
__getattr__ = lazy_attributes(__name__, "impedance_mil.specimens.sensor_kernels", KERNELS)
