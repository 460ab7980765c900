"""Implementation: discretization, runtime controller, code generators (report Sections 6.5, 7).

>>> from impedance_mil.implement import discretize, DiscreteController, MILRuntime
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

if TYPE_CHECKING:  # what the names are; each is imported on first use (below)
    from .discretization import ChannelRealization, DiscreteController, discretize, with_leak
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
        # the module is `discretization`, not `discretize`: a function named like its own
        # submodule could not be lazy (impedance_mil/lazy.py), and a lab file's reader, which
        # needs implement.io_units only, would import the discretization and the design package.
        "discretization": ("ChannelRealization", "DiscreteController", "discretize", "with_leak"),
        "runtime": ("MILRuntime", "MILStep", "MILTrace", "mil_step_kernel", "precision_dtype"),
    },
)
