"""Running the sampled-data loop: the compiled path and the Python plant-interface path.

:func:`simulate` builds the named structures of the compiled loop
(:data:`impedance_mil.lab.tick.run_loop`: a
:class:`~impedance_mil.lab.structures.VirtualPlant`, a
:class:`~impedance_mil.lab.structures.LoopControl`, the VS tick and the
:class:`~impedance_mil.lab.structures.Records`) from value objects and
returns a :class:`~impedance_mil.lab.results.RunResult`.
:func:`simulate_interface` runs the same tick sequence
(:func:`impedance_mil.lab.tick.run_ticks`, in Python) against any
:class:`~impedance_mil.lab.plant_interface.PlantInterface` (the virtual table,
the solve_ivp reference of :mod:`impedance_mil.lab.reference`, or a real
controller link); with :class:`VirtualTable` both give the same trajectories.

The loop mode follows from the arguments: a ``command`` history alone is an
open-loop test (e.g. the multisine of Section 4.5), a runtime without a VS
tracks ``a_g`` (Section 8, ``z_vs = a_g``), a runtime with a VS is a MIL run
(Section 9).
"""

from __future__ import annotations

import functools
from dataclasses import asdict, replace

import numpy as np

from ..errors import ConfigError
from ..implement.runtime import ControllerArrays
from ..implement.vs_tick import VSArrays, no_vs_tick
from ..plant.nonlinear import N_TABLE_STATES
from .chunks import CHUNK_LOOPS, RecordSink, run_in_chunks
from .lti_plant import LTIVirtualTable, check_feedback, lti_limits, virtual_table_for
from .plant_interface import PlantInterface, VirtualLTITable, VirtualTable, lti_plant, specimen_arrays
from .results import RunResult
from .setup import (
    NoiseDraws,
    SafetyLimits,
    accelerometer_noise,
    default_sensors,
    output_line,
    sensor_arrays,
)
from .structures import (
    FEEDBACK_FE,
    FEEDBACK_LC,
    HELD_STATE,
    MODE_MIL,
    MODE_OPEN,
    MODE_TRACK,
    LoopControl,
    Records,
    VirtualPlant,
)
from .substeps import resolve_substeps
from .tick import run_loop, run_lti_loop, run_ticks
from .trips import Trip, TripCause

_FEEDBACK = {"lc": FEEDBACK_LC, "fe": FEEDBACK_FE}
_MODES = {MODE_OPEN: "open", MODE_TRACK: "track", MODE_MIL: "mil"}


def _history(key: str, values, unit: str) -> np.ndarray:
    # A writable copy: numba compiles the loop once per argument type, and a
    # read-only array (a GroundMotion's samples) is another type.
    arr = np.array(values, dtype=float).ravel()
    if not np.all(np.isfinite(arr)):
        raise ConfigError(key, f"finite samples [{unit}], one per loop", "NaN or inf")
    return arr


def _mode_and_inputs(command, a_g, runtime, loop_time) -> tuple[int, np.ndarray, np.ndarray]:
    if runtime is None:
        if command is None:
            raise ConfigError("command", "a position command history [in] when no controller is given")
        cmd = _history("command", command, "in")
        return MODE_OPEN, np.zeros(cmd.size), cmd
    if a_g is None:
        raise ConfigError("a_g", "a ground acceleration history [in/s^2] for a controlled run")
    if not np.isclose(runtime.loop_time_s, loop_time, rtol=1e-9, atol=0.0):
        raise ConfigError("loop_time", f"the controller's loop time {runtime.loop_time_s:g} s", loop_time)
    ag = _history("a_g", a_g, "in/s^2")
    mode = MODE_MIL if getattr(runtime, "vs", None) is not None else MODE_TRACK
    return mode, ag, np.zeros(ag.size)


def _vs_names(runtime) -> tuple:
    vs = getattr(runtime, "vs", None)
    if vs is None:
        return ()
    names = getattr(vs, "state_names", None)
    return tuple(names) if names else tuple(f"s{i}" for i in range(vs.n_states))


def _config(
    table, specimen, runtime, sensors, limits, substeps: dict, seed, feedback, quantize, extra
) -> dict:
    cfg = {
        "table": table.to_dict() if isinstance(table, LTIVirtualTable) else asdict(table),
        "sensors": sensors.to_dict(),
        "limits": limits.to_dict(),
        **substeps,
        "seed": seed,
        "feedback": feedback,
        "quantize": quantize,
    }
    for key, obj in (("specimen", specimen), ("vs", getattr(runtime, "vs", None))):
        if obj is not None:
            cfg[key] = obj.to_dict() if hasattr(obj, "to_dict") else repr(obj)
    if runtime is not None:
        ctrl = getattr(runtime, "controller", None)
        cfg["controller"] = ctrl.info() if hasattr(ctrl, "info") else repr(ctrl)
        cfg["precision"] = getattr(runtime, "precision", "double")
    cfg.update(extra or {})
    return cfg


def _controller_arrays(runtime) -> tuple:
    """``(ControllerArrays, VS tick, VSArrays)`` of the runtime, reset; float64 placeholders without one."""
    if runtime is None:
        z = np.zeros((1, 1))
        s = np.zeros((2, 0))
        placeholder = ControllerArrays(z, z, s, s.copy(), np.zeros(1), False)
        return placeholder, no_vs_tick(np.float64), VSArrays(np.zeros(0), np.zeros(0), np.zeros(1))
    runtime.reset()
    return runtime.controller_arrays, runtime.vs_tick, runtime.vs_arrays


def _trip(done: int, cause: TripCause, value: float, loop_time: float) -> Trip | None:
    return None if cause == TripCause.NONE else Trip(cause, done * loop_time, float(value))


def _virtual_plant(table, specimen, sens, limits, nsub, noise, line, accel_noise) -> VirtualPlant:
    """The physical table's :class:`VirtualPlant`, at equilibrium."""
    spec = specimen_arrays(specimen)
    n_y = N_TABLE_STATES + spec.B.size
    y = np.zeros(n_y)
    y[:N_TABLE_STATES] = table.equilibrium_state()
    return VirtualPlant(
        table=table.parameter_array(),
        y=y,
        specimen=spec,
        sensors=sens,
        limits=limits.kernel_values(table, accel_noise),
        substeps=nsub,
        noise=noise,
        work=np.zeros((5, n_y)),
        readings=np.zeros(noise.shape[1]),
        held=np.zeros(1, HELD_STATE),
        output_line=line,
    )


def simulate(
    table,
    *,
    command=None,
    a_g=None,
    runtime=None,
    specimen=None,
    feedback: str = "lc",
    sensors=None,
    limits: SafetyLimits | None = None,
    substeps: int | str = "auto",
    seed: int = 0,
    quantize: bool = True,
    output_delay: int = 1,
    config: dict | None = None,
    sink: RecordSink | None = None,
    chunk_loops: int = CHUNK_LOOPS,
) -> RunResult:
    """Run the compiled sampled-data loop.

    The loop runs in chunks (:func:`~impedance_mil.lab.chunks.run_in_chunks`,
    the same run bit for bit): the sensor noise of the next chunk is drawn,
    and the records of the previous one go to ``sink``, while it runs.

    Parameters
    ----------
    table : NonlinearTable, LTIVirtualTable or a linear table model
        The virtual table (its ``loop_time`` is the loop time): the physical
        (nonlinear) table, or a table given by a linear model
        (:func:`~impedance_mil.lab.lti_plant.virtual_table_for`: a
        :class:`~impedance_mil.plant.linear.LinearTable`, an LTI table file's
        model), run by its own compiled loop (:mod:`impedance_mil.lab.lti_kernels`;
        the interlocks it cannot have are listed in
        ``config["interlocks_unavailable"]``, see :func:`~impedance_mil.lab.lti_plant.lti_limits`).
    command : array_like, optional
        Open-loop position command u [in] per loop.
    a_g : array_like, optional
        Ground acceleration [in/s^2] per loop (sampled at the loop time).
    runtime : MILRuntime, optional
        Discrete controller (and VS) of :mod:`impedance_mil.implement`.
    specimen : object, optional
        Test article with ``state_space()``; ``None`` for the bare table.
    feedback : {"lc", "fe"}
        Source of w for the VS and controller: load cells or force equilibrium.
    sensors : SensorSuite, optional
        Default :func:`~impedance_mil.lab.setup.default_sensors` (Table 7.1, 16 bits, 1 mV noise).
    limits : SafetyLimits, optional
        Default interlocks.
    substeps : int or "auto"
        RK4 substeps per loop; ``"auto"`` chooses the smallest count that keeps
        RK4's step error on the coupled plant's fastest mode within
        :data:`~impedance_mil.lab.substeps.RK4_STEP_TOLERANCE`
        (:func:`~impedance_mil.lab.substeps.choose_substeps`).  The count used
        is stored in ``config["substeps"]`` (``config["substeps_rule"]`` says
        which way it was chosen).
    seed : int
        Sensor-noise seed.
    quantize : bool
        16-bit quantization of the sensors (``False`` for model studies).
    output_delay : int
        The controller's output delay N [loops]: the valve command computed at
        loop k is applied over loop k + N - 1 (default 1, the report's: at
        once, with the previous loop's measurements in it); stored in
        ``config["output_delay"]``.
    config : dict, optional
        Extra entries for the stored configuration (e.g. the motion's name).
    sink : RecordSink, optional
        Told of the records chunk by chunk as the run goes (the run file,
        :class:`~impedance_mil.lab.run_stream.RunFileStream`); a user-defined VS
        (run through the plant interface) tells it nothing.
    chunk_loops : int
        Loops per chunk (the run is the same for any value).

    Returns
    -------
    RunResult
        With ``trip`` set (and records up to it) if an interlock stopped the run.
    """
    if feedback not in _FEEDBACK:
        raise ConfigError("feedback", "'lc' (load cells) or 'fe' (force equilibrium)", feedback)
    table = virtual_table_for(table)
    lti = isinstance(table, LTIVirtualTable)
    if lti:
        check_feedback(table, feedback)
    nsub, sub_cfg = resolve_substeps(substeps, table, specimen)
    sensors = sensors or default_sensors()
    sens = sensor_arrays(sensors, feedback, quantize, table.loop_time / nsub, table.loop_time)
    limits = limits or SafetyLimits()
    lti_lim = lti_limits(limits, table, accelerometer_noise(sensors)) if lti else None
    mode, ag, cmd = _mode_and_inputs(command, a_g, runtime, table.loop_time)
    line = output_line(output_delay)
    config = {**(config or {}), "output_delay": int(output_delay)}
    if lti_lim is not None:
        config["interlocks_unavailable"] = dict(lti_lim.unavailable)
        config["integration"] = "exact ZOH of table + specimen; substeps split a loop for the filters only"
    if mode == MODE_MIL and getattr(runtime, "python_vs", False):
        # A user-defined VS has no kernel: the same ticks through the plant interface
        # (VirtualTable calls the compiled plant kernels; trajectories are the same).
        virtual_table = (VirtualLTITable if lti else VirtualTable)(
            table,
            specimen=specimen,
            sensors=sensors,
            limits=limits,
            substeps=nsub,
            seed=seed,
            feedback=feedback,
            quantize=quantize,
            output_delay=output_delay,
        )
        result = simulate_interface(virtual_table, a_g=ag, runtime=runtime, feedback=feedback)
        cfg = _config(
            table,
            specimen,
            runtime,
            sensors,
            limits,
            sub_cfg,
            seed,
            feedback,
            quantize,
            {**config, "path": "python-vs"},
        )
        return replace(result, config=cfg)
    n = ag.size
    noise = NoiseDraws.allocate(np.random.default_rng(seed), sensors, n, table.loop_time)
    ctrl, vs_tick, vs = _controller_arrays(runtime)
    control = LoopControl(mode, _FEEDBACK[feedback], ag, cmd, float(table.loop_time), ctrl, vs)
    log = Records.allocate(n, vs.x.size)
    # The compiled loop allocates nothing (it runs without reference counting): every
    # structure is made here and outlives the call.
    if lti_lim is not None:
        plant_lti = lti_plant(table, specimen, sens, lti_lim.values, nsub, noise.values, output_delay)
        run_chunk = functools.partial(run_lti_loop, plant_lti, control, vs_tick, log)
    else:
        plant = _virtual_plant(
            table, specimen, sens, limits, nsub, noise.values, line, accelerometer_noise(sensors)
        )
        run_chunk = functools.partial(run_loop, plant, control, vs_tick, log)
    records, states = log.up_to(n)
    finished = None if sink is None else lambda start, stop: sink.receive(records, states, start, stop)
    done, cause, value = run_in_chunks(run_chunk, n, prepare=noise.fill, finished=finished, size=chunk_loops)
    channels, vs_states = log.up_to(done)
    return RunResult(
        channels=channels,
        vs_states=vs_states,
        vs_state_names=_vs_names(runtime),
        mode=_MODES[mode],
        loop_time=table.loop_time,
        trip=_trip(done, cause, value, table.loop_time),
        config=_config(table, specimen, runtime, sensors, limits, sub_cfg, seed, feedback, quantize, config),
    )


def simulate_interface(
    plant: PlantInterface, *, command=None, a_g=None, runtime=None, feedback: str = "lc"
) -> RunResult:
    """Run the loop in Python against a :class:`PlantInterface`: the tick sequence of :func:`simulate`.

    :data:`impedance_mil.lab.tick.run_ticks`, the same sequence as the compiled
    loop with the stages of :mod:`impedance_mil.lab.interface_stages`.  The VS
    and controller are stepped through ``runtime.mil_step`` /
    ``runtime.step_parts``.  True plant quantities are recorded when the plant
    offers ``truth()`` (the virtual table does), NaN otherwise; a trip raised
    by ``read_sensors`` ends the run with its cause and value.
    """
    if feedback not in _FEEDBACK:
        raise ConfigError("feedback", "'lc' (load cells) or 'fe' (force equilibrium)", feedback)
    mode, ag, cmd = _mode_and_inputs(command, a_g, runtime, plant.loop_time)
    if runtime is not None:
        runtime.reset()
    plant.reset()
    control = LoopControl(mode, _FEEDBACK[feedback], ag, cmd, float(plant.loop_time), runtime, None)
    log = Records.allocate(ag.size, 0 if runtime is None else len(runtime.x_vs))
    done, cause, value = run_ticks(plant, control, None, log, 0, ag.size)
    channels, vs_states = log.up_to(done)
    return RunResult(
        channels={name: arr.copy() for name, arr in channels.items()},
        vs_states=vs_states.copy(),
        vs_state_names=_vs_names(runtime),
        mode=_MODES[mode],
        loop_time=plant.loop_time,
        trip=_trip(done, cause, value, plant.loop_time),
        config={"plant": type(plant).__name__, "feedback": feedback}
        | ({"output_delay": plant.output_delay} if hasattr(plant, "output_delay") else {}),
    )


__all__ = ["simulate", "simulate_interface", "VirtualTable"]
