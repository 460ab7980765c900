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

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

# ``passivity`` is also its submodule's name: it cannot be lazy (impedance_mil/lazy.py).
from .passivity import PassivityResult, delay_model_tolerance_deg, passivity

if TYPE_CHECKING:  # what the names are; each is imported on first use (below)
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

# Each name's submodule, imported when the name is first read (PEP 562, impedance_mil/lazy.py):
# reading a design's names does not import python-control with every design module.
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "adapters": ("table_model", "virtual_model"),
        "constraints": (
            "HALF_POWER_ERROR",
            "ConstraintResult",
            "ControlledTable",
            "DesignCriteria",
            "controlled_table",
            "evaluate_constraints",
        ),
        "controller": ("ControllerDesign", "FilterSpec", "design_controller", "filter_controller"),
        "coupled": ("CoupledStability", "closed_loop_poles", "coupled_stability"),
        "filters": ("FAMILIES", "LowpassFilter", "apply_filter", "required_order"),
        "forms": ("FORMS", "IdealController", "TableModel", "VirtualModel", "ideal_controller"),
        "io": ("load_design", "save_design"),
        "linearize": (
            "EquivalentLinearization",
            "HarmonicCycle",
            "equivalent_linearization",
            "harmonic_cycle",
        ),
    },
)
