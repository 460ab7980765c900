"""Characterize the shake table: linear model, tuning, valve fit (report Section 4).

>>> from impedance_mil.plant import TableParameters, LinearTable
>>> tbl = LinearTable(TableParameters.report_default())
>>> tbl.is_stable()
True
"""

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
