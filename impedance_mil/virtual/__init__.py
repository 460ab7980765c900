"""Virtual systems (isolators) the table imitates: SD, LR, FP and user-defined (report Section 5).

The dynamics live once, in the compiled kernels of
:mod:`impedance_mil.virtual.kernels`; the classes here are value objects
that call them.  See ``docs/virtual.md``.
"""

from . import kernels, presets
from .base import LinearPart, VirtualSystem, VSOutput, VSResponse
from .models import FrictionPendulum, LeadRubber, SpringDamper
from .targets import BASEMAT_MASS, TEST_ARTICLE_WEIGHT, FPTargets, LRTargets, SDTargets
from .two_storey import IsolatedTwoStorey, example_two_storey

__all__ = [
    "kernels",
    "presets",
    "VirtualSystem",
    "VSOutput",
    "VSResponse",
    "LinearPart",
    "SpringDamper",
    "LeadRubber",
    "FrictionPendulum",
    "SDTargets",
    "LRTargets",
    "FPTargets",
    "BASEMAT_MASS",
    "TEST_ARTICLE_WEIGHT",
    "IsolatedTwoStorey",
    "example_two_storey",
]
