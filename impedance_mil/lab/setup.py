"""Configuration of a virtual-lab run: sensors and safety limits.

Sensors are a :class:`~impedance_mil.specimens.sensors.SensorSuite` (report
Table 7.1 calibration, 16-bit analog inputs over +-10 V).  Noise levels are
not reported; the lab's default, :data:`DEFAULT_NOISE_V` = 1 mV rms per
channel (about 3 LSB), is an assumption of this tool.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ..errors import ConfigError
from ..lazy import LazyModule
from ..specimens.sensor_noise import NOISE_PERIOD_LOOPS, unit_noise_block
from ..specimens.sensors import QUANTITIES, SensorSuite
from .oscillation import (
    HF_CUTOFF_HZ,
    HF_GROWTH,
    HF_WINDOW_S,
    HF_WINDOWS,
    HIGHPASS_OFF,
    HighPass,
    default_floor,
    highpass_coefficients,
)
from .structures import DelayArrays, FilterArrays, LimitValues, SensorArrays

#: scipy.linalg, imported on first use (issue 16: a command that only reads a configuration does not need it).
scipy_linalg = LazyModule("scipy.linalg")

#: Default sensor noise of the virtual lab [V rms per channel].
DEFAULT_NOISE_V = 1.0e-3

#: Quantities the loop must read, in the order of the channel-index array.
_REQUIRED = ("table_acceleration", "table_displacement", "differential_pressure")


#: Quantities the loop reads (the actuator load cells of Table 7.1 are not used).
LOOP_QUANTITIES = _REQUIRED + ("interface_force",)

#: LSB [V] standing for "no quantization" (exact to double precision within +-10 V).
UNQUANTIZED_LSB_V = 1.0e-14


def default_sensors(noise_rms_v: float = DEFAULT_NOISE_V) -> SensorSuite:
    """The Table 7.1 channels the loop reads, with ``noise_rms_v`` [V rms] of noise each.

    Accelerometer, string potentiometer, dP cell and the four reaction load
    cells; the actuator load cells are left out (nothing in the loop reads them).
    """
    suite = SensorSuite.report_default(noise_rms_v=noise_rms_v)
    return SensorSuite(tuple(s for s in suite.sensors if s.quantity in LOOP_QUANTITIES))


def ideal_sensors() -> SensorSuite:
    """:func:`default_sensors` without noise (pass ``quantize=False`` to drop the 16 bits too)."""
    return default_sensors(0.0)


def accelerometer_noise(suite: SensorSuite) -> float:
    """rms noise [in/s**2] of the suite's first table-acceleration channel: its noise and quantization.

    ``sqrt(noise_rms_v^2 + lsb^2 / 12) |scale|`` (uniform quantization error
    of one LSB); 0 when no channel measures the table acceleration.
    """
    for s in suite.sensors:
        if s.quantity == "table_acceleration":
            return abs(s.scale) * math.sqrt(s.noise_rms_v**2 + s.lsb_v**2 / 12.0)
    return 0.0


def draw_noise(
    rng: np.random.Generator,
    suite: SensorSuite,
    n_loops: int | None = None,
    loop_time_s: float | None = None,
):
    """Standard-normal draws for the sensor kernel, float32, ``(n_loops, n_channels)``.

    One row per loop; drawing row by row (``n_loops=None``) gives the same
    numbers as drawing the block, so the plant interface and the compiled
    loop agree.  A channel with a noise spectrum then has its column replaced
    by its :class:`ColouredNoise` rows 0 ... n_loops - 1 (``loop_time_s`` [s]
    needed); row by row, the plant interface does so itself
    (:meth:`ColouredNoise.row`).  Without spectra the draws are as they were.
    The block is :class:`NoiseDraws` filled at once.
    """
    if n_loops is None:
        return rng.standard_normal((suite.n_channels,), dtype=np.float32)
    draws = NoiseDraws.allocate(rng, suite, n_loops, loop_time_s)
    draws.fill(0, n_loops)
    return draws.values


@dataclass(frozen=True, eq=False)
class NoiseDraws:
    """The noise block of a run, filled chunk by chunk with the numbers of :func:`draw_noise`.

    The white rows are drawn in loop order (numpy's generator gives the same
    numbers for a block and for its rows in order); the coloured columns
    come from their :class:`ColouredNoise`, drawn at :meth:`allocate` from a
    child stream that does not depend on the white draws.

    Attributes
    ----------
    rng : numpy.random.Generator
        The run's generator (its white draws).
    values : ndarray (n_loops, n_channels), float32
        The block (rows filled by :meth:`fill`; the others uninitialized).
    colour : ColouredNoise or None
        The channels with a spectrum.
    """

    rng: np.random.Generator
    values: np.ndarray
    colour: ColouredNoise | None

    @classmethod
    def allocate(
        cls, rng: np.random.Generator, suite: SensorSuite, n_loops: int, loop_time_s: float | None
    ) -> NoiseDraws:
        """An unfilled block for ``n_loops`` loops of ``loop_time_s`` [s] (needed with a noise spectrum)."""
        colour = coloured_noise(rng, suite, loop_time_s)
        return cls(rng, np.empty((n_loops, suite.n_channels), np.float32), colour)

    def fill(self, start: int, stop: int) -> None:
        """Draw rows ``start ... stop - 1`` (after rows ``0 ... start - 1``: in loop order)."""
        rows = self.values[start:stop]
        self.rng.standard_normal(dtype=np.float32, out=rows)
        if self.colour is not None:
            period = self.colour.block.shape[0]
            rows[:, self.colour.channel] = self.colour.block[np.arange(start, stop) % period]


@dataclass(frozen=True, eq=False)
class ColouredNoise:
    """One period of the shaped noise of the channels with a spectrum, in units of their rms.

    ``channel`` (int64, nc) are their indices in the suite, ``block``
    (:data:`~impedance_mil.specimens.sensor_noise.NOISE_PERIOD_LOOPS`, nc)
    float32 their noise, rms 1 over the period; loop k reads row
    ``k mod period`` (the block is circular, so the noise repeats without a seam).
    """

    channel: np.ndarray
    block: np.ndarray

    def row(self, k: int) -> np.ndarray:
        """The noise of loop ``k`` [units of each channel's rms]."""
        return self.block[k % self.block.shape[0]]


def coloured_noise(
    rng: np.random.Generator, suite: SensorSuite, loop_time_s: float | None
) -> ColouredNoise | None:
    """The :class:`ColouredNoise` of the suite's channels with a spectrum (None: none has one).

    Drawn from ``rng.spawn(1)[0]``, a child stream of the run's seed: it does
    not depend on how many white draws were taken from ``rng`` before, so the
    block and the row-by-row renderings agree.  Channels in suite order, each
    from the same child stream in turn.
    """
    coloured = [(i, s, s.noise_spectrum) for i, s in enumerate(suite.sensors) if s.noise_spectrum is not None]
    if not coloured:
        return None
    if loop_time_s is None or not (np.isfinite(loop_time_s) and loop_time_s > 0):
        raise ConfigError(
            "loop_time_s", "the loop time [s] at which the coloured noise is sampled", loop_time_s
        )
    child = rng.spawn(1)[0]
    block = np.empty((NOISE_PERIOD_LOOPS, len(coloured)), np.float32)
    for j, (_, s, spectrum) in enumerate(coloured):
        block[:, j] = unit_noise_block(spectrum, s.noise_rms_v, loop_time_s, child)
    return ColouredNoise(np.array([i for i, _, _ in coloured], dtype=np.int64), block)


#: Longest converter delay of a channel [loops] (the ring of :class:`DelayArrays` holds this many + 2).
MAX_SENSOR_DELAY_LOOPS = 100


def delay_arrays(suite: SensorSuite, loop_time_s: float | None, filters: FilterArrays) -> DelayArrays:
    """The :class:`~impedance_mil.lab.structures.DelayArrays` of the suite's converter delays.

    A delay of ``delay_s / loop_time_s`` loops splits into whole loops (a
    ring buffer) and a fraction interpolated linearly between two loop
    samples.  The interpolation ``(1 - a) + a e^{-j w T}`` (a the fraction)
    stands for ``e^{-j w a T}``: its gain is low by at most
    ``a (1 - a) (w T)^2 / 2`` (1.2 % at 50 Hz and a 1 ms loop, a = 0.5) and
    its phase error is third order in ``w T`` (0.03 degrees there);
    a whole number of loops is exact.

    Raises
    ------
    ConfigError
        A delay beyond :data:`MAX_SENSOR_DELAY_LOOPS` loops, or delays without a loop time.
    """
    delayed = [(i, s) for i, s in enumerate(suite.sensors) if s.delay_s > 0]
    if not delayed:
        return DelayArrays.none()
    if loop_time_s is None or not (np.isfinite(loop_time_s) and loop_time_s > 0):
        raise ConfigError("loop_time_s", "the loop time [s] of the converter delays", loop_time_s)
    loops = [s.delay_s / loop_time_s for _, s in delayed]
    for (_, s), n in zip(delayed, loops):
        if n > MAX_SENSOR_DELAY_LOOPS:
            raise ConfigError(
                f"sensors.{s.name}.delay",
                f"a delay of at most {MAX_SENSOR_DELAY_LOOPS} loops ({MAX_SENSOR_DELAY_LOOPS * loop_time_s:g} s)",
                s.delay_s,
            )
    # a fraction within 1e-9 of a whole loop is that loop (0.3 ms / 0.1 ms is 2.9999999999999996)
    loops = [float(round(n)) if abs(n - round(n)) < 1e-9 else n for n in loops]
    whole = np.array([math.floor(n) for n in loops], dtype=np.int64)
    frac = np.array([n - math.floor(n) for n in loops])
    filter_of = {int(c): k for k, c in enumerate(filters.channel)}
    return DelayArrays(
        channel=np.array([i for i, _ in delayed], dtype=np.int64),
        filter_index=np.array([filter_of.get(i, -1) for i, _ in delayed], dtype=np.int64),
        whole=whole,
        frac=frac,
        line=np.zeros((len(delayed), int(whole.max()) + 2)),
        head=np.zeros(1, np.int64),
        primed=np.zeros(1, np.int64),
    )


#: Longest output delay a controller may have [loops] (a buffer of this many commands).
MAX_OUTPUT_DELAY = 100


def output_line(output_delay: int) -> np.ndarray:
    """The ring buffer of the output delay: ``output_delay`` valve commands [V], zero (valve at rest).

    Raises
    ------
    ConfigError
        ``output_delay`` is not a whole number of loops from 1 to :data:`MAX_OUTPUT_DELAY`.
    """
    if isinstance(output_delay, bool) or not isinstance(output_delay, (int, np.integer)):
        raise ConfigError(
            "output_delay", f"a whole number of loops from 1 to {MAX_OUTPUT_DELAY}", output_delay
        )
    if not 1 <= output_delay <= MAX_OUTPUT_DELAY:
        raise ConfigError(
            "output_delay", f"a whole number of loops from 1 to {MAX_OUTPUT_DELAY}", output_delay
        )
    return np.zeros(int(output_delay))


def first_order_hold(A: np.ndarray, B: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact discretization of ``x' = A x + B u`` over ``h`` [s] with ``u`` linear in between.

    Returns ``(phi, g0, g1)`` with ``x(h) = phi x(0) + g0 u(0) + g1 u(h)``
    for a single input (``B`` of n entries), from one matrix exponential of
    ``[[A h, B h, 0], [0, 0, 1], [0, 0, 0]]``: its first block row is
    ``[phi, G, H]`` with ``x(h) = phi x(0) + G u(0) + H (u(h) - u(0))``.
    """
    n = A.shape[0]
    block = np.zeros((n + 2, n + 2))
    block[:n, :n] = A * h
    block[:n, n] = B * h
    block[n, n + 1] = 1.0
    E = scipy_linalg.expm(block)
    return E[:n, :n], E[:n, n] - E[:n, n + 1], E[:n, n + 1]


def filter_arrays(suite: SensorSuite, substep_s: float | None) -> FilterArrays:
    """The :class:`~impedance_mil.lab.structures.FilterArrays` of the suite's anti-alias filters.

    Each filter (:meth:`~impedance_mil.specimens.sensors.Sensor.anti_alias_filter`)
    is discretized exactly over one RK4 substep ``substep_s`` [s] (the loop
    time over the substeps) with its input, the true channel value, linear
    between the substep's ends (:func:`first_order_hold`).  Why not integrate
    the filter with RK4 in the plant state: the substeps are chosen for the
    plant's fastest mode (:mod:`~impedance_mil.lab.substeps`), and a filter
    near the Nyquist frequency has ``omega_c h`` up to pi/2 with the bare
    table's two substeps, where RK4 is inaccurate (and beyond 2.8, unstable);
    the exact discretization is right for any bandwidth.  Why a first-order
    and not a zero-order hold of the input: holding the substep's first value
    delays the input by half a substep (a quarter loop with two substeps, a
    phase error of the size of the filter's own lag at tens of Hz); the
    linear hold has no such delay.
    """
    filters = [(i, s, s.anti_alias_filter()) for i, s in enumerate(suite.sensors)]
    filtered = [(i, s, lp) for i, s, lp in filters if lp is not None]
    if not filtered:
        return FilterArrays.none()
    if substep_s is None or not (np.isfinite(substep_s) and substep_s > 0):
        raise ConfigError("substep_s", "a positive RK4 substep [s] for the anti-alias filters", substep_s)
    nf = len(filtered)
    phi, g0, g1 = np.zeros((nf, 2, 2)), np.zeros((nf, 2)), np.zeros((nf, 2))
    for j, (_, _, lp) in enumerate(filtered):
        n = lp.n_states
        A, B = np.zeros((2, 2)), np.zeros(2)  # a first-order filter padded with a state that stays 0
        A[:n, :n], B[:n] = lp.A, lp.B[:, 0]
        phi[j], g0[j], g1[j] = first_order_hold(A, B, substep_s)
    return FilterArrays(
        channel=np.array([i for i, _, _ in filtered], dtype=np.int64),
        quantity_index=np.array([QUANTITIES.index(s.quantity) for _, s, _ in filtered], dtype=np.int64),
        gain=np.array([s.gain for _, s, _ in filtered]),
        phi=phi,
        g0=g0,
        g1=g1,
        state=np.zeros((nf, 2)),
        previous=np.zeros(nf),
        primed=np.zeros(1, np.int64),
    )


def sensor_arrays(
    suite: SensorSuite,
    feedback: str = "lc",
    quantize: bool = True,
    substep_s: float | None = None,
    loop_time_s: float | None = None,
) -> SensorArrays:
    """The :class:`~impedance_mil.lab.structures.SensorArrays` the sensing kernel reads.

    The suite's channel arrays, the first channel measuring z, x and dP, a
    quantity buffer and the anti-alias filters (:func:`filter_arrays`, over the
    RK4 substep ``substep_s`` [s], needed only when a channel has a
    ``bandwidth_hz``) and the converter delays (:func:`delay_arrays`, at the
    loop time ``loop_time_s`` [s], needed only when a channel has a ``delay_s``).  ``quantize=False`` replaces the 16-bit LSB by
    :data:`UNQUANTIZED_LSB_V` (model studies only).
    """
    qi = np.asarray(suite.quantity_index)
    idx = []
    for name in _REQUIRED:
        hits = np.nonzero(qi == QUANTITIES.index(name))[0]
        if hits.size == 0:
            raise ConfigError("sensors", f"a channel measuring {name}", suite.names)
        idx.append(int(hits[0]))
    if feedback == "lc" and not np.any(suite.load_cell_weights != 0):
        raise ConfigError(
            "sensors", "reaction load cells (interface_force channels) for feedback 'lc'", suite.names
        )
    z_channel, x_channel, dp_channel = idx
    filters = filter_arrays(suite, substep_s)
    return SensorArrays(
        quantity_index=np.ascontiguousarray(qi, dtype=np.int64),
        gain=np.array(suite.gain),
        scale=np.array(suite.scale),
        offset=np.array(suite.offset),
        noise_rms=np.array(suite.noise_rms),
        lsb=np.array(suite.lsb) if quantize else np.full(suite.n_channels, UNQUANTIZED_LSB_V),
        v_low=np.array(suite.v_low),
        v_high=np.array(suite.v_high),
        load_cell_weights=np.array(suite.load_cell_weights),
        z_channel=z_channel,
        x_channel=x_channel,
        dp_channel=dp_channel,
        quantities=np.zeros(len(QUANTITIES)),
        filters=filters,
        delays=delay_arrays(suite, loop_time_s, filters),
    )


#: Frequency [Hz] of the full-scale valve-command oscillation that sets the default
#: divergence detector (``SafetyLimits.command_slew``): the top of the report's
#: 15-50 Hz error band; a command that swings its whole range faster than this is
#: not tracking a ground motion.
OSCILLATION_HZ = 50.0


@dataclass(frozen=True)
class SafetyLimits:
    """Interlocks of the virtual controller; a run that crosses one stops cleanly.

    Parameters
    ----------
    stroke : float
        Measured displacement limit [in] (report Section 8.2: +-3 in).
    velocity : float
        Table velocity limit [in/s] (the valve's rated flow over A_p is 27.5 in/s;
        default 40 in/s).
    actuator_force : float, optional
        |A_p dP| limit [lbf]; default 95 % of the stall force A_p (P_s - P_R).
    valve_saturation_time : float
        Longest time the valve command may sit at its limit without a break [s].
    divergence : float
        Displacement beyond which the simulation is declared divergent [in].
    valve_duty : float
        Largest fraction of time the valve command may sit at its limit,
        averaged over ``interlock_window`` (a command that chatters between
        the limits never stays saturated 0.25 s, but is saturated most of the
        time).  Default 0.5.
    valve_current : float, optional
        Largest rms valve current [mA] over ``interlock_window``; default the
        table's rated current (``rated_current``, 25 mA for the report's MOOG
        760F264A: above it the valve is driven beyond its rating).
    command_slew : float, optional
        Largest rms rate of change of the valve command [V/s] over
        ``interlock_window``: the detector of a run going unstable, whose
        command grows at high frequency (a sign flip every few loops).
        Default that of a full-scale valve command oscillating at
        :data:`OSCILLATION_HZ` (50 Hz, the top of the report's error bands):
        ``2 pi 50 u_v,max / sqrt 2`` (2221 V/s for a 10 V valve command).
    interlock_window : float
        Averaging time [s] of ``valve_duty``, ``valve_current`` and
        ``command_slew`` (exponential weighting, time constant).  Default 0.25 s.
    acceleration : float, optional
        Measured table acceleration limit [in/s**2]; default none (the report's
        controller had none).
    pressure : float, optional
        Measured differential-pressure limit |dP| [psi]; default none (the
        actuator-force interlock, A_p |dP|, stands for it).
    hf_cutoff : float, optional
        Lower edge [Hz] of the band of the high-frequency instability detector
        (trip ``hf_oscillation``, :mod:`impedance_mil.lab.oscillation`);
        default 15 Hz (report Figures 9.33-9.34: the oscillation of the
        unstable MIL runs is at 15+ Hz); None switches the detector off.
    hf_window : float
        rms window of the detector [s]; default 0.2 s (three periods at 15 Hz).
    hf_growth : float
        Window-to-window rms ratio counted as growth [-], > 1; default 2.
    hf_windows : int
        Consecutive growing windows that trip [-], >= 1; default 3.
    hf_floor : float, optional
        rms [in/s**2] of the high-passed acceleration a growth must start
        from; default ten times the run's accelerometer noise, at least ten
        times the default's (2.59 in/s**2,
        :func:`~impedance_mil.lab.oscillation.default_floor`).
    """

    stroke: float = 3.0
    velocity: float = 40.0
    actuator_force: float | None = None
    valve_saturation_time: float = 0.25
    divergence: float = 20.0
    valve_duty: float = 0.5
    valve_current: float | None = None
    command_slew: float | None = None
    interlock_window: float = 0.25
    acceleration: float | None = None
    pressure: float | None = None
    hf_cutoff: float | None = HF_CUTOFF_HZ
    hf_window: float = HF_WINDOW_S
    hf_growth: float = HF_GROWTH
    hf_windows: int = HF_WINDOWS
    hf_floor: float | None = None

    def __post_init__(self):
        for key in ("stroke", "velocity", "valve_saturation_time", "divergence", "interlock_window"):
            value = getattr(self, key)
            if not (np.isfinite(value) and value > 0):
                raise ConfigError(f"limits.{key}", "a positive finite number", value)
        if self.actuator_force is not None and not self.actuator_force > 0:
            raise ConfigError("limits.actuator_force", "a positive force [lbf]", self.actuator_force)
        if not (np.isfinite(self.valve_duty) and 0 < self.valve_duty <= 1):
            raise ConfigError("limits.valve_duty", "a fraction in (0, 1]", self.valve_duty)
        for key, unit in (
            ("valve_current", "current [mA]"),
            ("command_slew", "rate [V/s]"),
            ("acceleration", "acceleration [in/s**2]"),
            ("pressure", "pressure [psi]"),
            ("hf_cutoff", "frequency [Hz]"),
            ("hf_floor", "acceleration [in/s**2]"),
        ):
            value = getattr(self, key)
            if value is not None and not (np.isfinite(value) and value > 0):
                raise ConfigError(f"limits.{key}", f"a positive {unit}", value)
        if not (np.isfinite(self.hf_window) and self.hf_window > 0):
            raise ConfigError("limits.hf_window", "a positive time [s]", self.hf_window)
        if not (np.isfinite(self.hf_growth) and self.hf_growth > 1):
            raise ConfigError("limits.hf_growth", "a ratio above 1", self.hf_growth)
        windows = self.hf_windows
        if isinstance(windows, bool) or not float(windows).is_integer() or not windows >= 1:
            raise ConfigError("limits.hf_windows", "a whole number of windows >= 1", windows)

    @classmethod
    def disabled(cls) -> SafetyLimits:
        """Only NaN and divergence checks remain (for studies beyond the rig's limits)."""
        return cls(
            stroke=1e9,
            velocity=1e9,
            actuator_force=1e12,
            valve_saturation_time=1e9,
            divergence=1e3,
            valve_duty=1.0,
            valve_current=1e12,
            command_slew=1e15,
            hf_cutoff=None,
        )

    def kernel_values(self, table, accel_noise: float | None = None) -> LimitValues:
        """The thresholds for ``table`` (a NonlinearTable: it sets the default force, current and slew).

        ``accel_noise`` [in/s**2 rms] is the run's accelerometer noise
        (:func:`accelerometer_noise`), which sets the default ``hf_floor``.
        """
        force = 0.95 * table.max_force if self.actuator_force is None else self.actuator_force
        current = table.spool_limit if self.valve_current is None else self.valve_current
        full_scale = 2.0 * np.pi * OSCILLATION_HZ * table.valve_command_limit / np.sqrt(2.0)
        slew = full_scale if self.command_slew is None else self.command_slew
        return LimitValues(
            stroke=float(self.stroke),
            velocity=float(self.velocity),
            actuator_force=float(force),
            valve_saturation_time=float(self.valve_saturation_time),
            divergence=float(self.divergence),
            valve_duty=float(self.valve_duty),  # 1 never trips (the duty cannot exceed 1)
            valve_current=float(current),
            command_slew=float(slew),
            interlock_window=float(self.interlock_window),
            acceleration=math.inf if self.acceleration is None else float(self.acceleration),
            pressure=math.inf if self.pressure is None else float(self.pressure),
            **self.hf_values(table.loop_time, accel_noise),
        )

    def hf_detector(self, loop_time: float) -> HighPass:
        """The detector's high-pass at the loop time ``loop_time`` [s] (:data:`HIGHPASS_OFF` when off)."""
        if self.hf_cutoff is None:
            return HIGHPASS_OFF
        return highpass_coefficients(float(self.hf_cutoff), float(loop_time), float(self.hf_window))

    def hf_values(self, loop_time: float, accel_noise: float | None = None) -> dict:
        """The detector's fields of :class:`LimitValues` at the loop time ``loop_time`` [s].

        ``accel_noise`` [in/s**2 rms]: the accelerometer's noise, for the
        default floor (:func:`~impedance_mil.lab.oscillation.default_floor`).
        """
        return {
            "hf_filter": self.hf_detector(loop_time),
            "hf_growth": float(self.hf_growth),
            "hf_windows": int(self.hf_windows),
            "hf_floor": default_floor(accel_noise) if self.hf_floor is None else float(self.hf_floor),
        }

    def to_dict(self) -> dict:
        return asdict(self)
