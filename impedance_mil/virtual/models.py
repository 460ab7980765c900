"""The three isolation systems of the report: SD, LR and FP (Section 5).

Each is a frozen dataclass of its isolation-system parameters (sums over the
bearings, Section 5.3) whose dynamics are the compiled kernels of
:mod:`impedance_mil.virtual.kernels`.  Build them from design targets with
:mod:`impedance_mil.virtual.targets` or take a preset from
:mod:`impedance_mil.virtual.presets`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from ..errors import ConfigError
from ..units import G0, TWO_PI
from .base import VirtualSystem, _nonnegative, _positive
from .kernels import KIND_FP, KIND_LR, KIND_SD


@dataclass(frozen=True)
class SpringDamper(VirtualSystem):
    """Linear spring-damper VS (report Section 5.3, Eq 5-1, 5-2).

    Parameters
    ----------
    m_vs : float
        Basemat mass [lbf*s**2/in].
    k_s : float
        Horizontal stiffness of the isolation system [lbf/in].
    c : float
        Viscous damping coefficient [lbf*s/in].

    Examples
    --------
    >>> sd = SpringDamper(m_vs=2000 / G0, k_s=894.0, c=57.0)
    >>> round(sd.linear_part().H_zag.dcgain(), 6)
    1.0
    """

    k_s: float
    c: float

    kind = "SD"
    kind_code = KIND_SD

    def __post_init__(self):
        super().__post_init__()
        _positive("k_s", self.k_s)
        _nonnegative("c", self.c)

    def derived(self) -> dict[str, float]:
        """Frequency [Hz] and damping ratio of the basemat alone on the isolators."""
        return {
            "f_vs": math.sqrt(self.k_s / self.m_vs) / TWO_PI,
            "zeta_vs": self.c / (2.0 * math.sqrt(self.k_s * self.m_vs)),
        }


@dataclass(frozen=True)
class LeadRubber(VirtualSystem):
    """Lead-rubber VS with Bouc-Wen hysteresis (report Section 5.4, Eq 5-3..5-8).

    Parameters
    ----------
    m_vs : float
        Basemat mass [lbf*s**2/in].
    k_i : float
        Initial stiffness of the isolation system, hysteretic plus rubber [lbf/in].
    alpha : float
        Ratio of post-yield to initial stiffness, 0 <= alpha < 1 (``k_s = alpha*k_i``).
    q_d : float
        Characteristic strength [lbf].
    c : float
        Damping coefficient of the rubber [lbf*s/in].
    n : float
        Bouc-Wen smoothing exponent (> 0; the report uses 2).

    Notes
    -----
    The yield displacement is derived: ``u_y = q_d / ((1 - alpha)*k_i)``.
    """

    k_i: float
    alpha: float
    q_d: float
    c: float
    n: float = 2.0

    kind = "LR"
    kind_code = KIND_LR

    def __post_init__(self):
        super().__post_init__()
        _positive("k_i", self.k_i)
        if not (math.isfinite(self.alpha) and 0.0 <= self.alpha < 1.0):
            raise ConfigError("alpha", "a stiffness ratio in [0, 1)", self.alpha)
        _positive("q_d", self.q_d)
        _nonnegative("c", self.c)
        _positive("n", self.n)

    @property
    def k_s(self) -> float:
        """Post-elastic stiffness ``alpha*k_i`` [lbf/in]."""
        return self.alpha * self.k_i

    @property
    def u_y(self) -> float:
        """Yield displacement ``q_d/((1 - alpha)*k_i)`` [in]."""
        return self.q_d / ((1.0 - self.alpha) * self.k_i)

    @property
    def f_y(self) -> float:
        """Yield strength ``k_i*u_y`` [lbf]."""
        return self.k_i * self.u_y

    def derived(self) -> dict[str, float]:
        """k_s [lbf/in], u_y [in], f_y [lbf] and the post-elastic frequency of the basemat [Hz]."""
        return {
            "k_s": self.k_s,
            "u_y": self.u_y,
            "f_y": self.f_y,
            "f_post_vs": math.sqrt(self.k_s / self.m_vs) / TWO_PI,
        }


@dataclass(frozen=True)
class FrictionPendulum(VirtualSystem):
    """Single concave Friction Pendulum VS (report Section 5.5, Eq 5-9..5-13).

    Parameters
    ----------
    m_vs : float
        Basemat mass [lbf*s**2/in].
    k_s : float
        Sliding (pendulum) stiffness ``W/R_eff`` [lbf/in].
    mu_max, mu_min : float
        Friction coefficients at fast and slow sliding (mu_min <= mu_max).
    a : float
        Rate parameter of Eq 5-10 [s/in].
    u_y : float
        Yield displacement of the hysteretic element [in].
    w_ps : float
        Weight of the test article carried by the bearings [lbf] (report:
        vessel with 36 in of water, about 3600 lbf, Section 3.2).
    n : float
        Bouc-Wen smoothing exponent (the report's program uses 2).

    Notes
    -----
    The axial load is ``W = m_vs*G0 + w_ps`` [lbf]: basemat plus test
    article, as in the report's FP program (Figure 7.11, ``Wa``).
    """

    k_s: float
    mu_max: float
    mu_min: float
    a: float
    u_y: float
    w_ps: float
    n: float = 2.0

    kind = "FP"
    kind_code = KIND_FP

    def __post_init__(self):
        super().__post_init__()
        _positive("k_s", self.k_s)
        _positive("mu_max", self.mu_max)
        _positive("mu_min", self.mu_min)
        if self.mu_min > self.mu_max:
            raise ConfigError("mu_min", f"mu_min <= mu_max = {self.mu_max}", self.mu_min)
        _nonnegative("a", self.a)
        _positive("u_y", self.u_y)
        _nonnegative("w_ps", self.w_ps)
        _positive("n", self.n)

    @property
    def W(self) -> float:
        """Axial load on the bearings ``m_vs*G0 + w_ps`` [lbf]."""
        return self.m_vs * G0 + self.w_ps

    @property
    def k_i(self) -> float:
        """Initial stiffness of the friction element ``mu_max*W/u_y`` [lbf/in] (as in Table 9.3)."""
        return self.mu_max * self.W / self.u_y

    @property
    def R_eff(self) -> float:
        """Effective radius of curvature ``W/k_s`` [in] (Eq 5-9b)."""
        return self.W / self.k_s

    def friction(self, v: float) -> float:
        """Friction coefficient mu(v) of Eq 5-10 at sliding velocity ``v`` [in/s]."""
        return self.mu_max - (self.mu_max - self.mu_min) * math.exp(-self.a * abs(v))

    def derived(self) -> dict[str, float]:
        """W [lbf], k_i [lbf/in], R_eff [in], q_d = mu_max*W [lbf], sliding period [s]."""
        return {
            "W": self.W,
            "k_i": self.k_i,
            "R_eff": self.R_eff,
            "q_d": self.mu_max * self.W,
            "T_s": TWO_PI * math.sqrt(self.W / G0 / self.k_s),
        }

    def with_rigid_article(self, m_article: float) -> FrictionPendulum:
        """Lump a rigid article of mass ``m_article`` [lbf*s**2/in] on the basemat, keeping W.

        The article's weight is already part of ``w_ps``; lumping moves it
        from ``w_ps`` into ``m_vs``, so it must not exceed ``w_ps``.
        """
        _nonnegative("m_article", m_article)
        w_rest = self.w_ps - m_article * G0
        if w_rest < -1e-9 * max(self.w_ps, 1.0):
            raise ConfigError("m_article", f"a weight of at most w_ps = {self.w_ps:g} lbf", m_article * G0)
        return dataclasses.replace(self, m_vs=self.m_vs + m_article, w_ps=max(w_rest, 0.0))
