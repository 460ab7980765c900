"""A channel's converter delay and noise spectrum in a lab file (``[sensors.NAME]``, issue 17).

::

    [sensors.lc]
    quantity = "load_cell"
    range = "2000 lbf"
    noise = "0.4 lbf"            # total rms over 0 ... the loop's Nyquist frequency
    delay = "0.3 ms"             # converter / conditioner group delay (or delay_loops = 0.3)
    [sensors.lc.noise_spectrum]
    kind = "pink"                # white, pink (white + 1/f) or table (a measured PSD)
    corner = "20 Hz"             # pink: the 1/f corner, S(f) = S0 (1 + corner / f)
    hum = "60 Hz"                # mains fundamental; its harmonics follow hum_rms
    hum_rms = ["0.1 lbf", "0.03 lbf"]   # rms of 60 Hz, 120 Hz ...: part of the total

``kind = "table"`` reads ``file`` (a CSV, relative to the lab file): two
columns, frequency [Hz] and PSD [``psd_unit``, default the channel's unit^2/Hz,
one-sided], an optional header line and ``#`` comments; the table is
interpolated log-log.  With a table, ``noise`` scales it to that total rms;
without, the total rms is the table's own integral over 0 ... Nyquist plus the
hum lines.  ``noise_spectrum = "white"`` (a string) is white noise as without it.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..config import quantity
from ..errors import ConfigError, DataFileError
from ..fileio import read_text
from ..specimens.sensor_noise import SPECTRUM_KINDS, NoiseSpectrum
from .setup import MAX_SENSOR_DELAY_LOOPS

#: Keys of ``[sensors.NAME.noise_spectrum]``.
SPECTRUM_KEYS = ("kind", "corner", "file", "psd_unit", "hum", "hum_rms")

#: Largest PSD file [bytes].
MAX_PSD_BYTES = 10_000_000


def channel_delay(entry: Mapping[str, Any], loop_time: float, key: str) -> float:
    """The channel's converter delay [s] (``delay`` [time] or ``delay_loops`` [loops]; 0 without).

    Raises
    ------
    ConfigError
        Both keys, a negative delay, or one longer than
        :data:`~impedance_mil.lab.setup.MAX_SENSOR_DELAY_LOOPS` loops.
    """
    if "delay" in entry and "delay_loops" in entry:
        raise ConfigError(f"{key}delay_loops", "either delay [time] or delay_loops [loops]")
    if "delay" in entry:
        name = "delay"
        delay = quantity(f"{key}delay", entry["delay"], "second", "nonnegative")
    elif "delay_loops" in entry:
        name = "delay_loops"
        delay = (
            quantity(f"{key}delay_loops", entry["delay_loops"], "dimensionless", "nonnegative") * loop_time
        )
    else:
        return 0.0
    if delay > MAX_SENSOR_DELAY_LOOPS * loop_time * (1 + 1e-12):
        raise ConfigError(
            f"{key}{name}",
            f"a delay of at most {MAX_SENSOR_DELAY_LOOPS} loops ({MAX_SENSOR_DELAY_LOOPS * loop_time * 1e3:g} ms)",
            entry[name],
        )
    return delay


def channel_spectrum(
    value: Any, unit: str, volts_per_unit: float, loop_time: float, base: Path | None, key: str
) -> NoiseSpectrum:
    """The :class:`NoiseSpectrum` [V] of a ``noise_spectrum`` value (module docstring).

    Parameters
    ----------
    value : str or mapping
        ``"white"``, ``"pink"`` ... or the table of :data:`SPECTRUM_KEYS`.
    unit : str
        The channel's internal unit (pint).
    volts_per_unit : float
        ``1 / |scale|`` [V/unit]: hum rms and PSD values go to volts with it.
    loop_time : float
        The controller's loop time [s] (hum lines must lie below its Nyquist frequency).
    base : Path, optional
        Folder a relative ``file`` is read from (the lab file's).
    key : str
        Prefix of the messages (``"lab.toml: sensors.lc.noise_spectrum."``).
    """
    section = {"kind": value} if isinstance(value, str) else value
    if not isinstance(section, Mapping):
        raise ConfigError(
            key.rstrip("."), "a spectrum kind or a table with " + ", ".join(SPECTRUM_KEYS), value
        )
    unknown = sorted(set(section) - set(SPECTRUM_KEYS))
    if unknown:
        raise ConfigError(f"{key}{unknown[0]}", "one of the keys " + ", ".join(SPECTRUM_KEYS))
    kind = section.get("kind")
    if kind not in SPECTRUM_KINDS:
        raise ConfigError(f"{key}kind", " or ".join(SPECTRUM_KINDS), kind)
    corner = None
    if "corner" in section:
        if kind != "pink":
            raise ConfigError(f"{key}corner", "no corner except with kind = 'pink'")
        corner = quantity(f"{key}corner", section["corner"], "hertz", "positive")
    elif kind == "pink":
        raise ConfigError(f"{key}corner", "the 1/f corner frequency of kind = 'pink' (e.g. '10 Hz')")
    freqs: tuple[float, ...] = ()
    psd: tuple[float, ...] = ()
    source = ""
    if kind == "table":
        if "file" not in section or not isinstance(section["file"], str) or not section["file"].strip():
            raise ConfigError(f"{key}file", "the PSD file (CSV of frequency [Hz], PSD) of kind = 'table'")
        psd_unit = section.get("psd_unit", f"({unit}) ** 2 / hertz")
        factor = quantity(f"{key}psd_unit", f"1 {psd_unit}", f"({unit}) ** 2 / hertz", "positive")
        path = (base or Path.cwd()) / section["file"]
        f, s = read_psd_table(path)
        freqs, psd = tuple(f), tuple(s * factor * volts_per_unit**2)
        source = str(path)
    else:
        for name in ("file", "psd_unit"):
            if name in section:
                raise ConfigError(f"{key}{name}", "no PSD file except with kind = 'table'")
    hum_hz, hum_rms = _hum(section, unit, volts_per_unit, loop_time, key)
    try:
        return NoiseSpectrum(kind, corner, freqs, psd, hum_hz, hum_rms, source)
    except ConfigError as exc:
        raise ConfigError(f"{key}{exc.key.split('.', 1)[-1]}", exc.expected, exc.got) from None


def _hum(
    section: Mapping[str, Any], unit: str, volts_per_unit: float, loop_time: float, key: str
) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Hum lines [Hz] and their rms [V]: the fundamental ``hum`` and one ``hum_rms`` per harmonic."""
    if ("hum" in section) != ("hum_rms" in section):
        raise ConfigError(
            f"{key}hum_rms", "hum (the mains frequency) and hum_rms (one rms per harmonic) together"
        )
    if "hum" not in section:
        return (), ()
    fundamental = quantity(f"{key}hum", section["hum"], "hertz", "positive")
    levels = section["hum_rms"]
    if isinstance(levels, (str, int, float)):
        levels = [levels]
    if not isinstance(levels, list) or not levels:
        raise ConfigError(
            f"{key}hum_rms", "a list of rms values, one per harmonic (fundamental first)", levels
        )
    rms = tuple(
        quantity(f"{key}hum_rms[{i}]", v, unit, "nonnegative") * volts_per_unit for i, v in enumerate(levels)
    )
    hz = tuple(fundamental * (i + 1) for i in range(len(rms)))
    nyquist = 0.5 / loop_time
    if hz[-1] >= nyquist:
        raise ConfigError(
            f"{key}hum_rms",
            f"harmonics below the loop's Nyquist frequency ({nyquist:g} Hz)",
            f"{hz[-1]:g} Hz",
        )
    return hz, rms


def read_psd_table(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Frequency [Hz] and PSD columns of a noise file (CSV, optional header line, ``#`` comments).

    Raises
    ------
    DataFileError
        One line naming the file: missing, not two numeric columns, fewer than
        two rows, frequencies not positive and increasing, a PSD not positive.
    """
    text = read_text(path, "a noise PSD file (CSV)", max_bytes=MAX_PSD_BYTES)
    lines = [(n, line) for n, line in enumerate(text.split("\n"), start=1) if line.strip()]
    lines = [(n, line) for n, line in lines if not line.lstrip().startswith("#")]
    rows: list[tuple[float, float]] = []
    for index, (n, line) in enumerate(lines):
        cells = next(csv.reader([line]))
        try:
            numbers = [float(c) for c in cells]
        except ValueError:
            if index == 0:
                continue  # a header line naming the columns
            raise DataFileError(
                path, f"line {n}: expected two numbers (frequency [Hz], PSD), got {line.strip()!r}"
            ) from None
        if len(numbers) != 2 or not all(math.isfinite(x) for x in numbers):
            raise DataFileError(path, f"line {n}: expected two finite numbers (frequency [Hz], PSD)")
        rows.append((numbers[0], numbers[1]))
    if len(rows) < 2:
        raise DataFileError(path, "expected at least two rows of frequency [Hz], PSD")
    f, s = (np.array(c) for c in zip(*rows))
    if np.any(f <= 0) or np.any(np.diff(f) <= 0):
        raise DataFileError(
            path, "expected positive, strictly increasing frequencies [Hz] in the first column"
        )
    if np.any(s <= 0):
        raise DataFileError(path, "expected positive PSD values in the second column (interpolated log-log)")
    return f, s
