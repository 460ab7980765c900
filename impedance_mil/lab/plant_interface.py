"""The plant interface: what a shake-table controller link offers, and the virtual table behind it.

A MIL program sees the table through four calls (the RMC75E's axis, Section
7.3.4): read the sensors of this loop, write the position command, let one
loop time pass.  :class:`PlantInterface` is that contract; a link to a real
controller can implement it, and :class:`VirtualTable` implements it with the
nonlinear table of :mod:`impedance_mil.plant.nonlinear`, calling the same
compiled functions (``plant_sense``, ``hydraulic_step``, ``plant_advance``,
``check_limits``) as the compiled loop of :mod:`impedance_mil.lab.kernels`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from ..errors import LimitTripped
from ..plant.nonlinear import IX_P1, IX_P2, IX_S, IX_V, IX_X, N_TABLE_STATES
from .kernels import (
    M_DP,
    M_W,
    M_WFE,
    M_WLC,
    M_X,
    M_Z,
    M_ZM,
    SPEC_BANK,
    SPEC_CSR,
    TRIP_NAMES,
    check_limits,
    hydraulic_step,
    plant_advance,
    plant_sense,
)
from .setup import SafetyLimits, default_sensors, draw_noise, sensor_arrays
from .substeps import resolve_substeps, specimen_state_space


@dataclass(frozen=True)
class Measurements:
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


def specimen_arrays(specimen, oscillator_bank: bool = True) -> tuple:
    """Kernel arrays ``(A_val, A_col, A_ptr, B, C, D, kind, osc_k, osc_c)`` of a specimen.

    Input z [in/s^2], output w [lbf].  ``A`` is stored in compressed-row form
    (most specimens are sparse: a vessel's 8x8 matrix has 12 nonzeros);
    ``specimen`` is an object with ``state_space()`` or a state space with
    ``A, B, C, D``; ``None`` gives no states and ``w = 0``.  When the state
    space is a bank of base-excited oscillators (:func:`oscillator_bank_of`:
    a vessel, a rigid mass, a single-DOF article) and ``oscillator_bank`` is
    true, ``kind`` is ``SPEC_BANK`` and ``osc_k``, ``osc_c`` hold its
    coefficients; otherwise ``kind`` is ``SPEC_CSR`` (``oscillator_bank=False``
    forces the general path, for comparisons).
    """
    if specimen is None:
        A, B, C, D = np.zeros((0, 0)), np.zeros(0), np.zeros(0), 0.0
    else:
        A, B, C, D = specimen_state_space(specimen)
    rows, cols = np.nonzero(A)
    ptr = np.searchsorted(rows, np.arange(A.shape[0] + 1)).astype(np.int64)
    bank = oscillator_bank_of(A, B) if oscillator_bank else None
    kind, osc_k, osc_c = (SPEC_CSR, np.zeros(0), np.zeros(0)) if bank is None else (SPEC_BANK, *bank)
    return (
        np.ascontiguousarray(A[rows, cols]),
        cols.astype(np.int64),
        ptr,
        np.ascontiguousarray(B),
        np.ascontiguousarray(C),
        D,
        kind,
        osc_k,
        osc_c,
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


class VirtualTable:
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
    ):
        self.table = table
        self.loop_time = table.loop_time
        self._pa = table.parameter_array()
        self._spec = specimen_arrays(specimen)
        self._C, self._D = self._spec[4], self._spec[5]
        self.sensors = sensors or default_sensors()
        self._sens = sensor_arrays(self.sensors, feedback, quantize)
        self._readings = np.zeros(self.sensors.n_channels)
        self._lim = (limits or SafetyLimits()).array(table)
        self.substeps = resolve_substeps(substeps, table, specimen)[0]
        self.seed = seed
        n = N_TABLE_STATES + self._C.size
        self.y = np.zeros(n)
        self._work = np.zeros((5, n))
        self._meas = np.zeros(7)
        self.reset()

    def reset(self) -> None:
        self.y[:] = 0.0
        self.y[:N_TABLE_STATES] = self.table.equilibrium_state()
        self._rng = np.random.default_rng(self.seed)
        self._tick = 0
        self._x_prev = 0.0
        self._dp_prev = 0.0
        self._sat = 0
        self.valve_command = 0.0
        self.current = 0.0
        self.trip_value = float("nan")
        self._sense()

    def _sense(self) -> None:
        noise = draw_noise(self._rng, self.sensors)
        plant_sense(self._pa, self.y, self._C, self._D, *self._sens, noise, self._readings, self._meas)

    @property
    def time_s(self) -> float:
        return self._tick * self.loop_time

    def read_sensors(self) -> Measurements:
        code, value = check_limits(self._pa, self._lim, self.y, self._meas, self.valve_command, self._sat)
        if code:
            self.trip_value = float(value)
            raise LimitTripped(TRIP_NAMES[code], self.time_s, f"value {value:.6g}")
        m = self._meas
        return Measurements(self.time_s, m[M_X], m[M_DP], m[M_ZM], m[M_WLC], m[M_WFE])

    def write_command(self, u: float) -> None:
        self.valve_command, self._sat, self.current = hydraulic_step(
            self._pa, float(u), self._x_prev, self._dp_prev, self._sat
        )
        self._x_prev, self._dp_prev = self._meas[M_X], self._meas[M_DP]

    def advance(self) -> None:
        plant_advance(self._pa, self.y, *self._spec, self.current, self.loop_time, self.substeps, self._work)
        self._tick += 1
        self._sense()

    def truth(self) -> dict:
        """True (unmeasured) plant quantities of the current loop."""
        y = self.y
        return {
            "x": y[IX_X],
            "v": y[IX_V],
            "z": self._meas[M_Z],
            "dp": y[IX_P1] - y[IX_P2],
            "p1": y[IX_P1],
            "p2": y[IX_P2],
            "spool": y[IX_S],
            "w": self._meas[M_W],
            "u_v": self.valve_command,
            "current": self.current,
        }
