"""The named structures of the lab loop: what the stages pass and what the compiled loop takes.

numba types a named tuple by its fields, so the compiled kernels read
``plant.specimen.B`` or ``limits.stroke`` instead of the n-th of 35
positional arrays, at no cost (field access is resolved when compiling).
Every structure is built once per run by :mod:`impedance_mil.lab.loop` (or
by :class:`~impedance_mil.lab.plant_interface.VirtualTable`) and outlives the
compiled call, which allocates nothing.

* :class:`Measurements` -- what the sensors read in one loop (the plant
  interface's answer, also built by the compiled sensing stage);
* :class:`PlantTruth` -- the true plant quantities of one loop (recorded beside
  the measurements when the plant knows them);
* :class:`SpecimenArrays`, :class:`SensorArrays` (with its :class:`FilterArrays`), :class:`LimitValues` and
  :data:`HELD_STATE` -- the pieces of the compiled :class:`VirtualPlant`
  (:class:`LTIArrays`, :data:`LTI_HELD_STATE` and :class:`LTIPlant` for an LTI table);
* :class:`LoopControl` -- mode, inputs and the controller (and VS) arrays;
* :class:`Channels` and :class:`Records` -- the records, one array per
  channel.  :data:`CHANNELS` is their order.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..specimens.sensors import QUANTITIES
from .oscillation import HighPass

# Slots of the true quantities the sensors measure (the order of QUANTITIES).
Q_Z = QUANTITIES.index("table_acceleration")
Q_X = QUANTITIES.index("table_displacement")
Q_DP = QUANTITIES.index("differential_pressure")
Q_FORCE = QUANTITIES.index("actuator_force")
Q_W = QUANTITIES.index("interface_force")

#: Loop modes (:class:`LoopControl`): open loop (``u`` given), tracking (``z_vs = a_g``), MIL.
MODE_OPEN, MODE_TRACK, MODE_MIL = 0, 1, 2
#: Feedback sources of w: reaction load cells or force equilibrium (Section 8.3.2, App. C).
FEEDBACK_LC, FEEDBACK_FE = 0, 1


class Measurements(NamedTuple):
    """Sensor readings of one loop.

    Attributes
    ----------
    time_s : float
        Time of the readings [s].
    x : float
        Table displacement (string potentiometer) [in].
    dp : float
        Differential pressure [psi].
    z : float
        Table acceleration [in/s^2].
    w_lc : float
        Force of the test article on the table, reaction load cells [lbf].
    w_fe : float
        Same force from equilibrium, ``m_st z - A_p dP`` [lbf] (Section 8.3.2).
    """

    time_s: float
    x: float
    dp: float
    z: float
    w_lc: float
    w_fe: float


class PlantTruth(NamedTuple):
    """True (unmeasured) plant quantities of one loop; NaN where the plant cannot know them.

    Attributes
    ----------
    x, v : float
        Table displacement [in] and velocity [in/s].
    z : float
        Table acceleration [in/s^2].
    dp, p1, p2 : float
        Differential and chamber pressures [psi].
    spool : float
        Spool position, mA-equivalent [mA].
    w : float
        Force of the test article on the table [lbf].
    u_v : float
        Valve command the valve receives this loop [V].
    current : float
        Valve current of this loop [mA].
    """

    x: float
    v: float
    z: float
    dp: float
    p1: float
    p2: float
    spool: float
    w: float
    u_v: float
    current: float

    @classmethod
    def unknown(cls) -> PlantTruth:
        """Every quantity NaN (a plant that only offers its sensors)."""
        return cls(*([np.nan] * len(cls._fields)))


class SpecimenArrays(NamedTuple):
    """A specimen's state space for the plant kernels (input z [in/s^2], output w [lbf]).

    ``x' = A x + B z``, ``w = C x + D z``; ``A`` in compressed-row form (row
    ``i`` has the values ``A_val[A_ptr[i]:A_ptr[i+1]]`` in the columns
    ``A_col[...]``).  ``kind`` is ``SPEC_CSR`` or ``SPEC_BANK``
    (:mod:`impedance_mil.lab.stepping`); for a bank of base-excited oscillators
    ``osc_k = -omega^2`` [1/s^2] and ``osc_c = -2 zeta omega`` [1/s].
    ``w_LC = C_lc x + D_lc z`` [lbf] is what the load cells read (the interface
    force quantity of the sensors): ``lc_own`` is 0 when it is ``w`` itself
    (``C_lc``, ``D_lc`` then equal ``C``, ``D``), 1 for a specimen on a mounting
    (:mod:`impedance_mil.specimens.mounting`) whose load cells read another force.
    Built by :func:`impedance_mil.lab.plant_interface.specimen_arrays`.
    """

    A_val: np.ndarray
    A_col: np.ndarray
    A_ptr: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: float
    kind: int
    osc_k: np.ndarray
    osc_c: np.ndarray
    C_lc: np.ndarray
    D_lc: float
    lc_own: int


class FilterArrays(NamedTuple):
    """The channels' anti-alias filters for the sensing and stepping kernels, one entry per filter.

    Each filter is a channel's continuous Butterworth low-pass
    (:meth:`~impedance_mil.specimens.sensors.Sensor.anti_alias_filter`, two
    states, a first-order one padded with a state that stays 0), driven by the
    true channel value ``gain * quantities[quantity_index]`` and discretized
    exactly over one RK4 substep with the input linear between the substep's
    ends (first-order hold): ``state <- phi state + g0 u(start) + g1 u(end)``.
    The filtered value is ``state[:, 0]``.  ``channel`` is the filtered
    channel's index in the suite; ``state`` (nf, 2) and ``previous`` (nf,),
    the input at the last substep boundary, are written in place; ``primed``
    (1,) is 0 until the first sensing sets each filter at rest at its input.
    Built by :func:`impedance_mil.lab.setup.filter_arrays`; a suite without
    filters has nf = 0.
    """

    channel: np.ndarray
    quantity_index: np.ndarray
    gain: np.ndarray
    phi: np.ndarray
    g0: np.ndarray
    g1: np.ndarray
    state: np.ndarray
    previous: np.ndarray
    primed: np.ndarray

    @classmethod
    def none(cls) -> FilterArrays:
        """No filters (nf = 0): every channel reads its value as it is."""
        index = np.zeros(0, np.int64)
        return cls(
            index,
            index.copy(),
            np.zeros(0),
            np.zeros((0, 2, 2)),
            np.zeros((0, 2)),
            np.zeros((0, 2)),
            np.zeros((0, 2)),
            np.zeros(0),
            np.zeros(1, np.int64),
        )

    def reset(self) -> None:
        """Back to unprimed: the next sensing sets each filter at rest at its input."""
        self.state[:] = 0.0
        self.previous[:] = 0.0
        self.primed[:] = 0


class DelayArrays(NamedTuple):
    """The channels' converter / conditioner delays for the sensing kernel, one entry per delayed channel.

    Channel ``channel[i]`` reads its analog value (the filter's output when it
    has a filter, ``filter_index[i]`` >= 0, else the true value) delayed by
    ``whole[i] + frac[i]`` loops: a ring ``line`` (nd, L) of the analog
    values at the last L sensings (``head`` (1,) the slot of the newest),
    read at ``whole`` and ``whole + 1`` loops back and interpolated linearly
    with the weight ``frac`` on the older one.  ``primed`` (1,) is 0 until
    the first sensing fills each ring with its value (the table has stood at
    rest).  Built by :func:`impedance_mil.lab.setup.delay_arrays`; a suite
    without delays has nd = 0.
    """

    channel: np.ndarray
    filter_index: np.ndarray
    whole: np.ndarray
    frac: np.ndarray
    line: np.ndarray
    head: np.ndarray
    primed: np.ndarray

    @classmethod
    def none(cls) -> DelayArrays:
        """No delays (nd = 0): every channel reads its value at once."""
        index = np.zeros(0, np.int64)
        return cls(
            index,
            index.copy(),
            index.copy(),
            np.zeros(0),
            np.zeros((0, 2)),
            np.zeros(1, np.int64),
            np.zeros(1, np.int64),
        )

    def reset(self) -> None:
        """Back to unprimed: the next sensing fills each ring with its value."""
        self.line[:] = 0.0
        self.head[:] = 0
        self.primed[:] = 0


class SensorArrays(NamedTuple):
    """A :class:`~impedance_mil.specimens.sensors.SensorSuite` for the sensing kernel.

    One entry per channel: ``quantity_index`` (into
    :data:`~impedance_mil.specimens.sensors.QUANTITIES`), calibration ``gain``,
    ``scale``, ``offset``, ``noise_rms`` [V], ``lsb`` [V], range ``v_low``,
    ``v_high`` [V] and ``load_cell_weights``; ``z_channel``, ``x_channel`` and
    ``dp_channel`` are the first channels measuring the table acceleration,
    displacement and differential pressure; ``quantities`` is the scratch the
    kernel fills with the true quantities before measuring them; ``filters``
    the channels' anti-alias filters (:class:`FilterArrays`), ``delays`` their
    converter delays (:class:`DelayArrays`).  Built by
    :func:`impedance_mil.lab.setup.sensor_arrays`.
    """

    quantity_index: np.ndarray
    gain: np.ndarray
    scale: np.ndarray
    offset: np.ndarray
    noise_rms: np.ndarray
    lsb: np.ndarray
    v_low: np.ndarray
    v_high: np.ndarray
    load_cell_weights: np.ndarray
    z_channel: int
    x_channel: int
    dp_channel: int
    quantities: np.ndarray
    filters: FilterArrays
    delays: DelayArrays


class LimitValues(NamedTuple):
    """Interlock thresholds for the safety kernel (:meth:`SafetyLimits.kernel_values`).

    ``stroke`` [in], ``velocity`` [in/s], ``actuator_force`` [lbf],
    ``valve_saturation_time`` [s], ``divergence`` [in], ``valve_duty`` [-],
    ``valve_current`` [mA rms], ``command_slew`` [V/s rms] and their averaging
    time ``interlock_window`` [s], measured table ``acceleration`` [in/s^2] and
    measured differential ``pressure`` [psi] (inf: no such interlock; see
    :class:`~impedance_mil.lab.setup.SafetyLimits`), and the high-frequency
    instability detector (:mod:`impedance_mil.lab.oscillation`): its high-pass
    ``hf_filter`` (a :class:`~impedance_mil.lab.oscillation.HighPass`; 0 loops
    in a window: off), the window-to-window rms ratio ``hf_growth`` [-], the
    count of consecutive growing windows ``hf_windows`` [-] and the ``hf_floor``
    [in/s^2] the growth must start from.
    """

    stroke: float
    velocity: float
    actuator_force: float
    valve_saturation_time: float
    divergence: float
    valve_duty: float
    valve_current: float
    command_slew: float
    interlock_window: float
    acceleration: float
    pressure: float
    hf_filter: HighPass
    hf_growth: float
    hf_windows: int
    hf_floor: float


#: Fields of the high-frequency instability detector's state, in :data:`HELD_STATE` and
#: :data:`LTI_HELD_STATE` alike (:func:`impedance_mil.lab.kernels.hf_oscillation_check`): the
#: high-pass's last two inputs ``hf_x1``, ``hf_x2`` and outputs ``hf_y1``, ``hf_y2`` [in/s^2],
#: the sum of squares ``hf_sum`` [(in/s^2)^2] and loop count ``hf_n`` of the current window,
#: the previous window's rms ``hf_prev`` [in/s^2] and the count ``hf_count`` of consecutive
#: growing windows.
HF_STATE_FIELDS = [
    ("hf_x1", np.float64),
    ("hf_x2", np.float64),
    ("hf_y1", np.float64),
    ("hf_y2", np.float64),
    ("hf_sum", np.float64),
    ("hf_n", np.int64),
    ("hf_prev", np.float64),
    ("hf_count", np.int64),
]


#: What the virtual plant carries from one stage, or loop, to the next (a one-element
#: record array, written in place): the previous loop's measured ``x_prev`` [in] and
#: ``dp_prev`` [psi] (the hydraulic loop's feedback), ``sat`` (consecutive loops with
#: the valve command at its limit), the valve command ``u_v`` [V] and current [mA]
#: the valve receives this loop (computed N - 1 loops ago, N the output delay), the
#: slot ``head`` of the next write into the output delay's ring buffer
#: (``VirtualPlant.output_line``), the true ``z`` [in/s^2] and ``w`` [lbf] of this loop's sensing, and the
#: running averages of the valve interlocks (exponentially weighted over
#: ``LimitValues.interlock_window``): ``duty`` (fraction of loops saturated),
#: ``current_sq`` [mA^2] and ``slew_sq`` [(V/s)^2] (the command's loop-to-loop change);
#: then the :data:`HF_STATE_FIELDS`.
HELD_STATE = np.dtype(
    [
        ("x_prev", np.float64),
        ("dp_prev", np.float64),
        ("sat", np.int64),
        ("u_v", np.float64),
        ("current", np.float64),
        ("z", np.float64),
        ("w", np.float64),
        ("duty", np.float64),
        ("current_sq", np.float64),
        ("slew_sq", np.float64),
        ("head", np.int64),
    ]
    + HF_STATE_FIELDS,
    align=True,
)


class VirtualPlant(NamedTuple):
    """The virtual table and specimen as the compiled stages see them.

    Attributes
    ----------
    table : ndarray
        Parameter array of the nonlinear table (:meth:`NonlinearTable.parameter_array`,
        layout ``PA_*`` of :mod:`impedance_mil.plant.nonlinear`).
    y : ndarray
        Plant state ``[table states (6), specimen states]``, advanced in place.
    specimen : SpecimenArrays
    sensors : SensorArrays
    limits : LimitValues
    substeps : int
        RK4 substeps per loop.
    noise : ndarray (n, n_channels)
        Standard normal draws, one row per loop (float32).
    work : ndarray (5, len(y))
        Scratch of the plant step.
    readings : ndarray (n_channels,)
        Scratch: every channel's reading of the current loop.
    held : ndarray (1,) of :data:`HELD_STATE`
        State held between stages and loops.
    output_line : ndarray (N,)
        The valve commands [V] of the last N loops, N the controller's output
        delay in loops (a ring buffer; N = 1: the command is applied at once).
    """

    table: np.ndarray
    y: np.ndarray
    specimen: SpecimenArrays
    sensors: SensorArrays
    limits: LimitValues
    substeps: int
    noise: np.ndarray
    work: np.ndarray
    readings: np.ndarray
    held: np.ndarray
    output_line: np.ndarray


class LTIArrays(NamedTuple):
    """An LTI table coupled with its specimen, for the compiled stages of :mod:`impedance_mil.lab.lti_kernels`.

    The coupled state ``y`` (table model states, then the specimen's) with the
    command u [in] held advances exactly: ``y <- phi y + gamma u`` with
    ``phi = loop_phi_t.T``, ``gamma = loop_gamma`` over a loop, and
    ``step_phi_t``, ``step_gamma`` over one substep-long part of it (with
    anti-alias filters).  The matrices are stored transposed (the kernels
    take the products column by column).  Row ``i`` of ``out_t.T`` (with
    ``out_u[i] u``) is the true quantity ``QUANTITIES[i]`` (z [in/s^2], x
    [in], dP [psi], actuator force [lbf], w [lbf]); row 5 is the velocity v
    [in/s].  Rows of quantities the model lacks are zero; ``has_dp`` says
    whether dP exists, ``mass`` [lbf*s^2/in] and ``area`` [in^2] are NaN when
    unknown.  Built by :func:`impedance_mil.lab.lti_plant.lti_arrays`.
    """

    loop_phi_t: np.ndarray
    loop_gamma: np.ndarray
    step_phi_t: np.ndarray
    step_gamma: np.ndarray
    out_t: np.ndarray
    out_u: np.ndarray
    loop_time: float
    mass: float
    area: float
    has_dp: bool


#: What an LTI plant carries between stages and loops (cf. :data:`HELD_STATE`): the
#: command ``u`` [in] the model receives this loop (after the output delay), the true
#: ``x`` [in], ``v`` [in/s], ``z`` [in/s^2], ``dp`` [psi] and ``w`` [lbf] of this
#: loop's sensing, the ``head`` of the output delay's ring buffer, then the :data:`HF_STATE_FIELDS`.
LTI_HELD_STATE = np.dtype(
    [
        ("u", np.float64),
        ("x", np.float64),
        ("v", np.float64),
        ("z", np.float64),
        ("dp", np.float64),
        ("w", np.float64),
        ("head", np.int64),
    ]
    + HF_STATE_FIELDS,
    align=True,
)


class LTIPlant(NamedTuple):
    """An LTI table (and specimen) as the compiled stages of :mod:`impedance_mil.lab.lti_kernels` see it.

    Attributes are those of :class:`VirtualPlant`, except ``table`` (the
    :class:`LTIArrays`), ``work`` (n,) and ``held`` (:data:`LTI_HELD_STATE`);
    ``output_line`` holds the last N position commands [in].
    """

    table: LTIArrays
    y: np.ndarray
    sensors: SensorArrays
    limits: LimitValues
    substeps: int
    noise: np.ndarray
    work: np.ndarray
    readings: np.ndarray
    held: np.ndarray
    output_line: np.ndarray


class LoopControl(NamedTuple):
    """What decides the command: the mode, the inputs and the controller.

    Attributes
    ----------
    mode : int
        ``MODE_OPEN`` (``command`` is u), ``MODE_TRACK`` (``z_vs = a_g``) or ``MODE_MIL``.
    feedback : int
        ``FEEDBACK_LC`` or ``FEEDBACK_FE``: which w the VS and the controller use.
    a_g : ndarray (n,)
        Ground acceleration [in/s^2] per loop (zeros in open loop).
    command : ndarray (n,)
        Open-loop position command [in] per loop (zeros otherwise).
    dt : float
        Loop time [s] (the VS step).
    controller : ControllerArrays or object
        Compiled loop: :class:`impedance_mil.implement.runtime.ControllerArrays`;
        Python loop: the :class:`~impedance_mil.implement.MILRuntime` (or None).
    vs : VSArrays or None
        Compiled loop: the VS slot's arrays (:class:`impedance_mil.implement.vs_tick.VSArrays`);
        unused by the Python loop (the runtime steps its VS).
    """

    mode: int
    feedback: int
    a_g: np.ndarray
    command: np.ndarray
    dt: float
    controller: object
    vs: object


class Channels(NamedTuple):
    """One array per recorded channel, one sample per loop (units: s, in/s^2, in, V, mA, in/s, psi, lbf)."""

    t: np.ndarray
    a_g: np.ndarray
    z_vs: np.ndarray
    u: np.ndarray
    u_z: np.ndarray
    u_w: np.ndarray
    u_v: np.ndarray
    current: np.ndarray
    x: np.ndarray
    v: np.ndarray
    z: np.ndarray
    dp: np.ndarray
    p1: np.ndarray
    p2: np.ndarray
    spool: np.ndarray
    w: np.ndarray
    w_lc: np.ndarray
    w_fe: np.ndarray
    w_used: np.ndarray
    x_meas: np.ndarray
    dp_meas: np.ndarray
    z_meas: np.ndarray


#: Recorded channels, in order.
CHANNELS: tuple[str, ...] = Channels._fields


class Records(NamedTuple):
    """The records of a run: every channel, and the VS state at the start of each loop."""

    channels: Channels
    vs_states: np.ndarray

    @classmethod
    def allocate(cls, n: int, n_vs: int) -> Records:
        """Uninitialized records for ``n`` loops and a VS of ``n_vs`` states (the loop writes every sample)."""
        return cls(Channels(*(np.empty(n) for _ in CHANNELS)), np.empty((n, n_vs)))

    def up_to(self, n: int) -> tuple[dict, np.ndarray]:
        """``({channel: first n samples}, first n VS states)``: what a run of n loops recorded."""
        return {name: arr[:n] for name, arr in zip(CHANNELS, self.channels)}, self.vs_states[:n]


def record_loop(log, k, m, truth, a_g, z_vs, u, u_w, w_used):
    """Write loop ``k`` into the :class:`Records` ``log``.

    ``m`` are its :class:`Measurements`, ``truth`` its :class:`PlantTruth`,
    ``a_g`` [in/s^2], ``z_vs`` [in/s^2], the command ``u`` [in] with its
    feedback part ``u_w`` [in], and the force ``w_used`` [lbf] the controller
    used.  Plain Python, compiled into the loop as it is
    (:func:`impedance_mil.lab.kernels.record`): one definition of the records.
    """
    c = log.channels
    c.t[k] = m.time_s
    c.a_g[k] = a_g
    c.z_vs[k] = z_vs
    c.u[k] = u
    c.u_z[k] = u - u_w
    c.u_w[k] = u_w
    c.u_v[k] = truth.u_v
    c.current[k] = truth.current
    c.x[k] = truth.x
    c.v[k] = truth.v
    c.z[k] = truth.z
    c.dp[k] = truth.dp
    c.p1[k] = truth.p1
    c.p2[k] = truth.p2
    c.spool[k] = truth.spool
    c.w[k] = truth.w
    c.w_lc[k] = m.w_lc
    c.w_fe[k] = m.w_fe
    c.w_used[k] = w_used
    c.x_meas[k] = m.x
    c.dp_meas[k] = m.dp
    c.z_meas[k] = m.z
