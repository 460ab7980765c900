"""Linear spring-damper isolation system, SD (report Section 5.3, Eq 5-1 and 5-2; Table 9.1).

``m_vs z_vs = w - F`` with the isolator force ``F = k_s x + c v`` (Eq 5-1,
corrected: docs/errata.md), ``x`` and ``v`` the basemat displacement and
velocity relative to the ground.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...units import INTERNAL_UNITS, TWO_PI
from ..base import nonnegative, positive
from ..definition import Derived, Parameter, VSDefinition
from ..system import DefinedVS
from ..targets import BASEMAT_MASS, MASS_FIELDS, TEST_ARTICLE_WEIGHT, total_mass
from ..vstype import VSType

ORDER = 10

DEFINITION = VSDefinition(
    kind="SD",
    title="linear spring-damper isolation system",
    source="report Section 5.3, Eq 5-1, 5-2 (corrected, docs/errata.md)",
    parameters=(
        Parameter("m_vs", INTERNAL_UNITS["mass"], "Mass of the basemat"),
        Parameter("k_s", "force_pound / inch", "Post-elastic (horizontal) stiffness"),
        Parameter("c", "force_pound * second / inch", "Damping coefficient", "nonnegative"),
    ),
    states=("x", "v"),
    state_units=("inch", "inch / second"),
    intermediates=(("F", "k_s*x + c*v"),),
    rates={"x": "v", "v": "(w - k_s*x - c*v)/m_vs - a_g"},
    outputs={"z_vs": "(w - F)/m_vs", "force": "F"},
    derived=(
        Derived("f_vs", "sqrt(k_s/m_vs)/two_pi", "hertz", "Frequency of the basemat alone"),
        Derived("zeta_vs", "c/(2.0*sqrt(k_s*m_vs))", "dimensionless", "Damping ratio of the basemat alone"),
    ),
    kinematics=("x", "v"),
    reference={"m_vs": 5.18, "k_s": 895.0, "c": 57.0},
)


@dataclass(frozen=True)
class SDTargets:
    """Spring-damper targets (Section 9.2, Table 9.1).

    Parameters
    ----------
    f : float
        Target frequency of the isolated article [Hz].
    zeta : float
        Target damping ratio (fraction of critical).
    m_vs : float
        Basemat mass [lbf*s**2/in].
    w_ps : float
        Test-article weight [lbf].
    """

    f: float
    zeta: float
    m_vs: float = BASEMAT_MASS
    w_ps: float = TEST_ARTICLE_WEIGHT

    kind = "SD"

    def build(self) -> DefinedVS:
        """``k_s = (2*pi*f)**2*M``, ``c = 2*zeta*sqrt(k_s*M)``, ``M = m_vs + w_ps/G0``."""
        M = total_mass(self.m_vs, self.w_ps)
        positive("f", self.f)
        nonnegative("zeta", self.zeta)
        k_s = (TWO_PI * self.f) ** 2 * M
        return DefinedVS(
            DEFINITION, {"m_vs": self.m_vs, "k_s": k_s, "c": 2.0 * self.zeta * math.sqrt(k_s * M)}
        )


TYPE = VSType(
    DEFINITION,
    targets=SDTargets,
    target_fields=(
        Parameter("f", "hertz", "Target frequency"),
        Parameter("zeta", "dimensionless", "Target damping ratio", "nonnegative"),
        *MASS_FIELDS,
    ),
    target_only=frozenset({"f", "zeta"}),
    presets={  # Table 9.1: f [Hz], zeta
        "SD1": SDTargets(f=0.75, zeta=0.30),
        "SD2": SDTargets(f=1.25, zeta=0.25),
        "SD3": SDTargets(f=1.75, zeta=0.20),
    },
)
