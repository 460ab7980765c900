"""The ``[sensors]`` section of a lab file: the channels the virtual controller reads.

A lab file describes each channel in physical terms (``[sensors.NAME]``)::

    [sensors]
    clipping = "warn"            # or "fail": what a channel driven beyond its range does
    [sensors.accel]
    quantity = "acceleration"    # acceleration, displacement, differential_pressure, load_cell
    range = "4 g0"               # +- full scale, mapped onto the converter's +- input range
    bits = 16                    # converter resolution (or resolution = "0.1 mm")
    noise = "0.002 g0"           # rms, white

or, for a calibrated channel as in report Table 7.1, ``scale`` [unit/V] and
``offset`` [unit] instead of ``range``.  A load cell carries ``share`` of the
interface force w with its mounting sign (four cells of a table: ``0.25``
each).  ``preset = "table-7.1"`` stands for the report's channels (the
accelerometer, string potentiometer, dP cell and four reaction load cells of
Table 7.1, exactly as :func:`impedance_mil.lab.setup.default_sensors`); a
preset channel's own ``[sensors.NAME]`` may add its dynamics, which the report
does not give (``bandwidth``, ``filter_order``, ``delay``, ``delay_loops``,
``noise_spectrum``), never change its calibration.

Without a ``[sensors]`` section, :func:`generic_sensors` sizes one channel
per quantity from the table (documented in ``docs/your-lab.md``): the
displacement over 1.25 mid-strokes, the pressure over 1.25 (P_S - P_R), the
acceleration over twice the stall force over the moving mass and the load
cell over twice the stall force, each read by the controller's converter
with :data:`~impedance_mil.lab.setup.DEFAULT_NOISE_V` of noise.

A channel may have an analog anti-alias filter: ``bandwidth = "200 Hz"`` (its
-3 dB frequency) and ``filter_order = 1`` or ``2`` (Butterworth, default 2),
acting on the true signal before noise, saturation and the converter
(:meth:`~impedance_mil.specimens.sensors.Sensor.anti_alias_filter`).  A
bandwidth that is not a positive frequency is refused; one at or above the
Nyquist frequency of the controller's loop, 1 / (2 loop_time), is accepted (a
real conditioner may be set so, and its lag is then modelled) with a
:class:`~impedance_mil.plausibility.PlausibilityWarning`: such a filter does
not prevent aliasing.

A channel may also have a converter / conditioner group delay (``delay =
"0.3 ms"`` or ``delay_loops = 0.3``) and a noise spectrum (``noise_spectrum``,
white + 1/f, mains hum lines or a measured PSD file): :mod:`.labnoise`.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from ..config import quantity
from ..errors import ConfigError
from ..plant import TableParameters
from ..plausibility import PlausibilityWarning
from ..specimens.sensors import FILTER_ORDERS, Sensor, SensorSuite
from .labnoise import channel_delay, channel_spectrum
from .setup import DEFAULT_NOISE_V, default_sensors

if TYPE_CHECKING:  # a table is a TableDefinition: an LTI table is the one that is not TableParameters
    from ..plant.lti_table import LTITable

#: What a clipped channel does: ``warn`` (the run goes on, the summary records it) or ``fail``.
CLIPPING_POLICIES = ("warn", "fail")

#: Quantity names of a lab file -> (quantity of the sensing kernel, internal unit).
QUANTITY_NAMES = {
    "acceleration": ("table_acceleration", "inch / second ** 2"),
    "displacement": ("table_displacement", "inch"),
    "differential_pressure": ("differential_pressure", "psi"),
    "load_cell": ("interface_force", "force_pound"),
}

#: Named channel sets a lab file may give as ``preset``.
PRESETS = ("table-7.1",)

_CHANNEL_KEYS = (
    "quantity",
    "range",
    "scale",
    "offset",
    "bits",
    "resolution",
    "noise",
    "share",
    "bandwidth",
    "filter_order",
    "delay",
    "delay_loops",
    "noise_spectrum",
)


@dataclass(frozen=True)
class SensorSetup:
    """The channels of a lab and what a clipped channel does (``clipping``: warn or fail)."""

    suite: SensorSuite
    clipping: str
    source: str


@dataclass(frozen=True)
class Converter:
    """The controller's analog inputs: ``bits`` and the +- ``range_v`` [V]."""

    bits: int
    range_v: float


def generic_ranges(table: TableParameters) -> dict[str, float]:
    """Full scale of each generic channel of a physical table (internal units; module docstring)."""
    stall = table.piston_area * (table.supply_pressure - table.return_pressure)
    return {
        "acceleration": 2.0 * stall / table.mass,
        "displacement": 1.25 * table.mid_stroke,
        "differential_pressure": 1.25 * (table.supply_pressure - table.return_pressure),
        "load_cell": 2.0 * stall,
    }


def generic_sensors(table: TableParameters | Mapping[str, float], adc: Converter) -> SensorSuite:
    """One channel per loop quantity, sized from ``table`` (module docstring), or of the given full scales.

    ``table`` may be the full scale [internal unit] of each channel by quantity
    (what :func:`impedance_mil.lab.lti_lab.lti_sensor_ranges` gives an LTI table).
    """
    ranges = table if isinstance(table, Mapping) else generic_ranges(table)
    return SensorSuite(
        tuple(
            _sensor(name, name, full / adc.range_v, 0.0, 1.0, DEFAULT_NOISE_V, adc.bits, adc)
            for name, full in ranges.items()
        )
    )


def sensor_setup(
    section: Any,
    table: TableParameters | LTITable,
    adc: Converter,
    where: str,
    generic: Mapping[str, float] | None = None,
    base: Path | None = None,
) -> SensorSetup:
    """The :class:`SensorSetup` of a ``[sensors]`` section (None: :func:`generic_sensors`).

    ``generic``: the generic channels' full scales when they are not sized from
    ``table``'s physical parameters (an LTI table); ``table`` then gives only its loop time.
    ``base``: the folder a channel's noise PSD file is read from (the lab file's).
    """
    if section is None:
        if generic is None and not isinstance(table, TableParameters):  # an LTI table
            raise ConfigError(
                f"{where}sensors", "a [sensors] section or the LTI table's generic channel ranges"
            )
        sized = generic if generic is not None else cast(TableParameters, table)
        return SensorSetup(generic_sensors(sized, adc), "warn", "default")
    if not isinstance(section, Mapping):
        raise ConfigError(f"{where}sensors", "a table of [sensors.NAME] channels")
    clipping = section.get("clipping", "warn")
    if clipping not in CLIPPING_POLICIES:
        raise ConfigError(f"{where}sensors.clipping", " or ".join(CLIPPING_POLICIES), clipping)
    channels = {k: v for k, v in section.items() if k not in ("clipping", "preset")}
    preset = section.get("preset")
    if preset is not None:
        if preset not in PRESETS:
            raise ConfigError(f"{where}sensors.preset", " or ".join(PRESETS), preset)
        return SensorSetup(_amended_preset(channels, table.loop_time, base, where), clipping, "file")
    if not channels:
        raise ConfigError(f"{where}sensors", "a preset or at least one [sensors.NAME] channel")
    sensors = []
    for name, entry in channels.items():
        if not isinstance(entry, Mapping):
            raise ConfigError(f"{where}sensors.{name}", "a table with " + ", ".join(_CHANNEL_KEYS), entry)
        sensor = _channel(name, entry, adc, f"{where}sensors.{name}.")
        sensor = _with_filter(sensor, entry, table.loop_time, f"{where}sensors.{name}.")
        sensors.append(_with_dynamics(sensor, entry, table.loop_time, base, f"{where}sensors.{name}."))
    return SensorSetup(SensorSuite(tuple(sensors)), clipping, "file")


#: Keys a preset's channel may take in its own ``[sensors.NAME]`` table: its dynamics, not its calibration.
PRESET_AMENDMENT_KEYS = ("bandwidth", "filter_order", "delay", "delay_loops", "noise_spectrum")


def _amended_preset(
    channels: Mapping[str, Any], loop_time: float, base: Path | None, where: str
) -> SensorSuite:
    """The preset's channels, each named ``[sensors.NAME]`` with its filter, delay or noise spectrum added.

    A preset keeps its calibration (Table 7.1); a lab may add what the report does
    not give: ``[sensors.LC-03] delay = "0.5 ms"`` (:data:`PRESET_AMENDMENT_KEYS`).
    """
    suite = default_sensors()
    sensors = []
    for sensor in suite.sensors:
        entry = channels.get(sensor.name)
        if entry is None:
            sensors.append(sensor)
            continue
        key = f"{where}sensors.{sensor.name}."
        if not isinstance(entry, Mapping):
            raise ConfigError(key.rstrip("."), "a table with " + ", ".join(PRESET_AMENDMENT_KEYS), entry)
        if unknown := sorted(set(entry) - set(PRESET_AMENDMENT_KEYS)):
            raise ConfigError(
                f"{key}{unknown[0]}", "beside a preset, only " + ", ".join(PRESET_AMENDMENT_KEYS)
            )
        sensor = _with_filter(sensor, entry, loop_time, key)
        sensors.append(_with_dynamics(sensor, entry, loop_time, base, key))
    if unknown_names := sorted(set(channels) - set(suite.names)):
        raise ConfigError(
            f"{where}sensors.{unknown_names[0]}", "a channel of the preset: " + ", ".join(suite.names)
        )
    return SensorSuite(tuple(sensors))


def _channel(name: str, entry: Mapping[str, Any], adc: Converter, key: str) -> Sensor:
    unknown = sorted(set(entry) - set(_CHANNEL_KEYS))
    if unknown:
        raise ConfigError(f"{key}{unknown[0]}", "one of the keys " + ", ".join(_CHANNEL_KEYS))
    kind = entry.get("quantity")
    if kind not in QUANTITY_NAMES:
        raise ConfigError(f"{key}quantity", "one of " + ", ".join(QUANTITY_NAMES), kind)
    unit = QUANTITY_NAMES[kind][1]
    if ("range" in entry) == ("scale" in entry):
        raise ConfigError(f"{key}range", "either range (+- full scale) or scale and offset (calibration)")
    if "range" in entry:
        if "offset" in entry:
            raise ConfigError(f"{key}offset", "no offset with range (range is +- about zero)")
        scale = quantity(f"{key}range", entry["range"], unit, "positive") / adc.range_v
        offset = 0.0
    else:
        scale = quantity(f"{key}scale", entry["scale"], f"({unit}) / volt", "any")
        offset = quantity(f"{key}offset", entry.get("offset", 0.0), unit, "any")
    if "bits" in entry and "resolution" in entry:
        raise ConfigError(f"{key}resolution", "either bits or resolution")
    bits = adc.bits
    if "bits" in entry:
        bits = int(quantity(f"{key}bits", entry["bits"], "dimensionless", "positive", integer=True))
    range_v = adc.range_v
    if "resolution" in entry:
        step = quantity(f"{key}resolution", entry["resolution"], unit, "positive")
        full = abs(scale) * adc.range_v
        if step >= full:
            raise ConfigError(f"{key}resolution", f"a step smaller than the range ({full:.6g} {unit})", step)
        # A physical step: the converter's codes over its range, rounded up to whole bits.
        bits = _bits_for(2.0 * full / step)
    noise = DEFAULT_NOISE_V
    if "noise" in entry:
        noise = quantity(f"{key}noise", entry["noise"], unit, "nonnegative") / abs(scale)
    share = quantity(f"{key}share", entry.get("share", 1.0), "dimensionless", "any")
    if share == 0:
        raise ConfigError(f"{key}share", "a nonzero share of the force (with its sign)", share)
    return _sensor(name, kind, scale, offset, share, noise, bits, Converter(bits, range_v))


def _with_filter(sensor: Sensor, entry: Mapping[str, Any], loop_time: float, key: str) -> Sensor:
    """``sensor`` with the entry's anti-alias filter (``bandwidth``, ``filter_order``), if any.

    ``loop_time`` [s] is the controller's: a bandwidth at or above its Nyquist
    frequency is a :class:`PlausibilityWarning` (see the module docstring).
    """
    if "bandwidth" not in entry:
        if "filter_order" in entry:
            raise ConfigError(f"{key}filter_order", "a bandwidth beside it (the filter's -3 dB frequency)")
        return sensor
    bandwidth = quantity(f"{key}bandwidth", entry["bandwidth"], "hertz", "positive")
    order = entry.get("filter_order", 2)
    if isinstance(order, bool) or order not in FILTER_ORDERS:
        raise ConfigError(f"{key}filter_order", "1 or 2 (Butterworth)", order)
    nyquist = 0.5 / loop_time
    if bandwidth >= nyquist:
        warnings.warn(
            f"{key}bandwidth: {bandwidth:g} Hz is at or above the Nyquist frequency ({nyquist:g} Hz) of the "
            f"{loop_time * 1e6:g} us loop: the filter does not prevent aliasing",
            PlausibilityWarning,
            stacklevel=4,
        )
    return replace(sensor, bandwidth_hz=bandwidth, filter_order=int(order))


def _with_dynamics(
    sensor: Sensor, entry: Mapping[str, Any], loop_time: float, base: Path | None, key: str
) -> Sensor:
    """``sensor`` with the entry's converter delay and noise spectrum, if any (:mod:`.labnoise`).

    A PSD table without ``noise`` sets the channel's total rms to the table's
    own over 0 ... the loop's Nyquist frequency, plus its hum lines.
    """
    delay = channel_delay(entry, loop_time, key)
    if "noise_spectrum" not in entry:
        return replace(sensor, delay_s=delay) if delay > 0 else sensor
    volts_per_unit = 1.0 / abs(sensor.scale)
    spectrum = channel_spectrum(
        entry["noise_spectrum"], sensor.unit, volts_per_unit, loop_time, base, f"{key}noise_spectrum."
    )
    noise = sensor.noise_rms_v
    if spectrum.kind == "table" and "noise" not in entry:
        noise = (spectrum.table_power(loop_time) + spectrum.hum_power) ** 0.5
    if spectrum.hum_power > noise**2 * (1 + 1e-12):
        raise ConfigError(
            f"{key}noise_spectrum.hum_rms",
            f"hum lines whose total rms is within the channel's noise ({noise / volts_per_unit:.6g} {sensor.unit})",
        )
    return replace(sensor, delay_s=delay, noise_rms_v=noise, noise_spectrum=spectrum)


def channel_dynamics(sensor: Sensor) -> dict[str, Any]:
    """The delay [s] and noise spectrum of a channel for ``imil lab show`` (empty when it has neither).

    Keys carry their unit suffix (``delay_s``, ``corner_hz``, ``hum_hz``);
    ``hum_rms`` is in the channel's ``unit``; a PSD table is named by its file.
    """
    out: dict[str, Any] = {}
    if sensor.delay_s > 0:
        out["delay_s"] = sensor.delay_s
    spectrum = sensor.noise_spectrum
    if spectrum is not None:
        out["noise_spectrum"] = {
            "kind": spectrum.kind,
            "corner_hz": spectrum.corner_hz,
            "file": spectrum.source or None,
            "hum_hz": list(spectrum.hum_hz),
            "hum_rms": [abs(sensor.scale) * a for a in spectrum.hum_rms_v],
        }
    return out


def _bits_for(codes: float) -> int:
    """Fewest bits whose codes cover ``codes`` steps."""
    bits = 2
    while 2**bits < codes:
        bits += 1
    return bits


def _sensor(
    name: str, kind: str, scale: float, offset: float, share: float, noise_v: float, bits: int, adc: Converter
) -> Sensor:
    quantity_name, unit = QUANTITY_NAMES[kind]
    try:
        return Sensor(
            name,
            quantity_name,
            unit,
            scale,
            offset,
            gain=share,
            noise_rms_v=noise_v,
            saturation_v=adc.range_v,
            adc_bits=bits,
            adc_range_v=adc.range_v,
        )
    except ConfigError as exc:
        raise ConfigError(f"sensors.{exc.key}", exc.expected, exc.got) from None
