"""The report's three isolation systems by name (Section 5): SD, LR and FP.

Each name is the :class:`~impedance_mil.virtual.vstype.VSType` of its
definition in :mod:`impedance_mil.virtual.types`; calling it builds a system
from parameter values, e.g. ``SpringDamper(m_vs=2000/G0, k_s=894.0, c=57.0)``.
"""

from __future__ import annotations

from .registry import BUILTIN

#: Linear spring-damper (Section 5.3).
SpringDamper = BUILTIN["SD"]
#: Lead-rubber with Bouc-Wen hysteresis (Section 5.4).
LeadRubber = BUILTIN["LR"]
#: Single concave Friction Pendulum (Section 5.5).
FrictionPendulum = BUILTIN["FP"]
