"""Motion sources by name: a built-in record, a FEMA P695 record, or a file; one naming for all.

A *source* is the text a user or a campaign gives for a ground motion:

* a key of :data:`~impedance_mil.signals.readers.BUILTIN_MOTIONS` (``elcentro``);
* ``fema:SET:RECORDCOMPONENT``, a FEMA P695 record such as ``fema:farfield:14a``
  (record 14, component a, written as the FEMA P695 tables write it); the older
  spelling ``fema:SET:RECORD:COMPONENT`` (``fema:farfield:14:a``) is still read;
* a path to a PEER ``.AT2``, two-column text or CSV file.

:func:`fema_source` writes the one canonical FEMA name (the campaigns hash it
into run names; the CLI prints it); :func:`parse_fema` reads both spellings.
:func:`scaled_motion` reads a source and applies time compression and PGA
scaling, in that order (report Section 8.2), for the CLI, the campaigns and
the virtual-system loops alike.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ..errors import ConfigError
from .fema import read_fema_p695
from .motion import GroundMotion
from .readers import BUILTIN_MOTIONS, builtin_motion, check_units, read_motion

#: Prefix of a FEMA P695 source.
FEMA_PREFIX = "fema:"

_RECORD = re.compile(r"^(\d+)([A-Za-z])$")


@dataclass(frozen=True)
class FemaRecord:
    """One horizontal component of a FEMA P695 record: set, 1-based record id, component ``a``/``b``."""

    record_set: str
    record: int
    component: str

    @property
    def source(self) -> str:
        """The canonical source name, ``fema:farfield:14a``."""
        return fema_source(self.record_set, self.record, self.component)


def fema_source(record_set: str, record: int, component: str) -> str:
    """``fema:SET:RECORDCOMPONENT``, e.g. ``fema_source("farfield", 14, "a") == "fema:farfield:14a"``."""
    return f"{FEMA_PREFIX}{record_set}:{int(record)}{component}"


def parse_fema(text: str, key: str = "SOURCE") -> FemaRecord:
    """Read ``[fema:]SET:RECORDCOMPONENT`` or the older ``[fema:]SET:RECORD:COMPONENT``.

    Raises
    ------
    ConfigError
        Naming ``key``: not of that form, or the record id is not an integer.
    """
    body = text[len(FEMA_PREFIX) :] if text.lower().startswith(FEMA_PREFIX) else text
    parts = body.split(":")
    expected = "fema:SET:RECORDCOMPONENT, e.g. fema:farfield:14a (or fema:farfield:14:a)"
    if len(parts) == 3:
        record_text, component = parts[1], parts[2]
    elif len(parts) == 2 and (match := _RECORD.match(parts[1])):
        record_text, component = match.groups()
    else:
        raise ConfigError(key, expected, text)
    try:
        record = int(record_text)
    except ValueError:
        raise ConfigError(key, "an integer record id in " + expected, text) from None
    return FemaRecord(parts[0], record, component)


def read_source(
    source: str, motion_units: str | None = None, key: str = "SOURCE", units_key: str = "motion_units"
) -> GroundMotion:
    """The motion a source names (see the module docstring), as recorded [in/s^2].

    Parameters
    ----------
    source : str
        Built-in name, FEMA P695 source or file path.
    motion_units : str or None
        Unit of the accelerations of a column file that states none (required
        for such a file); the built-in and FEMA records and AT2 files are in g.
    key : str
        Name of the source in error messages (``--motion``, ``SOURCE`` ...).
    units_key : str
        Name of ``motion_units`` in error messages (``--motion-units`` ...).

    Raises
    ------
    ConfigError
        A malformed FEMA source, an unknown record, a ``motion_units`` that is not an
        acceleration unit (whatever the source), or none for a column file
        that states no unit.
    DataFileError
        A missing or malformed file.
    """
    check_units(motion_units, units_key)
    name = source.strip().lower()
    if name in BUILTIN_MOTIONS:
        return builtin_motion(name)
    if name.startswith(FEMA_PREFIX):
        rec = parse_fema(source.strip(), key)
        return read_fema_p695(rec.record_set, rec.record, rec.component)
    return read_motion(Path(source), motion_units, units_key)


def scaled_motion(
    source: str,
    motion_units: str | None = None,
    time_scale: float | None = None,
    pga_g: float | None = None,
    key: str = "SOURCE",
    units_key: str = "motion_units",
) -> GroundMotion:
    """:func:`read_source`, then time compression (t' = t / ``time_scale``), then scaling to ``pga_g`` [g].

    ``motion_units``: the acceleration unit of a column file that states none
    (``units_key`` names it in errors).
    """
    motion = read_source(source, motion_units, key, units_key)
    if time_scale is not None:
        motion = motion.time_scaled(time_scale)
    if pga_g is not None:
        motion = motion.scaled_to_pga(pga_g)
    return motion


def motion_summary(motion: GroundMotion) -> dict:
    """Points, interval [s], duration [s], PGA [g], and PGV [in/s] / PGD [in] after and before baseline correction."""
    corrected = motion.baseline_corrected()
    return {
        "name": motion.name,
        "source": motion.source,
        "npts": motion.npts,
        "dt_s": motion.time_step,
        "duration_s": motion.duration,
        "pga_g": motion.pga_g,
        "pgv_in_s": corrected.pgv,
        "pgd_in": corrected.pgd,
        "pgv_in_s_uncorrected": motion.pgv,
        "pgd_in_uncorrected": motion.pgd,
    }
