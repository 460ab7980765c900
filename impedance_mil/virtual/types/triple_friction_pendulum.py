"""Triple Friction Pendulum bearings, TFP: the series model of Fenz and Constantinou (2008).

The bearing has four concave surfaces: the outer ones, 1 (bottom) and 4 (top),
of effective radii ``R1``, ``R4``, friction ``mu1``, ``mu4`` and displacement
limits ``d1``, ``d4``; and the two inner ones of the articulated slider, 2 and
3, taken equal (``R2``, ``mu2``, ``d2``), the configuration of Fenz and
Constantinou (2008a, b) with ``mu2 < mu1 <= mu4`` and ``R2 < R1, R4``.  Its
force-displacement relation passes through five sliding regimes (Fenz and
Constantinou 2008a, Table 1), each linear with the tangent flexibility of the
surfaces that slide::

    I    surfaces 2, 3   W/(2 R2)       from F = mu2 W
    II   surfaces 1, 3   W/(R1 + R2)    from F = mu1 W
    III  surfaces 1, 4   W/(R1 + R4)    from F = mu4 W
    IV   surfaces 2, 4   W/(R2 + R4)    from F = W (d1/R1 + mu1)  (surface 1 at its restrainer)
    V    surfaces 2, 3   W/(2 R2)       from F = W (d4/R4 + mu4)  (surface 4 at its restrainer)

up to ``F = W (d1/R1 + d2/R2 + mu2)``, when the slider reaches its own
restrainers (surface 2 has moved ``(mu1 - mu2) R2`` in regime I, nothing in
II and III, and ``R2/W`` per unit force since regime IV).  The model holds for
this order of the regimes, which the rules enforce: outer limits in the same
proportion to their radii (``d1/R1 = d4/R4``, so that both inner restrainers
engage together), and ``mu4 < d2/R2 + mu2`` (regime V is reached before the
slider's travel ends).

The series model (Fenz and Constantinou 2008c) reproduces this with three
elements in series, each a friction element (here Bouc-Wen smoothed, yield
displacement ``u_y``, as the report's FP), a linear spring and a stop, with
*modified* parameters chosen so that the elements' flexibilities add up to
each regime's: element A (surfaces 2 and 3) ``R = 2 R2``, ``mu = mu2``, stop at
``2 (d2 + R2 d1/R1)``; element B (surface 1) ``R = R1 - R2``, ``mu = mu1``, stop at
``d1 (1 - R2/R1)``; element C (surface 4) ``R = R4 - R2``, ``mu = mu4``, stop at
``d4 (1 - R2/R4)``.  Series equilibrium (one force ``F`` through the three
elements, displacements adding up to the bearing's ``x``) gives explicit
rates: each element takes the share ``(1/K_i)/sum(1/K_j)`` of the velocity,
``K_i`` its tangent stiffness; a relaxation at :data:`FORCE_RELAXATION`
holds the three element forces equal against the integration error.  A stop
is a spring of stiffness ``W/u_y`` beyond the element's limit.

As for the FP, the parameters are those of the whole isolation system (the
bearings act in parallel under the axial load ``W = m_vs g + w_ps``, so radii,
friction coefficients and displacement limits are those of one bearing), and
the linear part of the design is the basemat on the regime-III stiffness
``W/(R1 + R4)`` with ``f_h = F - W x/(R1 + R4)`` as its input.
"""

from __future__ import annotations

from ...units import INTERNAL_UNITS
from ..definition import Derived, Parameter, Rule, VSDefinition
from ..targets import BASEMAT_MASS, TEST_ARTICLE_WEIGHT
from ..vstype import VSType

ORDER = 40

#: Rate [1/s] at which the series model pulls the three element forces together.
FORCE_RELAXATION = 200.0

_IN = "inch"
_F = "force_pound"


def _element(e: str) -> tuple[tuple[str, str], ...]:
    """Intermediates of element ``e`` (A, B or C): smoothing factor, stop, tangent stiffness, force."""
    u = f"u{e}"
    return (
        (f"g{e}", f"1.0 - 0.5*pow(abs(z{e}), n)*(1.0 + sign(v*z{e}))"),
        (f"o{e}", f"where(abs({u}) > d{e}, 1.0, 0.0)"),
        (f"K{e}", f"k{e} + q{e}*inv_uy*g{e} + k_stop*o{e}"),
        (f"F{e}", f"k{e}*{u} + q{e}*z{e} + k_stop*o{e}*(abs({u}) - d{e})*sign({u})"),
    )


DEFINITION = VSDefinition(
    kind="TFP",
    title="triple Friction Pendulum bearings (series model)",
    source="Fenz and Constantinou 2008a (EESD 37:163-183, regimes I-V), 2008c (Earthq. Spectra 24:1011, "
    "series model)",
    parameters=(
        Parameter("m_vs", INTERNAL_UNITS["mass"], "Mass of the basemat"),
        Parameter("R1", _IN, "Effective radius of outer surface 1"),
        Parameter("R2", _IN, "Effective radius of inner surfaces 2 and 3"),
        Parameter("R4", _IN, "Effective radius of outer surface 4"),
        Parameter("mu1", "dimensionless", "Friction coefficient of surface 1"),
        Parameter("mu2", "dimensionless", "Friction coefficient of surfaces 2 and 3"),
        Parameter("mu4", "dimensionless", "Friction coefficient of surface 4"),
        Parameter("d1", _IN, "Displacement limit of surface 1"),
        Parameter("d2", _IN, "Displacement limit of surfaces 2 and 3"),
        Parameter("d4", _IN, "Displacement limit of surface 4"),
        Parameter("u_y", _IN, "Yield displacement"),
        Parameter("w_ps", _F, "Weight of the test article", "nonnegative"),
        Parameter("n", "dimensionless", "Smoothing parameter", default=2.0),
    ),
    states=("x", "v", "uB", "uC", "zA", "zB", "zC"),
    state_units=(_IN, "inch / second", _IN, _IN, "dimensionless", "dimensionless", "dimensionless"),
    intermediates=(
        ("inv_uy", "1.0/u_y"),
        ("uA", "x - uB - uC"),
        *_element("A"),
        *_element("B"),
        *_element("C"),
        ("flex", "1.0/KA + 1.0/KB + 1.0/KC"),
        ("F_mean", "(FA/KA + FB/KB + FC/KC)/flex"),
        ("f_h", "FA - k_lin*x"),
        ("F", "k_lin*x + f_h"),
        ("vA", "(v/flex + relax*(F_mean - FA))/KA"),
        ("vB", "(v/flex + relax*(F_mean - FB))/KB"),
        ("vC", "(v/flex + relax*(F_mean - FC))/KC"),
    ),
    rates={
        "x": "v",
        "v": "(w - F)/m_vs - a_g",
        "uB": "vB",
        "uC": "vC",
        "zA": "vA*inv_uy*gA",
        "zB": "vB*inv_uy*gB",
        "zC": "vC*inv_uy*gC",
    },
    outputs={"z_vs": "(w - F)/m_vs", "force": "F"},
    nonlinear_inputs=("f_h",),
    derived=(
        Derived("W", "m_vs*g0 + w_ps", _F, "Axial load"),
        Derived("kA", "W/(2.0*R2)", "force_pound / inch", "Stiffness of element A (surfaces 2, 3)"),
        Derived("kB", "W/(R1 - R2)", "force_pound / inch", "Stiffness of element B (surface 1)"),
        Derived("kC", "W/(R4 - R2)", "force_pound / inch", "Stiffness of element C (surface 4)"),
        Derived("qA", "mu2*W", _F, "Friction force of element A"),
        Derived("qB", "mu1*W", _F, "Friction force of element B"),
        Derived("qC", "mu4*W", _F, "Friction force of element C"),
        Derived("dA", "2.0*(d2 + R2*d1/R1)", _IN, "Stop of element A"),
        Derived("dB", "d1*(1.0 - R2/R1)", _IN, "Stop of element B"),
        Derived("dC", "d4*(1.0 - R2/R4)", _IN, "Stop of element C"),
        Derived("k_stop", "W/u_y", "force_pound / inch", "Stiffness of a stop"),
        Derived("k_lin", "W/(R1 + R4)", "force_pound / inch", "Regime III stiffness (linear part)"),
        Derived("relax", str(FORCE_RELAXATION), "1 / second", "Relaxation rate of the series forces"),
        Derived("capacity", "2.0*d2 + d1 + d4", _IN, "Displacement capacity of the bearing"),
    ),
    kinematics=("x", "v"),
    article_weight="w_ps",
    transition_length="u_y",
    rules=(
        Rule("mu2", "mu2 < mu1", "mu2 < mu1 (the inner surfaces slide first, regime I)"),
        Rule("mu1", "mu1 <= mu4", "mu1 <= mu4 (surface 1 slides before surface 4)"),
        Rule("R2", "R2 < R1", "R2 < R1 (regime II softer than regime I)"),
        Rule("R4", "R2 < R4", "R2 < R4 (regime III softer than regime II)"),
        Rule(
            "d4",
            "abs(d1/R1 - d4/R4) <= 1e-9*(d1/R1)",
            "d4/R4 = d1/R1 (outer limits in proportion to their radii)",
        ),
        Rule("d2", "mu4 < d2/R2 + mu2", "mu4 < d2/R2 + mu2 (the slider's travel outlasts regime IV)"),
        Rule("u_y", "u_y < d2", "u_y < d2 (the yield displacement below the slider's travel)"),
    ),
    reference={
        "m_vs": 5.18,
        "R1": 49.2,
        "R2": 14.2,
        "R4": 49.2,
        "mu1": 0.052,
        "mu2": 0.012,
        "mu4": 0.14,
        "d1": 7.87,
        "d2": 3.94,
        "d4": 7.87,
        "u_y": 0.04,
        "w_ps": 3600.0,  # the point where expressions are checked finite; never a run's article weight
    },
)

_M = 1.0 / 0.0254  # inches per metre

#: TFP1: the bearing of the OpenSees TripleFrictionPendulum verification example 4 (N. Dao,
#: University of Nevada, Reno; constant friction; OpenSees tests/Elements/TripleFrictionPendulum):
#: L1 = 0.36 m (inner surfaces), L2 = L3 = 1.25 m (outer), mu = 0.012 / 0.052 / 0.14,
#: d1 = 0.1 m (inner), d2 = d3 = 0.2 m (outer), u_y = 1 mm.
TFP1 = {
    "R1": 1.25 * _M,
    "R2": 0.36 * _M,
    "R4": 1.25 * _M,
    "mu1": 0.052,
    "mu2": 0.012,
    "mu4": 0.14,
    "d1": 0.2 * _M,
    "d2": 0.1 * _M,
    "d4": 0.2 * _M,
    "u_y": 0.001 * _M,
}

#: TFP2: the bearing of the OpenSees TFP element example (T. Becker, UC Berkeley; OpenSees
#: documentation, TripleFrictionPendulumBearing): radii 12 in (inner) and 88 in (outer),
#: heights 3 in and 4.5 in, surface diameters 12 in and 44 in, slider diameters 8 in and
#: 12.5 in, mu = 0.02 (inner), 0.09 (bottom), 0.12 (top).  Effective radii R - h and
#: effective displacement limits (D - d)/2 * (R - h)/R (Fenz and Constantinou 2008a).
TFP2 = {
    "R1": 88.0 - 4.5,
    "R2": 12.0 - 3.0,
    "R4": 88.0 - 4.5,
    "mu1": 0.09,
    "mu2": 0.02,
    "mu4": 0.12,
    "d1": (44.0 - 12.5) / 2 * (88.0 - 4.5) / 88.0,
    "d2": (12.0 - 8.0) / 2 * (12.0 - 3.0) / 12.0,
    "d4": (44.0 - 12.5) / 2 * (88.0 - 4.5) / 88.0,
    "u_y": 0.04,
}

#: Length scale of TFP3: TFP1 with every length x 1/5 (a reduced-scale bearing whose 4.7 in
#: capacity suits a +-3 in table at moderate motions); friction unchanged.
SCALE_TFP3 = 0.2

#: The report's basemat and article (Section 9.2) on the bearings.
_ON_REPORT_BASEMAT = {"m_vs": BASEMAT_MASS, "w_ps": TEST_ARTICLE_WEIGHT}

TYPE = VSType(
    DEFINITION,
    presets={
        "TFP1": {**TFP1, **_ON_REPORT_BASEMAT},
        "TFP2": {**TFP2, **_ON_REPORT_BASEMAT},
        "TFP3": {
            **{k: (v * SCALE_TFP3 if k[0] in "Rdu" else v) for k, v in TFP1.items()},
            **_ON_REPORT_BASEMAT,
        },
    },
)
