"""The linear table model taken from the nonlinear virtual table, with its optional dynamics (issue 17).

Eq 4-11 (:func:`impedance_mil.plant.statespace.plant_state_space`) knows none of the
dynamics of :mod:`impedance_mil.plant.table_dynamics`.  :func:`linearized_plant`
differentiates the virtual table's kernel instead (:meth:`NonlinearTable.linearize
<impedance_mil.plant.nonlinear.NonlinearTable.linearize>`) and returns it in the
coordinates of Eq 4-11, so that the same loop closure and delay treatments apply
(:func:`impedance_mil.plant.linear.closed_loop_state_space` with ``open_loop``); the
design takes it through :func:`impedance_mil.design.adapters.table_model` with
``linearized=True``.

Linearized at rest (``x = v = 0``, spool closed, ``P_1 = P_2 = (P_s + P_R)/2``):

* the Coulomb friction, with its pressure terms, is left out (zero slope): the smoothed
  sign law's slope at rest, ``F_c / v_s`` (400 lbf*s/in for 8 lbf and 0.02 in/s), is an
  artifact of the smoothing, not damping the table shows at test amplitudes; the viscous
  term is the table's platen damping (0 when not given, as in Eq 4-11);
* the spool rate limit is inactive (its saturation has slope 1 at 0);
* the compliant mount stays: the oil column and the mount act in series.

Without dynamics the model equals Eq 4-11 (tested to 1e-6 over 0.1-200 Hz).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import ConfigError
from .nonlinear import IX_P1, IX_P2, IX_S, IX_SD, IX_V, IX_X, Friction, NonlinearTable
from .parameters import TableParameters
from .statespace import TableStateSpace, plant_states

#: Largest coupling [relative to the largest entry] of the pressure-sum mode with the other
#: states that :func:`linearized_plant` drops it over (exactly 0 at mid-stroke rest).
SUM_MODE_COUPLING = 1e-9


def linearized_plant(p: TableParameters) -> TableStateSpace:
    """Open-loop model (input u_i [mA], force w [lbf]) of the virtual table linearized at rest.

    Parameters
    ----------
    p : TableParameters
        The table, with its optional ``dynamics``.

    Returns
    -------
    TableStateSpace
        States ``x, v, dp, spool[, spool_rate]`` as Eq 4-11's
        (:func:`~impedance_mil.plant.statespace.plant_states`), outputs ``z, x, v, dp``.

    Raises
    ------
    ConfigError
        The pressure-sum mode does not decouple (it does at rest at mid-stroke).
    """
    friction = Friction(coulomb=0.0, viscous=p.platen_damping or 0.0)
    table = NonlinearTable.from_linear(p, friction=friction)
    dyn = table.dynamics
    if dyn is not None:  # Coulomb terms have zero slope here (module docstring)
        table = replace(table, dynamics=replace(dyn, pressure_friction=0.0, load_pressure_friction=0.0))
    lin = table.linearize(continuous_feedback=False)
    n6 = lin.A.shape[0]
    # coordinates (x, v, dp, sum, s, sd): P1 = (sum + dp)/2, P2 = (sum - dp)/2
    T = np.eye(n6)
    T[IX_P1, IX_P1], T[IX_P1, IX_P2] = 1.0, -1.0
    T[IX_P2, IX_P1], T[IX_P2, IX_P2] = 1.0, 1.0
    Ti = np.linalg.inv(T)
    A = T @ lin.A @ Ti
    B_u, B_w = T @ lin.B_u, T @ lin.B_w
    z_row = lin.C["z"][0] @ Ti
    sum_ix = IX_P2
    others = [i for i in range(n6) if i != sum_ix]
    coupling = max(np.abs(A[sum_ix, others]).max(), np.abs(A[others, sum_ix]).max(), abs(z_row[sum_ix]))
    if coupling > SUM_MODE_COUPLING * np.abs(A).max():
        raise ConfigError("table", "a table whose pressure-sum mode decouples at rest", coupling)
    order = table.valve_dynamics.order
    keep = [IX_X, IX_V, IX_P1, IX_S, IX_SD] if order == 2 else [IX_X, IX_V, IX_P1, IX_SD]
    sel = np.ix_(keep, keep)
    n = len(keep)
    eye = np.eye(n)
    C = {"z": z_row[keep], "x": eye[0], "v": eye[1], "dp": eye[2]}
    D = {"z": (0.0, lin.C["z"][2]), "x": (0.0, 0.0), "v": (0.0, 0.0), "dp": (0.0, 0.0)}
    return TableStateSpace.build(A[sel], B_u[keep], B_w[keep], C, D, plant_states(p), input_name="u_i")
