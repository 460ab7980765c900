"""Filtered MIL controller design: one form, one cut-off, constraints checked (Eq 6-9, 6-11).

:func:`design_controller` is the entry point: it builds the ideal controller
of the chosen form (:mod:`.forms`), filters each path with a low-pass filter
of the order its relative degree requires (:mod:`.filters`), evaluates the
three constraints (:mod:`.constraints`) at the cut-off and at any other
cut-offs asked for, and returns a :class:`ControllerDesign`.

The design is continuous-time: a cut-off at or above the Nyquist frequency
of the loop is allowed for analysis (Table 9.5 uses 1000 Hz with a 2000 Hz
loop) but carries a warning; :mod:`impedance_mil.implement` refuses it.
"""

from __future__ import annotations

import warnings as _warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from .. import __version__
from ..errors import ConfigError, DesignWarning, NotEvaluatedError, UnstableDesignError
from ..report_config import report_config
from ..systems import TransferFunction
from ..units import TWO_PI
from .constraints import (
    ConstraintResult,
    ControlledTable,
    DesignCriteria,
    controlled_table,
    evaluate_constraints,
)
from .filters import FAMILIES, apply_filter
from .forms import (
    FORMS,
    IdealController,
    TableModel,
    VirtualModel,
    environment,
    ideal_controller,
    imaginary_axis,
    right_half_plane,
)
from .sampling import implementable_fc


@dataclass(frozen=True)
class FilterSpec:
    """The filters of a design: family and the order on each path.

    Attributes
    ----------
    family : str
        Filter family.
    order_z, order_w : int
        Order on the reference path (``H_uz``) and on the ``w`` path.
    order_fh : int
        Order on the ``f_h`` path (0 when absent).
    ripple_db : float
        Chebyshev I ripple [dB].
    fc_w_hz : float or None
        Separate cut-off of the ``w`` path [Hz]; None: same as ``fc_hz``.
    """

    family: str
    order_z: int = 3
    order_w: int = 3
    order_fh: int = 0
    ripple_db: float = 0.5
    fc_w_hz: float | None = None

    def to_dict(self) -> dict:
        return {
            "family": self.family,
            "order_z": int(self.order_z),
            "order_w": int(self.order_w),
            "order_fh": int(self.order_fh),
            "ripple_db": float(self.ripple_db),
            "fc_w_hz": None if self.fc_w_hz is None else float(self.fc_w_hz),
        }


@dataclass(frozen=True)
class ControllerDesign:
    """A filtered, proper MIL controller ``u = H_uz r + H_uw w [+ H_ufh f_h]``.

    Attributes
    ----------
    form : str
        ``standardized``, ``vs-specific``, ``tracking`` or ``general``.
    reference : str
        The signal ``H_uz`` multiplies: ``"z_vs"`` (standardized) or ``"a_g"``.
    fc_hz : float
        Cut-off frequency of the filters [Hz].
    filter : FilterSpec
    loop_time_s : float
        Loop time of the table controller [s].
    H_uz, H_uw : TransferFunction
        Filtered controller paths, proper, descending powers of s [rad/s];
        every path is *added* (the minus sign of Eq 6-9 is inside H_uw).
    H_ufh : TransferFunction or None
    constraints : tuple of ConstraintResult
        Constraints at ``fc_hz`` first, then at the other cut-offs asked for.
    feasible_fc_hz : (float, float) or None
        Range of cut-offs satisfying all constraints, when computed.
    warnings : tuple of str
    table : mapping
        Table parameters (``TableParameters.to_dict()``).
    vs : mapping or None
        ``{"kind", "name", "parameters"}`` of the VS (None for tracking).
    software_version : str
    optimization : mapping or None
        The solver's report of an optimized design (:mod:`impedance_mil.design.optimized`);
        None for a filter design.
    amplitude_certificate : mapping or None
        Constraint III of an LR/FP design over a range of isolator amplitudes
        (:mod:`impedance_mil.design.optimized.amplitudes`), when computed.
    capacity : mapping
        Stated capacity of a table given as a linear model (``TableModel.capacity``,
        internal units); empty for a physical table.
    table_paths : mapping
        For a table given as a linear model, the paths the design used:
        ``{"H_zu": ..., "H_zw": ...}`` (so that a run can check it is the same
        table); empty for a physical table, whose ``table`` parameters say it.
    """

    form: str
    reference: str
    fc_hz: float
    filter: FilterSpec
    loop_time_s: float
    H_uz: TransferFunction
    H_uw: TransferFunction
    H_ufh: TransferFunction | None = None
    constraints: tuple[ConstraintResult, ...] = ()
    feasible_fc_hz: tuple[float, float] | None = None
    warnings: tuple[str, ...] = ()
    table: Mapping[str, Any] = field(default_factory=dict)
    vs: Mapping[str, Any] | None = None
    software_version: str = __version__
    optimization: Mapping[str, Any] | None = None
    amplitude_certificate: Mapping[str, Any] | None = None
    capacity: Mapping[str, float] = field(default_factory=dict)
    table_paths: Mapping[str, TransferFunction] = field(default_factory=dict)

    def constraint_at(self, fc_hz: float) -> ConstraintResult:
        """The constraint result for a cut-off [Hz] (NotEvaluatedError, a KeyError, when not evaluated)."""
        for c in self.constraints:
            if np.isclose(c.fc_hz, fc_hz, rtol=1e-9):
                return c
        raise NotEvaluatedError(f"constraints not evaluated at fc = {fc_hz} Hz")

    def to_json(self) -> dict:
        """The ``imil design --json`` document (see docs/design.md)."""
        return {
            "form": self.form,
            "reference": self.reference,
            "fc_hz": float(self.fc_hz),
            "filter": self.filter.to_dict(),
            "loop_time_s": float(self.loop_time_s),
            "H_uz": self.H_uz.to_dict(),
            "H_uw": self.H_uw.to_dict(),
            "H_ufh": None if self.H_ufh is None else self.H_ufh.to_dict(),
            "sign_convention": f"u = H_uz*{self.reference} + H_uw*w"
            + (" + H_ufh*f_h" if self.H_ufh is not None else ""),
            "constraints": [c.to_dict() for c in self.constraints],
            "feasible_fc_hz": None
            if self.feasible_fc_hz is None
            else [float(x) for x in self.feasible_fc_hz],
            "warnings": list(self.warnings),
            **(
                {}
                if self.optimization is None
                else {"method": "optimized", "optimization": self.optimization}
            ),
            **(
                {}
                if self.amplitude_certificate is None
                else {"passivity_amplitude_certificate": self.amplitude_certificate}
            ),
        }


@dataclass(frozen=True)
class FilteredPaths:
    """The filtered paths of an ideal controller at one cut-off (internal result)."""

    H_uz: TransferFunction
    H_uw: TransferFunction
    H_ufh: TransferFunction | None
    spec: FilterSpec


def report_design_choices(form: str | None, family: str | None) -> tuple[str, str]:
    """Controller form and filter family, the report's (``[design]`` of the report's setup) where None."""
    design = report_config().design
    return (design.form if form is None else form, design.filter if family is None else family)


def filter_controller(
    ideal: IdealController,
    fc_hz: float,
    family: str,
    order: int | None = None,
    ripple_db: float = 0.5,
    fc_w_hz: float | None = None,
) -> FilteredPaths:
    """Filter every path of an ideal controller (Eq 6-9).

    Parameters
    ----------
    ideal : IdealController
    fc_hz : float
        Cut-off [Hz] of the reference (and f_h) paths, and of the w path
        unless ``fc_w_hz`` is given.
    family : str
        Filter family, one of :data:`~impedance_mil.design.filters.FAMILIES`.
    order : int, optional
        One order for every path; default the lowest each path needs.
    ripple_db : float
        Chebyshev I ripple [dB].
    fc_w_hz : float, optional
        Separate cut-off of the w path [Hz].

    Raises
    ------
    ConfigError
        Bad family, non-positive cut-off, or an order below a path's relative degree.
    """
    if family not in FAMILIES:
        raise ConfigError("filter", "one of " + ", ".join(FAMILIES), family)
    fw = fc_hz if fc_w_hz is None else fc_w_hz
    H_uz, oz = apply_filter(ideal.H_uz, family, fc_hz, order, ripple_db)
    H_uw, ow = apply_filter(ideal.H_uw, family, fw, order, ripple_db)
    H_ufh, of = (None, 0)
    if ideal.H_ufh is not None:
        H_ufh, of = apply_filter(ideal.H_ufh, family, fc_hz, order, ripple_db)
    return FilteredPaths(H_uz, H_uw, H_ufh, FilterSpec(family, oz, ow, of, ripple_db, fc_w_hz))


class DesignAtFc(NamedTuple):
    """One cut-off of a design: filtered paths, controlled table, constraints (internal result)."""

    paths: FilteredPaths
    controlled: ControlledTable
    constraints: ConstraintResult


def design_at_fc(
    table: TableModel,
    env: VirtualModel,
    ideal: IdealController,
    fc_hz: float,
    criteria: DesignCriteria | None = None,
    *,
    family: str,
    order: int | None = None,
    ripple_db: float = 0.5,
    fc_w_hz: float | None = None,
) -> DesignAtFc:
    """Filter ``ideal`` at ``fc_hz`` [Hz] (:func:`filter_controller`) and evaluate constraints I, II, III.

    ``env`` is the VS model of :func:`~impedance_mil.design.forms.environment`;
    the other parameters are those of :func:`filter_controller` and
    :func:`~impedance_mil.design.constraints.evaluate_constraints`.
    """
    paths = filter_controller(ideal, fc_hz, family, order, ripple_db, fc_w_hz)
    ct = controlled_table(table, env, paths.H_uz, paths.H_uw, ideal.form)
    return DesignAtFc(paths, ct, evaluate_constraints(table, env, ct, fc_hz, criteria))


def check_proper_and_stable(paths: FilteredPaths) -> list[str]:
    """Refuse an improper or unstable filtered controller; return warnings for marginal poles.

    Poles at the origin (the double integrator of ``1/H_zu``, Eq 6-8a) and
    simple poles on the imaginary axis (the lossless FP linear part) are
    allowed with a warning for the latter.

    Raises
    ------
    UnstableDesignError
        A path is improper or has a right-half-plane pole.
    """
    notes = []
    for name, H in (("H_uz", paths.H_uz), ("H_uw", paths.H_uw), ("H_ufh", paths.H_ufh)):
        if H is None:
            continue
        if not H.is_proper:
            raise UnstableDesignError(f"filtered {name} is improper (relative degree {H.relative_degree})")
        p = H.poles()
        bad = right_half_plane(p)
        if bad.size:
            worst = bad[np.argmax(bad.real)]
            raise UnstableDesignError(
                f"filtered {name} has an unstable pole at {worst.real:.4g}{worst.imag:+.4g}j rad/s"
            )
        axis = imaginary_axis(p)
        axis = axis[np.abs(axis) > 1e-9]  # poles at the origin are expected (Eq 6-8a)
        if axis.size:
            notes.append(
                f"{name} has undamped poles at {np.abs(axis[0]) / TWO_PI:.3g} Hz "
                "(lossless VS linear part): the controller relies on the VS model's f_h for damping"
            )
    return notes


def design_controller(
    table: TableModel,
    vs: VirtualModel | None = None,
    *,
    fc_hz: float,
    form: str | None = None,
    family: str | None = None,
    order: int | None = None,
    ripple_db: float = 0.5,
    fc_w_hz: float | None = None,
    evaluate_fc_hz: Sequence[float] = (),
    criteria: DesignCriteria | None = None,
    feasible_fc_hz: tuple[float, float] | None = None,
    emit_warnings: bool = True,
) -> ControllerDesign:
    """Design the filtered MIL controller of one form at one cut-off.

    Parameters
    ----------
    table : TableModel
        Linear table model (Eq 4-15a, 4-15d) and loop time.
    vs : VirtualModel, optional
        Linear part of the VS.  Required for ``general`` and ``vs-specific``;
        for ``standardized`` it is used only to evaluate the constraints
        (without it they are evaluated as for tracking); ignored for ``tracking``.
    fc_hz : float
        Cut-off [Hz], > 0 (the report's is ``report_config().design.fc_hz``, 80 Hz).
    form : str, optional
        One of :data:`~impedance_mil.design.forms.FORMS`; default the report's
        (``[design] form`` of the report's setup: standardized).
    family : str, optional
        Filter family; default the report's (``[design] filter``: butterworth).
    order, ripple_db, fc_w_hz
        Filter choice (see :func:`filter_controller`).
    evaluate_fc_hz : sequence of float
        Further cut-offs [Hz] at which to evaluate the constraints.
    criteria : DesignCriteria, optional
        Constraint thresholds.
    feasible_fc_hz : (float, float), optional
        Feasible range to record (from :func:`~impedance_mil.design.feasibility.feasible_fc_range`).
    emit_warnings : bool
        Also issue each warning as a :class:`~impedance_mil.errors.DesignWarning`.

    Returns
    -------
    ControllerDesign

    Raises
    ------
    ConfigError
        Unknown form or filter, non-positive cut-off, order below the relative degree.
    UnstableDesignError, UnstableSystemError
        An unstable table, a non-minimum-phase ``H_zu``, an improper or
        unstable VS, or an unstable filtered controller.

    Examples
    --------
    >>> from impedance_mil.plant import TableParameters
    >>> from impedance_mil.design import table_model
    >>> d = design_controller(table_model(TableParameters.report_default()), fc_hz=80.0,
    ...                       emit_warnings=False)
    >>> d.H_uw.is_proper, d.filter.order_w
    (True, 3)
    """
    form, family = report_design_choices(form, family)
    if form not in FORMS:
        raise ConfigError("form", "one of " + ", ".join(FORMS), form)
    for key, value in (("fc", fc_hz), ("fc_w", fc_w_hz)):
        if value is not None and not (np.isfinite(value) and value > 0):
            raise ConfigError(key, "a positive cut-off frequency in Hz", value)
    c = criteria or DesignCriteria()
    env = environment(form, vs)
    ideal = ideal_controller(form, table, env)
    notes: list[str] = []
    results = []
    paths = None
    for k, fc in enumerate([fc_hz, *[x for x in evaluate_fc_hz if not np.isclose(x, fc_hz)]]):
        if not (np.isfinite(fc) and fc > 0):
            raise ConfigError("fc", "a positive cut-off frequency in Hz", fc)
        at = design_at_fc(
            table,
            env,
            ideal,
            fc,
            c,
            family=family,
            order=order,
            ripple_db=ripple_db,
            fc_w_hz=fc_w_hz if k == 0 else None,
        )
        if k == 0:
            paths = at.paths
            notes += check_proper_and_stable(at.paths)
        results.append(at.constraints)
    notes += _warnings_for(table, fc_hz, fc_w_hz, results, vs is None and form == "standardized")
    if form == "tracking" or vs is None:
        notes.append(
            "tracking: the target impedance is zero (a lossless, rigid environment), so constraint I "
            "is measured against the bare table and the passivity verdict III of the small residual "
            "impedance is not a stability criterion; see docs/design.md, Limitations"
        )
    elif vs.H_zfh is not None and (vs.equivalent is None or form != "standardized"):
        notes.append(
            f"{vs.kind}: constraints are evaluated on the VS linear part with f_h as an open input "
            "(initial stiffness, no hysteretic damping): conservative; see docs/design.md, Limitations"
        )
    elif vs.H_zfh is not None:
        eq = vs.equivalent
        notes.append(
            f"{vs.kind}: constraints use the {eq.method} linearization of the isolator at "
            f"{eq.amplitude_in:g} in (k_eff = {eq.k_eff:.4g} lbf/in, beta_eff = {eq.beta_eff:.2f}); "
            "verdicts depend on that amplitude; see docs/design.md, Limitations"
        )
    design = ControllerDesign(
        form=form,
        reference=ideal.reference,
        fc_hz=float(fc_hz),
        filter=paths.spec,
        loop_time_s=float(table.loop_time_s),
        H_uz=paths.H_uz,
        H_uw=paths.H_uw,
        H_ufh=paths.H_ufh,
        constraints=tuple(results),
        feasible_fc_hz=feasible_fc_hz,
        warnings=tuple(notes),
        table=dict(table.parameters),
        capacity=dict(table.capacity),
        table_paths={} if table.parameters else {"H_zu": table.H_zu, "H_zw": table.H_zw},
        vs=None
        if form == "tracking" or vs is None
        else {
            "kind": vs.kind,
            "name": vs.name,
            "parameters": dict(vs.parameters),
            **({"linearization": vs.equivalent.to_dict()} if vs.equivalent is not None else {}),
            **({"definition": dict(vs.definition)} if vs.definition is not None else {}),
        },
    )
    if emit_warnings:
        for text in notes:
            _warnings.warn(text, DesignWarning, stacklevel=2)
    return design


def _warnings_for(
    table: TableModel, fc_hz: float, fc_w_hz: float | None, results: list[ConstraintResult], no_vs: bool
) -> list[str]:
    notes = []
    nyq = table.nyquist_hz
    for name, fc in (("fc", fc_hz), ("fc_w", fc_w_hz)):
        if fc is not None and not implementable_fc(fc, table.loop_time_s):
            notes.append(
                f"{name} = {fc:g} Hz is at or above the Nyquist frequency {nyq:g} Hz of the "
                f"{table.loop_time_s * 1e6:g} us loop: valid for continuous-time analysis only; "
                "the implementation step will refuse it"
            )
    first = results[0]
    notes += first.violations()
    if first.III and first.passivity_margin_deg < 0:
        notes.append(
            f"marginally non-passive: margin {first.passivity_margin_deg:.2f} deg at "
            f"{first.passivity_worst_hz:.3g} Hz, within the first-order delay-model tolerance "
            "(see docs/design.md)"
        )
    if no_vs:
        notes.append("no virtual system given: constraints evaluated for acceleration tracking (H_zw^vs = 0)")
    return notes
