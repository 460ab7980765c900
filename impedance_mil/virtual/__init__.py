"""Virtual systems the table imitates: SD, LR, FP, TFP and user-defined types (report Section 5).

Each type is written once, as a :class:`~impedance_mil.virtual.definition.VSDefinition`
in a module of :mod:`impedance_mil.virtual.types` (or in a user's file, see
:mod:`impedance_mil.virtual.registry`); its compiled kernels, linear part,
describing function and generated C/ST code are derived from it.  See
``docs/virtual.md``.
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

if TYPE_CHECKING:  # what the names are; each is imported on first use (below)
    from . import presets
    from .base import LinearPart, PythonVS, VirtualSystem, VSOutput, VSResponse
    from .codegen import CompiledVS, compiled
    from .definition import Derived, Parameter, Rule, VSDefinition, VSDefinitionError
    from .models import FrictionPendulum, LeadRubber, SpringDamper
    from .registry import BUILTIN, get_type, kinds, load_type_file
    from .system import DefinedVS
    from .targets import BASEMAT_MASS, TEST_ARTICLE_WEIGHT
    from .types.friction_pendulum import FPTargets
    from .types.lead_rubber import LRTargets
    from .types.spring_damper import SDTargets
    from .vstype import VSType

__all__ = [
    "presets",
    "VirtualSystem",
    "DefinedVS",
    "PythonVS",
    "VSOutput",
    "VSResponse",
    "LinearPart",
    "VSDefinition",
    "VSDefinitionError",
    "VSType",
    "Parameter",
    "Derived",
    "Rule",
    "CompiledVS",
    "compiled",
    "BUILTIN",
    "kinds",
    "get_type",
    "load_type_file",
    "SpringDamper",
    "LeadRubber",
    "FrictionPendulum",
    "SDTargets",
    "LRTargets",
    "FPTargets",
    "BASEMAT_MASS",
    "TEST_ARTICLE_WEIGHT",
]

# Each name's submodule, imported when the name is first read (PEP 562, impedance_mil/lazy.py):
# the presets and definitions do not import numba and the generated kernels.
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "base": ("LinearPart", "PythonVS", "VirtualSystem", "VSOutput", "VSResponse"),
        "codegen": ("CompiledVS", "compiled"),
        "definition": ("Derived", "Parameter", "Rule", "VSDefinition", "VSDefinitionError"),
        "models": ("FrictionPendulum", "LeadRubber", "SpringDamper"),
        "registry": ("BUILTIN", "get_type", "kinds", "load_type_file"),
        "system": ("DefinedVS",),
        "targets": ("BASEMAT_MASS", "TEST_ARTICLE_WEIGHT"),
        "types.friction_pendulum": ("FPTargets",),
        "types.lead_rubber": ("LRTargets",),
        "types.spring_damper": ("SDTargets",),
        "vstype": ("VSType",),
    },
    submodules=("presets",),
)
