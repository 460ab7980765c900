"""Build the design's table and VS models from :mod:`impedance_mil.plant` and :mod:`impedance_mil.virtual`.

The rest of :mod:`impedance_mil.design` works on transfer functions only;
this module is the one place that knows the classes of the other packages.
"""

from __future__ import annotations

import numpy as np

from ..errors import ConfigError, UnstableSystemError
from ..plant import LinearTable, TableParameters
from ..plant.linear import closed_loop_state_space
from ..plant.lti_table import LTITable
from ..plant.table_dynamics_model import linearized_plant
from ..virtual.base import VirtualSystem
from ..virtual.registry import BUILTIN
from ..virtual.system import DefinedVS
from .forms import TableModel, VirtualModel
from .linearize import DEFAULT_AMPLITUDE_IN, DEFAULT_ARTICLE_WEIGHT_LBF, METHODS, equivalent_linearization


def table_model(
    params: TableParameters | LTITable, delay: str = "first-order", *, linearized: bool = False
) -> TableModel:
    """The design's view of a table: ``H_zu``, ``H_zw`` (Eq 4-15a, 4-15d) and the loop time.

    Parameters
    ----------
    params : TableParameters or LTITable
        Table parameters (Table 4.1), with the controller's output delay
        ``output_delay_loops`` [loops] (a lab's; 1 for the report's); or a
        table given as a linear model (:class:`~impedance_mil.plant.lti_table.LTITable`),
        whose paths are taken with the delay treatment its file states.
    delay : str
        Delay treatment of :class:`~impedance_mil.plant.LinearTable`; the
        report designs with ``"first-order"``.  Not used for an LTI table.
    linearized : bool
        Take the open-loop plant from the nonlinear virtual table linearized at
        rest, with the table's optional ``dynamics`` (issue 17:
        :func:`impedance_mil.plant.table_dynamics_model.linearized_plant`),
        instead of Eq 4-11; the loop is closed with the same ``delay``
        (``"none"``, ``"first-order"`` or ``"pade"``).  Equals Eq 4-11 for a
        table without dynamics.

    Returns
    -------
    TableModel
        For an LTI table with no ``parameters`` (there are no physical ones)
        and its stated ``capacity``, from which the generated code's limits
        come (:func:`impedance_mil.implement.safety.command_limits`).

    Raises
    ------
    UnstableSystemError
        The table loop is unstable for these parameters (physical table).
    """
    if isinstance(params, LTITable):
        return TableModel(
            params.tf("z", "u"), params.tf("z", "w"), float(params.loop_time), {}, params.capacity.stated()
        )
    if linearized:
        loop = closed_loop_state_space(params, delay, open_loop=linearized_plant(params))
        if not np.all(loop.poles().real < 0):
            raise UnstableSystemError(
                f"the linearized table loop is unstable (Ke={params.Ke:g} V/in, Kp={params.Kp:g} V/psi)"
            )
        return TableModel(loop.tf("z", "u"), loop.tf("z", "w"), float(params.loop_time), params.to_dict())
    tbl = LinearTable(params, delay=delay).require_stable()
    return TableModel(tbl.tf("z", "u"), tbl.tf("z", "w"), float(params.loop_time), params.to_dict())


def virtual_model(
    vs: VirtualSystem,
    name: str | None = None,
    *,
    linearization: str = "describing-function",
    amplitude_in: float = DEFAULT_AMPLITUDE_IN,
    article_weight_lbf: float = DEFAULT_ARTICLE_WEIGHT_LBF,
) -> VirtualModel:
    """The design's view of a VS: its linear part (Eq 5-2, 5-8, 5-13) and, if hysteretic, its linearization.

    Parameters
    ----------
    vs : VirtualSystem
    name : str, optional
        Preset name, kept for the design file.
    linearization : str
        For a VS with a nonlinear input (LR, FP): ``describing-function``
        (default), ``equivalent-viscous`` or ``open-fh`` (none: the linear part
        with ``f_h`` open, the conservative model); see
        :mod:`impedance_mil.design.linearize`.  Ignored for a linear VS.
    amplitude_in : float
        Design displacement amplitude of the isolator [in].
    article_weight_lbf : float
        Test-article weight [lbf] for the effective frequency of ``equivalent-viscous``.
    """
    if linearization not in METHODS:
        raise ConfigError("linearization", "one of " + ", ".join(METHODS), linearization)
    lp = vs.linear_part()
    eq = None
    if lp.H_zfh is not None and linearization != "open-fh":
        eq = equivalent_linearization(vs, amplitude_in, linearization, article_weight_lbf)
    definition = None
    if isinstance(vs, DefinedVS) and BUILTIN.get(vs.kind, None) is None:
        definition = vs.definition.to_dict()  # a user's type travels with the design
    return VirtualModel(
        lp.H_zag,
        lp.H_zw,
        lp.H_zfh,
        kind=str(vs.kind),
        name=name,
        parameters=vs.to_dict(),
        equivalent=eq,
        definition=definition,
    )
