"""Lead-rubber bearings with Bouc-Wen hysteresis, LR (report Section 5.4, Eq 5-3 to 5-8; Table 9.2).

Isolator force ``F = alpha k_i x + c v + q_d h`` (Eq 5-3) with the hysteretic
variable ``h`` of Eq 5-4 (written with ``|h|``):
``dh/dt = v/u_y (1 - 0.5 |h|**n (1 + sign(v h)))``, ``u_y = q_d/((1 - alpha) k_i)``.
The linear part (Figure 5.3) takes ``f_h = v/u_y 0.5 |h|**n (1 + sign(v h))``
[1/s] as its input, so that ``dh/dt = v/u_y - f_h`` (Eq 5-7c).
"""

from __future__ import annotations

from dataclasses import dataclass

from ...units import G0, INTERNAL_UNITS
from ..base import positive
from ..definition import Derived, Parameter, VSDefinition
from ..system import DefinedVS
from ..targets import BASEMAT_MASS, MASS_FIELDS, TEST_ARTICLE_WEIGHT, post_elastic_stiffness, total_mass
from ..vstype import VSType

ORDER = 20

DEFINITION = VSDefinition(
    kind="LR",
    title="lead-rubber bearings with Bouc-Wen hysteresis",
    source="report Section 5.4, Eq 5-3 to 5-8 (Eq 5-4 with |h|, docs/errata.md)",
    parameters=(
        Parameter("m_vs", INTERNAL_UNITS["mass"], "Mass of the basemat"),
        Parameter("k_i", "force_pound / inch", "Initial stiffness"),
        Parameter("alpha", "dimensionless", "Stiffness ratio", "fraction"),
        Parameter("q_d", "force_pound", "Characteristic strength"),
        Parameter("c", "force_pound * second / inch", "Damping coefficient", "nonnegative"),
        Parameter("n", "dimensionless", "Smoothing parameter", default=2.0),
    ),
    states=("x", "v", "h"),
    state_units=("inch", "inch / second", "dimensionless"),
    intermediates=(
        ("inv_uy", "(1.0 - alpha)*k_i/q_d"),
        ("f_h", "inv_uy*0.5*pow(abs(h), n)*(1.0 + sign(v*h))*v"),
        ("F", "alpha*k_i*x + c*v + q_d*h"),
    ),
    rates={"x": "v", "v": "(w - alpha*k_i*x - c*v - q_d*h)/m_vs - a_g", "h": "inv_uy*v - f_h"},
    outputs={"z_vs": "(w - F)/m_vs", "force": "F"},
    nonlinear_inputs=("f_h",),
    derived=(
        Derived("k_s", "alpha*k_i", "force_pound / inch", "Post-elastic (horizontal) stiffness"),
        Derived("u_y", "q_d/((1.0 - alpha)*k_i)", "inch", "Yield displacement"),
        Derived("f_y", "k_i*u_y", "force_pound", "Yield strength"),
        Derived("f_post_vs", "sqrt(k_s/m_vs)/two_pi", "hertz", "Post-elastic frequency of the basemat alone"),
    ),
    kinematics=("x", "v"),
    transition_length="q_d/((1.0 - alpha)*k_i)",
    reference={"m_vs": 5.18, "k_i": 2500.0, "alpha": 0.1, "q_d": 500.0, "c": 0.15},
)


@dataclass(frozen=True)
class LRTargets:
    """Lead-rubber targets (Section 9.2, Table 9.2).

    Parameters
    ----------
    q_ratio : float
        Characteristic strength over total weight, ``q_d/(M*G0)``.
    T_s : float
        Post-elastic period of the isolated article [s].
    u_y : float
        Yield displacement [in].
    c : float
        Damping coefficient of the rubber [lbf*s/in] (an input: Table 9.2 prints it).
    n : float
        Bouc-Wen smoothing exponent.
    m_vs : float
        Basemat mass [lbf*s**2/in].
    w_ps : float
        Test-article weight [lbf].
    """

    q_ratio: float
    T_s: float
    u_y: float = 0.4
    c: float = 0.0
    n: float = 2.0
    m_vs: float = BASEMAT_MASS
    w_ps: float = TEST_ARTICLE_WEIGHT

    kind = "LR"

    def build(self) -> DefinedVS:
        """``q_d = q_ratio*M*G0``, ``k_s = (2*pi/T_s)**2*M``, ``k_i = k_s + q_d/u_y``, ``alpha = k_s/k_i``."""
        M = total_mass(self.m_vs, self.w_ps)
        positive("q_ratio", self.q_ratio)
        positive("u_y", self.u_y)
        q_d = self.q_ratio * M * G0
        k_s = post_elastic_stiffness(self.T_s, M)
        k_i = k_s + q_d / self.u_y
        return DefinedVS(
            DEFINITION,
            {"m_vs": self.m_vs, "k_i": k_i, "alpha": k_s / k_i, "q_d": q_d, "c": self.c, "n": self.n},
        )


TYPE = VSType(
    DEFINITION,
    targets=LRTargets,
    target_fields=(
        Parameter("q_ratio", "dimensionless", "Characteristic strength ratio"),
        Parameter("T_s", "second", "Post-elastic period"),
        Parameter("u_y", "inch", "Yield displacement", default=0.4),
        Parameter("c", "force_pound * second / inch", "Damping coefficient", "nonnegative", default=0.0),
        Parameter("n", "dimensionless", "Smoothing parameter", default=2.0),
        *MASS_FIELDS,
    ),
    target_only=frozenset({"q_ratio", "T_s", "u_y"}),
    presets={  # Table 9.2: q_ratio, T_s [s], c [lbf*s/in]; u_y = 0.4 in
        "LR1": LRTargets(q_ratio=0.09, T_s=2.0, u_y=0.4, c=0.11, n=2.0),
        "LR2": LRTargets(q_ratio=0.15, T_s=1.5, u_y=0.4, c=0.15, n=2.0),
        "LR3": LRTargets(q_ratio=0.21, T_s=1.0, u_y=0.4, c=0.22, n=2.0),
    },
)
