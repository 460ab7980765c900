"""The C floor of the lab's loop tick (``tick_floor.c``): build it, fill its case, run it, compare.

Used by ``benchmarks/bench_tick_floor.py`` and ``tests/lab/test_tick_floor.py``
(loaded by path: the benchmarks are scripts, not a package).  The C loop gets
exactly what :data:`impedance_mil.lab.tick.run_loop` gets: the structures are
made here as :func:`impedance_mil.lab.loop.simulate` makes them (its own
helpers ``_virtual_plant`` and ``_controller_arrays``, on purpose: the same
arrays, not a copy of their construction), and :class:`CLoop` passes their
arrays to C by pointer (ctypes and numpy; no compiled dependency).

The C file transcribes one configuration: the physical table, a specimen taken
as a bank of oscillators (the fluid vessel), sensors without anti-alias filters
or delays, a MIL run with a float32 controller and a spring-damper (SD) VS;
:meth:`CLoop.run` refuses another (:class:`UnsupportedCase`).
"""

from __future__ import annotations

import ctypes
import shutil
import subprocess
from pathlib import Path
from typing import NamedTuple

import numpy as np

from impedance_mil.implement.vs_tick import vs_tick_function
from impedance_mil.lab import loop as lab_loop
from impedance_mil.lab.setup import (
    SafetyLimits,
    accelerometer_noise,
    default_sensors,
    draw_noise,
    output_line,
    sensor_arrays,
)
from impedance_mil.lab.stepping import SPEC_BANK
from impedance_mil.lab.structures import (
    CHANNELS,
    FEEDBACK_LC,
    HELD_STATE,
    MODE_MIL,
    LoopControl,
    Records,
)
from impedance_mil.lab.substeps import resolve_substeps
from impedance_mil.lab.tick import run_loop
from impedance_mil.lab.trips import TripCause
from impedance_mil.virtual import presets

#: The transcription.
SOURCE = Path(__file__).with_name("tick_floor.c")
#: Flags every build gets: C99 without contraction of multiply-adds (numba does not
#: contract; gcc does by default in its GNU modes, and -march=native brings FMA).
BASE_FLAGS = ("-std=c99", "-ffp-contract=off", "-fPIC", "-shared")
#: The two optimization levels the benchmark prints.
OPT_LEVELS = {"-O2": ("-O2",), "-O3 -march=native": ("-O3", "-march=native")}


class UnsupportedCase(ValueError):
    """The structures are of a configuration the C transcription does not cover."""


def c_compiler() -> str | None:
    """The system C compiler (``cc``, else ``gcc``, ``clang``), or None."""
    for name in ("cc", "gcc", "clang"):
        path = shutil.which(name)
        if path:
            return path
    return None


def build(workdir: Path, flags: tuple[str, ...], compiler: str | None = None) -> Path:
    """Compile :data:`SOURCE` with ``flags`` into a shared library in ``workdir``; its path."""
    cc = compiler or c_compiler()
    if cc is None:
        raise FileNotFoundError("no C compiler (cc, gcc or clang) on PATH")
    tag = "".join(ch for ch in "_".join(flags) if ch.isalnum() or ch == "_")
    lib = Path(workdir) / f"libtick_floor{tag}.so"
    subprocess.run([cc, *BASE_FLAGS, *flags, "-o", str(lib), str(SOURCE), "-lm"], check=True)
    return lib


class LoopArgs(NamedTuple):
    """The structures ``run_loop`` takes: ``(plant, control, vs_tick, log)``, before its loop range."""

    plant: object
    control: LoopControl
    vs_tick: object
    log: Records


def loop_args(case, a_g: np.ndarray | None = None, seed: int = 0) -> LoopArgs:
    """Fresh ``run_loop`` arguments as :func:`~impedance_mil.lab.loop.simulate` makes them, for ``case``
    (``benchmarks/cases.py``'s ``BenchCase``: its table, vessel, runtime and ``a_g``).

    Its defaults: load-cell feedback, default sensors (Table 7.1, 16 bits,
    1 mV noise), default interlocks, ``substeps="auto"``, output delay 1,
    noise of ``seed``.  The runtime is reset (its arrays are the controller's).
    """
    table, vessel, runtime = case.table, case.vessel, case.runtime
    ag = np.array(case.a_g if a_g is None else a_g, dtype=float).ravel()
    nsub, _ = resolve_substeps("auto", table, vessel)
    sensors = default_sensors()
    sens = sensor_arrays(sensors, "lc", True, table.loop_time / nsub, table.loop_time)
    noise = draw_noise(np.random.default_rng(seed), sensors, ag.size, table.loop_time)
    ctrl, vs_tick, vs = lab_loop._controller_arrays(runtime)
    control = LoopControl(MODE_MIL, FEEDBACK_LC, ag, np.zeros(ag.size), float(table.loop_time), ctrl, vs)
    log = Records.allocate(ag.size, vs.x.size)
    plant = lab_loop._virtual_plant(
        table, vessel, sens, SafetyLimits(), nsub, noise, output_line(1), accelerometer_noise(sensors)
    )
    return LoopArgs(plant, control, vs_tick, log)


class LoopRun(NamedTuple):
    """What a loop recorded: loops done, the trip cause and value, ``{channel: samples}``, VS states."""

    done: int
    cause: TripCause
    value: float
    channels: dict
    vs_states: np.ndarray


def run_numba(args: LoopArgs) -> LoopRun:
    """``run_loop`` on ``args`` (compiled on the first call)."""
    done, cause, value = run_loop(*args, 0, args.control.a_g.shape[0])  # every loop, one chunk
    channels, vs_states = args.log.up_to(done)
    return LoopRun(int(done), TripCause(int(cause)), float(value), channels, vs_states)


# ----------------------------------------------------------------- the C side
_D = ctypes.POINTER(ctypes.c_double)
_F = ctypes.POINTER(ctypes.c_float)
_I = ctypes.POINTER(ctypes.c_int64)
_V = ctypes.c_void_p
_i64 = ctypes.c_int64
_f64 = ctypes.c_double


#: The interlock limits the C case takes as they are, by their names in ``LimitValues``.
LIMIT_FIELDS = (
    "stroke",
    "velocity",
    "actuator_force",
    "valve_saturation_time",
    "divergence",
    "valve_duty",
    "valve_current",
    "command_slew",
    "interlock_window",
    "acceleration",
    "pressure",
)


class _Case(ctypes.Structure):
    # Field by field the tick_floor_case of tick_floor.c (its size is checked on load).
    _fields_ = [
        ("n", _i64),
        ("a_g", _D),
        ("noise", _F),
        ("pa", _D),
        ("y", _D),
        ("n_y", _i64),
        ("substeps", _i64),
        ("n_osc", _i64),
        ("spec_C", _D),
        ("spec_D", _f64),
        ("osc_k", _D),
        ("osc_c", _D),
        ("C_lc", _D),
        ("D_lc", _f64),
        ("lc_own", _i64),
        ("n_channels", _i64),
        ("quantity_index", _I),
        *((name, _D) for name in ("gain", "scale", "offset", "noise_rms", "lsb", "v_low", "v_high")),
        ("load_cell_weights", _D),
        ("z_channel", _i64),
        ("x_channel", _i64),
        ("dp_channel", _i64),
        *((name, _f64) for name in LIMIT_FIELDS),
        *(
            (name, _f64)
            for name in (
                "hf_b0",
                "hf_b1",
                "hf_b2",
                "hf_a1",
                "hf_a2",
            )
        ),
        ("hf_window_loops", _i64),
        ("hf_growth", _f64),
        ("hf_windows", _i64),
        ("hf_floor", _f64),
        ("held", _V),
        ("output_line", _D),
        ("n_line", _i64),
        ("feedback", _i64),
        ("m_z", _F),
        ("n_z", _i64),
        ("m_w", _F),
        ("n_w", _i64),
        ("s_z", _F),
        ("s_w", _F),
        ("compensated", _i64),
        ("vs_params", _F),
        ("vs_x", _F),
        ("dt", _f64),
        ("channels", _D),
        ("vs_states", _D),
    ]


class _Result(ctypes.Structure):
    _fields_ = [("done", _i64), ("cause", _i64), ("value", _f64)]


#: Size limits of the C file's local arrays (MAX_Y, MAX_CH, MAX_CTRL).
_MAX_Y, _MAX_CH, _MAX_CTRL = 64, 16, 16

_POINTER = {np.dtype(np.float64): _D, np.dtype(np.float32): _F, np.dtype(np.int64): _I}


def _ptr(arr: np.ndarray, dtype, keep: list):
    a = np.ascontiguousarray(arr, dtype=dtype)
    keep.append(a)
    return a.ctypes.data_as(_POINTER[np.dtype(dtype)])


def _check_supported(args: LoopArgs) -> None:
    plant, control = args.plant, args.control
    s, sens = plant.specimen, plant.sensors
    reasons = []
    if control.mode != MODE_MIL:
        reasons.append("a MIL run")
    if s.kind != SPEC_BANK:
        reasons.append("a specimen taken as an oscillator bank")
    if sens.filters.channel.size or sens.delays.channel.size:
        reasons.append("sensors without anti-alias filters or delays")
    if control.controller.m_z.dtype != np.float32:
        reasons.append("a single-precision controller")
    # The tick of every SD VS is one compiled function (its definition's), so identity says "SD".
    if args.vs_tick is not vs_tick_function(presets.get("SD2"), np.float32):
        reasons.append("a spring-damper (SD) VS")
    if plant.y.size > _MAX_Y or sens.gain.size > _MAX_CH or plant.output_line.size > _MAX_CH:
        reasons.append(f"at most {_MAX_Y - 6} specimen states, {_MAX_CH} channels and loops of delay")
    if max(control.controller.s_z.shape[1], control.controller.s_w.shape[1]) > _MAX_CTRL:
        reasons.append(f"at most {_MAX_CTRL} controller states per channel")
    if reasons:
        raise UnsupportedCase("the C tick transcribes " + ", ".join(reasons))


class CLoop:
    """The compiled ``tick_floor.c`` (a shared library from :func:`build`)."""

    def __init__(self, library: Path):
        self.library = Path(library)
        self._so = ctypes.CDLL(str(library))
        self._so.tick_floor_run.argtypes = [ctypes.POINTER(_Case), ctypes.POINTER(_Result)]
        self._so.tick_floor_run.restype = None
        for name in ("tick_floor_case_size", "tick_floor_held_size"):
            getattr(self._so, name).restype = _i64
        if self._so.tick_floor_case_size() != ctypes.sizeof(_Case):
            raise RuntimeError("tick_floor.c's case and the ctypes mirror differ: update both")
        if self._so.tick_floor_held_size() != HELD_STATE.itemsize:
            raise RuntimeError("tick_floor.c's held_t and HELD_STATE differ: update both")

    def prepare(self, args: LoopArgs) -> tuple[_Case, np.ndarray, np.ndarray, list]:
        """The C case of ``args``: ``(case, channels (22, n), vs_states (n, 2), arrays kept alive)``."""
        _check_supported(args)
        plant, control = args.plant, args.control
        s, sens, lim, ctrl, vs = plant.specimen, plant.sensors, plant.limits, control.controller, control.vs
        n = control.a_g.size
        keep: list = []
        channels = np.zeros((len(CHANNELS), n))
        vs_states = np.zeros((n, vs.x.size))
        f64, f32 = np.float64, np.float32
        hf = lim.hf_filter
        case = _Case(
            n=n,
            a_g=_ptr(control.a_g, f64, keep),
            noise=_ptr(plant.noise, f32, keep),
            pa=_ptr(plant.table, f64, keep),
            y=plant.y.ctypes.data_as(_D),
            n_y=plant.y.size,
            substeps=plant.substeps,
            n_osc=s.osc_k.size,
            spec_C=_ptr(s.C, f64, keep),
            spec_D=s.D,
            osc_k=_ptr(s.osc_k, f64, keep),
            osc_c=_ptr(s.osc_c, f64, keep),
            C_lc=_ptr(s.C_lc, f64, keep),
            D_lc=s.D_lc,
            lc_own=int(s.lc_own),
            n_channels=sens.gain.size,
            quantity_index=_ptr(sens.quantity_index, np.int64, keep),
            **{
                name: _ptr(getattr(sens, name), f64, keep)
                for name in ("gain", "scale", "offset", "noise_rms", "lsb", "v_low", "v_high")
            },
            load_cell_weights=_ptr(sens.load_cell_weights, f64, keep),
            z_channel=sens.z_channel,
            x_channel=sens.x_channel,
            dp_channel=sens.dp_channel,
            **{name: getattr(lim, name) for name in LIMIT_FIELDS},
            hf_b0=hf.b0,
            hf_b1=hf.b1,
            hf_b2=hf.b2,
            hf_a1=hf.a1,
            hf_a2=hf.a2,
            hf_window_loops=hf.window_loops,
            hf_growth=lim.hf_growth,
            hf_windows=lim.hf_windows,
            hf_floor=lim.hf_floor,
            held=plant.held.ctypes.data,
            output_line=plant.output_line.ctypes.data_as(_D),
            n_line=plant.output_line.size,
            feedback=control.feedback,
            m_z=_ptr(ctrl.m_z, f32, keep),
            n_z=ctrl.s_z.shape[1],
            m_w=_ptr(ctrl.m_w, f32, keep),
            n_w=ctrl.s_w.shape[1],
            s_z=ctrl.s_z.ctypes.data_as(_F),
            s_w=ctrl.s_w.ctypes.data_as(_F),
            compensated=int(ctrl.compensated),
            vs_params=_ptr(vs.params, f32, keep),
            vs_x=vs.x.ctypes.data_as(_F),
            dt=control.dt,
            channels=channels.ctypes.data_as(_D),
            vs_states=vs_states.ctypes.data_as(_D),
        )
        for arr in (plant.y, plant.held, plant.output_line, ctrl.s_z, ctrl.s_w, vs.x):
            if not arr.flags.c_contiguous:
                raise UnsupportedCase("the states the C loop writes back must be C-contiguous")
        return case, channels, vs_states, keep

    def call(self, case: _Case) -> _Result:
        """Run the loop of a prepared case (what the benchmark times)."""
        result = _Result()
        self._so.tick_floor_run(ctypes.byref(case), ctypes.byref(result))
        return result

    def run(self, args: LoopArgs) -> LoopRun:
        """The C loop on ``args`` (their states advanced in place, as ``run_loop`` does)."""
        case, channels, vs_states, _keep = self.prepare(args)
        result = self.call(case)
        done = int(result.done)
        return LoopRun(
            done,
            TripCause(int(result.cause)),
            float(result.value),
            {name: channels[i, :done] for i, name in enumerate(CHANNELS)},
            vs_states[:done],
        )


class Agreement(NamedTuple):
    """Largest |C - numba| of each recorded channel over its peak |numba| (``vs_states`` included)."""

    relative: dict

    @property
    def worst(self) -> tuple[str, float]:
        name = max(self.relative, key=self.relative.get)
        return name, self.relative[name]


def agreement(c: LoopRun, ref: LoopRun) -> Agreement:
    """Per-channel agreement of two runs of the same length (NaN where the lengths differ)."""
    out = {}
    pairs = [*((name, c.channels[name], ref.channels[name]) for name in CHANNELS)]
    pairs.append(("vs_states", c.vs_states, ref.vs_states))
    for name, a, b in pairs:
        if a.shape != b.shape:
            out[name] = float("nan")
            continue
        peak = float(np.max(np.abs(b))) if b.size else 0.0
        diff = float(np.max(np.abs(a - b))) if b.size else 0.0
        out[name] = diff / peak if peak > 0.0 else diff
    return Agreement(out)
