"""MIL controller design: controller forms, filters, constraints I/II/III (report Sections 6, 8.1, 9.4).

>>> from impedance_mil.plant import TableParameters
>>> from impedance_mil.design import design_controller, table_model
>>> d = design_controller(table_model(TableParameters.report_default()), form="tracking",
...                       fc_hz=80.0, emit_warnings=False)
>>> d.H_uz.is_proper, d.filter.order_z
(True, 3)

Sign convention: ``u = H_uz*r + H_uw*w [+ H_ufh*f_h]``, every path added;
``r`` is ``z_vs`` for the standardized form and ``a_g`` otherwise.
"""

from .adapters import table_model, virtual_model
from .constraints import (
    HALF_POWER_ERROR,
    ConstraintResult,
    ControlledTable,
    DesignCriteria,
    controlled_table,
    evaluate_constraints,
)
from .controller import ControllerDesign, FilterSpec, design_controller, filter_controller
from .coupled import CoupledStability, closed_loop_poles, coupled_stability
from .filters import FAMILIES, LowpassFilter, apply_filter, required_order
from .forms import FORMS, IdealController, TableModel, VirtualModel, ideal_controller
from .io import load_design, save_design
from .linearize import EquivalentLinearization, HarmonicCycle, equivalent_linearization, harmonic_cycle
from .passivity import PassivityResult, delay_model_tolerance_deg, passivity

__all__ = [
    "CoupledStability",
    "EquivalentLinearization",
    "HarmonicCycle",
    "closed_loop_poles",
    "coupled_stability",
    "equivalent_linearization",
    "harmonic_cycle",
    "FAMILIES",
    "FORMS",
    "HALF_POWER_ERROR",
    "ConstraintResult",
    "ControlledTable",
    "ControllerDesign",
    "DesignCriteria",
    "FilterSpec",
    "IdealController",
    "LowpassFilter",
    "PassivityResult",
    "TableModel",
    "VirtualModel",
    "apply_filter",
    "controlled_table",
    "delay_model_tolerance_deg",
    "design_controller",
    "evaluate_constraints",
    "filter_controller",
    "ideal_controller",
    "load_design",
    "passivity",
    "required_order",
    "save_design",
    "table_model",
    "virtual_model",
]
