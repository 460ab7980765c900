"""Reference runtime of the discrete MIL controller (report Section 6.5 Step 6, Figures 7.8-7.11).

:class:`MILRuntime` is the object the virtual lab steps and the code
generators render: the controller ``u = H_uz z_vs + H_uw w`` in delta form
with compensated state accumulation (:mod:`impedance_mil.implement.kernels`),
optionally preceded, inside the same loop, by one RK3 step of a virtual
system as in the RMC programs of Figures 7.9-7.11:

1. ``z_vs`` from the VS state at the start of the loop (``(w - F)/m_vs``);
2. advance the VS state by one RK3 step with ``a_g`` and ``w`` held;
3. ``u = C_z x_z + D_z z_vs + C_w x_w + D_w w``  [in];
4. advance the controller states with ``z_vs`` and ``w`` (the report's programs
   use ``a_g`` here, an erratum: see docs/errata.md).

Precision: ``"single"`` stores every array in float32 and the controller
arithmetic is float32 throughout (bit-identical to the generated C with
``float``); ``"double"`` uses float64.  The VS enters the step as its tick
(:mod:`impedance_mil.implement.vs_tick`: z_vs, then one RK3 step), compiled
for state arrays of the same dtype; the step itself knows no VS kinds.  No
step allocates.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numba
import numpy as np

from ..errors import ConfigError
from ..virtual.system import DefinedVS
from .discretization import DiscreteController
from .kernels import controller_run, controller_step, controller_step_parts
from .vs_tick import VSArrays, no_vs_tick, vs_tick_function

#: Precisions understood by the runtime and the generators, and their dtypes.
PRECISIONS = {"single": np.float32, "double": np.float64}


def precision_dtype(precision: str):
    """numpy dtype of ``"single"`` or ``"double"``."""
    if precision not in PRECISIONS:
        raise ConfigError("precision", "'single' or 'double'", precision)
    return PRECISIONS[precision]


@dataclass(frozen=True)
class MILStep:
    """Outputs of one MIL loop.

    Attributes
    ----------
    u : float
        Displacement command to the table [in].
    z_vs : float
        Target basemat acceleration computed by the VS [in/s**2].
    u_w : float
        Feedback part of ``u`` (the H_uw channel's output) [in].
    """

    u: float
    z_vs: float
    u_w: float = 0.0


@dataclass(frozen=True, eq=False)
class MILTrace:
    """Histories of a run of :meth:`MILRuntime.run_mil`.

    Attributes
    ----------
    u : ndarray
        Displacement command [in] per loop.
    z_vs : ndarray
        Target acceleration [in/s**2] per loop.
    """

    u: np.ndarray
    z_vs: np.ndarray


class ControllerArrays(NamedTuple):
    """The controller's arrays for the compiled kernels, in the runtime dtype.

    ``m_z``, ``m_w``: system matrices ``[[A - I, B], [C, D]]`` of H_uz and H_uw;
    ``s_z``, ``s_w``: states and compensations (2, n), updated in place;
    ``tmp``: scratch (>= max(n_z, n_w, 1)); ``compensated``: Kahan accumulation
    (:mod:`impedance_mil.implement.kernels`).
    """

    m_z: np.ndarray
    m_w: np.ndarray
    s_z: np.ndarray
    s_w: np.ndarray
    tmp: np.ndarray
    compensated: bool


@numba.njit(cache=True, nogil=True, inline="always")
def mil_step_kernel(ctrl, vs_tick, vs, dt, a_g, w):
    """One MIL loop of Figure 7.9 (corrected): the VS tick, then the controller.

    Parameters
    ----------
    ctrl : ControllerArrays
        The controller (states updated in place).
    vs_tick : VSTick
        The VS slot (:mod:`impedance_mil.implement.vs_tick`): z_vs from the
        state at the start of the loop, then one RK3 step of the state.
    vs : VSArrays
        The VS parameters, state (updated in place) and RK3 work space.
    dt : float
        Loop time [s].
    a_g : float
        Ground acceleration [in/s**2].
    w : float
        Measured force [lbf].

    Returns
    -------
    tuple of float
        ``(u [in], z_vs [in/s**2], u_w [in])`` in the controller's dtype
        (``u_w``, the feedback part of ``u``, for the virtual lab's records).
    """
    # Inputs are rounded to the controller's dtype through its scratch vector, so
    # that the tick receives exactly the arguments of its signature.
    tmp = ctrl.tmp
    tmp[0] = a_g
    ag = tmp[0]
    tmp[0] = w
    wv = tmp[0]
    tmp[0] = dt
    h = tmp[0]
    z = vs_tick(vs.params, vs.x, ag, wv, h, vs.work)
    tmp[0] = z
    z = tmp[0]
    u, u_w = controller_step_parts(ctrl.m_z, ctrl.m_w, ctrl.s_z, ctrl.s_w, tmp, z, wv, ctrl.compensated)
    return u, z, u_w


@numba.njit(cache=True, nogil=True)
def mil_run_kernel(ctrl, vs_tick, vs, dt, a_g, w, u, z_vs):
    """:func:`mil_step_kernel` over whole records ``a_g``, ``w``; writes ``u`` and ``z_vs``."""
    for k in range(a_g.shape[0]):
        u[k], z_vs[k], _ = mil_step_kernel(ctrl, vs_tick, vs, dt, a_g[k], w[k])


class MILRuntime:
    """The discrete MIL controller (and optionally its VS) stepped loop by loop.

    Parameters
    ----------
    controller : DiscreteController
        From :func:`~impedance_mil.implement.discretize`.
    vs : VirtualSystem, optional
        The virtual system; needed by :meth:`mil_step`.  A VS of a defined type
        (:class:`~impedance_mil.virtual.system.DefinedVS`, built-in or the user's
        own definition) is stepped by its generated kernel; one written as Python
        methods (:class:`~impedance_mil.virtual.base.PythonVS`) through those methods
        (same sequence, ~100x slower, and not renderable by the code generators).
    precision : {"single", "double"}
        Arithmetic of the controller (float32 as on the RMC75E, or float64).
    compensated : bool
        Kahan-compensated state accumulation (default; ``False`` only to
        quantify what it buys).

    Attributes
    ----------
    m_z, m_w : ndarray
        System matrices ``[[A - I, B], [C, D]]`` in the runtime dtype.
    s_z, s_w : ndarray
        States and compensations, shape (2, n).
    controller_arrays : ControllerArrays
        The controller's arrays (the same arrays) as the compiled kernels take them.
    vs_tick : VSTick
        The VS slot of the compiled MIL step (a placeholder without a compiled VS).
    vs_arrays : VSArrays
        The VS parameters, state and RK3 work space, in the runtime dtype.

    Examples
    --------
    >>> rt = MILRuntime(controller, precision="single")   # doctest: +SKIP
    >>> u = rt.step(z_vs=12.0, w=-150.0)                  # doctest: +SKIP
    """

    def __init__(
        self, controller: DiscreteController, vs=None, precision: str = "single", compensated: bool = True
    ):
        self.controller = controller
        self.precision = precision
        self.dtype = precision_dtype(precision)
        self.compensated = bool(compensated)
        self.m_z = controller.z.system_matrix().astype(self.dtype)
        self.m_w = controller.w.system_matrix().astype(self.dtype)
        self.s_z = np.zeros((2, controller.z.n_states), self.dtype)
        self.s_w = np.zeros((2, controller.w.n_states), self.dtype)
        self.tmp = np.zeros(max(controller.z.n_states, controller.w.n_states, 1), self.dtype)
        self.vs = vs
        n_vs = vs.n_states if vs is not None else 0
        self.vs_params = (
            vs.parameter_array().astype(self.dtype) if isinstance(vs, DefinedVS) else np.zeros(0, self.dtype)
        )
        self.x_vs = np.zeros(n_vs, float if self.python_vs else self.dtype)
        self.work = np.zeros(4 * max(n_vs, 1), self.dtype)
        self.vs_tick = (
            vs_tick_function(vs, self.dtype) if isinstance(vs, DefinedVS) else no_vs_tick(self.dtype)
        )
        self.controller_arrays = ControllerArrays(
            self.m_z, self.m_w, self.s_z, self.s_w, self.tmp, self.compensated
        )
        self.vs_arrays = VSArrays(
            self.vs_params, self.x_vs if not self.python_vs else np.zeros(0, self.dtype), self.work
        )
        self.reset()

    @property
    def python_vs(self) -> bool:
        """True for a VS written as Python methods: it has no kernel, so :meth:`mil_step` calls
        the object (float64 state, the VS's own Python arithmetic); the controller is the same."""
        return self.vs is not None and not isinstance(self.vs, DefinedVS)

    @property
    def loop_time_s(self) -> float:
        """Loop time [s]."""
        return self.controller.loop_time_s

    def reset(self) -> None:
        """Zero the controller states; put the VS at its initial state."""
        self.s_z[:] = 0
        self.s_w[:] = 0
        if self.vs is not None:
            self.x_vs[:] = np.asarray(self.vs.initial_state(), float)

    def step(self, z_vs: float, w: float) -> float:
        """One controller loop: displacement command ``u`` [in] from ``z_vs`` [in/s**2], ``w`` [lbf]."""
        return float(
            controller_step(
                self.m_z, self.m_w, self.s_z, self.s_w, self.tmp, float(z_vs), float(w), self.compensated
            )
        )

    def step_parts(self, z_vs: float, w: float) -> tuple[float, float]:
        """:meth:`step` returning ``(u, u_w)`` [in]: the command and its feedback part."""
        u, u_w = controller_step_parts(
            self.m_z, self.m_w, self.s_z, self.s_w, self.tmp, float(z_vs), float(w), self.compensated
        )
        return float(u), float(u_w)

    def mil_step(self, a_g: float, w: float) -> MILStep:
        """One MIL loop: VS (RK3) then controller, from ``a_g`` [in/s**2] and ``w`` [lbf]."""
        if self.vs is None:
            raise ConfigError("vs", "a virtual system for mil_step (MILRuntime(controller, vs=...))")
        if self.python_vs:
            return self._python_mil_step(float(a_g), float(w))
        u, z_vs, u_w = mil_step_kernel(
            self.controller_arrays, self.vs_tick, self.vs_arrays, self.loop_time_s, float(a_g), float(w)
        )
        return MILStep(float(u), float(z_vs), float(u_w))

    def _python_mil_step(self, a_g: float, w: float) -> MILStep:
        """:meth:`mil_step` for a user-defined VS: the same sequence as the kernel, in Python.

        Inputs and ``z_vs`` are rounded to the runtime dtype, as in the kernel (so that
        :meth:`run_mil`, whose records are in that dtype, gives the same numbers).
        """
        a_g, w = float(self.dtype(a_g)), float(self.dtype(w))
        z_vs = float(self.dtype(self.vs.outputs(self.x_vs, a_g, w).z_vs))
        self.x_vs[:] = self.vs.step_rk3(self.x_vs, a_g, w, self.loop_time_s)
        u, u_w = self.step_parts(z_vs, w)
        return MILStep(u, z_vs, u_w)

    def run(self, z_vs, w) -> np.ndarray:
        """Step over records ``z_vs`` [in/s**2] and ``w`` [lbf]; return ``u`` [in] (runtime dtype)."""
        zz, ww = self._records(z_vs, w)
        u = np.empty(zz.size, self.dtype)
        controller_run(self.m_z, self.m_w, self.s_z, self.s_w, self.tmp, zz, ww, self.compensated, u)
        return u

    def run_mil(self, a_g, w) -> MILTrace:
        """:meth:`mil_step` over records ``a_g`` [in/s**2] and ``w`` [lbf]."""
        if self.vs is None:
            raise ConfigError("vs", "a virtual system for run_mil (MILRuntime(controller, vs=...))")
        aa, ww = self._records(a_g, w)
        u = np.empty(aa.size, self.dtype)
        z = np.empty(aa.size, self.dtype)
        if self.python_vs:
            for k in range(aa.size):
                step = self._python_mil_step(float(aa[k]), float(ww[k]))
                u[k], z[k] = step.u, step.z_vs
            return MILTrace(u, z)
        mil_run_kernel(self.controller_arrays, self.vs_tick, self.vs_arrays, self.loop_time_s, aa, ww, u, z)
        return MILTrace(u, z)

    def _records(self, a, b) -> tuple[np.ndarray, np.ndarray]:
        # Writable copies: numba compiles a kernel once per argument type, and a read-only
        # array (a broadcast record, a GroundMotion's samples) is another type.
        a = np.array(a, dtype=self.dtype).ravel()
        return a, np.array(np.broadcast_to(np.asarray(b, dtype=self.dtype), a.shape))
