"""The robust set of the optimized design: table-and-VS models as frequency-response tables.

Every model answers, at a frequency ``f`` [Hz], the responses of the table
acceleration ``z`` [in/s**2] and velocity ``v`` [in/s] to the command ``u``
[in] and the force ``w`` [lbf], the VS impedance ``Z = z_vs/w`` that closes
the standardized controller's reference path, and the complex frequency at
which the controller is evaluated.  With ``u = C_z z_vs + C_w w``::

    H_c  = P_zw + P_zu (C_w + C_z Z)      (controlled impedance, Eq 6-5)
    H_vw = P_vw + P_vu (C_w + C_z Z)      (force-velocity, Eq 9-2)

both affine in the controller's coefficients.

Two table models are built from one :class:`~impedance_mil.plant.TableParameters`:

* ``first-order``: the report's design model (``exp(-s tau) ~ 1 - s tau``,
  Eq 4-13), controller continuous, ``s = j 2 pi f``;
* ``sampled``: the exact sampled-data loop (ZOH, one-loop feedback delay,
  :mod:`impedance_mil.plant.sampled`) with the controller as its Tustin
  discretization, evaluated at the warped frequency
  ``s = j (2/T) tan(pi f T)``; the VS model is taken as continuous.  The
  responses are those at the sampling instants (first harmonic) to a
  continuous force: :class:`~impedance_mil.plant.sampled.SampledTable` holds
  ``w`` over each loop, and that hold's factor ``(1 - exp(-j w T))/(j w T)``
  (a half-sample delay the real force does not have) is divided out of the
  ``w`` paths.  The command ``u`` is held, as the controller holds it.

The sampled model contains the command hold (half a sample) that the
first-order model lacks.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ...plant import LinearTable, TableParameters
from ...plant.sampled import SampledTable
from ...units import TWO_PI
from ..constraints import target_impedance

#: Highest frequency of the sampled model as a fraction of the Nyquist frequency (Tustin's warp is infinite there).
SAMPLED_TOP_FRACTION = 0.999

#: Table models of the robust set.
TABLE_MODELS = ("first-order", "sampled")


@dataclass(frozen=True)
class LoopResponses:
    """Responses of one model at a set of frequencies (all complex arrays of the same length)."""

    P_zu: np.ndarray
    P_zw: np.ndarray
    P_vu: np.ndarray
    P_vw: np.ndarray
    Z: np.ndarray
    s_controller: np.ndarray


@dataclass(frozen=True, eq=False)
class LoopModel:
    """One member of the robust set: a table model closed with one VS target.

    Attributes
    ----------
    name : str
        ``"<table model>/<target label>"``, e.g. ``"sampled/DF 1 in"``.
    table_kind : str
        ``"first-order"`` or ``"sampled"``.
    target_label : str
        Which VS model closes ``w -> z_vs`` (``"linear"``, ``"DF 0.25 in"`` ...).
    target : object
        ``frequency_response(f_hz)`` of ``Z`` [in/s**2 per lbf] and rational ``H_zw``.
    loop_time_s : float
        Loop time [s].
    table : object
        ``LinearTable`` (first-order) or ``SampledTable``.
    """

    name: str
    table_kind: str
    target_label: str
    target: Any
    loop_time_s: float
    table: Any

    def responses(self, f_hz) -> LoopResponses:
        """The responses at ``f_hz`` [Hz]."""
        f = np.atleast_1d(np.asarray(f_hz, dtype=float))
        Z = self.target.frequency_response(f)
        if self.table_kind == "first-order":
            ss = self.table.state_space()
            s = 1j * TWO_PI * f
            P_zu = ss.tf("z", "u").frequency_response(f)
            P_zw = ss.tf("z", "w").frequency_response(f)
            return LoopResponses(P_zu, P_zw, P_zu / s, P_zw / s, Z, s)
        T = self.loop_time_s
        f = np.minimum(f, SAMPLED_TOP_FRACTION * 0.5 / T)  # Tustin's warp diverges at the Nyquist frequency
        s_c = 1j * (2.0 / T) * np.tan(np.pi * f * T)
        sm: SampledTable = self.table
        z = np.exp(1j * TWO_PI * f * T)
        # SampledTable holds w over each loop; the article's force is continuous, so the
        # hold's first-harmonic factor (1 - exp(-j w T))/(j w T) is divided out of the w paths.
        wT = TWO_PI * f * T
        hold = (1.0 - np.exp(-1j * wT)) / (1j * wT)
        return LoopResponses(
            _modal(sm, "z", "u", z),
            _modal(sm, "z", "w", z) / hold,
            _modal(sm, "v", "u", z),
            _modal(sm, "v", "w", z) / hold,
            Z,
            s_c,
        )


@dataclass(frozen=True)
class RationalTarget:
    """A rational VS impedance ``H_zw`` [in/s**2 per lbf] seen through the target interface."""

    H_zw: Any

    def frequency_response(self, f_hz) -> np.ndarray:
        return self.H_zw.frequency_response(f_hz)


def _modal(sm: SampledTable, output: str, input: str, z: np.ndarray) -> np.ndarray:
    """``c (zI - A)^-1 b + d`` of the sampled table by its eigenvalues (vectorized over ``z``)."""
    lam, V = np.linalg.eig(sm.A)
    b = sm.B_w if input == "w" else sm.B_u
    left = sm.C[output] @ V
    right = np.linalg.solve(V, b)
    d = sm.D[output][1 if input == "w" else 0]
    return d + (1.0 / (z[:, None] - lam[None, :])) @ (left * right)


def robust_set(
    params: TableParameters,
    targets: dict[str, Any],
    table_models: tuple[str, ...] = TABLE_MODELS,
) -> tuple[LoopModel, ...]:
    """Every table model closed with every VS target.

    Parameters
    ----------
    params : TableParameters
        The table (Table 4.1).
    targets : dict of str to VirtualModel or RationalTarget
        Label -> VS model; a VirtualModel's equivalent linearization (when
        present) closes the reference path, as in the filter design's
        constraints; a :class:`RationalTarget` is used as it is.
    table_models : tuple of str
        Subset of :data:`TABLE_MODELS`.
    """
    out = []
    for kind in table_models:
        table: Any = LinearTable(params, delay="first-order") if kind == "first-order" else params
        if kind == "sampled":
            table = SampledTable.from_params(params)
        for label, vm in targets.items():
            out.append(
                LoopModel(
                    f"{kind}/{label}",
                    kind,
                    label,
                    vm if isinstance(vm, RationalTarget) else target_impedance(vm, "standardized"),
                    float(params.loop_time),
                    table,
                )
            )
    return tuple(out)
