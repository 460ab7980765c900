"""Judging a recorded tracking or MIL test with the metrics and the run file of a virtual run.

:func:`evaluate_recording` takes a checked :class:`~impedance_mil.signals.recordings.Recording`
(the recorded ``a_g``, table acceleration ``z``, test-article force ``w`` and,
when recorded, table displacement ``x`` and command ``u``) and

1. recomputes the target ``z_vs`` as the controller did (:func:`replay_vs`):
   for a MIL test, one RK3 step of the virtual system per loop from the recorded
   ``a_g`` and ``w``, in the controller's arithmetic (``single``: float32, as the
   runtime and the generated code, :mod:`impedance_mil.implement.runtime`); for a
   tracking test ``z_vs = a_g`` (Section 8);
2. builds a :class:`~impedance_mil.lab.results.RunResult` with the lab's channel
   names (``z_meas``, ``x_meas``, ``w_used`` ... and the recomputed VS states), so
   that :func:`~impedance_mil.lab.metrics.evaluate_run` gives the same metrics as
   for a virtual run (spectral errors per band, NRMS, peak, energy);
3. states them under the shared names (:func:`~impedance_mil.lab.runfile.run_summary`)
   and writes the same run file and HTML page.

:func:`compare_summaries` sets a virtual-lab prediction of the same test against
the measurement, metric by metric.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numba
import numpy as np

from ..errors import ConfigError
from ..implement.runtime import precision_dtype
from ..signals import GroundMotion
from ..signals.recordings import Recording
from ..virtual.codegen import compiled
from ..virtual.files import VSSpec
from ..virtual.system import DefinedVS
from .metrics import RunMetrics, evaluate_run
from .results import RunResult
from .runfile import METRIC_KEYS, MIN_METRICS_S, MODEL_LOOP, model_loop, run_summary

#: Kind of an evaluation in its summary and run file.
KIND = "evaluate"
#: Summary entries compared by :func:`compare_summaries` (the shared metric names and the peaks).
COMPARED = (*METRIC_KEYS, "peak_table_accel_g", "peak_target_accel_g", "peak_table_disp_in")


@numba.njit(cache=True, nogil=True)
def _replay_records(fns, p, x, a_g, w, dt, work, z, states):
    """The VS part of the lab's MIL tick over records: state at the start of each loop, then ``z_vs``."""
    tick = fns[0]
    for k in range(a_g.shape[0]):
        for i in range(x.shape[0]):
            states[k, i] = x[i]
        z[k] = tick(p, x, a_g[k], w[k], dt, work)


@dataclass(frozen=True, eq=False)
class VSReplay:
    """The target and states of a VS driven by recorded inputs.

    Attributes
    ----------
    z_vs : ndarray
        Target acceleration per loop [in/s^2] (float64 copy of the controller's values).
    states : ndarray (n, n_states)
        VS state at the start of each loop (internal units).
    """

    z_vs: np.ndarray
    states: np.ndarray


def replay_vs(vs, a_g, w, loop_time: float, precision: str) -> VSReplay:
    """Recompute ``z_vs`` as the MIL controller did, from the recorded ``a_g`` [in/s^2] and ``w`` [lbf].

    The same sequence and arithmetic as the runtime's MIL loop
    (:func:`impedance_mil.implement.runtime.mil_step_kernel`): the inputs and the
    loop time rounded to the controller's precision, ``z_vs`` from the state at
    the start of the loop, then one RK3 step (report Figure 7.9).

    Parameters
    ----------
    vs : VirtualSystem
        The virtual system of the test.
    a_g, w : array_like
        Recorded ground acceleration [in/s^2] and test-article force [lbf] per loop.
    loop_time : float
        Controller loop time [s].
    precision : {"single", "double"}
        The controller's arithmetic.
    """
    dtype = precision_dtype(precision)
    a = np.ascontiguousarray(a_g, dtype=dtype)
    ww = np.ascontiguousarray(w, dtype=dtype)
    n = a.size
    states = np.zeros((n, vs.n_states))
    if isinstance(vs, DefinedVS):
        x = np.asarray(vs.initial_state(), dtype=float).astype(dtype)
        z = np.empty(n, dtype)
        work = np.zeros(4 * max(vs.n_states, 1), dtype)
        fns = (compiled(vs.definition).tick(dtype),)
        _replay_records(fns, vs.parameter_array().astype(dtype), x, a, ww, dtype(loop_time), work, z, states)
        return VSReplay(z.astype(float), states)
    # A VS written in Python: the runtime's _python_mil_step (float64 state, inputs rounded).
    x = np.asarray(vs.initial_state(), dtype=float)
    z = np.empty(n)
    for k in range(n):
        states[k] = x
        ak, wk = float(a[k]), float(ww[k])
        z[k] = float(dtype(vs.outputs(x, ak, wk).z_vs))
        x = vs.step_rk3(x, ak, wk, loop_time)
    return VSReplay(z, states)


def _channels(rec: Recording, z_vs: np.ndarray) -> dict[str, np.ndarray]:
    """The recording under the lab's channel names (a measured channel stands for the true one too)."""
    ch = rec.channels
    out = {"t": rec.time, "a_g": ch["a_g"], "z_vs": z_vs, "z_meas": ch["z"], "z": ch["z"]}
    if "x" in ch:
        out.update(x_meas=ch["x"], x=ch["x"])
    if "w" in ch:
        out.update(w_used=ch["w"], w=ch["w"])
    if "dp" in ch:
        out.update(dp_meas=ch["dp"], dp=ch["dp"])
    if "u" in ch:
        out["u"] = ch["u"]
    return out


@dataclass(frozen=True, eq=False)
class Evaluation:
    """A recorded test judged like a virtual run.

    Attributes
    ----------
    run : RunResult
        The recording as a run (``mode`` ``"mil"`` or ``"track"``), target recomputed.
    metrics : RunMetrics or None
        The run's metrics (None for a recording shorter than 1 s).
    recording : Recording
    vs_spec : VSSpec or None
        The virtual system (None for tracking).
    precision : str
        Controller arithmetic the target was recomputed in.
    """

    run: RunResult
    metrics: RunMetrics | None
    recording: Recording
    vs_spec: VSSpec | None
    precision: str

    def summary(self) -> dict[str, Any]:
        """The metrics under the shared names (as ``imil simulate --json``), the recording and the test."""
        run = self.run
        if "x" not in run.channels:  # not recorded: no displacement peak
            run = replace(run, channels={**run.channels, "x": np.full(run.n_samples, np.nan)})
        clipped = [c.to_dict() for c in self.recording.clipped]
        return {
            "kind": KIND,
            "mode": self.run.mode,
            "vs": None if self.vs_spec is None else self.vs_spec.name,
            "precision": self.precision,
            **run_summary(run, self.metrics),
            "recording": self.recording.provenance(),
            "clipped": clipped,
            "warnings": [f"clipped channel {c['channel']} accepted (--allow-clipped)" for c in clipped],
        }

    def arrays(self) -> dict[str, dict[str, np.ndarray]]:
        """The VS model's own isolator loop along the recomputed states (MIL only)."""
        return {} if self.vs_spec is None else {MODEL_LOOP: model_loop(self.run, self.vs_spec.vs)}


def evaluate_recording(
    recording: Recording, *, vs_spec: VSSpec | None = None, precision: str = "single"
) -> Evaluation:
    """Judge a recorded tracking test (``vs_spec`` None) or MIL test with the virtual lab's metrics.

    Parameters
    ----------
    recording : Recording
        With ``a_g`` and ``z`` (and ``w`` for MIL; ``x`` for the energy error and the loops).
    vs_spec : VSSpec, optional
        The virtual system the MIL test imitated.
    precision : {"single", "double"}
        The controller's arithmetic (the target is recomputed in it).

    Raises
    ------
    ConfigError
        A channel the evaluation needs is not in the recording.
    """
    need = ["a_g", "z"] + (["w"] if vs_spec is not None else [])
    missing = [c for c in need if c not in recording.channels]
    if missing:
        what = "a MIL test" if vs_spec is not None else "a tracking test"
        raise ConfigError(
            "--channel", f"the channels {', '.join(need)} for {what} (map {missing[0]}=COLUMN[UNIT])"
        )
    dt = recording.time_step
    a_g = recording.channels["a_g"]
    if vs_spec is None:
        z_vs = a_g.copy()
        states = np.zeros((a_g.size, 0))
        mode, config_vs = "track", {}
    else:
        replay = replay_vs(vs_spec.vs, a_g, recording.channels["w"], dt, precision)
        z_vs, states = replay.z_vs, replay.states
        mode, config_vs = "mil", {"vs": vs_spec.vs.to_dict()}
    run = RunResult(
        channels=_channels(recording, z_vs),
        vs_states=states,
        vs_state_names=tuple(vs_spec.vs.state_names) if vs_spec is not None else (),
        mode=mode,
        loop_time=dt,
        config={"experiment": KIND, "precision": precision, "recording": recording.provenance(), **config_vs},
    )
    metrics = None
    if recording.duration_s >= MIN_METRICS_S:
        ground = GroundMotion(dt, a_g).displacement() if "x" in recording.channels else None
        metrics = evaluate_run(run, vs=None if vs_spec is None else vs_spec.vs, ground_displacement=ground)
    return Evaluation(run, metrics, recording, vs_spec, precision)


def compare_summaries(measured: Mapping[str, Any], predicted: Mapping[str, Any]) -> dict[str, dict]:
    """Prediction against measurement for every compared entry (:data:`COMPARED`).

    Returns ``{name: {"measured", "predicted", "difference"}}`` with
    ``difference = measured - predicted`` (None where either is missing).
    """
    out = {}
    for key in COMPARED:
        m, p = measured.get(key), predicted.get(key)
        diff = None if m is None or p is None else float(m) - float(p)
        out[key] = {"measured": m, "predicted": p, "difference": diff}
    return out
