"""Characterize the shake table: linear model, tuning, valve fit (report Section 4).

>>> from impedance_mil.plant import TableParameters, LinearTable
>>> tbl = LinearTable(TableParameters.report_default())
>>> tbl.is_stable()
True
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

if TYPE_CHECKING:  # what the names are; each is imported on first use (below)
    from .linear import DELAYS, LinearTable, closed_loop_state_space
    from .parameters import (
        TableParameters,
        bulk_modulus_from_frequency,
        default_table_path,
        model_constant_d,
        oil_column_damping,
        oil_column_frequency,
    )
    from .sampled import DiscreteTransferFunction, SampledTable
    from .statespace import INPUTS, OUTPUTS, TableStateSpace, plant_state_space
    from .valve import ValveCurve, ValveFit, fit_valve_poles, read_valve_curve

__all__ = [
    "DELAYS",
    "INPUTS",
    "OUTPUTS",
    "DiscreteTransferFunction",
    "LinearTable",
    "SampledTable",
    "TableParameters",
    "TableStateSpace",
    "bulk_modulus_from_frequency",
    "closed_loop_state_space",
    "default_table_path",
    "model_constant_d",
    "oil_column_damping",
    "oil_column_frequency",
    "plant_state_space",
    "ValveCurve",
    "ValveFit",
    "fit_valve_poles",
    "read_valve_curve",
]

# Each name's submodule, imported when the name is first read (PEP 562, impedance_mil/lazy.py):
# ``from impedance_mil.plant import TableParameters`` does not import python-control.
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "linear": ("DELAYS", "LinearTable", "closed_loop_state_space"),
        "parameters": (
            "TableParameters",
            "bulk_modulus_from_frequency",
            "default_table_path",
            "model_constant_d",
            "oil_column_damping",
            "oil_column_frequency",
        ),
        "sampled": ("DiscreteTransferFunction", "SampledTable"),
        "statespace": ("INPUTS", "OUTPUTS", "TableStateSpace", "plant_state_space"),
        "valve": ("ValveCurve", "ValveFit", "fit_valve_poles", "read_valve_curve"),
    },
)
