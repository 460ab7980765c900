"""What the design targets of the report's isolation systems share (report Section 9.2).

The report sizes every isolation system for the *total* mass on the
bearings, basemat plus test article: ``M = m_vs + m_ps`` with
``m_ps = w_ps/G0`` (Section 9.2, "the sum of the masses ... is the total
axial load on the isolation system").  The test article of the report is the
vessel with 36 in of water, about 3.6 kip (Section 3.2); the basemat of
Tables 9.1-9.3 is 2000 lb (Table 9.3 prints 2150 lb, which its own
stiffnesses contradict; see docs/errata.md).

Each type module of :mod:`impedance_mil.virtual.types` defines its target
class (a frozen dataclass whose :meth:`build` returns the system); this module
holds the pieces they share.
"""

from __future__ import annotations

from ..report_config import report_config
from ..units import G0, INTERNAL_UNITS, TWO_PI
from .base import nonnegative, positive
from .definition import Parameter

#: Weight of the report's test article: vessel with 36 in of water [lbf] (Section 3.2, Table 9.1).
TEST_ARTICLE_WEIGHT = report_config().specimen.article_weight_lbf
#: Basemat mass of Tables 9.1-9.3 [lbf*s**2/in]: 2000 lb (about 1.25 m_st, Section 9.4.4).
BASEMAT_MASS = 2000.0 / G0

#: Target fields every isolator type shares (units and labels for files and listings).
MASS_FIELDS = (
    Parameter("m_vs", INTERNAL_UNITS["mass"], "Mass of the basemat", default=BASEMAT_MASS),
    Parameter(
        "w_ps", "force_pound", "Weight of the test article", "nonnegative", default=TEST_ARTICLE_WEIGHT
    ),
)


def total_mass(m_vs: float, w_ps: float) -> float:
    """``M = m_vs + w_ps/G0`` [lbf*s**2/in] (checked: m_vs > 0, w_ps >= 0)."""
    positive("m_vs", m_vs)
    nonnegative("w_ps", w_ps)
    return m_vs + w_ps / G0


def post_elastic_stiffness(T_s: float, total: float) -> float:
    """``(2 pi / T_s)**2 M`` [lbf/in] for the post-elastic period ``T_s`` [s]."""
    positive("T_s", T_s)
    return (TWO_PI / T_s) ** 2 * total
