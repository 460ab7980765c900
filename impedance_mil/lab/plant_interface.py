"""The plant interface: what a shake-table controller link offers, and the virtual table behind it.

A MIL program sees the table through four calls (the RMC75E's axis, Section
7.3.4): read the sensors of this loop, write the position command, let one
loop time pass.  :class:`PlantInterface` is that contract; a link to a real
controller can implement it, and :class:`VirtualTable` implements it with the
nonlinear table of :mod:`impedance_mil.plant.nonlinear`, calling the same
compiled kernels as the stages of the compiled loop
(:func:`~impedance_mil.lab.kernels.sense_and_check`, ``hydraulic_command``,
``plant_truth`` and ``plant_advance`` of :mod:`impedance_mil.lab.kernels`),
on the arrays of the same :class:`~impedance_mil.lab.structures.VirtualPlant`.
The order in which a loop calls them is :func:`impedance_mil.lab.tick.sequence`.
:class:`VirtualLTITable` does the same for a table given by a linear model,
on the stages of :mod:`impedance_mil.lab.lti_kernels` (:func:`lti_plant`
builds their :class:`~impedance_mil.lab.structures.LTIPlant`).
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..errors import LimitTripped
from ..plant.nonlinear import N_TABLE_STATES
from ..specimens.mounting import load_cell_output
from . import kernels, lti_kernels
from .kernels import SPEC_BANK, SPEC_CSR, plant_advance
from .lti_plant import LTIVirtualTable, check_feedback, lti_arrays, lti_limits, virtual_table_for
from .setup import (
    SafetyLimits,
    accelerometer_noise,
    coloured_noise,
    default_sensors,
    draw_noise,
    output_line,
    sensor_arrays,
)
from .structures import (
    HELD_STATE,
    LTI_HELD_STATE,
    LimitValues,
    LTIPlant,
    Measurements,
    SensorArrays,
    SpecimenArrays,
    VirtualPlant,
)
from .substeps import resolve_substeps, specimen_state_space


@runtime_checkable
class PlantInterface(Protocol):
    """A shake table under its own hydraulic control, stepped one loop at a time.

    ``read_sensors`` raises :class:`~impedance_mil.errors.LimitTripped` when an
    interlock has tripped; the caller stops and keeps what it recorded.
    """

    loop_time: float

    def reset(self) -> None:
        """Table at rest at mid-stroke; clocks at zero."""

    def read_sensors(self) -> Measurements:
        """Readings of the current loop."""

    def write_command(self, u: float) -> None:
        """Position command u [in] of the current loop."""

    def advance(self) -> None:
        """Let one loop time pass."""


def specimen_arrays(specimen, oscillator_bank: bool = True) -> SpecimenArrays:
    """The :class:`~impedance_mil.lab.structures.SpecimenArrays` of a specimen (writable copies).

    Input z [in/s^2], output w [lbf].  ``A`` is stored in compressed-row form
    (most specimens are sparse: a vessel's 8x8 matrix has 12 nonzeros);
    ``specimen`` is an object with ``state_space()`` or a state space with
    ``A, B, C, D``; ``None`` gives no states and ``w = 0``.  When the state
    space is a bank of base-excited oscillators (:func:`oscillator_bank_of`:
    a vessel, a rigid mass, a single-DOF article) and ``oscillator_bank`` is
    true, ``kind`` is ``SPEC_BANK`` and ``osc_k``, ``osc_c`` hold its
    coefficients; otherwise ``kind`` is ``SPEC_CSR`` (``oscillator_bank=False``
    forces the general path, for comparisons).  A specimen on a mounting
    (:class:`~impedance_mil.specimens.mounting.MountedSpecimen`) gives its
    load cells' output as ``C_lc``, ``D_lc`` (``lc_own = 1``); any other
    specimen's load cells read its ``w`` (``C_lc``, ``D_lc`` = ``C``, ``D``,
    ``lc_own = 0``).  Every array is a writable
    copy: numba compiles the loop once per argument type, and a read-only
    array (a specimen's cached matrices) is another type.
    """
    if specimen is None:
        A, B, C, D = np.zeros((0, 0)), np.zeros(0), np.zeros(0), 0.0
    else:
        A, B, C, D = specimen_state_space(specimen)
    lc = load_cell_output(specimen)
    C_lc, D_lc = (C, D) if lc is None else (lc.C, lc.D)
    rows, cols = np.nonzero(A)
    ptr = np.searchsorted(rows, np.arange(A.shape[0] + 1)).astype(np.int64)
    bank = oscillator_bank_of(A, B) if oscillator_bank else None
    kind, osc_k, osc_c = (SPEC_CSR, np.zeros(0), np.zeros(0)) if bank is None else (SPEC_BANK, *bank)
    return SpecimenArrays(
        A_val=np.array(A[rows, cols]),
        A_col=cols.astype(np.int64),
        A_ptr=ptr,
        B=np.array(B, dtype=float),
        C=np.array(C, dtype=float),
        D=float(D),
        kind=kind,
        osc_k=np.array(osc_k),
        osc_c=np.array(osc_c),
        C_lc=np.array(C_lc, dtype=float),
        D_lc=float(D_lc),
        lc_own=int(lc is not None),
    )


def oscillator_bank_of(A, B):
    """``(osc_k, osc_c)`` if ``x' = A x + B z`` is a bank of base-excited oscillators, else None.

    The bank form: states ``[q (n), q' (n)]`` (relative displacements [in],
    velocities [in/s]) with ``q_i'' = -z + osc_k_i q_i + osc_c_i q_i'``, i.e.
    ``A = [[0, I], [diag(osc_k), diag(osc_c)]]`` and ``B = [0, -1]``
    exactly; ``osc_k = -omega^2`` [1/s^2], ``osc_c = -2 zeta omega`` [1/s].
    No states (a rigid mass) is an empty bank.
    """
    m = B.size
    if m % 2:
        return None
    n = m // 2
    osc_k = np.ascontiguousarray(np.diag(A[n:, :n]))
    osc_c = np.ascontiguousarray(np.diag(A[n:, n:]))
    pattern = np.block([[np.zeros((n, n)), np.eye(n)], [np.diag(osc_k), np.diag(osc_c)]])
    if not (np.array_equal(A, pattern) and np.array_equal(B, np.r_[np.zeros(n), -np.ones(n)])):
        return None
    return osc_k, osc_c


class _CompiledPlant:
    """What the virtual tables behind :class:`PlantInterface` share: one sensing per loop, the clock.

    A subclass sets ``plant`` (the compiled stages' structure), ``sensors``,
    ``seed`` and ``loop_time``, and ``_sense_and_check`` (the compiled
    ``sense_and_check`` of its stage module).
    """

    plant: Any
    sensors: Any
    seed: int
    loop_time: float
    _sense_and_check: Any

    @property
    def y(self) -> np.ndarray:
        """Plant state ``[table states, specimen states]`` (advanced in place)."""
        return self.plant.y

    def _restart(self) -> None:
        """Filters and converter delays unprimed, output delay empty, noise from its seed, clock at zero."""
        self.plant.sensors.filters.reset()
        self.plant.sensors.delays.reset()
        self.plant.output_line[:] = 0.0
        self._rng = np.random.default_rng(self.seed)
        self._colour = coloured_noise(self._rng, self.sensors, self.loop_time)
        self._tick = 0
        self._read: tuple | None = None
        self.trip_value = float("nan")

    @property
    def time_s(self) -> float:
        return self._tick * self.loop_time

    def _sense(self) -> tuple:
        """This loop's ``(Measurements, TripCause, value)``, sensed once per loop."""
        if self._read is None:
            self.plant.noise[0] = draw_noise(self._rng, self.sensors)
            if self._colour is not None:
                self.plant.noise[0, self._colour.channel] = self._colour.row(self._tick)
            self._read = self._sense_and_check(self.plant, self.plant.noise[0], self.time_s)
        return self._read

    def read_sensors(self) -> Measurements:
        m, cause, value = self._sense()
        if cause:
            self.trip_value = float(value)
            raise LimitTripped(cause, self.time_s, f"value {value:.6g}", value=float(value))
        return m

    def _step(self) -> None:
        """The clock moves on: the next loop senses anew."""
        self._tick += 1
        self._read = None


class VirtualTable(_CompiledPlant):
    """The nonlinear virtual table (and specimen) behind :class:`PlantInterface`.

    Parameters
    ----------
    table : NonlinearTable
        Physical table (:meth:`NonlinearTable.from_linear`).
    specimen : object, optional
        Test article with ``state_space()`` (input z [in/s^2], output w [lbf]).
    sensors : SensorSuite, optional
        Sensor channels (default :func:`~impedance_mil.lab.setup.default_sensors`).
    feedback : {"lc", "fe"}
        Which force the caller will use (checks that load cells exist for "lc").
    quantize : bool
        16-bit quantization of the sensors.
    limits : SafetyLimits
        Interlocks.
    substeps : int or "auto"
        RK4 substeps per loop (``"auto"``: :func:`~impedance_mil.lab.substeps.choose_substeps`).
    seed : int
        Seed of the sensor noise (numpy ``default_rng``; one row of
        ``n_channels`` normals per loop, as in the compiled loop).
    output_delay : int
        The controller's output delay N [loops]: the command written at loop
        k reaches the valve over loop k + N - 1 (default 1, the report's
        controller: at once, with the previous loop's measurements in it).
    """

    def __init__(
        self,
        table,
        specimen=None,
        sensors=None,
        limits: SafetyLimits | None = None,
        substeps: int | str = "auto",
        seed: int = 0,
        feedback: str = "lc",
        quantize: bool = True,
        output_delay: int = 1,
    ):
        self.table = table
        self.loop_time = table.loop_time
        self.sensors = sensors or default_sensors()
        self.substeps = resolve_substeps(substeps, table, specimen)[0]
        self.seed = seed
        self.output_delay = int(output_delay)
        spec = specimen_arrays(specimen)
        n = N_TABLE_STATES + spec.B.size
        #: The compiled stages' view of this table: one row of noise, drawn per loop.
        self.plant = VirtualPlant(
            table=table.parameter_array(),
            y=np.zeros(n),
            specimen=spec,
            sensors=sensor_arrays(
                self.sensors, feedback, quantize, self.loop_time / self.substeps, self.loop_time
            ),
            limits=(limits or SafetyLimits()).kernel_values(table, accelerometer_noise(self.sensors)),
            substeps=self.substeps,
            noise=np.zeros((1, self.sensors.n_channels), np.float32),
            work=np.zeros((5, n)),
            readings=np.zeros(self.sensors.n_channels),
            held=np.zeros(1, HELD_STATE),
            output_line=output_line(output_delay),
        )
        self.reset()

    _sense_and_check = staticmethod(kernels.sense_and_check)

    def reset(self) -> None:
        self.y[:] = 0.0
        self.y[:N_TABLE_STATES] = self.table.equilibrium_state()
        self.plant.held[:] = np.zeros(1, HELD_STATE)
        self._restart()

    @property
    def valve_command(self) -> float:
        """Valve command of the current loop [V]."""
        return float(self.plant.held[0]["u_v"])

    @property
    def current(self) -> float:
        """Valve current of the current loop [mA]."""
        return float(self.plant.held[0]["current"])

    def write_command(self, u: float) -> None:
        p = self.plant
        kernels.hydraulic_command(p.table, p.limits, p.held, p.output_line, self._sense()[0], float(u))

    def advance(self) -> None:
        p = self.plant
        self._sense()  # the filters are brought to this instant by the sensing, read or not
        plant_advance(
            p.table, p.y, *p.specimen, self.current, self.loop_time, self.substeps, p.work, p.sensors.filters
        )
        self._step()

    def truth(self) -> dict:
        """True (unmeasured) plant quantities of the current loop."""
        return kernels.plant_truth(self.plant.y, self.plant.held)._asdict()


def lti_plant(
    table: LTIVirtualTable,
    specimen,
    sensors: SensorArrays,
    limits: LimitValues,
    substeps: int,
    noise,
    output_delay,
) -> LTIPlant:
    """The :class:`~impedance_mil.lab.structures.LTIPlant` of an LTI table and specimen, at rest.

    ``sensors`` and ``limits`` are the kernels' arrays (:func:`~impedance_mil.lab.setup.sensor_arrays`,
    :func:`~impedance_mil.lab.lti_plant.lti_limits`), ``substeps`` the parts of a loop the
    anti-alias filters advance by, ``noise`` the sensors' draws (one row per loop),
    ``output_delay`` N [loops].
    """
    coupled = table.coupled(*specimen_state_space(specimen))
    n = coupled.system.n_states
    return LTIPlant(
        table=lti_arrays(table, coupled, substeps),
        y=np.zeros(n),
        sensors=sensors,
        limits=limits,
        substeps=substeps,
        noise=noise,
        work=np.zeros(n),
        readings=np.zeros(noise.shape[1]),
        held=np.zeros(1, LTI_HELD_STATE),
        output_line=output_line(output_delay),
    )


class VirtualLTITable(_CompiledPlant):
    """An LTI table (and specimen) behind :class:`PlantInterface`, on the compiled LTI stages.

    Parameters are those of :class:`VirtualTable`, with ``table`` an
    :class:`~impedance_mil.lab.lti_plant.LTIVirtualTable` (or a linear table
    model, :func:`~impedance_mil.lab.lti_plant.virtual_table_for`); the stages
    are those of :mod:`impedance_mil.lab.lti_kernels`, so this and the
    compiled loop give the same numbers.
    """

    _sense_and_check = staticmethod(lti_kernels.sense_and_check)

    def __init__(
        self,
        table,
        specimen=None,
        sensors=None,
        limits: SafetyLimits | None = None,
        substeps: int | str = "auto",
        seed: int = 0,
        feedback: str = "lc",
        quantize: bool = True,
        output_delay: int = 1,
    ):
        self.table = virtual_table_for(table)
        check_feedback(self.table, feedback)
        self.loop_time = self.table.loop_time
        self.sensors = sensors or default_sensors()
        self.substeps = resolve_substeps(substeps, self.table, specimen)[0]
        self.seed = seed
        self.output_delay = int(output_delay)
        #: The compiled stages' view of this table: one row of noise, drawn per loop.
        self.plant = lti_plant(
            self.table,
            specimen,
            sensor_arrays(self.sensors, feedback, quantize, self.loop_time / self.substeps, self.loop_time),
            lti_limits(limits or SafetyLimits(), self.table, accelerometer_noise(self.sensors)).values,
            self.substeps,
            np.zeros((1, self.sensors.n_channels), np.float32),
            output_delay,
        )
        self.reset()

    def reset(self) -> None:
        self.y[:] = 0.0
        self.plant.held[:] = np.zeros(1, LTI_HELD_STATE)
        self._restart()

    def write_command(self, u: float) -> None:
        self._sense()  # the command is written in the loop that was read
        lti_kernels.lti_command(self.plant.held, self.plant.output_line, float(u))

    def advance(self) -> None:
        self._sense()  # the filters are brought to this instant by the sensing, read or not
        lti_kernels.advance(self.plant)
        self._step()

    def truth(self) -> dict:
        """True (unmeasured) plant quantities of the current loop (NaN: chambers, spool, valve)."""
        return lti_kernels.truth(self.plant)._asdict()
