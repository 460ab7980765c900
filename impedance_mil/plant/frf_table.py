"""A measured frequency-response table: the table known only by its FRFs (issue 13, item 3).

A lab that measured its table (``imil identify`` or its own analyser) gives
the two responses the design needs, with no fitted model:

* ``H_zu``: table acceleration per position command [in/s**2 per in];
* ``H_zw``: table acceleration per test-article force [in/s**2 per lbf];

and, optionally, the coherence of each path.  The table file is TOML::

    [model]
    kind = "frf"
    file = "table_frf.csv"          # relative to this file
    loop_time = "500 us"            # the table controller's loop time
    units = { z = "m/s**2", u = "mm", w = "kN" }   # any pint units, by dimension

and the CSV file has a header line naming its columns (``#`` starts a
comment line)::

    frequency_hz, H_zu_re, H_zu_im, H_zw_re, H_zw_im[, coherence_zu, coherence_zw]

Each path may instead be given as magnitude and phase, ``H_zu_mag,
H_zu_phase_deg`` (phase in deg, ``H = mag * exp(j phase)``).  The frequencies
are in Hz, strictly increasing and positive.  A measured FRF holds the loop
delay as it is (``[model] delay``, if given, must be ``"included"``).

:func:`read_frf_table` converts to the internal units (in, lbf, s) by the
dimension of each signal's unit; :func:`write_frf_table` writes the pair of
files back.  Bad input is refused in one line naming the file and the key or
column (:class:`~impedance_mil.errors.DataFileError`).
"""

from __future__ import annotations

import csv
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..config import quantity, read_toml
from ..errors import ConfigError, DataFileError
from ..fileio import atomic_write_text, read_text
from ..units import INTERNAL_UNITS

#: ``[model] kind`` of a measured-FRF table file.
KIND = "frf"

#: Internal unit of each signal of an FRF table (pint expressions).
SIGNAL_UNITS: dict[str, str] = {
    "z": INTERNAL_UNITS["acceleration"],
    "u": INTERNAL_UNITS["length"],
    "w": INTERNAL_UNITS["force"],
}

#: The paths of an FRF table: name -> (output, input).
PATHS: dict[str, tuple[str, str]] = {"H_zu": ("z", "u"), "H_zw": ("z", "w")}

#: Keys of ``[model]`` in an FRF table file.
MODEL_KEYS = ("kind", "file", "loop_time", "units", "delay")

#: Largest FRF data file [bytes] (a dense 100,000-line table is about 10 MB).
MAX_CSV_BYTES = 64 << 20


@dataclass(frozen=True, eq=False)
class FRFTable:
    """A table's measured frequency responses, in internal units.

    Parameters
    ----------
    frequency_hz : ndarray
        Frequencies [Hz], positive and strictly increasing.
    H_zu : ndarray of complex
        Table acceleration per position command [in/s**2 per in] at ``frequency_hz``.
    H_zw : ndarray of complex
        Table acceleration per test-article force [in/s**2 per lbf] at ``frequency_hz``.
    loop_time_s : float
        Loop time of the table controller [s] (sets the Nyquist frequency of the checks).
    coherence_zu, coherence_zw : ndarray or None
        Coherence of each path (dimensionless, in [0, 1]); None when not measured.
    source : Path or None
        The table file read, for messages.

    Raises
    ------
    ConfigError
        Arrays of different lengths, fewer than 2 points, non-increasing or
        non-positive frequencies, a non-finite value, coherence outside [0, 1],
        a non-positive loop time (the message names the field).

    Examples
    --------
    >>> t = FRFTable(np.array([1.0, 2.0]), np.array([1j, 2j]), np.array([0.1, 0.2]), 5e-4)
    >>> t.range_hz, t.nyquist_hz
    ((1.0, 2.0), 1000.0)
    """

    frequency_hz: np.ndarray
    H_zu: np.ndarray
    H_zw: np.ndarray
    loop_time_s: float
    coherence_zu: np.ndarray | None = None
    coherence_zw: np.ndarray | None = None
    source: Path | None = None

    def __post_init__(self):
        f = np.asarray(self.frequency_hz, dtype=float)
        if f.ndim != 1 or f.size < 2:
            raise ConfigError("frequency_hz", "at least 2 frequencies in Hz", f"{f.size} values")
        if not np.all(np.isfinite(f)) or f[0] <= 0:
            raise ConfigError("frequency_hz", "positive finite frequencies in Hz")
        if not np.all(np.diff(f) > 0):
            i = int(np.flatnonzero(np.diff(f) <= 0)[0])
            raise ConfigError(
                "frequency_hz", "strictly increasing frequencies", f"{f[i]:g} then {f[i + 1]:g}"
            )
        object.__setattr__(self, "frequency_hz", f)
        for name in ("H_zu", "H_zw"):
            h = np.asarray(getattr(self, name), dtype=complex)
            if h.shape != f.shape:
                raise ConfigError(name, f"{f.size} values (one per frequency)", f"{h.size}")
            if not np.all(np.isfinite(h)):
                raise ConfigError(name, "finite complex values", "NaN or inf")
            object.__setattr__(self, name, h)
        for name in ("coherence_zu", "coherence_zw"):
            c = getattr(self, name)
            if c is None:
                continue
            c = np.asarray(c, dtype=float)
            if c.shape != f.shape:
                raise ConfigError(name, f"{f.size} values (one per frequency)", f"{c.size}")
            if not np.all((c >= 0) & (c <= 1)):  # NaN fails too
                raise ConfigError(name, "a coherence in [0, 1] at every frequency")
            object.__setattr__(self, name, c)
        if not 0 < self.loop_time_s < np.inf:
            raise ConfigError("loop_time", "a positive loop time in s", self.loop_time_s)
        object.__setattr__(self, "loop_time_s", float(self.loop_time_s))

    @property
    def range_hz(self) -> tuple[float, float]:
        """Lowest and highest measured frequency [Hz]."""
        return (float(self.frequency_hz[0]), float(self.frequency_hz[-1]))

    @property
    def nyquist_hz(self) -> float:
        """Nyquist frequency of the table controller's loop [Hz]."""
        return 0.5 / self.loop_time_s

    def in_band(self, band_hz: tuple[float, float]) -> np.ndarray:
        """Boolean mask of the measured frequencies inside ``band_hz`` [Hz] (edges included)."""
        lo, hi = band_hz
        return (self.frequency_hz >= lo) & (self.frequency_hz <= hi)

    def coherence(self, path: str) -> np.ndarray | None:
        """The coherence of ``"H_zu"`` or ``"H_zw"`` (None when not measured)."""
        return self.coherence_zu if path == "H_zu" else self.coherence_zw


def read_frf_table(path: str | os.PathLike, document: Mapping[str, Any] | None = None) -> FRFTable:
    """Read a measured-FRF table file (``[model] kind = "frf"``, see the module docstring).

    Parameters
    ----------
    path : str or PathLike
        The TOML table file; its ``[model] file`` is relative to its folder.
    document : mapping, optional
        The file already parsed (``read_toml(path)``), e.g. by the dispatcher
        of ``--table``; read from ``path`` when omitted.

    Returns
    -------
    FRFTable
        In internal units: frequencies [Hz], ``H_zu`` [in/s**2 per in],
        ``H_zw`` [in/s**2 per lbf], loop time [s].

    Raises
    ------
    DataFileError
        One line naming the TOML file and key (missing ``[model]``, ``kind`` not
        ``"frf"``, missing ``file`` or ``loop_time``, a unit of the wrong
        dimension, an unknown key) or the CSV file and column (missing column,
        unknown column, a value that is not a finite number, non-increasing
        frequencies, coherence outside [0, 1]).
    """
    toml_path = Path(path)
    doc = read_toml(toml_path) if document is None else document
    try:
        model = _model_section(doc)
        loop_time = quantity("model.loop_time", model["loop_time"], "second", "positive")
        scale = _path_scales(model["units"])
    except ConfigError as exc:
        raise DataFileError(toml_path, str(exc)) from None
    csv_path = toml_path.parent / model["file"]
    columns = _read_columns(csv_path)
    try:
        responses = {name: _response(columns, name) * scale[name] for name in PATHS}
        return FRFTable(
            columns["frequency_hz"],
            responses["H_zu"],
            responses["H_zw"],
            loop_time,
            columns.get("coherence_zu"),
            columns.get("coherence_zw"),
            toml_path,
        )
    except ConfigError as exc:
        raise DataFileError(csv_path, str(exc)) from None


def _model_section(doc: Mapping[str, Any]) -> Mapping[str, Any]:
    """``[model]`` of an FRF table file, its keys checked (ConfigError naming the key)."""
    model = doc.get("model")
    if not isinstance(model, Mapping):
        raise ConfigError("model", 'a [model] table with kind = "frf"')
    unknown = sorted(set(model) - set(MODEL_KEYS))
    if unknown:
        raise ConfigError(f"model.{unknown[0]}", "one of the keys " + ", ".join(MODEL_KEYS))
    if model.get("kind") != KIND:
        raise ConfigError("model.kind", f'"{KIND}" for a measured-FRF table', model.get("kind"))
    if model.get("delay", "included") != "included":
        raise ConfigError("model.delay", '"included" (a measured FRF holds the loop delay)', model["delay"])
    for key, what in (
        ("file", "the FRF data file (CSV), relative to the table file"),
        ("loop_time", 'the table controller\'s loop time, e.g. "500 us"'),
        ("units", '{ z = "...", u = "...", w = "..." } (pint units of each signal)'),
    ):
        if key not in model:
            raise ConfigError(f"model.{key}", what)
    if not isinstance(model["file"], str) or not model["file"].strip():
        raise ConfigError("model.file", "a file name (CSV)", model["file"])
    return model


def _path_scales(units: Any) -> dict[str, float]:
    """Factor from the file's units to the internal ones, per path (``H_zu``, ``H_zw``)."""
    if not isinstance(units, Mapping):
        raise ConfigError("model.units", '{ z = "...", u = "...", w = "..." }', units)
    unknown = sorted(set(units) - set(SIGNAL_UNITS))
    if unknown:
        raise ConfigError(f"model.units.{unknown[0]}", "one of the signals " + ", ".join(SIGNAL_UNITS))
    factor = {}
    for signal, internal in SIGNAL_UNITS.items():
        key = f"model.units.{signal}"
        text = units.get(signal)
        if not isinstance(text, str) or not text.strip() or text.strip()[0].isdigit():
            raise ConfigError(key, f"a unit with the dimension of {internal} (e.g. a pint unit name)", text)
        try:
            factor[signal] = quantity(key, f"1 {text}", internal, "positive")
        except ConfigError as exc:  # echo the unit as written, not the "1 <unit>" read
            raise ConfigError(key, exc.expected, text) from None
    return {name: factor[out] / factor[inp] for name, (out, inp) in PATHS.items()}


def _read_columns(path: Path) -> dict[str, np.ndarray]:
    """The named columns of an FRF data file, each a finite float array (DataFileError naming the column)."""
    text = read_text(path, "an FRF data file (CSV)", max_bytes=MAX_CSV_BYTES)
    lines = [(n, line) for n, line in enumerate(text.split("\n"), start=1) if line.strip()]
    lines = [(n, line) for n, line in lines if not line.lstrip().startswith("#")]
    if not lines:
        raise DataFileError(path, "empty FRF data file (expected a header line and data lines)")
    header = [h.strip() for h in next(csv.reader([lines[0][1]]))]
    known = _known_columns()
    for name in header:
        if name not in known:
            raise DataFileError(path, f"unknown column {name!r} (expected some of {', '.join(known)})")
    if len(set(header)) != len(header):
        raise DataFileError(path, "a column is named twice in the header")
    if "frequency_hz" not in header:
        raise DataFileError(path, "missing column 'frequency_hz'")
    for name in PATHS:
        _check_path_columns(path, header, name)
    values: dict[str, list[float]] = {h: [] for h in header}
    for n, row in zip((n for n, _ in lines[1:]), csv.reader(line for _, line in lines[1:])):
        if len(row) != len(header):
            raise DataFileError(path, f"line {n}: expected {len(header)} values, got {len(row)}")
        for name, cell in zip(header, row):
            try:
                number = float(cell)
            except ValueError:
                raise DataFileError(
                    path, f"line {n}: column {name} is not a number: {cell.strip()!r}"
                ) from None
            if not np.isfinite(number):
                raise DataFileError(path, f"line {n}: column {name} is not finite ({cell.strip()})")
            values[name].append(number)
    columns = {name: np.array(v) for name, v in values.items()}
    for name in ("coherence_zu", "coherence_zw"):
        c = columns.get(name)
        if c is not None and c.size and not np.all((c >= 0) & (c <= 1)):
            n = lines[1 + int(np.flatnonzero((c < 0) | (c > 1))[0])][0]
            raise DataFileError(path, f"line {n}: column {name} is outside [0, 1]")
    f = columns["frequency_hz"]
    bad = np.flatnonzero(np.diff(f) <= 0)
    if bad.size:
        n = lines[2 + int(bad[0])][0]
        raise DataFileError(path, f"line {n}: column frequency_hz is not increasing ({f[bad[0] + 1]:g} Hz)")
    return columns


def _known_columns() -> list[str]:
    cols = ["frequency_hz"]
    for name in PATHS:
        cols += [f"{name}_re", f"{name}_im", f"{name}_mag", f"{name}_phase_deg"]
    return cols + ["coherence_zu", "coherence_zw"]


def _check_path_columns(path: Path, header: list[str], name: str) -> None:
    """One complete form per path: ``_re`` and ``_im``, or ``_mag`` and ``_phase_deg``."""
    cartesian = {f"{name}_re", f"{name}_im"}
    polar = {f"{name}_mag", f"{name}_phase_deg"}
    has = set(header)
    if has & cartesian and has & polar:
        raise DataFileError(path, f"{name} given both as re/im and as mag/phase columns: keep one form")
    wanted = polar if has & polar else cartesian
    missing = sorted(wanted - has)
    if missing:
        raise DataFileError(path, f"missing column {missing[0]!r}")


def _response(columns: Mapping[str, np.ndarray], name: str) -> np.ndarray:
    """The complex response of path ``name`` from its columns (in the file's units)."""
    if f"{name}_re" in columns:
        return columns[f"{name}_re"] + 1j * columns[f"{name}_im"]
    mag = columns[f"{name}_mag"]
    if np.any(mag < 0):
        raise ConfigError(f"{name}_mag", "non-negative magnitudes")
    return mag * np.exp(1j * np.radians(columns[f"{name}_phase_deg"]))


def write_frf_table(
    table: FRFTable,
    path: str | os.PathLike,
    units: Mapping[str, str] | None = None,
    header: tuple[str, ...] = (),
) -> Path:
    """Write ``table`` as a TOML table file and its CSV data file beside it (``<stem>.csv``).

    Parameters
    ----------
    table : FRFTable
        Internal units.
    path : str or PathLike
        The TOML file to write; the CSV takes its name with the suffix ``.csv``.
    units : mapping, optional
        Pint unit of each signal ``z``, ``u``, ``w`` in the files (e.g.
        ``{"z": "m/s**2", "u": "mm", "w": "kN"}``); default the internal units.
    header : tuple of str
        Comment lines at the top of the TOML file (where the data came from).

    Returns
    -------
    Path
        The TOML file.
    """
    toml_path = Path(path)
    shown = {
        "z": "inch / second ** 2",
        "u": "inch",
        "w": "force_pound",
        **(units or {}),
    }
    scale = _path_scales(shown)
    cols = ["frequency_hz", "H_zu_re", "H_zu_im", "H_zw_re", "H_zw_im"]
    data = [table.frequency_hz]
    for name in PATHS:
        h = getattr(table, name) / scale[name]
        data += [h.real, h.imag]
    for name in ("coherence_zu", "coherence_zw"):
        c = getattr(table, name)
        if c is not None:
            cols.append(name)
            data.append(c)
    rows = [", ".join(cols)] + [", ".join(repr(float(v)) for v in row) for row in zip(*data)]
    csv_path = atomic_write_text(toml_path.with_suffix(".csv"), "\n".join(rows) + "\n")
    unit_text = ", ".join(f'{k} = "{shown[k]}"' for k in SIGNAL_UNITS)
    text = (
        "".join(f"# {line}\n" for line in header)
        + "[model]\n"
        + f'kind = "{KIND}"\n'
        + f'file = "{csv_path.name}"\n'
        + f'loop_time = "{table.loop_time_s!r} s"\n'
        + f"units = {{ {unit_text} }}\n"
    )
    return atomic_write_text(toml_path, text)
