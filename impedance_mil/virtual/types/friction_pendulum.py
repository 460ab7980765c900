"""Single concave Friction Pendulum bearings, FP (report Section 5.5, Eq 5-9 to 5-13; Table 9.3).

Isolator force ``F = k_s x + mu(v) W h`` with the pendulum stiffness
``k_s = W/R_eff`` (Eq 5-9b), the axial load ``W = m_vs g + w_ps`` (basemat plus
test article, as the report's FP program, Figure 7.11), the velocity-dependent
friction of Mokha et al. ``mu(v) = mu_max - (mu_max - mu_min) exp(-a |v|)``
(Eq 5-10) and a Bouc-Wen variable ``h`` of yield displacement ``u_y``.  The
linear part (Figure 5.5) is the basemat on ``k_s``, with ``f_h = mu(v) W h``
[lbf] as its input.
"""

from __future__ import annotations

from dataclasses import dataclass

from ...units import INTERNAL_UNITS
from ..definition import Derived, Parameter, Rule, VSDefinition
from ..system import DefinedVS
from ..targets import BASEMAT_MASS, MASS_FIELDS, TEST_ARTICLE_WEIGHT, post_elastic_stiffness, total_mass
from ..vstype import VSType

ORDER = 30

DEFINITION = VSDefinition(
    kind="FP",
    title="single concave Friction Pendulum bearings",
    source="report Section 5.5, Eq 5-9 to 5-13",
    parameters=(
        Parameter("m_vs", INTERNAL_UNITS["mass"], "Mass of the basemat"),
        Parameter("k_s", "force_pound / inch", "Post-elastic (horizontal) stiffness"),
        Parameter("mu_max", "dimensionless", "Fast friction coefficient"),
        Parameter("mu_min", "dimensionless", "Slow friction coefficient"),
        Parameter("a", "second / inch", "Rate parameter", "nonnegative"),
        Parameter("u_y", "inch", "Yield displacement"),
        Parameter("w_ps", "force_pound", "Weight of the test article", "nonnegative"),
        Parameter("n", "dimensionless", "Smoothing parameter", default=2.0),
    ),
    states=("x", "v", "h"),
    state_units=("inch", "inch / second", "dimensionless"),
    intermediates=(
        ("mu", "mu_max - (mu_max - mu_min)*exp(-a*abs(v))"),
        ("inv_uy", "1.0/u_y"),
        ("f_h", "mu*W*h"),
        ("F", "k_s*x + f_h"),
        ("bw", "inv_uy*0.5*pow(abs(h), n)*(1.0 + sign(v*h))*v"),
    ),
    rates={"x": "v", "v": "(w - k_s*x - f_h)/m_vs - a_g", "h": "inv_uy*v - bw"},
    outputs={"z_vs": "(w - F)/m_vs", "force": "F"},
    nonlinear_inputs=("f_h",),
    derived=(
        Derived("W", "m_vs*g0 + w_ps", "force_pound", "Axial load"),
        Derived("k_i", "mu_max*W/u_y", "force_pound / inch", "Initial stiffness"),
        Derived("R_eff", "W/k_s", "inch", "Effective radius"),
        Derived("q_d", "mu_max*W", "force_pound", "Characteristic strength"),
        Derived("T_s", "two_pi*sqrt(W/g0/k_s)", "second", "Post-elastic period"),
    ),
    kinematics=("x", "v"),
    article_weight="w_ps",
    transition_length="u_y",
    rules=(Rule("mu_min", "mu_min <= mu_max", "mu_min <= mu_max"),),
    reference={
        "m_vs": 5.18,
        "k_s": 187.0,
        "mu_max": 0.12,
        "mu_min": 0.06,
        "a": 2.54,
        "u_y": 0.04,
        "w_ps": 3600.0,  # the point where expressions are checked finite; never a run's article weight
    },
)


@dataclass(frozen=True)
class FPTargets:
    """Friction Pendulum targets (Section 9.2, Table 9.3).

    Parameters
    ----------
    mu_max, mu_min : float
        Fast and slow friction coefficients (``mu_max`` is the target q_ratio).
    T_s : float
        Post-elastic (sliding) period of the isolated article [s].
    a : float
        Rate parameter [s/in].
    u_y : float
        Yield displacement [in]; 0.04 in reproduces Table 9.3's k_i.
    n : float
        Bouc-Wen smoothing exponent.
    m_vs : float
        Basemat mass [lbf*s**2/in].
    w_ps : float
        Test-article weight [lbf].
    """

    mu_max: float
    mu_min: float
    T_s: float
    a: float = 2.54
    u_y: float = 0.04
    n: float = 2.0
    m_vs: float = BASEMAT_MASS
    w_ps: float = TEST_ARTICLE_WEIGHT

    kind = "FP"

    def build(self) -> DefinedVS:
        """``k_s = (2*pi/T_s)**2*M`` (``R_eff = g*(T_s/2/pi)**2``); the rest passes through."""
        M = total_mass(self.m_vs, self.w_ps)
        return DefinedVS(
            DEFINITION,
            {
                "m_vs": self.m_vs,
                "k_s": post_elastic_stiffness(self.T_s, M),
                "mu_max": self.mu_max,
                "mu_min": self.mu_min,
                "a": self.a,
                "u_y": self.u_y,
                "w_ps": self.w_ps,
                "n": self.n,
            },
        )

    @property
    def q_ratio(self) -> float:
        """Characteristic strength ratio: ``mu_max``."""
        return self.mu_max


TYPE = VSType(
    DEFINITION,
    targets=FPTargets,
    target_fields=(
        Parameter("mu_max", "dimensionless", "Fast friction coefficient"),
        Parameter("mu_min", "dimensionless", "Slow friction coefficient"),
        Parameter("T_s", "second", "Post-elastic period"),
        Parameter("a", "second / inch", "Rate parameter", "nonnegative", default=2.54),
        Parameter("u_y", "inch", "Yield displacement", default=0.04),
        Parameter("n", "dimensionless", "Smoothing parameter", default=2.0),
        *MASS_FIELDS,
    ),
    target_only=frozenset({"T_s"}),
    presets={  # Table 9.3: mu_max, mu_min, T_s [s]; a = 2.54 s/in
        "FP1": FPTargets(mu_max=0.06, mu_min=0.03, T_s=2.25, a=2.54),
        "FP2": FPTargets(mu_max=0.12, mu_min=0.06, T_s=1.75, a=2.54),
        "FP3": FPTargets(mu_max=0.18, mu_min=0.09, T_s=1.25, a=2.54),
    },
)
