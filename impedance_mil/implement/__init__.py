"""Implementation: discretization, runtime controller, code generators (report Sections 6.5, 7).

>>> from impedance_mil.implement import discretize, DiscreteController, MILRuntime
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

# ``discretize`` is also its submodule's name: it cannot be lazy (impedance_mil/lazy.py).
from .discretize import ChannelRealization, DiscreteController, discretize, with_leak

if TYPE_CHECKING:  # what the names are; each is imported on first use (below)
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

# Each name's submodule, imported when the name is first read (PEP 562, impedance_mil/lazy.py):
# ``from impedance_mil.implement import MILRuntime`` imports the numba runtime, not before.
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "runtime": ("MILRuntime", "MILStep", "MILTrace", "mil_step_kernel", "precision_dtype"),
    },
)
