"""Robust stability of one design over a table's uncertainty set (issue 17, item 3).

A controller is designed for the nominal table; the real table's oil column,
flow gain, valve and loop delay are known only within ranges
(:class:`~impedance_mil.plant.uncertainty.UncertaintySet`).  For each point
of the set the *same* controller is closed around the table of that point,
and three checks are evaluated as the design reports them:

* ``passivity``: the passivity margin of ``H_vw`` on the first-order delay
  model (constraint III, :func:`~impedance_mil.design.passivity.passivity`),
  with its delay-model tolerance; the robust verdict uses the tolerant margin;
* ``sampled passivity``: the margin on the exact sampled-data table
  (:func:`~impedance_mil.design.optimized.indices.sampled_margin_deg`; the
  standardized form with a VS only, as the design reports it);
* ``coupled stability``: the closed-loop poles of the controlled table with
  the article on it (:func:`~impedance_mil.design.coupled.coupled_stability`);
  its margin is the damping ratio of the least damped pole above 15 Hz, or
  the (negative) damping of an unstable pole wherever it is.

A table with optional dynamics (a lab's ``[dynamics]``, issue 17; possibly varied by
the set) is judged on its linearization at rest with them
(``table_model(params, linearized=True)``) for ``passivity`` and ``coupled
stability``; ``sampled passivity`` stays on Eq 4-11.

The points are the vertices of the box and a seeded Latin-hypercube sample
(:meth:`UncertaintySet.latin_hypercube`), plus the nominal point.  Neither is
exhaustive: the worst case found is an upper bound on the true worst margin.
The check that *binds* is the one with the smallest worst margin, the
coupled damping ratio zeta taken as its angle ``asin(zeta)`` [deg] from the
imaginary axis so that it compares with the passivity margins (both are
angles by which the Nyquist plot, or a pole, stays off the stability limit).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..errors import UnstableSystemError
from ..plant import LinearTable, TableParameters
from ..plant.linear import closed_loop_state_space
from ..plant.table_dynamics_model import linearized_plant
from ..plant.uncertainty import UncertaintySet
from ..systems import TransferFunction
from .adapters import table_model
from .constraints import DesignCriteria, controlled_table
from .controller import ControllerDesign
from .coupled import CoupledStability, coupled_stability, stability_of_poles
from .forms import VirtualModel, environment
from .optimized.indices import sampled_margin_deg
from .optimized.models import SAMPLED_TOP_FRACTION
from .passivity import passivity
from .sensor_channels import sensed_impedance

#: Latin-hypercube points evaluated besides the vertices, unless asked otherwise.
DEFAULT_LHS_SAMPLES = 16

#: Names of the checks (``RobustMargins.binding``).
CHECKS = ("passivity", "sampled passivity", "coupled stability")


@dataclass(frozen=True)
class PointMargins:
    """The margins of the design at one point of the uncertainty set.

    Attributes
    ----------
    point : mapping of str to float
        The parameter values (internal units; ``valve_poles_hz`` a factor,
        ``extra_delay`` loops).
    passivity_margin_deg : float
        Raw first-order passivity margin [deg].
    tolerant_margin_deg : float
        Margin after the delay-model tolerance [deg] (constraint III's).
    passivity_stable : bool
        ``H_vw`` is stable.
    sampled_margin_deg : float or None
        Passivity margin on the sampled-data table [deg] (None: not evaluated for this form).
    coupled : CoupledStability
        The controlled table with the article.
    """

    point: Mapping[str, float]
    passivity_margin_deg: float
    tolerant_margin_deg: float
    passivity_stable: bool
    sampled_margin_deg: float | None
    coupled: CoupledStability

    @property
    def passive(self) -> bool:
        """Constraint III holds at this point."""
        return self.passivity_stable and self.tolerant_margin_deg >= 0.0

    @property
    def coupled_margin(self) -> float:
        """Coupled-stability margin: the HF damping ratio when stable, else the unstable pole's (< 0)."""
        if self.coupled.stable:
            return float(self.coupled.hf_damping_ratio)
        return float(min(self.coupled.min_damping_ratio, self.coupled.hf_damping_ratio))

    def margin_deg(self, check: str) -> float | None:
        """The margin of ``check`` (:data:`CHECKS`) as an angle [deg]; None when not evaluated."""
        if check == "passivity":
            return self.tolerant_margin_deg if self.passivity_stable else -math.inf
        if check == "sampled passivity":
            return self.sampled_margin_deg
        return math.degrees(math.asin(max(-1.0, min(1.0, self.coupled_margin))))

    def to_dict(self) -> dict[str, Any]:
        return {
            "parameters": _parameters(self.point),
            "passivity_margin_deg": self.passivity_margin_deg,
            "passivity_tolerant_margin_deg": self.tolerant_margin_deg,
            "passive": self.passive,
            "passivity_margin_sampled_deg": self.sampled_margin_deg,
            "coupled_stable": bool(self.coupled.stable),
            "coupled_hf_damping_ratio": self.coupled_margin,
            "coupled_damping_hz": float(self.coupled.hf_damping_hz),
        }


@dataclass(frozen=True)
class RobustMargins:
    """Worst-case margins of one design over an uncertainty set.

    Attributes
    ----------
    specimen : str
        The article of the coupled check.
    seed : int
        Seed of the Latin-hypercube sample.
    vertices, lhs_samples : int
        Points evaluated at the box's vertices and in the Latin-hypercube sample
        (the nominal point is evaluated too).
    nominal : PointMargins
    worst_passivity, worst_coupled : PointMargins
        Points with the smallest tolerant first-order margin (an unstable
        ``H_vw`` first) and the smallest coupled margin.
    worst_sampled : PointMargins or None
        Point with the smallest sampled-data margin (None: not evaluated).
    binding : str
        The check (:data:`CHECKS`) with the smallest worst margin as an angle.
    points : tuple of PointMargins
        Every point evaluated (nominal first, then vertices, then the sample).
    """

    specimen: str
    seed: int
    vertices: int
    lhs_samples: int
    nominal: PointMargins
    worst_passivity: PointMargins
    worst_coupled: PointMargins
    worst_sampled: PointMargins | None
    binding: str
    points: tuple[PointMargins, ...]

    @property
    def robustly_passive(self) -> bool:
        """Constraint III holds at every point evaluated."""
        return all(p.passive for p in self.points)

    @property
    def robustly_stable(self) -> bool:
        """The table with the article is stable at every point evaluated."""
        return all(p.coupled.stable for p in self.points)

    @property
    def worst(self) -> PointMargins:
        """The point of the binding check."""
        return {
            "passivity": self.worst_passivity,
            "coupled stability": self.worst_coupled,
        }.get(self.binding, self.worst_sampled or self.worst_passivity)

    @property
    def method(self) -> str:
        return (
            f"{self.vertices} vertices of the box + {self.lhs_samples} Latin-hypercube points "
            f"(seed {self.seed}) + the nominal point"
        )

    def line(self) -> str:
        """One sentence: robustly stable or not, with the worst margins."""
        verdict = "robustly stable" if self.robustly_stable else "NOT robustly stable"
        sampled = (
            ""
            if self.worst_sampled is None or self.worst_sampled.sampled_margin_deg is None
            else f", sampled {self.worst_sampled.sampled_margin_deg:.2f} deg"
        )
        return (
            f"{verdict} with {self.specimen} over the lab's uncertainty set ({len(self.points)} points): "
            f"worst coupled damping {self.worst_coupled.coupled_margin:.4f}, worst passivity margin "
            f"{self.worst_passivity.tolerant_margin_deg:.2f} deg tolerant{sampled}"
            f" ({'passive' if self.robustly_passive else 'not passive'} over the set); binding: {self.binding} "
            f"at {_point_text(self.worst.point)}"
        )

    def to_dict(self) -> dict[str, Any]:
        """The ``robust`` block of the JSON (units by key suffix; ``extra_delay_loops`` in loops)."""
        return {
            "method": self.method,
            "specimen": self.specimen,
            "seed": self.seed,
            "vertices_count": self.vertices,
            "lhs_count": self.lhs_samples,
            "points_count": len(self.points),
            "robustly_passive": self.robustly_passive,
            "robustly_stable": self.robustly_stable,
            "binding": self.binding,
            "nominal": self.nominal.to_dict(),
            "worst": self.worst.to_dict(),
            "worst_passivity": self.worst_passivity.to_dict(),
            "worst_sampled": None if self.worst_sampled is None else self.worst_sampled.to_dict(),
            "worst_coupled": self.worst_coupled.to_dict(),
        }


def _parameters(point: Mapping[str, float]) -> dict[str, float]:
    """A point's values under JSON keys that name their unit (``extra_delay_loops``, ``valve_poles_factor``)."""
    names = {"extra_delay": "extra_delay_loops", "valve_poles_hz": "valve_poles_factor"}
    return {names.get(k, k): float(v) for k, v in point.items()}


def _point_text(point: Mapping[str, float]) -> str:
    return ", ".join(f"{k} = {v:.4g}" for k, v in point.items()) or "the nominal point"


def point_margins(
    design: ControllerDesign,
    params: TableParameters,
    vs: VirtualModel | None,
    article: TransferFunction,
    point: Mapping[str, float],
    specimen: str = "",
    criteria: DesignCriteria | None = None,
    force_sensor: TransferFunction | None = None,
) -> PointMargins:
    """The margins of ``design`` on the table ``params`` (a point of the set) with ``article``.

    Parameters
    ----------
    design : ControllerDesign
        The controller, designed for the nominal table.
    params : TableParameters
        The table at this point (:meth:`UncertaintySet.apply`).
    vs : VirtualModel or None
        The VS model the design answers to (None for tracking).
    article : TransferFunction
        Article impedance ``w/z`` [lbf per in/s**2] (0 for the bare table).
    point : mapping
        The point's values (recorded).
    specimen : str
        Label of the article.
    criteria : DesignCriteria, optional
        The passivity band's low end [Hz] and extra tolerance [deg].
    force_sensor : TransferFunction, optional
        ``S_w(s)``, measured over true fed-back force (anti-alias filters and
        converter delays, :func:`~impedance_mil.design.sensor_channels.force_channel`):
        the coupled stability is then judged on ``H_zw + H_zu H_wu S_w``
        (:func:`~impedance_mil.design.sensor_channels.sensed_impedance`).
        None: ideal channels, ``H_c`` as designed.
    """
    c = criteria or DesignCriteria()
    # a table with optional dynamics (issue 17) is judged on its linearization, which has them
    linearized = params.dynamics is not None
    try:
        tm = table_model(params, linearized=linearized)
    except UnstableSystemError:  # the table's own loop is unstable at this point: so is every check
        poles = (
            closed_loop_state_space(params, "first-order", open_loop=linearized_plant(params)).poles()
            if linearized
            else LinearTable(params, delay="first-order").poles()
        )
        worst = -math.inf
        return PointMargins(dict(point), worst, worst, False, None, stability_of_poles(poles, specimen))
    ct = controlled_table(tm, environment(design.form, vs), design.H_uz, design.H_uw, design.form)
    pas = passivity(
        ct.H_vw,
        (c.passivity_low_hz, tm.nyquist_hz),
        tm.loop_time_s,
        c.passivity_extra_tolerance_deg,
        response=ct.velocity_response,
    )
    sampled = None
    if design.form == "standardized" and vs is not None and params.loop_time > 0:
        band = (c.passivity_low_hz, SAMPLED_TOP_FRACTION * 0.5 / params.loop_time)
        sampled, _ = sampled_margin_deg(design, params, vs, band)
    return PointMargins(
        dict(point),
        pas.margin_deg,
        pas.tolerant_margin_deg,
        pas.stable,
        sampled,
        coupled_stability(sensed_impedance(ct, force_sensor), article, specimen),
    )


def robust_margins(
    design: ControllerDesign,
    params: TableParameters,
    vs: VirtualModel | None,
    uncertainty: UncertaintySet,
    article: TransferFunction | None = None,
    specimen: str = "bare table",
    *,
    samples: int = DEFAULT_LHS_SAMPLES,
    seed: int = 0,
    criteria: DesignCriteria | None = None,
    force_sensor: TransferFunction | None = None,
) -> RobustMargins:
    """Worst-case passivity and coupled-stability margins of ``design`` over ``uncertainty``.

    Parameters
    ----------
    design : ControllerDesign
        The controller, designed for ``params``.
    params : TableParameters
        The nominal table (with the lab's loop time and output delay).
    vs : VirtualModel or None
        The VS model of the design (None for tracking).
    uncertainty : UncertaintySet
        The ranges.
    article : TransferFunction, optional
        Article impedance ``w/z`` [lbf per in/s**2]; default none (the bare table).
    specimen : str
        Label of the article.
    samples : int
        Latin-hypercube points besides the vertices.
    seed : int
        Seed of the sample.
    criteria : DesignCriteria, optional
    force_sensor : TransferFunction, optional
        The fed-back force's sensor dynamics (:func:`point_margins`); None: ideal.

    Examples
    --------
    A degenerate set (every range its nominal value) gives the nominal margins:

    >>> from impedance_mil.design import design_controller
    >>> from impedance_mil.plant.uncertainty import parse_uncertainty
    >>> from impedance_mil.report_config import report_config
    >>> p = TableParameters.report_default()
    >>> fc = report_config().design.fc_hz  # the report's cut-off
    >>> d = design_controller(table_model(p), form="tracking", fc_hz=fc, emit_warnings=False)
    >>> box = parse_uncertainty({"f_oil_hz": "±0 %"}, p)
    >>> r = robust_margins(d, p, None, box, samples=2)
    >>> r.worst_passivity.tolerant_margin_deg == r.nominal.tolerant_margin_deg
    True
    """
    zero = TransferFunction.constant(0.0)
    z = article if article is not None else zero

    def at(point: Mapping[str, float]) -> PointMargins:
        return point_margins(
            design, uncertainty.apply(params, point), vs, z, point, specimen, criteria, force_sensor
        )

    nominal = at(uncertainty.nominal())
    corners = uncertainty.vertices()
    sample = uncertainty.latin_hypercube(samples, seed)
    points = (nominal, *(at(p) for p in corners), *(at(p) for p in sample))
    worst_pas = min(points, key=lambda p: (p.passivity_stable, p.tolerant_margin_deg))
    worst_cpl = min(points, key=lambda p: p.coupled_margin)
    with_sampled = [p for p in points if p.sampled_margin_deg is not None]
    worst_smp = min(with_sampled, key=lambda p: p.sampled_margin_deg or 0.0) if with_sampled else None
    candidates = {"passivity": worst_pas, "coupled stability": worst_cpl}
    if worst_smp is not None:
        candidates["sampled passivity"] = worst_smp
    binding = min(candidates, key=lambda name: candidates[name].margin_deg(name) or 0.0)
    return RobustMargins(
        specimen, seed, len(corners), len(sample), nominal, worst_pas, worst_cpl, worst_smp, binding, points
    )
