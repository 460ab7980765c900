"""How many RK4 substeps per loop: an accuracy rule from the coupled plant's fastest eigenvalue.

Between two controller ticks the lab integrates the continuous plant --
nonlinear table with the valve current held, coupled with the specimen's
state space (the digital hydraulic loop is open over the step) -- with
classical RK4.  One RK4 step of size ``h`` multiplies a mode
``exp(lambda t)`` by the stability polynomial

    R(q) = 1 + q + q^2/2 + q^3/6 + q^4/24,  q = lambda h,

instead of ``exp(q)``.  For an oscillatory mode, ``q = i theta`` with
``theta = omega h``, the one-step relative error ``|R(i theta) exp(-i theta) - 1|``
contains the amplitude error ``1 - |R(i theta)|`` (``|R|^2 = 1 - theta^6/72 +
theta^8/576``, so about ``theta^6/144``) and the phase error ``theta - arg R``
(about ``theta^5/120``).  :data:`RK4_STEP_TOLERANCE` bounds it at every
substep; :data:`RK4_STEP_BOUND` is the largest ``theta`` that meets it
(0.655: amplitude error 5.2e-4 and phase error 8.6e-4 rad per substep,
8.2e-3 rad per cycle, i.e. 1.3e-3 relative frequency error).  The rule is
``n = ceil(max|lambda| T / RK4_STEP_BOUND)`` with ``lambda`` the eigenvalues
of the plant linearized at equilibrium (:func:`coupled_state_matrix`) and
``T`` the loop time.  ``docs/lab.md`` has the derivation and the numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.optimize

from ..errors import ConfigError
from ..plant.nonlinear import IX_V, N_TABLE_STATES
from ..specimens.arrays import specimen_state_space
from .lti_plant import LTIVirtualTable

#: Largest one-step relative error ``|R(i theta) exp(-i theta) - 1|`` of RK4 allowed
#: for the plant's fastest (oscillatory) mode.
RK4_STEP_TOLERANCE = 1e-3


def rk4_factor(q):
    """RK4's one-step amplification ``R(q) = 1 + q + q^2/2 + q^3/6 + q^4/24`` (q = lambda h)."""
    return 1.0 + q + q * q / 2.0 + q**3 / 6.0 + q**4 / 24.0


def rk4_oscillation_error(theta: float) -> float:
    """One-step relative error of RK4 on an undamped mode, ``|R(i theta) e^(-i theta) - 1|``.

    ``theta = omega h`` [rad], the mode's angular frequency times the substep.
    """
    q = 1j * theta
    return float(abs(rk4_factor(q) * np.exp(-q) - 1.0))


#: Largest ``|lambda| h`` [rad] whose RK4 step error is :data:`RK4_STEP_TOLERANCE` (0.655).
RK4_STEP_BOUND = float(
    scipy.optimize.brentq(
        lambda theta: rk4_oscillation_error(theta) - RK4_STEP_TOLERANCE, 0.05, 2.0, xtol=1e-12
    )
)


@dataclass(frozen=True)
class SubstepChoice:
    """RK4 substeps per loop chosen from the fastest eigenvalue of the coupled plant.

    Attributes
    ----------
    substeps : int
        Substeps per loop.
    fastest_rad_s : float
        Largest eigenvalue magnitude of the linearized coupled plant [rad/s].
    theta : float
        ``fastest_rad_s * loop_time / substeps`` [rad], at most :data:`RK4_STEP_BOUND`.
    step_error : float
        RK4's one-step relative error of an undamped mode at ``theta``.
    """

    substeps: int
    fastest_rad_s: float
    theta: float
    step_error: float

    def to_dict(self) -> dict:
        """Plain entries for a run's configuration."""
        return {
            "substeps": self.substeps,
            "fastest_eigenvalue_rad_s": self.fastest_rad_s,
            "rk4_theta": self.theta,
            "rk4_step_error": self.step_error,
            "rk4_step_bound": RK4_STEP_BOUND,
            "rk4_step_tolerance": RK4_STEP_TOLERANCE,
        }


def coupled_state_matrix(table, specimen=None) -> np.ndarray:
    """State matrix of the table + specimen linearized at equilibrium, valve current held.

    The table's linearization with the current as input
    (:meth:`~impedance_mil.plant.nonlinear.NonlinearTable.linearize`,
    ``continuous_feedback=False``: the digital loop is open between ticks)
    is coupled with the specimen ``x_s' = A_s x_s + B_s z``, ``w = C_s x_s +
    D_s z``; the algebraic loop ``z = c_z x_t + b_z w`` is solved for z.
    States as in the lab loop: six table states, then the specimen's.  An
    :class:`~impedance_mil.lab.lti_plant.LTIVirtualTable` gives its coupled
    model's (:meth:`~impedance_mil.lab.lti_plant.LTIVirtualTable.coupled`).
    Units: rad/s (rows are the derivatives in each state's unit per second).
    """
    if isinstance(table, LTIVirtualTable):
        return table.coupled(*specimen_state_space(specimen)).system.A
    lin = table.linearize(continuous_feedback=False)
    c_z, _, b_z = lin.C["z"]
    As, Bs, Cs, Ds = specimen_state_space(specimen)
    m = Bs.size
    denom = 1.0 - b_z * Ds
    # z = (c_z x_t + b_z C_s x_s) / (1 - b_z D_s)
    z_row = np.concatenate([c_z, b_z * Cs]) / denom
    w_row = np.concatenate([np.zeros(N_TABLE_STATES), Cs]) + Ds * z_row
    a = np.zeros((N_TABLE_STATES + m, N_TABLE_STATES + m))
    a[:N_TABLE_STATES, :N_TABLE_STATES] = lin.A
    a[:N_TABLE_STATES] += np.outer(lin.B_w, w_row)
    a[IX_V] = z_row  # dv/dt = z exactly (B_w's v entry is b_z)
    a[N_TABLE_STATES:, N_TABLE_STATES:] = As
    a[N_TABLE_STATES:] += np.outer(Bs, z_row)
    return a


def choose_substeps(table, specimen=None) -> SubstepChoice:
    """Smallest RK4 substep count with ``max|lambda| T / n <= RK4_STEP_BOUND``.

    Parameters
    ----------
    table : NonlinearTable or LTIVirtualTable
        The virtual table (``loop_time`` T [s]).
    specimen : object, optional
        Test article with ``state_space()`` (or a state space); ``None`` for the bare table.
    """
    fastest = float(np.max(np.abs(np.linalg.eigvals(coupled_state_matrix(table, specimen)))))
    n = max(1, math.ceil(fastest * table.loop_time / RK4_STEP_BOUND))
    theta = fastest * table.loop_time / n
    return SubstepChoice(n, fastest, theta, rk4_oscillation_error(theta))


def resolve_substeps(substeps, table, specimen=None) -> tuple[int, dict]:
    """Substeps per loop and their configuration entries for ``substeps`` = ``"auto"`` or an int.

    Returns ``(n, entries)``; ``entries`` has ``substeps`` (n),
    ``substeps_rule`` (``"auto"`` or ``"explicit"``) and, for ``"auto"``, the
    eigenvalue and error of :class:`SubstepChoice`.
    """
    if isinstance(substeps, str):
        if substeps != "auto":
            raise ConfigError("substeps", "'auto' or a positive number of RK4 substeps", substeps)
        choice = choose_substeps(table, specimen)
        return choice.substeps, {**choice.to_dict(), "substeps_rule": "auto"}
    if isinstance(substeps, bool) or not isinstance(substeps, (int, np.integer)) or substeps < 1:
        raise ConfigError("substeps", "'auto' or a positive number of RK4 substeps", substeps)
    return int(substeps), {"substeps": int(substeps), "substeps_rule": "explicit"}


__all__ = [
    "RK4_STEP_BOUND",
    "RK4_STEP_TOLERANCE",
    "SubstepChoice",
    "choose_substeps",
    "coupled_state_matrix",
    "resolve_substeps",
    "rk4_factor",
    "rk4_oscillation_error",
    "specimen_state_space",
]
