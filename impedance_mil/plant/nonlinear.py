"""Nonlinear "virtual table": servovalve, orifice flow, compressible chambers (report Eq 4-3..4-8).

The physics of report Section 4.3 without the linearization of Eq 4-9:

* **Servovalve** (Eq 4-3): second-order spool dynamics with two real poles
  ``alpha_1, alpha_2``; the spool state ``s`` is expressed in *mA-equivalent*
  (the current that would hold the spool there statically), so that it is the
  state ``x4`` of Eq 4-11.  The port opening saturates at the rated current
  (full opening).  The general model's valves (``NonlinearTable.valve``): a
  complex pair (second order, same states) or a first-order lag (the spool
  in the ``spool_rate`` slot, :func:`table_rates`).
* **Orifice flow** (Eq 4-5): ``Q = K_q * s * f(dp)`` with the square-root law
  ``f(dp) ~ sign(dp) * sqrt(|dp|)`` through the metering edge that is open:
  for ``s > 0`` supply feeds chamber 1 and chamber 2 drains to return, for
  ``s < 0`` the roles are reversed.  The signed form handles reverse flow
  (chamber pressure above supply).  ``f`` is regularised below the laminar
  pressure ``p_lam`` as ``f(dp) = dp / (dp**2 + p_lam**2)**0.25`` so that
  its slope stays finite at ``dp = 0`` (fixed-step integration stays stable);
  above a few ``p_lam`` it is the square root to within 0.1 %.
* **Chambers** (Eq 4-6, 4-8c,d): ``dP_i/dt = kappa/V_i * (flow in)``, volumes
  ``V_1 = A_p (x_m + x) + V_dead``, ``V_2 = A_p (x_m - x) + V_dead`` change
  with stroke, plus cross-piston leakage ``K_l (P_1 - P_2)``.
* **Table** (Eq 4-7): ``m_st * z = A_p * dP + w - F_friction - k_g x + F_endstop``;
  friction at rails and seals is Coulomb (smoothed as ``v / sqrt(v^2 + v_s^2)``,
  cheaper than ``tanh`` in the hot loop) plus viscous (the platen damping c_p);
  ``k_g`` is the general model's grounded stiffness (0 in the report); beyond
  the end of stroke ``+-x_m`` a stiff cushion stops the table.
* **Hydraulic loop** (Section 4.3.4): ``u_v(k) = K_e (u(k) - x(k-1)) - K_p dP(k-1)``
  evaluated at the loop time with the measurements of the previous loop,
  limited to ``+-valve_command_limit`` and held (ZOH); the VC2124 driver gives
  ``u_i = K_v u_v``.  The general model's output gain g scales the measured
  displacement: ``K_e (u(k) - g x(k-1))``.

Physical parameters are *derived* from the linear model's parameters
(:meth:`NonlinearTable.from_linear`) so that the small-signal linearization
at equilibrium (``P_1 = P_2 = (P_s + P_R)/2``, ``x = v = s = 0``) is Eq 4-11
exactly: the bulk modulus from Eq 4-10a, the leakage from Eq 4-10b and the
flow gain from Eq 4-12 (see ``docs/lab.md``).

The derivative is written once, as numba kernels on a parameter array
(:mod:`impedance_mil.plant.nonlinear_kernels`, re-exported here); the Python
methods, the linearization and the compiled lab loop all call them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ConfigError
from ..lazy import LazyModule, lazy_attributes
from ..units import TWO_PI
from .physics import ValveDynamics
from .table_dynamics import TableDynamics

if TYPE_CHECKING:
    from ..lti import StateSpace

#: The LTI core, read by :attr:`LinearizedTable.system` only: a lab's limits need the table's
#: capacity, not its linear model (``imil lab show``: issue 16, start-up).
lti = LazyModule("impedance_mil.lti")

# --------------------------------------------------------------------------- layout
#: Table state layout (indices into the state vector).
IX_X, IX_V, IX_P1, IX_P2, IX_S, IX_SD = 0, 1, 2, 3, 4, 5
#: Number of table states: x [in], v [in/s], P1 [psi], P2 [psi], s [mA], ds/dt [mA/s].
N_TABLE_STATES = 6
TABLE_STATE_NAMES = ("x", "v", "P1", "P2", "spool", "spool_rate")

# Parameter-array layout (one definition, used by every kernel).
(
    PA_AREA,
    PA_MID,
    PA_MASS,
    PA_KAPPA,
    PA_KL,
    PA_KQ,
    PA_VDEAD,
    PA_PS,
    PA_PR,
    PA_PLAM,
    PA_A1,
    PA_A2,
    PA_SMAX,
    PA_FC,
    PA_FV,
    PA_VSMOOTH,
    PA_KSTOP,
    PA_CSTOP,
    PA_KE,
    PA_KP,
    PA_KV,
    PA_UVMAX,
    PA_LOOP,
    PA_VGAMMA,
    PA_VDELTA,
    PA_VQ,
    PA_KG,
    PA_GOUT,
    PA_FCSUM,
    PA_FCLOAD,
    PA_SRATE,
    PA_MOUNT,
) = range(32)
N_PARAMS = 32
#: The optional dynamics of :class:`~impedance_mil.plant.table_dynamics.TableDynamics` (0: off):
#: PA_FCSUM, PA_FCLOAD seal friction per psi of P1 + P2 and of |P1 - P2| [lbf/psi]; PA_SRATE the
#: spool rate limit [mA/s]; PA_MOUNT the mount's compliance 1/k_f [in/lbf].


def orifice_law(dp: float, p_lam: float) -> float:
    """Signed square-root law ``dp / (dp^2 + p_lam^2)^(1/4)`` [sqrt(psi)] (Eq 4-5).

    Plain Python, for the table's constants (:meth:`NonlinearTable.from_linear`); compiled as
    :func:`orifice` in :mod:`impedance_mil.plant.nonlinear_kernels` for the kernels.
    ``dp`` and ``p_lam`` in psi.
    """
    return dp / math.sqrt(math.sqrt(dp * dp + p_lam * p_lam))


#: The compiled kernels (numba), imported on first use: see :mod:`.nonlinear_kernels`.
kernels = LazyModule("impedance_mil.plant.nonlinear_kernels")

#: The kernels' names, read from :mod:`.nonlinear_kernels` on first use (PEP 562).
KERNELS = (
    "orifice",
    "port_flows",
    "acceleration",
    "table_acceleration",
    "table_rates",
    "table_derivative",
    "valve_command",
)
__getattr__ = lazy_attributes(__name__, "impedance_mil.plant.nonlinear_kernels", KERNELS)


# --------------------------------------------------------------------------- value objects
@dataclass(frozen=True)
class Friction:
    """Friction at the rails and actuator seals (not in the report's model).

    Parameters
    ----------
    coulomb : float
        Coulomb (dry) friction force [lbf].  Default 8 lbf, 0.5 % of the
        1600 lb moving weight: the report calls friction negligible compared
        with the actuator force (Section 4.3.3) but blames it for the
        low-frequency errors of Sections 8-9, so a small value is kept.
    viscous : float
        Viscous coefficient [lbf*s/in].  Default 0.5.
    smoothing_velocity : float
        Velocity v_s [in/s] of the smoothing ``v / sqrt(v^2 + v_s^2)`` of the
        Coulomb term (98 % of the full force at 5 v_s).  Default 0.02 in/s.
    """

    coulomb: float = 8.0
    viscous: float = 0.5
    smoothing_velocity: float = 0.02

    def __post_init__(self):
        if self.coulomb < 0 or self.viscous < 0:
            raise ConfigError(
                "friction", "non-negative coulomb [lbf] and viscous [lbf*s/in]", (self.coulomb, self.viscous)
            )
        if self.smoothing_velocity <= 0:
            raise ConfigError(
                "friction.smoothing_velocity", "a positive velocity [in/s]", self.smoothing_velocity
            )

    @classmethod
    def none(cls) -> Friction:
        """No friction (the report's assumption, Eq 4-7b)."""
        return cls(coulomb=0.0, viscous=0.0)


def _table_friction(p) -> Friction:
    """The friction of table parameters ``p``: its ``coulomb_friction`` and ``platen_damping``
    where given, else the :class:`Friction` defaults."""
    default = Friction()
    coulomb = default.coulomb if p.coulomb_friction is None else p.coulomb_friction
    viscous = default.viscous if p.platen_damping is None else p.platen_damping
    return Friction(coulomb=coulomb, viscous=viscous)


@dataclass(frozen=True)
class LinearizedTable:
    """Small-signal model ``dx = A dx + B_u du + B_w dw`` of the nonlinear table.

    ``C`` maps output names (``"x"``, ``"v"``, ``"z"``, ``"dp"``) to
    ``(C_row, D_u, D_w)``; states follow ``state_names``.
    """

    A: np.ndarray
    B_u: np.ndarray
    B_w: np.ndarray
    C: dict
    state_names: tuple

    @property
    def system(self) -> StateSpace:
        """The same model as one :class:`~impedance_mil.lti.StateSpace`, inputs ``("u", "w")``."""
        names = tuple(self.C)
        return lti.StateSpace(
            self.A,
            np.column_stack([self.B_u, self.B_w]),
            np.vstack([self.C[k][0] for k in names]),
            np.array([self.C[k][1:] for k in names], dtype=float),
            0.0,
            ("u", "w"),
            names,
            tuple(self.state_names),
        )

    def frequency_response(self, output: str, input: str, f_hz) -> np.ndarray:
        """Complex response of ``output`` to ``input`` (``"u"`` or ``"w"``) at ``f_hz`` [Hz]."""
        if output not in self.C or input not in ("u", "w"):
            raise ConfigError("output/input", f"one of {sorted(self.C)} / 'u' or 'w'", (output, input))
        f = np.atleast_1d(np.asarray(f_hz, dtype=float))
        return self.system.channel(output, input).frequency_response(f)


@dataclass(frozen=True)
class NonlinearTable:
    """Physical parameters of the nonlinear servo-hydraulic table (report Sections 4.2-4.3).

    Build it with :meth:`from_linear` so that it linearizes to Eq 4-11.

    Parameters
    ----------
    piston_area : float
        A_p [in^2].
    mid_stroke : float
        x_m [in]; the table hits its end stops at +-x_m.
    mass : float
        Moving mass m_st [lbf*s^2/in].
    bulk_modulus : float
        Oil bulk modulus kappa [psi].
    leakage : float
        Cross-piston leakage coefficient K_l [in^3/s/psi].
    flow_gain : float
        Orifice flow gain K_q [in^3/s per mA per sqrt(psi)].
    dead_volume : float
        Oil volume of each chamber beyond the swept volume (ports, manifold) [in^3].
    valve_poles_hz : tuple of float
        Servovalve poles alpha_1, alpha_2 [Hz] (Eq 4-3); ``()`` when ``valve`` is given.
    supply_pressure, return_pressure : float
        P_s, P_R [psi].
    laminar_pressure : float
        Regularisation pressure of the square-root law [psi].
    spool_limit : float
        Full port opening, in mA-equivalent (the rated current) [mA].
    Ke : float
        Proportional gain [V/in].
    Kp : float
        Delta-P gain [V/psi].
    Kv : float
        VC2124 voltage-to-current gain [mA/V].
    valve_command_limit : float
        Limit of the valve command [V].
    loop_time : float
        Controller loop time tau_s [s].
    friction : Friction
        Rail and seal friction; its viscous term is the platen damping c_p
        [lbf*s/in] of the linear model (one term, not two).
    endstop_stiffness, endstop_damping : float
        Cushion beyond +-x_m [lbf/in], [lbf*s/in].
    valve : ValveDynamics or None
        The servovalve (:class:`~impedance_mil.plant.parameters.ValveDynamics`);
        None: the two poles ``valve_poles_hz``.
    output_gain : float
        Displacement sensor gain g [-] in the hydraulic loop (:func:`valve_command`).
    grounded_stiffness : float
        Stiffness from the platen to ground k_g [lbf/in] (:func:`acceleration`).
    dynamics : TableDynamics or None
        Optional dynamics of issue 17 (pressure-dependent seal friction, spool
        rate limit, compliant mount; :mod:`impedance_mil.plant.table_dynamics`);
        None: none, the report's model to the last bit.
    """

    piston_area: float
    mid_stroke: float
    mass: float
    bulk_modulus: float
    leakage: float
    flow_gain: float
    dead_volume: float
    valve_poles_hz: tuple
    supply_pressure: float = 3000.0
    return_pressure: float = 0.0
    laminar_pressure: float = 20.0
    spool_limit: float = 25.0
    Ke: float = 5.0
    Kp: float = 0.001
    Kv: float = 3.0
    valve_command_limit: float = 10.0
    loop_time: float = 500e-6
    friction: Friction = field(default_factory=Friction)
    endstop_stiffness: float = 1.0e6
    endstop_damping: float = 2.0e3
    valve: ValveDynamics | None = None
    output_gain: float = 1.0
    grounded_stiffness: float = 0.0
    dynamics: TableDynamics | None = None

    def __post_init__(self):
        positive = (
            "piston_area",
            "mid_stroke",
            "mass",
            "bulk_modulus",
            "flow_gain",
            "dead_volume",
            "laminar_pressure",
            "spool_limit",
            "Kv",
            "valve_command_limit",
            "loop_time",
        )
        for name in positive:
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ConfigError(f"table.{name}", "a positive finite number", value)
        if self.leakage < 0:
            raise ConfigError("table.leakage", "a non-negative coefficient [in^3/s/psi]", self.leakage)
        if self.supply_pressure <= self.return_pressure:
            raise ConfigError(
                "table.supply_pressure", "a pressure above return_pressure [psi]", self.supply_pressure
            )
        if self.valve is None:
            if len(self.valve_poles_hz) != 2 or min(self.valve_poles_hz) <= 0:
                raise ConfigError(
                    "table.valve_poles_hz", "two positive frequencies [Hz]", self.valve_poles_hz
                )
        elif len(self.valve_poles_hz) > 0:
            raise ConfigError(
                "table.valve_poles_hz", "() when the valve is given as ValveDynamics", self.valve_poles_hz
            )
        elif not (self.valve.order in (1, 2) and self.valve.gamma > 0 and self.valve.delta >= 0):
            raise ConfigError("table.valve", "order 1 or 2, gamma > 0 and delta >= 0", self.valve)
        if not (np.isfinite(self.output_gain) and self.output_gain > 0):
            raise ConfigError("table.output_gain", "a positive finite gain", self.output_gain)
        if not (np.isfinite(self.grounded_stiffness) and self.grounded_stiffness >= 0):
            raise ConfigError(
                "table.grounded_stiffness", "a non-negative stiffness [lbf/in]", self.grounded_stiffness
            )
        rate_limited = self.dynamics is not None and self.dynamics.spool_rate_limit is not None
        if rate_limited and self.valve_dynamics.order == 2 and not self.valve_dynamics.delta > 0:
            # the limited second-order valve is delta (sat(gamma e / delta) - s'): it needs damping
            raise ConfigError("dynamics.valve.spool_rate_limit", "a damped valve (delta > 0)", self.valve)

    # ----------------------------------------------------------------- building
    @classmethod
    def from_linear(
        cls, p, *, dead_volume: float = 0.5, friction: Friction | None = None, laminar_pressure: float = 20.0
    ) -> NonlinearTable:
        """Physical table whose small-signal model is Eq 4-11 for the linear parameters ``p``.

        Parameters
        ----------
        p : TableParameters
            Linear-model parameters (``impedance_mil.plant.TableParameters`` or
            any object with the same fields).
        dead_volume : float
            Oil volume of each chamber at mid-stroke beyond ``A_p x_m`` [in^3].
            Not given in the report; default 0.5 in^3 (port passages).
        friction : Friction, optional
            Rail/seal friction.  Default: ``p.coulomb_friction`` [lbf] and
            ``p.platen_damping`` [lbf*s/in] where the table gives them, else
            the defaults of :class:`Friction` (8 lbf, 0.5 lbf*s/in: chosen in
            this toolkit, not the report's; existing runs keep them).
        laminar_pressure : float
            Regularisation pressure of the orifice law [psi].

        Notes
        -----
        With ``V_0 = A_p x_m + dead_volume`` the chamber volume at mid-stroke,
        Eq 4-10a,b and 4-12 generalise to

        * ``kappa = omega_oil^2 m_st V_0 / (2 A_p^2)``   (Eq 4-10a),
        * ``K_l = zeta_oil omega_oil V_0 / kappa``      (Eq 4-10b),
        * ``K_q = d V_0 / (2 kappa f((P_s - P_R)/2))``  (Eq 4-12),

        where ``f`` is the orifice law, so the linearization matches Eq 4-11
        exactly (tested in ``tests/lab/test_nonlinear_table.py``).  The valve
        kind, output gain and grounded stiffness of the general model carry
        over; the Coulomb friction has no linear counterpart (a Jacobian test
        needs ``coulomb_friction = 0``).
        """
        if dead_volume <= 0:
            raise ConfigError("table.dead_volume", "a positive volume [in^3]", dead_volume)
        omega = TWO_PI * p.f_oil_hz
        v0 = p.piston_area * p.mid_stroke + dead_volume
        kappa = omega**2 * p.mass * v0 / (2.0 * p.piston_area**2)
        half_drop = 0.5 * (p.supply_pressure - p.return_pressure)
        f_eq = orifice_law(half_drop, laminar_pressure)
        return cls(
            piston_area=p.piston_area,
            mid_stroke=p.mid_stroke,
            mass=p.mass,
            bulk_modulus=kappa,
            leakage=p.zeta_oil * omega * v0 / kappa,
            flow_gain=p.d * v0 / (2.0 * kappa * f_eq),
            dead_volume=dead_volume,
            valve_poles_hz=tuple(float(f) for f in p.valve_poles_hz) if p.valve == "two-pole" else (),
            supply_pressure=p.supply_pressure,
            return_pressure=p.return_pressure,
            laminar_pressure=laminar_pressure,
            spool_limit=p.rated_current,
            Ke=p.Ke,
            Kp=p.Kp,
            Kv=p.Kv,
            valve_command_limit=p.valve_command_limit,
            loop_time=p.loop_time,
            friction=_table_friction(p) if friction is None else friction,
            valve=None if p.valve == "two-pole" else p.valve_dynamics,
            output_gain=p.output_gain,
            grounded_stiffness=p.grounded_stiffness,
            dynamics=getattr(p, "dynamics", None),
        )

    def with_gains(self, **changes) -> NonlinearTable:
        """Copy with changed fields (e.g. ``Kp=0.0002``)."""
        return replace(self, **changes)

    # ----------------------------------------------------------------- derived
    @property
    def valve_dynamics(self) -> ValveDynamics:
        """The servovalve: ``valve``, or the two poles of ``valve_poles_hz`` (Eq 4-3)."""
        if self.valve is not None:
            return self.valve
        a1, a2 = TWO_PI * self.valve_poles_hz[0], TWO_PI * self.valve_poles_hz[1]
        return ValveDynamics(2, a1 * a2, a1 + a2)

    @property
    def equilibrium_pressure(self) -> float:
        """Chamber pressure at rest, ``(P_s + P_R)/2`` [psi]."""
        return 0.5 * (self.supply_pressure + self.return_pressure)

    @property
    def max_force(self) -> float:
        """Stall force ``A_p (P_s - P_R)`` [lbf]."""
        return self.piston_area * (self.supply_pressure - self.return_pressure)

    @property
    def implied_rated_flow(self) -> float:
        """Flow [in^3/s] at the rated current and a 1000 psi valve drop implied by K_q.

        Compare with the valve's rating (57.75 in^3/s for the MOOG 760F264A,
        report Section 4.3.2): a consistency check of the model constant d.
        """
        half = 500.0
        return self.flow_gain * self.spool_limit * orifice_law(half, self.laminar_pressure)

    def parameter_array(self) -> np.ndarray:
        """The parameter array read by the numba kernels (layout ``PA_*``)."""
        pa = np.zeros(N_PARAMS)
        pa[PA_AREA] = self.piston_area
        pa[PA_MID] = self.mid_stroke
        pa[PA_MASS] = self.mass
        pa[PA_KAPPA] = self.bulk_modulus
        pa[PA_KL] = self.leakage
        pa[PA_KQ] = self.flow_gain
        pa[PA_VDEAD] = self.dead_volume
        pa[PA_PS] = self.supply_pressure
        pa[PA_PR] = self.return_pressure
        pa[PA_PLAM] = self.laminar_pressure
        valve = self.valve_dynamics
        if self.valve is None:
            pa[PA_A1] = TWO_PI * self.valve_poles_hz[0]
            pa[PA_A2] = TWO_PI * self.valve_poles_hz[1]
        pa[PA_VGAMMA] = valve.gamma
        pa[PA_VDELTA] = valve.delta if valve.order == 2 else valve.gamma
        pa[PA_VQ] = 1.0 if valve.order == 2 else 0.0
        pa[PA_KG] = self.grounded_stiffness
        pa[PA_GOUT] = self.output_gain
        pa[PA_SMAX] = self.spool_limit
        pa[PA_FC] = self.friction.coulomb
        pa[PA_FV] = self.friction.viscous
        pa[PA_VSMOOTH] = self.friction.smoothing_velocity
        pa[PA_KSTOP] = self.endstop_stiffness
        pa[PA_CSTOP] = self.endstop_damping
        pa[PA_KE] = self.Ke
        pa[PA_KP] = self.Kp
        pa[PA_KV] = self.Kv
        pa[PA_UVMAX] = self.valve_command_limit
        pa[PA_LOOP] = self.loop_time
        dyn = self.dynamics
        if dyn is not None:
            pa[PA_FCSUM] = dyn.pressure_friction
            pa[PA_FCLOAD] = dyn.load_pressure_friction
            pa[PA_SRATE] = 0.0 if dyn.spool_rate_limit is None else dyn.spool_rate_limit
            pa[PA_MOUNT] = dyn.foundation_compliance
        return pa

    def equilibrium_state(self) -> np.ndarray:
        """Table at rest at mid-stroke, ``P_1 = P_2 = (P_s + P_R)/2``."""
        xt = np.zeros(N_TABLE_STATES)
        xt[IX_P1] = xt[IX_P2] = self.equilibrium_pressure
        return xt

    # ----------------------------------------------------------------- evaluation
    def derivative(self, state, current: float, w: float = 0.0) -> tuple[np.ndarray, float]:
        """State derivative and table acceleration z [in/s^2] for valve current [mA] and force w [lbf]."""
        out = np.empty(N_TABLE_STATES)
        z = kernels.table_derivative(
            self.parameter_array(), np.asarray(state, dtype=float), float(current), float(w), 0.0, out
        )
        return out, z

    def linearize(self, *, continuous_feedback: bool = True) -> LinearizedTable:
        """Numerical Jacobian at equilibrium (central differences).

        With ``continuous_feedback`` the hydraulic loop is closed in continuous
        time, ``u_i = K_v (K_e (u - g x) - K_p dP)`` (the analog controller of
        Eq 4-14b, g the output gain); otherwise the input is the valve current
        u_i [mA] (Eq 4-11).  The six states are those of the lab
        (``TABLE_STATE_NAMES``): with a first-order valve the ``spool`` slot
        (the spool's integral) is a decoupled mode at 0.
        """
        pa = self.parameter_array()
        x0 = self.equilibrium_state()
        steps = np.array([1e-6, 1e-5, 1e-3, 1e-3, 1e-6, 1e-3])
        n = N_TABLE_STATES

        def rhs(x, u, w):
            cur = (
                self.Kv * (self.Ke * (u - self.output_gain * x[IX_X]) - self.Kp * (x[IX_P1] - x[IX_P2]))
                if continuous_feedback
                else u
            )
            out = np.empty(n)
            z = kernels.table_derivative(pa, x, cur, w, 0.0, out)
            return np.append(out, z)

        jac = np.empty((n + 1, n))
        for j in range(n):
            e = np.zeros(n)
            e[j] = steps[j]
            jac[:, j] = (rhs(x0 + e, 0.0, 0.0) - rhs(x0 - e, 0.0, 0.0)) / (2 * steps[j])
        du, dw = 1e-6, 1e-3
        b_u = (rhs(x0, du, 0.0) - rhs(x0, -du, 0.0)) / (2 * du)
        b_w = (rhs(x0, 0.0, dw) - rhs(x0, 0.0, -dw)) / (2 * dw)
        dp_row = np.zeros(n)
        dp_row[IX_P1], dp_row[IX_P2] = 1.0, -1.0
        outputs = {
            "x": (np.eye(n)[IX_X], 0.0, 0.0),
            "v": (np.eye(n)[IX_V], 0.0, 0.0),
            "z": (jac[n], b_u[n], b_w[n]),
            "dp": (dp_row, 0.0, 0.0),
        }
        return LinearizedTable(A=jac[:n], B_u=b_u[:n], B_w=b_w[:n], C=outputs, state_names=TABLE_STATE_NAMES)
