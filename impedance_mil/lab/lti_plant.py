"""An LTI table in the virtual lab: a linear table model, coupled with the specimen, discretized exactly.

A table given by a linear model -- a transfer-function, zpk or state-space
table file, or the toolkit's own :class:`~impedance_mil.plant.linear.LinearTable`
-- has its hydraulic loop inside the model: its input is the position command
u [in] and the force w [lbf] of the test article on the table, its outputs the
table acceleration z [in/s**2], the displacement x [in] and, if the model has
them, the velocity v [in/s] and the differential pressure dP [psi].  The lab
runs it with the same sensors, interlocks, specimen coupling, controller and
output delay as the physical table (:mod:`impedance_mil.lab.lti_kernels`);
what differs:

* **no hydraulic stage of ours**: the command u after the output-delay line
  is the model's input, held over the loop (zero-order hold);
* **exact integration**: table + specimen is linear with the held input, so
  the loop is one step of the exact ZOH discretization of the coupled system
  (:meth:`LTIVirtualTable.coupled`, :func:`lti_arrays`), not RK4 substeps.
  With anti-alias filters on some channel the loop is split into the
  ``substeps`` of the run, still exact, and the filters advance at their
  boundaries as with the physical table;
* **the channels a model lacks**: the stroke interlock reads x, so a model
  without x is refused (naming ``x``); without v, v is derived from x
  (``v = C_x x'`` when x has no feedthrough); without dP (or without the piston
  area) there is no actuator-force interlock and no ``w_FE``; an LTI model
  has no valve, so the valve interlocks do not apply (:func:`lti_limits`
  says which interlocks a run has, and refuses an explicit limit it cannot
  enforce).

The coupling (specimen ``x_s' = A_s x_s + B_s z``, ``w = C_s x_s + D_s z``;
table ``x_t' = A x_t + B_u u + B_w w``, ``z = C_z x_t + D_zu u + D_zw w``)
solves the algebraic loop once: ``z = (C_z x_t + D_zw C_s x_s + D_zu u) / (1 - D_zw D_s)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..lti import StateSpace
from ..plant.statespace import TableStateSpace
from .setup import SafetyLimits
from .structures import Q_DP, Q_FORCE, Q_W, Q_X, Q_Z, LimitValues, LTIArrays

#: Row of the velocity [in/s] in (column of its transpose) :attr:`LTIArrays.out_t` (after the sensed quantities).
ROW_V = 5
#: Rows of :attr:`LTIArrays.out_t`: the quantities the sensors read (order of QUANTITIES), then v.
N_ROWS = 6


@dataclass(frozen=True, eq=False)
class OutputRow:
    """One output of the table model: ``y = c x_t + d_u u + d_w w``.

    Attributes
    ----------
    c : ndarray (n,)
        Row over the model's states.
    d_u : float
        Feedthrough of the command u [unit of y per in].
    d_w : float
        Feedthrough of the force w [unit of y per lbf].
    """

    c: np.ndarray
    d_u: float
    d_w: float


@dataclass(frozen=True, eq=False)
class CoupledTable:
    """Table + specimen as one linear system: state ``[table states, specimen states]``, input u [in].

    Attributes
    ----------
    system : StateSpace
        Continuous; A [1/s], input ``"u"``; outputs ``"z"`` [in/s**2],
        ``"x"`` [in], ``"v"`` [in/s], ``"dp"`` [psi] (zero rows where the model
        has no dP) and ``"w"`` [lbf].
    has_dp : bool
        Whether the model has a dP output.
    """

    system: StateSpace
    has_dp: bool


@dataclass(frozen=True, eq=False)
class LTIVirtualTable:
    """A shake table given by a continuous linear model, as the virtual lab runs it.

    Parameters
    ----------
    model : TableStateSpace
        Continuous model, inputs ``("u", "w")``: the position command u [in]
        held over each loop and the force w [lbf] of the test article on the
        table; outputs ``"z"`` [in/s**2] and ``"x"`` [in], optionally ``"v"``
        [in/s] and ``"dp"`` [psi].
    loop_time : float
        Controller loop time [s].
    piston_area : float, optional
        A_p [in**2]: with a dP output, the actuator force ``A_p dP`` (its
        interlock) and, with ``mass``, ``w_FE = m_st z - A_p dP``.
    mass : float, optional
        Moving mass m_st [lbf*s**2/in] (for ``w_FE``).
    max_force : float, optional
        Stall force ``A_p (P_s - P_R)`` [lbf]: the default actuator-force
        interlock is 95 % of it, as for the physical table.
    name : str
        What the run's configuration calls the table.

    Raises
    ------
    ConfigError
        Not a continuous model with inputs u and w, no ``z`` or ``x``
        output, or a non-positive loop time, area or mass.

    Examples
    --------
    >>> from impedance_mil.plant import TableParameters
    >>> from impedance_mil.plant.linear import LinearTable
    >>> table = virtual_table_for(LinearTable(TableParameters.report_default(), delay="pade"))
    >>> table.outputs
    ('z', 'x', 'v', 'dp')
    """

    model: TableStateSpace
    loop_time: float
    piston_area: float | None = None
    mass: float | None = None
    max_force: float | None = None
    name: str = "lti"

    def __post_init__(self):
        system = self.model.system
        if system.is_discrete:
            raise ConfigError("table.model", "a continuous state space (dt = 0)", f"dt={system.dt:g} s")
        if tuple(system.inputs) != ("u", "w"):
            raise ConfigError(
                "table.inputs", "('u', 'w'): command [in], test-article force [lbf]", system.inputs
            )
        for name, why in (
            ("z", "the table acceleration [in/s**2]"),
            ("x", "the stroke interlock's displacement [in]"),
        ):
            if name not in system.outputs:
                raise ConfigError("table.outputs", f"an output {name!r}, {why}", tuple(system.outputs))
        if not (np.isfinite(self.loop_time) and self.loop_time > 0):
            raise ConfigError("table.loop_time", "a positive loop time [s]", self.loop_time)
        for key in ("piston_area", "mass", "max_force"):
            value = getattr(self, key)
            if value is not None and not (np.isfinite(value) and value > 0):
                raise ConfigError(f"table.{key}", "a positive finite number", value)

    @property
    def outputs(self) -> tuple[str, ...]:
        """The model's output names."""
        return tuple(self.model.system.outputs)

    def given_row(self, name: str) -> OutputRow:
        """Output ``name`` as the model gives it (one of :attr:`outputs`)."""
        d_u, d_w = self.model.D[name]
        return OutputRow(np.asarray(self.model.C[name], dtype=float), d_u, d_w)

    def row(self, name: str) -> OutputRow | None:
        """Output ``name`` of the model; v derived from x when the model has no v; None if absent."""
        if name in self.outputs:
            return self.given_row(name)
        x = self.given_row("x")
        if name == "v" and x.d_u == 0.0 and x.d_w == 0.0:
            # v = x' = C_x (A x_t + B_u u + B_w w)
            return OutputRow(x.c @ self.model.A, float(x.c @ self.model.B_u), float(x.c @ self.model.B_w))
        return None

    @property
    def has_dp(self) -> bool:
        """Whether the model has a dP output (actuator force, ``w_FE``, the pressure interlock)."""
        return "dp" in self.outputs

    @property
    def has_force(self) -> bool:
        """Whether the actuator force ``A_p dP`` is known (a dP output and the piston area)."""
        return self.has_dp and self.piston_area is not None

    def coupled(self, As, Bs, Cs, Ds) -> CoupledTable:
        """The table coupled with a specimen ``(A_s, B_s, C_s, D_s)`` (input z [in/s**2], output w [lbf]).

        Raises
        ------
        ConfigError
            The algebraic loop ``1 - D_zw D_s = 0`` has no solution.
        """
        t = self.model
        n, m = t.A.shape[0], np.size(Bs)
        z = self.given_row("z")
        denom = 1.0 - z.d_w * Ds
        if abs(denom) < 1e-12:
            raise ConfigError("specimen", "a feedthrough D_s with 1 - D_zw D_s != 0", Ds)
        z_row = np.concatenate([z.c, z.d_w * Cs]) / denom
        z_u = z.d_u / denom
        w_row = np.concatenate([np.zeros(n), Cs]) + Ds * z_row
        w_u = Ds * z_u
        A = np.zeros((n + m, n + m))
        A[:n, :n], A[n:, n:] = t.A, As
        A += np.outer(np.concatenate([t.B_w, np.zeros(m)]), w_row)
        A += np.outer(np.concatenate([np.zeros(n), Bs]), z_row)
        B = np.concatenate([t.B_u + t.B_w * w_u, Bs * z_u])
        rows, feed = [z_row], [z_u]
        for name in ("x", "v", "dp"):
            r = self.row(name) or OutputRow(np.zeros(n), 0.0, 0.0)
            rows.append(np.concatenate([r.c, np.zeros(m)]) + r.d_w * w_row)
            feed.append(r.d_u + r.d_w * w_u)
        rows.append(w_row)
        feed.append(w_u)
        states = tuple(t.states) + tuple(f"specimen_{i + 1}" for i in range(m))
        system = StateSpace(
            A,
            B[:, None],
            np.vstack(rows),
            np.array(feed)[:, None],
            0.0,
            ("u",),
            ("z", "x", "v", "dp", "w"),
            states,
        )
        return CoupledTable(system, self.has_dp)

    def to_dict(self) -> dict:
        """Plain entries for a run's configuration."""
        return {
            "kind": "lti",
            "name": self.name,
            "loop_time": self.loop_time,
            "piston_area": self.piston_area,
            "mass": self.mass,
            "max_force": self.max_force,
            "model": self.model.system.to_dict(),
        }


def check_feedback(table: LTIVirtualTable, feedback: str) -> None:
    """Refuse ``feedback="fe"`` when the model cannot give ``w_FE = m_st z - A_p dP``.

    Raises
    ------
    ConfigError
        ``"fe"`` on a model without a dP output, a piston area or a mass.
    """
    if feedback == "fe" and not (table.has_force and table.mass is not None):
        raise ConfigError(
            "feedback",
            "'lc': w_FE = m_st z - A_p dP needs the table model's 'dp' output, piston_area and mass",
            feedback,
        )


def lti_arrays(table: LTIVirtualTable, coupled: CoupledTable, substeps: int) -> LTIArrays:
    """The compiled kernels' view of a coupled LTI table (:class:`~impedance_mil.lab.structures.LTIArrays`).

    The exact ZOH discretization of ``coupled`` over the loop and over one of
    ``substeps`` equal parts of it (the latter for the anti-alias filters),
    and the output rows in the slots of the sensed quantities.
    """
    system = coupled.system
    loop = system.zoh(table.loop_time)
    step = system.zoh(table.loop_time / substeps)
    n = system.n_states
    out, out_u = np.zeros((N_ROWS, n)), np.zeros(N_ROWS)
    index = {name: i for i, name in enumerate(system.outputs)}
    for slot, name in ((Q_Z, "z"), (Q_X, "x"), (Q_DP, "dp"), (Q_W, "w"), (ROW_V, "v")):
        out[slot], out_u[slot] = system.C[index[name]], system.D[index[name], 0]
    area = math.nan if table.piston_area is None else table.piston_area
    if table.has_force:
        out[Q_FORCE], out_u[Q_FORCE] = area * out[Q_DP], area * out_u[Q_DP]
    return LTIArrays(
        loop_phi_t=np.ascontiguousarray(loop.A.T),
        loop_gamma=np.ascontiguousarray(loop.B[:, 0]),
        step_phi_t=np.ascontiguousarray(step.A.T),
        step_gamma=np.ascontiguousarray(step.B[:, 0]),
        out_t=np.ascontiguousarray(out.T),
        out_u=out_u,
        loop_time=float(table.loop_time),
        mass=math.nan if table.mass is None else float(table.mass),
        area=area,
        has_dp=bool(coupled.has_dp),
    )


@dataclass(frozen=True)
class LTILimits:
    """The interlocks of a run on an LTI table: the kernel's thresholds and what is not checked, and why.

    Attributes
    ----------
    values : LimitValues
        Thresholds (inf for an interlock that does not apply).
    unavailable : dict of str to str
        Interlock name -> the reason it is not checked (stored with the run).
    """

    values: LimitValues
    unavailable: dict


def lti_limits(limits: SafetyLimits, table: LTIVirtualTable, accel_noise: float | None = None) -> LTILimits:
    """The interlocks of ``limits`` an LTI table can have.

    Stroke, divergence, acceleration and (with v, given or derived) velocity
    as for the physical table.  The actuator force ``A_p |dP|`` needs a dP
    output and the piston area; its default is 95 % of the stall force, as
    for the physical table, when the model states it (``max_force``), and
    none otherwise.  The pressure interlock
    needs dP.  The valve interlocks (saturation, duty, current, command
    oscillation) do not apply: the model has no valve.  The high-frequency
    instability detector applies as for the physical table (``accel_noise``
    [in/s**2 rms], the accelerometer's noise, sets its default floor).

    Raises
    ------
    ConfigError
        An explicit ``actuator_force`` or ``pressure`` limit the model cannot
        check (no dP output or no piston area): it would not protect anything.
    """
    unavailable = {
        "valve_saturation_time": "no valve in an LTI table model",
        "valve_duty": "no valve in an LTI table model",
        "valve_current": "no valve in an LTI table model",
        "command_slew": "no valve in an LTI table model",
    }
    force = math.inf
    if limits.actuator_force is not None and not table.has_force:
        raise ConfigError(
            "limits.actuator_force", "a table model with a 'dp' output and a piston_area", table.outputs
        )
    if limits.actuator_force is not None:
        force = float(limits.actuator_force)
    elif not table.has_force:
        unavailable["actuator_force"] = "the table model has no 'dp' output or no piston_area"
    elif table.max_force is None:
        unavailable["actuator_force"] = "no default: the table model states no stall force (supply pressure)"
    else:
        force = 0.95 * table.max_force
    if limits.pressure is not None and not table.has_dp:
        raise ConfigError("limits.pressure", "a table model with a 'dp' output", table.outputs)
    velocity = float(limits.velocity)
    if table.row("v") is None:
        velocity = math.inf
        unavailable["velocity"] = "the table model has no v, and its x has a feedthrough"
    values = LimitValues(
        stroke=float(limits.stroke),
        velocity=velocity,
        actuator_force=force,
        valve_saturation_time=math.inf,
        divergence=float(limits.divergence),
        valve_duty=math.inf,
        valve_current=math.inf,
        command_slew=math.inf,
        interlock_window=float(limits.interlock_window),
        acceleration=math.inf if limits.acceleration is None else float(limits.acceleration),
        pressure=math.inf if limits.pressure is None else float(limits.pressure),
        **limits.hf_values(table.loop_time, accel_noise),
    )
    return LTILimits(values, unavailable)


def virtual_table_for(table_model, *, piston_area: float | None = None, mass: float | None = None):
    """The table the virtual lab runs for ``table_model``.

    Parameters
    ----------
    table_model : NonlinearTable, LTIVirtualTable, or a linear table model
        A physical (nonlinear) table or an :class:`LTIVirtualTable` is
        returned as it is.  A linear table model is anything with
        ``state_space()`` (a continuous
        :class:`~impedance_mil.plant.statespace.TableStateSpace`, inputs u
        [in] and w [lbf]) and a loop time (``loop_time`` [s], or
        ``params.loop_time`` for a :class:`~impedance_mil.plant.linear.LinearTable`,
        whose ``params`` also give the piston area, the moving mass and
        the stall force).
    piston_area : float, optional
        A_p [in**2], if the model does not state it.
    mass : float, optional
        Moving mass [lbf*s**2/in], if the model does not state it.

    Raises
    ------
    ConfigError
        ``table_model`` is none of these, or its model cannot run (see
        :class:`LTIVirtualTable`; a sampled, discrete model has no continuous
        state space).
    """
    if isinstance(table_model, LTIVirtualTable) or hasattr(table_model, "parameter_array"):
        return table_model
    if not hasattr(table_model, "state_space"):
        raise ConfigError("table", "a physical table or a linear table model with state_space()", table_model)
    stated = {key: _stated(table_model, key) for key in ("loop_time", "piston_area", "mass")}
    params = getattr(table_model, "params", None)
    max_force = getattr(table_model, "max_force", None)
    if max_force is None and params is not None and hasattr(params, "supply_pressure"):
        max_force = params.piston_area * (params.supply_pressure - params.return_pressure)
    if stated["loop_time"] is None:
        raise ConfigError("table.loop_time", "the loop time [s] of the linear table model", None)
    return LTIVirtualTable(
        table_model.state_space(),
        float(stated["loop_time"]),
        piston_area=piston_area if stated["piston_area"] is None else stated["piston_area"],
        mass=mass if stated["mass"] is None else stated["mass"],
        max_force=max_force,
        name=type(table_model).__name__,
    )


def _stated(table_model, key: str):
    """``table_model.key``, else ``table_model.params.key``, else None."""
    value = getattr(table_model, key, None)
    if value is None:
        value = getattr(getattr(table_model, "params", None), key, None)
    return value


__all__ = [
    "CoupledTable",
    "check_feedback",
    "LTILimits",
    "LTIVirtualTable",
    "OutputRow",
    "lti_arrays",
    "lti_limits",
    "virtual_table_for",
]
