"""``design_optimized``: the MIL controller as an optimal trade-off (report Sections 1.3, 10.4).

The standardized controller ``u = C_z z_vs + C_w w`` (Eq 6-7) is designed by
convex optimization instead of by one cut-off: minimize the impedance error
of constraint I subject to the passivity margin (III) and the per-path and
summed high-frequency gain bounds (II) on every model of a robust set, with
DC tracking exact.  The result is the same :class:`ControllerDesign` as the
filter design's (same sign convention, same design file, same
implementation step), plus the solver's report in ``design.optimization``.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ConfigError
from ...plant import LinearTable, TableParameters
from ...units import TWO_PI
from ..adapters import table_model
from ..constraints import DesignCriteria, controlled_table, evaluate_constraints, target_impedance
from ..controller import ControllerDesign, FilterSpec, design_controller
from ..forms import VirtualModel, ideal_controller
from ..io import OPTIMIZED_FAMILY
from .basis import PoleBasis, default_basis
from .certify import certify, closed_velocity, path_state_space
from .exchange import dense_rows, exchange, log_points
from .indices import with_indices
from .models import RationalTarget, robust_set
from .problem import OptimizationSettings, Problem, Rows, rows_for
from .realize import realize


def _targets(vs: VirtualModel, robust_vs: Mapping[str, VirtualModel]) -> dict[str, Any]:
    """Label -> target: the design VS first, the robust extras, and a rational model to certify."""
    out: dict[str, Any] = {}
    if vs.equivalent is not None:
        out[f"DF {vs.equivalent.amplitude_in:g} in"] = vs
        out.update(robust_vs)
        out["rational"] = RationalTarget(vs.equivalent.H_zw)
    else:
        out["linear"] = vs
        out.update(robust_vs)
    return out


#: Re-solves driven by the certificate (points where it finds Re H_vw < 0 between grid points).
CERTIFY_ROUNDS = 4

#: Bisection steps on the cap of e_I when the direct minimization stalls.
BISECTION_STEPS = 6

#: Exchange rounds per bisection step.
BISECTION_ROUNDS = 6


def _certified_target(vs: VirtualModel):
    return vs.H_zw if vs.equivalent is None else vs.equivalent.H_zw


def _column_scale(problem: Problem) -> np.ndarray:
    """Inverse column sizes over every row family of the design model (coefficients of order 1)."""
    m = problem.design_model
    rows = rows_for(problem, "I", m, log_points(problem.band_hz, 20))
    rows += rows_for(problem, "III", m, log_points(problem.margin_band_hz, 20))
    rows += rows_for(problem, "II", m, log_points(problem.effort_band_hz, 20))
    rows += rows_for(problem, "T", m, log_points(problem.transition_band_hz, 20))
    size = np.max(np.vstack([np.abs(r.M) for r in rows]), axis=0)
    return 1.0 / np.where(size > 0, size, 1.0)


def build_problem(
    params: TableParameters,
    vs: VirtualModel,
    robust_vs: Mapping[str, VirtualModel],
    criteria: DesignCriteria,
    settings: OptimizationSettings,
    basis: PoleBasis,
) -> Problem:
    """Assemble the :class:`~.problem.Problem` of one design (models, bands, DC equalities, scaling)."""
    tm = table_model(params)
    nyq = tm.nyquist_hz
    models = robust_set(params, _targets(vs, robust_vs))
    ideal = ideal_controller("standardized", tm)
    den = np.asarray(ideal.H_uz.den)
    if not (den.size >= 3 and den[-1] == 0 and den[-2] == 0):
        raise ConfigError("table", "a table whose H_zu has a double zero at s = 0 (Eq 6-8a)")
    a2 = float(ideal.H_uz.num[-1] / den[-3])
    cw0 = float(ideal.H_uw.dcgain())
    fb = log_points(criteria.band_hz, 200)
    Z = target_impedance(vs, "standardized").frequency_response(fb)
    G = float(np.max(np.abs((Z - tm.H_zw.frequency_response(fb)) / tm.H_zu.frequency_response(fb))))
    eff = criteria.effort_band_hz(nyq)
    problem = Problem(
        basis=basis,
        design_model=models[0],
        models=models,
        band_hz=criteria.band_hz,
        effort_band_hz=eff,
        transition_band_hz=(criteria.band_hz[1], eff[0]),
        margin_band_hz=settings.margin_band(nyq),
        effort_gain=G,
        effort_max=criteria.effort_ratio_max,
        transition_max=settings.transition_gain_max,
        margin_deg=settings.margin_deg,
        a2=a2,
        cw0=cw0,
        effort_weight=settings.effort_weight,
        scale=np.ones(basis.n_z + basis.n_w),
    )
    return dataclasses.replace(problem, scale=_column_scale(problem))


def _margins_on(problem: Problem, dense: list[Rows], Cz, Cw) -> dict[str, float]:
    """Smallest raw passivity margin [deg] of each model on the dense grid, controller paths ``Cz``, ``Cw``."""
    out: dict[str, float] = {}
    for m in problem.models:
        f = next(R.f_hz for R in dense if R.kind == "III+" and R.model == m.name)
        r = m.responses(f)
        h = r.P_vw + r.P_vu * (Cw.response(r.s_controller) + Cz.response(r.s_controller) * r.Z)
        out[m.name] = float(np.min(90.0 - np.abs(np.degrees(np.angle(h)))))
    return out


def _tradeoff(
    problem: Problem,
    dense: list[Rows],
    settings: OptimizationSettings,
    t_max: float,
    rounds: int | None = None,
    last_resort: bool = False,
):
    """Smallest normalized passivity deficit ``rho`` with the impedance error capped at ``t_max``."""
    return exchange(
        problem,
        dense,
        initial_per_decade=settings.initial_per_decade,
        max_rounds=rounds or settings.max_rounds,
        tolerance=settings.tolerance,
        t_max=t_max,
        last_resort=last_resort,
    )


def _certificate(params: TableParameters, vs: VirtualModel, problem: Problem, x: np.ndarray):
    """The grid-free certificate of the coefficients ``x`` on the first-order model (see :mod:`.certify`)."""
    xz, xw = problem.split(x)
    Cz, Cw = path_state_space(problem.basis, xz, "z"), path_state_space(problem.basis, xw, "w")
    return _certificate_of(params, vs, problem, Cz, Cw)


def _certificate_of(params: TableParameters, vs: VirtualModel, problem: Problem, Cz, Cw):
    """The grid-free certificate of the realized paths ``Cz``, ``Cw`` (state spaces) on the first-order model."""
    table_ss = LinearTable(params, delay="first-order").state_space()
    return certify(
        "first-order/" + ("rational" if vs.equivalent is not None else "linear"),
        closed_velocity(table_ss, _certified_target(vs), Cz, Cw),
        problem.margin_band_hz,
    )


def _certified_exchange(params, vs, problem: Problem, dense: list[Rows], settings: OptimizationSettings):
    """Exchange loop, then certificate; where it finds ``Re H_vw < 0`` between grid points, add those
    frequencies to every model's passivity rows and solve again (at most :data:`CERTIFY_ROUNDS`)."""
    res = exchange(
        problem,
        dense,
        initial_per_decade=settings.initial_per_decade,
        max_rounds=settings.max_rounds,
        tolerance=settings.tolerance,
    )
    for rnd in range(CERTIFY_ROUNDS):
        x = res.solution.x
        if x is None or not res.solution.ok:
            return res, dense, rnd
        cert = _certificate(params, vs, problem, x)
        if cert.passive:
            return res, dense, rnd
        bad = np.array(
            [np.sqrt(a * b) for a, b in cert.negative_hz] + [f for a, b in cert.negative_hz for f in (a, b)]
        )
        for m in problem.models:
            dense = dense + rows_for(problem, "III", m, np.sort(bad))
        res = exchange(
            problem,
            dense,
            initial_per_decade=settings.initial_per_decade,
            max_rounds=settings.max_rounds,
            tolerance=settings.tolerance,
        )
    return res, dense, CERTIFY_ROUNDS


def _passive(res, settings: OptimizationSettings) -> bool:
    return bool(res.solution.ok and res.solution.t <= settings.tolerance)


def _bisect_error(problem, dense, settings, hi: float, best):
    """Lower the cap on e_I by bisection while the relaxed problem stays passive (``rho = 0``).

    Used when the direct minimization of e_I stalls in the solver; the
    feasibility problems of the bisection are better conditioned.
    """
    lo = 0.0
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        res = _tradeoff(problem, dense, settings, mid, rounds=BISECTION_ROUNDS)
        if _passive(res, settings):
            hi, best = mid, res
        else:
            lo = mid
    return hi, best


def _rebuild(problem: Problem, dense: list[Rows]) -> list[Rows]:
    """Dense rows for a new margin: only the passivity rows depend on it."""
    out, done = [], set()
    for R in dense:
        if not R.kind.startswith("III"):
            out.append(R)
        elif R.model not in done:
            done.add(R.model)
            model = next(m for m in problem.models if m.name == R.model)
            out += rows_for(problem, "III", model, R.f_hz)
    return out


def design_optimized(
    params: TableParameters,
    vs: VirtualModel,
    *,
    fc_hz: float,
    robust_vs: Mapping[str, VirtualModel] | None = None,
    basis: PoleBasis | None = None,
    criteria: DesignCriteria | None = None,
    settings: OptimizationSettings | None = None,
) -> ControllerDesign:
    """Design the standardized MIL controller by optimization (see the module docstring).

    Parameters
    ----------
    params : TableParameters
        The table (Table 4.1); the robust set uses its first-order-delay and
        exact sampled-data models.
    vs : VirtualModel
        The VS to imitate (:func:`~impedance_mil.design.virtual_model`); for
        LR/FP its describing function at the design amplitude is the target of I.
    robust_vs : mapping of str to VirtualModel, optional
        Further VS models on which II and III must hold too (e.g. the
        describing functions at other amplitudes, identified models).
    fc_hz : float
        Cut-off [Hz] of the reference filter design (Section 6.4; the report's
        is ``report_config().design.fc_hz``, no default here), whose
        Butterworth poles the default basis contains, so that the optimum is
        never worse than it when it is feasible.
    basis : PoleBasis, optional
        Default: :func:`~.basis.default_basis` at ``fc_hz``.
    criteria : DesignCriteria, optional
        Thresholds of I and II and the band of interest.
    settings : OptimizationSettings, optional
        Margin, passivity band, grids.

    Returns
    -------
    ControllerDesign
        ``design.optimization`` holds the solver's report: status, whether the
        problem is feasible, the binding constraint and best trade-off when it
        is not, the certificates, the grids and the times.

    Raises
    ------
    ConfigError
        A bad basis, a margin band above the Nyquist frequency, a bad setting.
    MissingDependencyError
        cvxpy or Clarabel is not installed (the ``optimize`` extra).
    """
    start = time.perf_counter()
    c = criteria or DesignCriteria()
    st = settings or OptimizationSettings()
    tm = table_model(params)
    if not (np.isfinite(fc_hz) and 0 < fc_hz < tm.nyquist_hz):
        raise ConfigError(
            "fc", f"a reference cut-off in Hz below the Nyquist frequency {tm.nyquist_hz:g}", fc_hz
        )
    st.margin_band(tm.nyquist_hz)
    basis = basis or default_basis(fc_hz, tm.nyquist_hz)
    if basis.max_hz is None or basis.max_hz > tm.nyquist_hz:
        basis = PoleBasis(basis.poles, basis.integrators, tm.nyquist_hz)
    problem = build_problem(params, vs, robust_vs or {}, c, st, basis)
    dense = dense_rows(problem, st.check_per_decade)
    res, dense, cert_rounds = _certified_exchange(params, vs, problem, dense, st)
    report: dict[str, Any] = {"method": "optimized", "status": res.solution.status}
    final = res
    if res.solution.ok and res.solution.t <= c.performance_max:
        report.update(feasible=True, binding=None)
    else:
        best = _tradeoff(problem, dense, st, c.performance_max)
        if _passive(best, st):  # feasible after all: the direct solve stalled
            cap, final = _bisect_error(problem, dense, st, c.performance_max, best)
            report.update(
                feasible=True,
                binding=None,
                status=f"{best.solution.status} (e_I minimized by bisection: the direct solve stalled)",
                error_cap=cap,
            )
        else:
            if not best.solution.ok:
                best = _tradeoff(problem, dense, st, c.performance_max, last_resort=True)
            binding = "III" if best.solution.ok else "I"
            report.update(feasible=False, binding=binding)
            report["best_tradeoff"] = {
                "performance_max": c.performance_max,
                "passivity_deficit": float(best.solution.t) if best.solution.ok else None,
                "performance_error_at_margin": float(res.solution.t) if res.solution.ok else None,
                "meaning": "passivity_deficit: smallest max_f -Re(exp(+-j delta) H_vw) over the robust set, "
                "in units of |H_vw^vs|, at the allowed impedance error (0: passive with margin delta); "
                "performance_error_at_margin: the smallest e_I with III held",
            }
            if best.solution.ok:
                final = best
            elif not res.solution.ok:
                raise ConfigError(
                    "basis", "a basis with which the DC equalities and the bounds of II can hold"
                )
    x = final.solution.x
    report["certificate_rounds"] = int(cert_rounds)
    design = _finish(params, vs, tm, problem, dense, x, c, st, fc_hz, report, final, start)
    return design


def _finish(
    params, vs, tm, problem, dense, x, criteria, settings, fc_hz, report, res, start
) -> ControllerDesign:
    """Render the coefficients as a ControllerDesign with the constraints, indices and certificates."""
    basis = problem.basis
    xz, xw = problem.split(x)

    def verdicts(Cz, Cw, H_uz, H_uw) -> dict:
        ct = controlled_table(tm, vs, H_uz, H_uw, "standardized")
        r = evaluate_constraints(tm, vs, ct, fc_hz, criteria)
        return {
            "I": r.I,
            "II": r.II,
            "III": r.III,
            "certified": _certificate_of(params, vs, problem, Cz, Cw).passive,
        }

    real = realize(
        basis, xz, xw, settings.reduce, settings.reduce_tolerance, criteria.band_hz, tm.nyquist_hz, verdicts
    )
    H_uz, H_uw, Cz, Cw = real.H_uz, real.H_uw, real.C_z, real.C_w
    f = log_points((criteria.band_hz[0], tm.nyquist_hz), 50)
    s = 1j * TWO_PI * f
    # The rendered transfer functions against the realization they come from (the basis, or the reduced paths).
    exact = np.concatenate([Cz.response(s), Cw.response(s)])
    rendered = np.concatenate([H_uz(s), H_uw(s)])
    ct = controlled_table(tm, vs, H_uz, H_uw, "standardized")
    result = evaluate_constraints(tm, vs, ct, fc_hz, criteria)
    cert = _certificate_of(params, vs, problem, Cz, Cw)
    filt = design_controller(tm, vs, fc_hz=fc_hz, criteria=criteria, emit_warnings=False)
    report.update(
        {
            "certificate": cert.to_dict(),
            "certified": cert.passive,
            "margin_deg": float(problem.margin_deg),
            "dense_margins_deg": _margins_on(problem, dense, Cz, Cw),
            "reduction": real.record,
            "objective_on_grid": float(res.solution.t)
            if report["binding"] is None and "error_cap" not in report
            else None,
            "rounds": int(res.rounds),
            "grid_points": int(res.grid_points),
            "dense_points_per_decade": int(settings.check_per_decade),
            "worst_dense_violation": float(res.worst_violation),
            "converged": bool(res.converged),
            "solver": "CLARABEL (cvxpy)",
            "solver_time_s": float(res.solver_time_s),
            "wall_time_s": float(time.perf_counter() - start),
            "basis": basis.to_dict(),
            "coefficients": {"C_z": [float(v) for v in xz], "C_w": [float(v) for v in xw]},
            "settings": settings.to_dict(),
            "models": [m.name for m in problem.models],
            "realization_error": float(np.max(np.abs(rendered / exact - 1.0))),
            "state_space": {"H_uz": Cz.to_dict(), "H_uw": Cw.to_dict()},
            "zpk": {"H_uz": Cz.zpk(), "H_uw": Cw.zpk()},
            "filter_design": filt.constraints[0].to_dict(),
        }
    )
    if not report["feasible"] and result.all_satisfied and cert.passive:
        # The trade-off solution meets I, II and III after all (its deficit was solver round-off).
        report.update(
            feasible=True, binding=None, status=report["status"] + " (trade-off solution satisfies I/II/III)"
        )
    notes = list(result.violations())
    if not report["feasible"]:
        notes.append(
            f"infeasible: no controller in the basis meets {report['binding']} with margin "
            f"{settings.margin_deg:g} deg; best trade-off: passivity deficit "
            f"{report['best_tradeoff']['passivity_deficit']} at e_I <= {criteria.performance_max:.3f}; "
            f"smallest e_I with III: {report['best_tradeoff']['performance_error_at_margin']}"
        )
    if not cert.passive:
        notes.append(f"passivity certificate failed on {cert.model}: Re H_vw < 0 on {cert.negative_hz} Hz")
    design = ControllerDesign(
        form="standardized",
        reference="z_vs",
        fc_hz=float(fc_hz),
        filter=FilterSpec(OPTIMIZED_FAMILY, basis.n_z - 1, basis.n_w - 1, 0, 0.5, None),
        loop_time_s=float(tm.loop_time_s),
        H_uz=H_uz,
        H_uw=H_uw,
        constraints=(result,),
        warnings=tuple(notes),
        table=dict(tm.parameters),
        vs=filt.vs,
        optimization=report,
    )
    return with_indices(design, params, vs)


__all__ = ["design_optimized", "build_problem", "OptimizationSettings", "PoleBasis"]
