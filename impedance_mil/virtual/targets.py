"""Design targets of the isolation systems, as in report Section 9.2.

The report sizes every isolation system for the *total* mass on the
bearings, basemat plus test article: ``M = m_vs + m_ps`` with
``m_ps = w_ps/G0`` (Section 9.2, "the sum of the masses ... is the total
axial load on the isolation system").  The test article of the report is the
vessel with 36 in of water, about 3.6 kip (Section 3.2); the basemat of
Tables 9.1-9.3 is 2000 lb (Table 9.3 prints 2150 lb, which its own
stiffnesses contradict; see docs/errata.md).

Each target object is a frozen dataclass with :meth:`build` returning the
virtual system.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..report_config import report_config
from ..units import G0, TWO_PI
from .base import _nonnegative, _positive
from .models import FrictionPendulum, LeadRubber, SpringDamper

#: Weight of the report's test article: vessel with 36 in of water [lbf] (Section 3.2, Table 9.1).
TEST_ARTICLE_WEIGHT = report_config().specimen.article_weight_lbf
#: Basemat mass of Tables 9.1-9.3 [lbf*s**2/in]: 2000 lb (about 1.25 m_st, Section 9.4.4).
BASEMAT_MASS = 2000.0 / G0


def _total_mass(m_vs: float, w_ps: float) -> float:
    _positive("m_vs", m_vs)
    _nonnegative("w_ps", w_ps)
    return m_vs + w_ps / G0


def _post_elastic_stiffness(T_s: float, total_mass: float) -> float:
    _positive("T_s", T_s)
    return (TWO_PI / T_s) ** 2 * total_mass


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

    def build(self) -> SpringDamper:
        """``k_s = (2*pi*f)**2*M``, ``c = 2*zeta*sqrt(k_s*M)``, ``M = m_vs + w_ps/G0``."""
        M = _total_mass(self.m_vs, self.w_ps)
        _positive("f", self.f)
        _nonnegative("zeta", self.zeta)
        k_s = (TWO_PI * self.f) ** 2 * M
        return SpringDamper(m_vs=self.m_vs, k_s=k_s, c=2.0 * self.zeta * math.sqrt(k_s * M))


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

    def build(self) -> LeadRubber:
        """``q_d = q_ratio*M*G0``, ``k_s = (2*pi/T_s)**2*M``, ``k_i = k_s + q_d/u_y``, ``alpha = k_s/k_i``."""
        M = _total_mass(self.m_vs, self.w_ps)
        _positive("q_ratio", self.q_ratio)
        _positive("u_y", self.u_y)
        q_d = self.q_ratio * M * G0
        k_s = _post_elastic_stiffness(self.T_s, M)
        k_i = k_s + q_d / self.u_y
        return LeadRubber(m_vs=self.m_vs, k_i=k_i, alpha=k_s / k_i, q_d=q_d, c=self.c, n=self.n)


@dataclass(frozen=True)
class FPTargets:
    """Friction Pendulum targets (Section 9.2, Table 9.3).

    Parameters
    ----------
    mu_max, mu_min : float
        Fast and slow friction coefficients (``mu_max`` is the target q_ratio).
    a : float
        Rate parameter [s/in].
    T_s : float
        Post-elastic (sliding) period of the isolated article [s].
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

    def build(self) -> FrictionPendulum:
        """``k_s = (2*pi/T_s)**2*M`` (``R_eff = g*(T_s/2/pi)**2``); the rest passes through."""
        M = _total_mass(self.m_vs, self.w_ps)
        return FrictionPendulum(
            m_vs=self.m_vs,
            k_s=_post_elastic_stiffness(self.T_s, M),
            mu_max=self.mu_max,
            mu_min=self.mu_min,
            a=self.a,
            u_y=self.u_y,
            w_ps=self.w_ps,
            n=self.n,
        )

    @property
    def q_ratio(self) -> float:
        """Characteristic strength ratio: ``mu_max``."""
        return self.mu_max


#: Target classes by kind.
TARGETS = {"SD": SDTargets, "LR": LRTargets, "FP": FPTargets}
