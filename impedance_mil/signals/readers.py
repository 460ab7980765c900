"""Ground-motion files: PEER NGA ``.AT2``, two-column text, CSV, and the built-in records.

Formats
-------
PEER ``.AT2``
    Four header lines; the third names the quantity and its unit (acceleration
    in g); the fourth gives the number of points and the sample interval, as
    ``NPTS=   5372, DT=   .0100 SEC,`` (NGA-West2) or as two bare numbers
    ``4000  .0050`` (older files, possibly followed by ``NPTS, DT``).  Then
    the samples, any number per line.  The sample count must equal NPTS and
    DT must be positive.
Two-column text or CSV
    ``time, accel`` per line, separated by commas, semicolons, tabs or blanks.
    Leading lines that are not two numbers (a header, ``#`` comments) are
    skipped; after the first data line every line must be data (``#`` comment
    lines and blank lines excepted).  Time must increase strictly and be
    uniform: every time must lie within :data:`UNIFORM_TIME_RTOL` of a sample
    interval from the straight line through the first and last times, else the
    file is refused (resample it yourself: we do not guess).  A record that
    starts at t0 != 0 is shifted to start at 0.  The unit of the accelerations
    is the one the file states (:func:`stated_units`: a comment ``# units:
    m/s**2`` or a header such as ``accel[g]``, ``acc (g)``, ``accel_g``), else
    the one the caller gives; a file that states none, read without a unit,
    is refused (we do not guess g).

Every malformed file raises :class:`~impedance_mil.errors.DataFileError`
naming the file and the problem.
"""

from __future__ import annotations

import io
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..bounds import MAX_MOTION_FILE_BYTES, MAX_RECORD_SAMPLES
from ..config import quantity
from ..errors import ConfigError, DataFileError
from ..fileio import atomic_path, read_text
from ..units import G0
from .motion import GroundMotion

#: Largest deviation of a sample time from uniform sampling, as a fraction of the interval.
UNIFORM_TIME_RTOL = 0.01

#: Folder of the records shipped with the package (see ``data/PROVENANCE.md``).
MOTIONS_DIR = Path(__file__).resolve().parent.parent / "data" / "motions"

# NPTS is read as a number token, so that "NPTS= 5372.5" is refused rather than read as 5372.
_NPTS_RE = re.compile(r"NPTS\s*=\s*([-+0-9.EeDd]+)", re.IGNORECASE)
_DT_RE = re.compile(r"DT\s*=\s*([-+0-9.EeDd]+)", re.IGNORECASE)
_NUMBER_RE = re.compile(r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[EeDd][-+]?[0-9]+)?")
_SPLIT_RE = re.compile(r"[,;\s]+")
#: The column separators other than white space (replaced by a space for numpy's reader).
_SEPARATORS_RE = re.compile(r"[,;]")
_OTHER_UNITS_RE = re.compile(r"CM/S|M/S|MM/S|IN/S|FT/S|GAL", re.IGNORECASE)
# "# units: m/s**2" (or "unit = g") in a comment line of a column file.
_UNITS_COMMENT_RE = re.compile(r"^#\s*units?\s*[:=]\s*(\S.*?)\s*$", re.IGNORECASE)
# A column name with its unit in brackets: accel[g], acc (g).
_BRACKET_UNIT_RE = re.compile(r"[\[(]\s*([^\])]+?)\s*[\])]\s*$")
_HEADER_SPLIT_RE = re.compile(r"\s*[,;\t]\s*")


@dataclass(frozen=True)
class BuiltinRecord:
    """A record shipped with the package.

    Parameters
    ----------
    filename : str
        File in :data:`MOTIONS_DIR`.
    name : str
        Label given to the motion.
    description : str
        One line for listings.
    units : str
        Unit of the file's accelerations.
    """

    filename: str
    name: str
    description: str
    units: str = "g"


#: The built-in records by key.  ``"elcentro"`` is the report's GM1 seed (Table 8.1, RSN 6).
BUILTIN_MOTIONS: dict[str, BuiltinRecord] = {
    "elcentro": BuiltinRecord(
        "RSN6_IMPVALL_I-ELC180.AT2",
        "Imperial Valley-02 1940, El Centro Array #9, 180 (RSN 6)",
        "PEER NGA-West2 RSN 6 I-ELC180, dt 0.01 s, 53.7 s, PGA 0.281 g (report Table 8.1 GM1 seed)",
    ),
    "elcentro-chopra": BuiltinRecord(
        "elcentro_chopra.csv",
        "Imperial Valley 1940, El Centro NS (Chopra, Appendix 6)",
        "El Centro NS as tabulated by Chopra, dt 0.02 s, 31.2 s, PGA 0.319 g",
    ),
}


def _read_text(path: Path) -> list[str]:
    lines = read_text(path, "a ground-motion file", max_bytes=MAX_MOTION_FILE_BYTES).splitlines()
    if not any(line.strip() for line in lines):
        raise DataFileError(path, "empty file")
    return lines


def _parse_float(token: str) -> float:
    return float(token.replace("D", "E").replace("d", "e"))


def _numbers(path: Path, lines: list[str], first_line: int) -> np.ndarray:
    """All whitespace-separated numbers of ``lines``; ``first_line`` is the 1-based number of lines[0]."""
    values: list[float] = []
    for offset, line in enumerate(lines):
        for token in line.split():
            try:
                values.append(_parse_float(token))
            except ValueError:
                raise DataFileError(
                    path, f"line {first_line + offset}: non-numeric token {token!r}"
                ) from None
            if not np.isfinite(values[-1]):
                raise DataFileError(
                    path, f"line {first_line + offset}: {token} sample (samples must be finite)"
                )
    return np.array(values, dtype=float)


def _at2_header(path: Path, lines: list[str]) -> tuple[int, float]:
    if len(lines) < 4:
        raise DataFileError(path, "truncated PEER AT2 header: expected 4 header lines")
    kind = lines[2].upper()
    if "VELOCITY" in kind or "DISPLACEMENT" in kind:
        raise DataFileError(path, f"line 3 says {lines[2].strip()!r}: expected an acceleration time series")
    if _OTHER_UNITS_RE.search(kind):
        raise DataFileError(path, f"line 3 says {lines[2].strip()!r}: expected accelerations in units of g")
    header = lines[3]
    npts_m, dt_m = _NPTS_RE.search(header), _DT_RE.search(header)
    if npts_m and dt_m:
        npts_text, dt_text = npts_m.group(1), dt_m.group(1)
    else:
        tokens = _NUMBER_RE.findall(header)
        if len(tokens) < 2:
            raise DataFileError(path, f"line 4: expected NPTS and DT, got {header.strip()!r}")
        npts_text, dt_text = tokens[0], tokens[1]
    try:
        npts_value = _parse_float(npts_text)
        dt = _parse_float(dt_text)
    except ValueError:
        raise DataFileError(path, f"line 4: expected NPTS and DT, got {header.strip()!r}") from None
    if not np.isfinite(npts_value) or npts_value != int(npts_value) or npts_value < 2:
        raise DataFileError(path, f"line 4: NPTS must be an integer >= 2, got {npts_text}")
    if npts_value > MAX_RECORD_SAMPLES:
        raise DataFileError(
            path, f"line 4: NPTS = {npts_text} is more than {MAX_RECORD_SAMPLES} samples (docs/limits.md)"
        )
    if not (np.isfinite(dt) and dt > 0):
        raise DataFileError(path, f"line 4: DT must be positive, got {dt_text}")
    return int(npts_value), dt


def read_at2(path: str | Path) -> GroundMotion:
    """Read a PEER NGA ``.AT2`` acceleration file (values in g).

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    GroundMotion
        Accelerations converted to [in/s**2]; ``name`` is the second header line.

    Raises
    ------
    DataFileError
        Empty or truncated file, unreadable NPTS/DT, DT <= 0, a non-numeric
        token, a NaN or infinite sample, or a sample count different from NPTS.
    """
    p = Path(path)
    lines = _read_text(p)
    npts, dt = _at2_header(p, lines)
    values = _numbers(p, lines[4:], 5)
    if values.size != npts:
        raise DataFileError(p, f"header says NPTS = {npts} but the file holds {values.size} samples")
    title = lines[1].strip() or p.stem
    return GroundMotion(dt, values * G0, title, f"{p.name} (PEER AT2, g)")


def _looks_like_at2(lines: list[str]) -> bool:
    return len(lines) >= 4 and bool(_NPTS_RE.search(lines[3]))


def _unit_factor(units: str, key: str = "units") -> float:
    """Factor from ``units`` to [in/s**2]; ``g`` means standard gravity here (errors name ``key``)."""
    text = str(units).strip()
    if text.lower() in ("g", "g0"):
        return G0
    return quantity(key, f"1 {text}", "inch / second**2", "positive")


def check_units(units: str | None, key: str = "units") -> None:
    """Refuse a ``units`` that is not an acceleration unit (None: not given, accepted).

    Raises
    ------
    ConfigError
        Naming ``key``.
    """
    if units is not None:
        _unit_factor(units, key)


def stated_units(path: Path, lines: list[str]) -> str | None:
    """The acceleration unit a column file states before its data, or None.

    Read from a comment ``# units: m/s**2`` (or ``# unit = g``) or from the
    header naming the acceleration column (the last): ``accel[g]``, ``acc (g)``,
    ``accel_m/s**2`` (as :func:`write_columns` writes it), ``a_g_g`` (as
    ``imil drive motion`` writes it).  A name whose suffix is no acceleration
    unit (``accel_m_s2``) states none.

    Raises
    ------
    DataFileError
        The ``# units:`` comment names no acceleration unit.
    """
    for number, line in enumerate(lines, start=1):
        stripped = line.strip()
        if not stripped:
            continue
        tokens = _split_row(stripped)
        if not stripped.startswith("#") and _row_values(tokens) is not None:
            return None  # the data begins: no unit stated
        comment = _UNITS_COMMENT_RE.match(stripped)
        if comment:
            try:
                _unit_factor(comment.group(1))
            except ConfigError:
                raise DataFileError(
                    path, f"line {number} states {comment.group(1)!r}: not an acceleration unit"
                ) from None
            return comment.group(1)
        if not stripped.startswith("#"):
            text = _header_unit(stripped)
            if text is not None:
                return text
    return None


def _header_unit(line: str) -> str | None:
    """The acceleration unit in the name of a header's last column (``accel[g]``, ``a_g_g``), or None.

    The unit is in brackets or after an underscore (the shortest suffix that
    is an acceleration unit); a name such as ``accel_m_s2`` states none.
    """
    fields = [f for f in _HEADER_SPLIT_RE.split(line) if f]
    name = fields[-1] if len(fields) > 1 else line
    bracket = _BRACKET_UNIT_RE.search(name)
    candidates = [bracket.group(1)] if bracket else []
    parts = name.split("_")
    candidates += ["_".join(parts[k:]) for k in range(1, len(parts))]
    for text in candidates:
        try:
            _unit_factor(text)
        except ConfigError:
            continue
        return text
    return None


def _column_units(path: Path, lines: list[str], units: str | None, key: str) -> str:
    """The unit of a column file's accelerations: the one it states, else ``units``."""
    stated = stated_units(path, lines)
    if stated is None:
        if units is None:
            raise ConfigError(
                key,
                f"the unit of the accelerations of {path.name} (the file states none: "
                "give it, or a header such as accel[g] or '# units: m/s**2')",
                "no unit",
            )
        return units
    if units is not None and _unit_factor(units, key) != _unit_factor(stated):
        raise ConfigError(key, f"{stated} as {path.name} states (or leave it out)", units)
    return stated


def _split_row(line: str) -> list[str]:
    return [tok for tok in _SPLIT_RE.split(line.strip()) if tok]


def _row_values(tokens: list[str]) -> list[float] | None:
    try:
        return [_parse_float(tok) for tok in tokens]
    except ValueError:
        return None


def _column_rows(path: Path, lines: list[str]) -> tuple[np.ndarray, int]:
    """Rows of two numbers and the 1-based line number of the first data row.

    The data after the header are parsed at once by numpy's C reader (measured on 1.2 million
    rows, 600 s at 500 us: 2.0 s against 13.9 s line by line, the same values bit for bit);
    whatever that reader does not take -- a bad token, a ragged row, NaN -- is read again line
    by line, which names the line (:func:`_column_rows_by_line`).
    """
    first = _first_data_line(lines)
    if first:
        body = [line for line in lines[first - 1 :] if line.strip() and not line.lstrip().startswith("#")]
        text = _SEPARATORS_RE.sub(" ", "\n".join(body)).replace("D", "E").replace("d", "e")
        try:
            rows = np.loadtxt(io.StringIO(text), dtype=float, ndmin=2, comments=None)
        except ValueError:
            rows = None
        if rows is not None and rows.shape == (len(body), 2) and len(body) >= 2 and np.isfinite(rows).all():
            return rows, first
    return _column_rows_by_line(path, lines)


def _first_data_line(lines: list[str]) -> int:
    """The 1-based number of the first line of two numbers (0: none)."""
    for number, line in enumerate(lines, start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        values = _row_values(_split_row(stripped))
        if values is not None and len(values) == 2:
            return number
    return 0


def _column_rows_by_line(path: Path, lines: list[str]) -> tuple[np.ndarray, int]:
    """:func:`_column_rows` line by line, naming the first bad line."""
    rows: list[list[float]] = []
    first = 0
    for number, line in enumerate(lines, start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        tokens = _split_row(stripped)
        values = _row_values(tokens)
        if not rows and (values is None or len(values) != 2):
            continue  # header line before the data
        if values is None:
            bad = next(tok for tok in tokens if _row_values([tok]) is None)
            raise DataFileError(path, f"line {number}: non-numeric token {bad!r}")
        if len(values) != 2:
            raise DataFileError(path, f"line {number}: expected 2 columns (time, accel), got {len(values)}")
        if not all(np.isfinite(values)):
            raise DataFileError(path, f"line {number}: non-finite value (NaN or inf)")
        if not rows:
            first = number
        rows.append(values)
    if not rows:
        raise DataFileError(path, "no data: expected lines of two numbers (time, accel)")
    if len(rows) < 2:
        raise DataFileError(path, "only one sample: expected at least 2")
    return np.array(rows, dtype=float), first


def _check_uniform(path: Path, time: np.ndarray, first_line: int) -> float:
    steps = np.diff(time)
    if np.any(steps <= 0):
        k = int(np.flatnonzero(steps <= 0)[0])
        raise DataFileError(
            path,
            f"time not strictly increasing at data row {k + 2} "
            f"(line >= {first_line + k + 1}): {time[k + 1]:.9g} s after {time[k]:.9g} s",
        )
    n = time.size
    dt = (time[-1] - time[0]) / (n - 1)
    deviation = np.abs(time - (time[0] + dt * np.arange(n)))
    worst = int(np.argmax(deviation))
    if deviation[worst] > UNIFORM_TIME_RTOL * dt:
        raise DataFileError(
            path,
            f"time not uniformly sampled: sample {worst + 1} at {time[worst]:.9g} s is "
            f"{deviation[worst]:.3g} s off the uniform grid of dt = {dt:.9g} s "
            f"(tolerance {UNIFORM_TIME_RTOL:g} dt); resample the record first",
        )
    return dt


def read_columns(path: str | Path, units: str | None = None, key: str = "units") -> GroundMotion:
    """Read a two-column (time [s], acceleration) text or CSV file.

    Parameters
    ----------
    path : str or Path
        The file.
    units : str or None
        Unit of the accelerations when the file states none (:func:`stated_units`):
        ``"g"`` (standard gravity) or any pint acceleration unit such as
        ``"m/s**2"``, ``"cm/s**2"``, ``"in/s**2"``.  Given with a file that
        states another unit, it is refused.
    key : str
        Name of ``units`` in error messages (``--motion-units`` for the CLI).

    Returns
    -------
    GroundMotion
        Accelerations in [in/s**2], time shifted to start at 0.

    Raises
    ------
    DataFileError
        Empty file, no data rows, a row without exactly two numbers, a
        non-numeric token or NaN inside the data, time not strictly increasing
        or not uniformly sampled (see :data:`UNIFORM_TIME_RTOL`), a ``# units:``
        comment that names no acceleration unit.
    ConfigError
        Naming ``key``: ``units`` is not an acceleration unit, differs from
        the file's, or is None for a file that states no unit.
    """
    p = Path(path)
    check_units(units, key)
    lines = _read_text(p)
    rows, first_line = _column_rows(p, lines)
    dt = _check_uniform(p, rows[:, 0], first_line)
    units = _column_units(p, lines, units, key)
    factor = _unit_factor(units, key)
    note = f"{p.name} (two-column, {units})"
    if rows[0, 0] != 0.0:
        note += f", shifted from t0 = {rows[0, 0]:.9g} s"
    return GroundMotion(dt, rows[:, 1] * factor, p.stem, note)


def read_motion(path: str | Path, units: str | None = None, key: str = "units") -> GroundMotion:
    """Read a ground-motion file: PEER ``.AT2``, two-column text or CSV.

    A file whose suffix is ``.at2`` (any case), or whose fourth line carries
    ``NPTS=``, is read as PEER AT2 (always in g; ``units``, if given, must
    then be g); any other file as two columns (time [s], acceleration in the
    unit the file states, else ``units``: see :func:`read_columns`).

    Parameters
    ----------
    path : str or Path
        The file.
    units : str or None
        Unit of the accelerations of a column file that states none.
    key : str
        Name of ``units`` in error messages.

    Returns
    -------
    GroundMotion
        Accelerations in [in/s**2].

    Raises
    ------
    DataFileError
        Missing, unreadable or malformed file (see :func:`read_at2`, :func:`read_columns`).
    ConfigError
        Naming ``key``: ``units`` is not an acceleration unit, is not g for an
        AT2 file, or is missing for a column file that states no unit.
    """
    p = Path(path)
    if p.suffix.lower() == ".at2" or (p.is_file() and _looks_like_at2(_read_text(p))):
        if units is not None and _unit_factor(units, key) != G0:
            raise ConfigError(key, "g for a PEER AT2 file (its header fixes the unit)", units)
        return read_at2(p)
    return read_columns(p, units, key)


def builtin_motion(name: str = "elcentro") -> GroundMotion:
    """A record shipped with the package.

    Parameters
    ----------
    name : str
        A key of :data:`BUILTIN_MOTIONS`: ``"elcentro"`` (PEER NGA-West2 RSN 6,
        El Centro Array #9, 180 component, the report's GM1 seed, PGA 0.281 g)
        or ``"elcentro-chopra"`` (the El Centro NS record as tabulated by
        Chopra, PGA 0.319 g).

    Raises
    ------
    ConfigError
        Unknown name.
    """
    key = str(name).strip().lower()
    if key not in BUILTIN_MOTIONS:
        raise ConfigError("motion", "one of the built-in records " + ", ".join(BUILTIN_MOTIONS), name)
    record = BUILTIN_MOTIONS[key]
    motion = read_motion(MOTIONS_DIR / record.filename, units=record.units)
    return GroundMotion(motion.time_step, motion.accel, record.name, f"built-in '{key}': {motion.source}")


def write_columns(motion: GroundMotion, path: str | Path, units: str = "g") -> Path:
    """Write a motion as CSV ``time_s,accel_<units>`` (readable by :func:`read_columns`).

    The file is written under a temporary name in the same folder and then
    renamed, so a failure leaves nothing half-written.

    Parameters
    ----------
    motion : GroundMotion
        The motion.
    path : str or Path
        Target file.
    units : str
        Unit of the written accelerations (default g).

    Raises
    ------
    ConfigError
        ``units`` is not an acceleration unit.
    OSError
        The folder does not exist or is not writable.
    """
    target = Path(path)
    factor = _unit_factor(units)
    rows = np.column_stack((motion.time, motion.accel / factor))
    with atomic_path(target) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        fh.write(f"# {motion.name}\n# {motion.source}\n")
        np.savetxt(fh, rows, delimiter=",", fmt="%.10g", header=f"time_s,accel_{units}", comments="")
    return target
