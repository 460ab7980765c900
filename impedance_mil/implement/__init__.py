"""Implementation: discretization, runtime controller, code generators (report Sections 6.5, 7).

>>> from impedance_mil.implement import discretize, DiscreteController, MILRuntime
"""

from .discretize import ChannelRealization, DiscreteController, discretize, with_leak
from .runtime import MILRuntime, MILStep, MILTrace, mil_step_kernel, precision_dtype

__all__ = [
    "ChannelRealization",
    "DiscreteController",
    "MILRuntime",
    "MILStep",
    "MILTrace",
    "discretize",
    "mil_step_kernel",
    "precision_dtype",
    "with_leak",
]
