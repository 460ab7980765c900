"""A run's summary: its metrics under the shared names, and where it is stored in the run file.

Every producer of runs (``imil simulate``/``track``/``frf``, the campaign kinds
``mil``/``tracking``/``frf``) and every reader (``imil report``, the HTML
page) uses this module, so that the metric names and the file layout exist
once:

* :func:`run_summary` gives a run's figures of merit under the names shared
  by the CLI's JSON, the run file and the campaign summaries
  (:data:`METRIC_KEYS`: ``spectral_error_0p25_15hz``, ``spectral_error_15_50hz``,
  ``nrms_error``, ``peak_error``, ``energy_error``, ``simulated_s``,
  ``aborted``, ``abort_reason``, ``trip`` with ``limit``, ``time_s``, ``value``);
* :func:`write_run_file` writes the lab's run file
  (:func:`impedance_mil.lab.results.save_run`) with the summary as the root
  attribute :data:`SUMMARY_ATTR` (JSON) and the producer's arrays in the group
  :data:`SUMMARY_GROUP` (the FRF in ``imil/frf``, the VS model's loop in
  ``imil/vs_model_loop``); :func:`read_summary` reads them back.

A trip is stated as ``limit 'stroke' tripped at t = 2.6500 s (value -3.001 in)``
(:func:`trip_text`).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from ..display import UnitSystem, format_value
from ..errors import DataFileError
from ..fileio import json_safe
from ..units import in_s2_to_g
from .metrics import RunMetrics, evaluate_run, vs_force_history
from .results import RunResult, attr_json, save_run
from .run_stream import RunFileStream

#: Root attribute of a run file holding the producer's summary (JSON).
SUMMARY_ATTR = "imil_summary_json"
#: HDF5 group holding the producer's extra arrays.
SUMMARY_GROUP = "imil"
#: Subgroup of :data:`SUMMARY_GROUP` with the FRF of a multisine run.
FRF_GROUP = "frf"
#: Subgroup of :data:`SUMMARY_GROUP` with the VS model's own isolator loop of a MIL run.
MODEL_LOOP = "vs_model_loop"
#: Datasets of :data:`MODEL_LOOP`: displacement [in], force [lbf].
MODEL_LOOP_KEYS = ("displacement_in", "force_lbf")

#: The shared metric names (CLI JSON, run files, campaign summaries), with the RunMetrics field of each.
METRIC_KEYS = {
    "spectral_error_0p25_15hz": "spectral_error_low",
    "spectral_error_15_50hz": "spectral_error_high",
    "nrms_error": "nrms_error",
    "peak_error": "peak_error",
    "energy_error": "energy_error",
}
#: Metric names of files written before the names were shared (campaign summaries), by shared name.
LEGACY_METRIC_KEYS = {
    "spectral_error_0p25_15hz": "spectral_error_low",
    "spectral_error_15_50hz": "spectral_error_high",
    "simulated_s": "duration_s",
    "model_error_0p25_100hz": "model_error",
}

#: How a run ended, in :func:`trip_summary` (the trip itself is flattened to ``trip_*`` in table rows).
TRIP_KEYS = ("simulated_s", "aborted", "abort_reason")

#: Shortest run with metrics [s] (lab.experiments computes none below it).
MIN_METRICS_S = 1.0


def trip_text(run: RunResult, units: UnitSystem = UnitSystem.US) -> str | None:
    """``"limit 'stroke' tripped at t = 2.6500 s (value -3.001 in)"`` (the value in ``units``), or None."""
    if run.trip is None:
        return None
    unit = run.trip.unit
    value = format_value(run.trip.value, unit, units) if unit else f"{run.trip.value:.4g}"
    return f"limit '{run.trip.limit}' tripped at t = {run.trip.time_s:.4f} s (value {value})"


def trip_summary(run: RunResult) -> dict[str, Any]:
    """``simulated_s`` [s], ``aborted``, ``abort_reason`` and ``trip`` (``limit``, ``time_s`` [s], ``value``)."""
    return {
        "simulated_s": run.n_samples * run.loop_time,
        "aborted": run.trip is not None,
        "abort_reason": trip_text(run),
        "trip": None if run.trip is None else run.trip.to_dict(),
    }


def metric_values(metrics: RunMetrics | None) -> dict[str, float | None]:
    """The :class:`RunMetrics` under the shared names (all None without metrics)."""
    m = metrics.to_dict() if metrics is not None else {}
    return {key: m.get(field) for key, field in METRIC_KEYS.items()}


def run_summary(run: RunResult, metrics: RunMetrics | None) -> dict[str, Any]:
    """The run's figures of merit under the shared names (fractions, g, in, s).

    ``spectral_error_*``: mean absolute relative error of the 5 %-damped PSA of
    the measured table acceleration against the target
    (:func:`impedance_mil.lab.metrics.spectral_error`); ``peak_table_accel_g``
    [g], ``peak_target_accel_g`` [g] and ``peak_table_disp_in`` [in] (None for
    a run without samples).
    """
    n = run.n_samples

    def peak(name: str) -> float | None:
        return float(np.max(np.abs(run.channels[name]))) if n else None

    table, target = peak("z_meas"), peak("z_vs")
    return {
        "mode": run.mode,
        **trip_summary(run),
        **metric_values(metrics),
        "peak_table_accel_g": None if table is None else in_s2_to_g(table),
        "peak_target_accel_g": None if target is None else in_s2_to_g(target),
        "peak_table_disp_in": peak("x"),
    }


def flat_summary(summary: Mapping[str, Any]) -> dict[str, Any]:
    """A summary with its ``trip`` as ``trip_limit``, ``trip_time_s``, ``trip_value`` (for table rows)."""
    out = {k: v for k, v in summary.items() if k != "trip"}
    trip = summary.get("trip")
    if trip:
        out.update({f"trip_{k}": v for k, v in trip.items()})
    return out


def recomputed_summary(run: RunResult) -> dict[str, Any]:
    """Summary of a run file without a stored one: lab metrics against ``z_vs`` (no energy error)."""
    metrics = None
    if run.mode in ("track", "mil") and run.n_samples * run.loop_time >= MIN_METRICS_S:
        metrics = evaluate_run(run)
    return run_summary(run, metrics)


def model_loop(run: RunResult, vs, force=None) -> dict[str, np.ndarray]:
    """The VS model's own isolator loop along a MIL run: displacement [in] and force [lbf].

    ``force``: ``vs_force_history(vs, run.vs_states)`` [lbf] when the caller has it already
    (``lab.experiments.ControlledRun.vs_force``); computed otherwise.
    """
    if force is None:
        force = vs_force_history(vs, run.vs_states)
    return {MODEL_LOOP_KEYS[0]: run.vs_states[:, 0], MODEL_LOOP_KEYS[1]: force}


def basemat_mass(run: RunResult) -> float | None:
    """m_vs [lbf*s^2/in] of a MIL run's VS (from the run's configuration), else None."""
    vs = run.config.get("vs") if run.mode == "mil" else None
    value = vs.get("m_vs") if isinstance(vs, Mapping) else None
    return float(value) if value is not None else None


def write_run_file(
    run: RunResult,
    path: str | Path,
    summary: Mapping[str, Any],
    arrays: Mapping[str, Mapping[str, Any]] | None = None,
) -> Path:
    """Write the lab's run file with ``summary`` and ``arrays``, atomically (``lab.results.save_run``).

    The summary is the root attribute :data:`SUMMARY_ATTR` (JSON, NaN as
    null); ``arrays`` (``{name: {dataset: array}}``) are subgroups of
    :data:`SUMMARY_GROUP`.
    """
    attrs, groups = summary_extras(summary, arrays)
    return save_run(run, path, extra_attrs=attrs, extra_groups=groups)


def finish_run_file(
    stream: RunFileStream,
    run: RunResult,
    summary: Mapping[str, Any],
    arrays: Mapping[str, Mapping[str, Any]] | None = None,
) -> Path:
    """:func:`write_run_file` for a run file written as the run went (``stream`` received its records)."""
    attrs, groups = summary_extras(summary, arrays)
    return stream.finish(run, extra_attrs=attrs, extra_groups=groups)


def summary_extras(
    summary: Mapping[str, Any], arrays: Mapping[str, Mapping[str, Any]] | None
) -> tuple[dict[str, str], dict[str, dict] | None]:
    """The summary as the root attribute :data:`SUMMARY_ATTR`, the arrays under :data:`SUMMARY_GROUP`."""
    groups = {SUMMARY_GROUP: dict(arrays)} if arrays else None
    return {SUMMARY_ATTR: json.dumps(json_safe(summary))}, groups


def read_summary(path: str | Path) -> tuple[dict | None, dict]:
    """The summary and arrays stored with a run (``(None, {})`` for a run file without them).

    Raises
    ------
    DataFileError
        The file is not HDF5 or its summary is not JSON.
    """
    try:
        with h5py.File(path, "r") as fh:
            if SUMMARY_ATTR not in fh.attrs:
                return None, {}
            group = fh.get(SUMMARY_GROUP, {})
            arrays = {
                name: {key: np.asarray(data) for key, data in sub.items()}
                for name, sub in group.items()
                if isinstance(sub, h5py.Group)
            }
            return attr_json(path, fh.attrs, SUMMARY_ATTR), arrays
    except (OSError, ValueError) as exc:
        raise DataFileError(path, f"cannot read the run summary ({exc})") from None


def legacy_value(row: Mapping[str, Any], key: str) -> Any:
    """``row[key]``, or the value under the name files used before the names were shared."""
    value = row.get(key)
    if value is None and key in LEGACY_METRIC_KEYS:
        value = row.get(LEGACY_METRIC_KEYS[key])
    return value
