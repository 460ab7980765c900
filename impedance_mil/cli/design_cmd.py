"""`imil design`: design the impedance-matching MIL controller (report Sections 6, 8.1, 9.4).

Builds the linear table model (``--table``, default the report's table) and
the VS linear part (``--vs``), designs the filtered controller of the chosen
form at one cut-off (``--fc 80``), several (``--fc 80,100,250``: the first is
the design, all are evaluated) or an automatic one (``--fc auto``), checks
constraints I, II, III, and writes the design file (``-o``) and the
Figure 9.31 plots (``--plots DIR``).  The form, the cut-off and the filter
family default to the report's (``[design]`` of the report's setup file), the
constraint thresholds to :class:`~impedance_mil.design.DesignCriteria`'s.
With ``--method both --map-x NAME=VALUES --map-y NAME=VALUES`` it maps a VS
family instead (:mod:`impedance_mil.cli.design_map`): where the filter design
meets I, II, III, where only the optimized design does, and where neither
does; ``-o`` then writes the map's plot.

Exit status: 0 on success (also when a constraint is violated: the
violation is a warning in the output and the JSON); 2 for bad input or an
impossible design (one line on stderr, nothing written).  Every option's
value is checked whatever ``--method`` and ``--filter`` are: ``--grid 0``
is refused under the filter method too, and ``--ripple-db nan`` with a
Butterworth filter (an option the method does not use is ignored, so one
command line can be tried with both methods).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import typer

from ..config import parse_overrides, quantity
from ..design import DesignCriteria, design_controller, save_design, table_model, virtual_model
from ..design.constraints import PASSIVITY_MODELS
from ..design.controller import ControllerDesign
from ..design.feasibility import FcScan, choose_fc, mass_ratio_study, scan_fc
from ..design.filters import FAMILIES, check_order, check_ripple
from ..design.forms import FORMS, TableModel, VirtualModel
from ..design.linearize import DEFAULT_AMPLITUDE_IN, METHODS
from ..design.measured import CONTROLLER_MODELS, TOLERANCES, check_loop_time, design_measured_checks
from ..design.optimized import OptimizationSettings, design_optimized, with_indices
from ..design.optimized.amplitudes import (
    HYSTERETIC_KINDS,
    VS_MODELS,
    amplitude_certificate,
    check_amplitude_range,
    summary,
    with_amplitude_certificate,
)
from ..design.robust import DEFAULT_LHS_SAMPLES, robust_margins
from ..display import UnitSystem, display_unit
from ..errors import ConfigError
from ..lab.labfile import LabSetup, load_lab
from ..lab.robust import article_impedance, lab_article, lab_force_sensor, require_uncertainty
from ..plant import TableParameters
from ..plant.frf_table import FRFTable, read_frf_table
from ..plant.lti_table import LTITable
from ..plant.table_files import TableDefinition
from ..report.design_plots import INDEX_UNIT, plot_constraint_summary, plot_design_rows
from ..report.motion_plots import save_figure
from ..report_config import report_config
from ..specimens import FluidVessel
from ..virtual.files import VSSpec, resolve
from .common import (
    LabOpt,
    UnitsOpt,
    console,
    option_errors,
    output_units,
    positive_numbers,
    print_json,
    table_definition,
)
from .design_map import MapRequest, run_map

_DESIGN = report_config().design
_BAND_TEXT = ",".join(f"{f:g}" for f in DesignCriteria().band_hz)


#: The options of the library's design keys, for its errors (``form`` -> ``--form``).
DESIGN_OPTIONS = {
    "form": "--form",
    "fc": "--fc",
    "fc_w": "--fc-w",
    "filter": "--filter",
}
#: The options of the constraint thresholds (DesignCriteria's keys).
CRITERIA_OPTIONS = {
    "band_hz": "--band",
    "performance_max": "--performance-max",
    "effort_ratio_max": "--effort-max",
    "passivity_extra_tolerance_deg": "--passivity-tol",
}


def _parse_fc(text: str) -> list[float] | None:
    """``"auto"`` -> None; ``"80"`` or ``"80,100,250"`` -> list of positive floats [Hz]."""
    if text.strip().lower() == "auto":
        return None
    return positive_numbers(
        "--fc",
        text,
        "a cut-off in Hz, a comma-separated list, or 'auto'",
        "positive cut-off frequencies in Hz",
    )


def _parse_list(option: str, text: str | None, count: int | None = None) -> list[float] | None:
    if text is None:
        return None
    return positive_numbers(
        option, text, "comma-separated numbers", f"{count or 'some'} positive comma-separated numbers", count
    )


def design(
    table: Path | None = typer.Option(None, "--table", help="Table file (TOML); default the report's table."),
    lab: str | None = LabOpt,
    vs: str | None = typer.Option(None, "--vs", help="VS preset (SD1..FP3) or VS file (TOML)."),
    sets: list[str] | None = typer.Option(None, "--set", help="Table value KEY=VALUE."),
    sets_vs: list[str] | None = typer.Option(None, "--set-vs", help="VS value KEY=VALUE."),
    form: str | None = typer.Option(
        None,
        "--form",
        help=f"standardized | vs-specific | tracking | general (default the report's {_DESIGN.form}).",
    ),
    fc: str | None = typer.Option(
        None,
        "--fc",
        help=f"Cut-off [Hz]: 80, 80,100,250 (first is the design) or auto (default the report's {_DESIGN.fc_hz:g}).",
    ),
    fc_w: float | None = typer.Option(None, "--fc-w", help="Separate cut-off of the w path [Hz]."),
    family: str | None = typer.Option(
        None, "--filter", help=f"butterworth | bessel | chebyshev1 (default the report's {_DESIGN.filter})."
    ),
    order: int | None = typer.Option(None, "--order", help="Filter order (default: the relative degree)."),
    ripple_db: float = typer.Option(0.5, "--ripple-db", help="Chebyshev I pass-band ripple [dB]."),
    band: str | None = typer.Option(
        None,
        "--band",
        help=f"Band of interest LO,HI [Hz] (default {_BAND_TEXT}).",
    ),
    performance_max: float | None = typer.Option(
        None,
        "--performance-max",
        help="Constraint I limit (relative impedance error; default the half-power error).",
    ),
    effort_max: float | None = typer.Option(
        None,
        "--effort-max",
        help=f"Constraint II limit (HF/in-band gain; default {DesignCriteria().effort_ratio_max:g}).",
    ),
    passivity_tol: float | None = typer.Option(
        None, "--passivity-tol", help="Extra passivity tolerance [deg] (default 0)."
    ),
    mass_ratios: str | None = typer.Option(
        None, "--mass-ratios", help="Basemat-mass study: m_vs/m_st values, e.g. 1.25,1,0.8."
    ),
    linearization: str = typer.Option(
        "describing-function",
        "--linearization",
        help="LR/FP in the constraints: " + " | ".join(METHODS) + ".",
    ),
    amplitude: float = typer.Option(
        DEFAULT_AMPLITUDE_IN, "--amplitude", help="Design displacement amplitude of the LR/FP isolator [in]."
    ),
    method: str = typer.Option(
        "filter",
        "--method",
        help="filter (Section 6.4) | optimized (Section 10.4: convex, certified passivity) "
        "| both (with --map-x/--map-y: the feasibility map of both methods).",
    ),
    map_x: str | None = typer.Option(
        None,
        "--map-x",
        help="Feasibility map (--method both): axis NAME=v1,v2,... or NAME=LO:HI:N; NAME mass_ratio "
        "(m_vs/m_st), period [s] or a VS key. -o then writes the map's plot (.png, .svg, .pdf).",
    ),
    map_y: str | None = typer.Option(None, "--map-y", help="Feasibility map: the second axis (as --map-x)."),
    margin: float = typer.Option(
        0.0, "--margin", help="Optimized: passivity margin delta [deg], phase of H_vw within +-(90 - delta)."
    ),
    margin_band: str | None = typer.Option(
        None, "--margin-band", help="Optimized: band LO,HI [Hz] of the margin (default 0.01 Hz to Nyquist)."
    ),
    robust_amplitudes: str = typer.Option(
        "0.25,4",
        "--robust-amplitudes",
        help="Optimized, LR/FP: further DF amplitudes [in] of the robust set.",
    ),
    amplitude_range: str | None = typer.Option(
        None,
        "--amplitude-range",
        help="LR/FP: certify III over the isolator amplitudes LO:HI [in, or with units: '6 mm:100 mm'] "
        "(default for --method optimized: the range of --robust-amplitudes and --amplitude).",
    ),
    grid: int = typer.Option(
        OptimizationSettings().check_per_decade, "--grid", help="Optimized: dense check grid [points/decade]."
    ),
    passivity_model: str = typer.Option(
        "first-order",
        "--passivity-model",
        help="Model of constraint III's verdict: first-order (delay model with its tolerance, "
        "reproduces Table 9.5) | sampled (exact sampled-data table, with the hold) | strictest (both).",
    ),
    reduce: str = typer.Option(
        "none",
        "--reduce",
        help="Optimized: order reduction of the realization: none | auto (smallest orders keeping the "
        "I/II/III verdicts and the certificate) | ORDER (states of each path).",
    ),
    frf: Path | None = typer.Option(
        None,
        "--frf",
        help='Measured-FRF table file (TOML, [model] kind = "frf"): also check I, III on the data, model-free.',
    ),
    frf_tolerance: str = typer.Option(
        "none",
        "--frf-tolerance",
        help="Passivity tolerance on the FRF: none (a measurement has no delay-model error) | delay-model.",
    ),
    frf_controller: str = typer.Option(
        "continuous",
        "--frf-controller",
        help="Controller response on the FRF: continuous (as designed) | tustin (as implemented).",
    ),
    robust: bool = typer.Option(
        False,
        "--robust",
        help="Worst-case passivity and coupled-stability margins over the lab's [uncertainty] set "
        "(--lab FILE), with the lab's article.",
    ),
    robust_samples: int = typer.Option(
        DEFAULT_LHS_SAMPLES,
        "--robust-samples",
        help="--robust: Latin-hypercube points besides the box's vertices.",
    ),
    robust_seed: int = typer.Option(0, "--robust-seed", help="--robust: seed of the Latin-hypercube sample."),
    linearized_table: bool = typer.Option(
        False,
        "--linearized-table",
        help="Design on the virtual table linearized at rest, with the lab's [dynamics] (issue 17), "
        "instead of Eq 4-11 (physical table, first-order passivity model, not with --robust).",
    ),
    json_out: bool = typer.Option(False, "--json", help="Print JSON."),
    plots: Path | None = typer.Option(None, "--plots", help="Folder for the Figure 9.31 plots."),
    output: Path | None = typer.Option(
        None, "-o", "--output", help="Write the design file (JSON); with --map-x the map's plot."
    ),
    units: str | None = UnitsOpt,
) -> None:
    """Design the impedance-matching MIL controller and check constraints I, II, III."""
    shown = output_units(units, lab, table)
    given = {"design.form": form, "design.fc": fc, "design.filter": family}
    defaults = {"design.form": _DESIGN.form, "design.fc": _DESIGN.fc_hz, "design.filter": _DESIGN.filter}
    from_report = {key: defaults[key] for key, value in given.items() if value is None}
    form = _DESIGN.form if form is None else form
    family = _DESIGN.filter if family is None else family
    if form not in FORMS:
        raise ConfigError("--form", "one of " + ", ".join(FORMS), form)
    if family not in FAMILIES:
        raise ConfigError("--filter", "one of " + ", ".join(FAMILIES), family)
    mapping = map_x is not None or map_y is not None
    if plots is not None and not plots.is_dir():
        raise ConfigError("--plots", "an existing folder", str(plots))
    if mapping and (form != "standardized" or mass_ratios is not None or frf is not None):
        raise ConfigError("--map-x", "the standardized form, without --mass-ratios and --frf")
    if output is not None and not output.parent.is_dir():
        raise ConfigError("-o", "a path in an existing folder", str(output))
    if passivity_model not in PASSIVITY_MODELS:
        raise ConfigError("--passivity-model", " | ".join(PASSIVITY_MODELS), passivity_model)
    if method not in ("filter", "optimized", "both") or (method == "both") != mapping:
        raise ConfigError(
            "--method", "filter or optimized, or both with --map-x and --map-y (the feasibility map)", method
        )
    # Every option's value is checked whatever the method and filter (one that does not use it ignores it).
    with option_errors({"ripple_db": "--ripple-db", "filter order": "--order"}):
        check_ripple(ripple_db)
        if order is not None:
            check_order(order)
    if fc_w is not None and not 0 < fc_w < math.inf:
        raise ConfigError("--fc-w", "a positive cut-off frequency in Hz", fc_w)
    settings, amplitudes = _optimization_options(margin, margin_band, grid, robust_amplitudes, reduce)
    amp_range = _parse_amplitude_range(amplitude_range)
    fcs = [_DESIGN.fc_hz] if fc is None else _parse_fc(fc)
    band_values = _parse_list("--band", band, 2)
    criteria_given: dict[str, Any] = {
        "band_hz": None if band_values is None else tuple(band_values),
        "performance_max": performance_max,
        "effort_ratio_max": effort_max,
        "passivity_extra_tolerance_deg": passivity_tol,
    }
    with option_errors(CRITERIA_OPTIONS):
        criteria = DesignCriteria(**{k: v for k, v in criteria_given.items() if v is not None})
    ratios = _parse_list("--mass-ratios", mass_ratios)
    params = table_definition(table, sets, lab)  # physical, or an LTI table ([model])
    setup = _robust_lab(robust, lab, table, sets, robust_samples, robust_seed, mapping or method != "filter")
    if linearized_table and (
        not isinstance(params, TableParameters)
        or passivity_model != "first-order"
        or robust
        or method != "filter"
    ):
        raise ConfigError(
            "--linearized-table",
            "a physical table, --method filter, --passivity-model first-order and no --robust",
        )
    tm = table_model(params, linearized=linearized_table)
    if passivity_model != "first-order" and not isinstance(params, TableParameters):
        raise ConfigError(
            "--passivity-model", "first-order for an LTI table (no sampled-data model)", passivity_model
        )
    measured_frf = _read_frf(frf, frf_tolerance, frf_controller, tm.loop_time_s)
    frf_kw: dict[str, Any] = dict(tolerance=frf_tolerance, controller_model=frf_controller, criteria=criteria)
    spec = None
    if vs is not None and form != "tracking":
        spec = resolve(vs, parse_overrides(sets_vs, option="--set-vs"))
    if linearization not in METHODS:
        raise ConfigError("--linearization", "one of " + ", ".join(METHODS), linearization)
    if not amplitude > 0:
        raise ConfigError("--amplitude", "a positive displacement amplitude in in", amplitude)
    lin: dict[str, Any] = dict(linearization=linearization, amplitude_in=amplitude)
    if mapping:
        if fcs is None:
            raise ConfigError("--fc", "a reference cut-off in Hz for the feasibility map (not auto)", fc)
        request = MapRequest(params, vs, sets_vs, lin, amplitudes, fcs[0], criteria, settings, from_report)
        run_map(request, map_x or "", map_y, output, json_out, shown)
        return
    if amp_range is not None and (
        spec is None or spec.vs.kind not in HYSTERETIC_KINDS or form != "standardized"
    ):
        raise ConfigError("--amplitude-range", "an LR or FP VS (--vs) and the standardized form")
    if amp_range is not None and not isinstance(params, TableParameters):
        raise ConfigError(
            "--amplitude-range", "a physical table (the certificate uses its sampled-data model)"
        )
    vm = virtual_model(spec.vs, spec.name, **lin) if spec is not None else None
    if vm is None and form in ("general", "vs-specific"):
        raise ConfigError("--vs", f"a VS preset or file for the {form} form")
    if method == "optimized":
        if isinstance(params, LTITable):
            raise ConfigError(
                "--method",
                "filter for an LTI table (optimized needs the physical table's sampled-data model)",
                method,
            )
        if vm is None or form != "standardized":
            raise ConfigError("--method", "a VS (--vs) and the standardized form for the optimized design")
        if spec is None:
            raise ConfigError("--vs", "a VS preset or file")
        if fcs is None:
            raise ConfigError("--fc", "a reference cut-off in Hz for --method optimized (not auto)", fc)
        result = _optimized(params, spec, lin, vm, fcs[0], criteria, settings, amplitudes)
        if passivity_model != "first-order":
            result = with_indices(result, params, vm, criteria, warn=False, passivity_model=passivity_model)
        if amp_range is None and spec.vs.kind in HYSTERETIC_KINDS:  # the range the robust set covers
            amp_range = (min(amplitudes + [amplitude]), max(amplitudes + [amplitude]))
        result = _with_certificate(result, params, spec, amp_range, criteria, linearization)
        measured = _measured_checks(result, measured_frf, None, vm, frf_kw)
        if output is not None:
            save_design(result, output)
        doc = result.to_json()
        doc["from_report"] = from_report
        doc["vs_linearization"] = vm.equivalent.to_dict() if vm.equivalent is not None else None
        if measured:
            doc["measured"] = _measured_doc(frf, measured)
        if json_out:
            print_json(doc, shown)
        else:
            _print_human(result, [], [], [output] if output is not None else [], measured, shown)
        return
    kw: dict[str, Any] = dict(form=form, family=family, order=order, criteria=criteria)
    with option_errors(DESIGN_OPTIONS):
        if fcs is None:
            choice = choose_fc(tm, vm, **kw)
            fcs, reasons, scan = [choice.fc_hz], list(choice.reasons), choice.scan
        else:
            reasons, scan = [], scan_fc(tm, vm, **kw)
        result = design_controller(
            tm,
            vm,
            fc_hz=fcs[0],
            evaluate_fc_hz=fcs[1:],
            fc_w_hz=fc_w,
            ripple_db=ripple_db,
            feasible_fc_hz=scan.feasible_fc_hz,
            emit_warnings=False,
            **kw,
        )
    # the sampled-data indices and the certificate are of Eq 4-11: not for --linearized-table
    if isinstance(params, TableParameters) and not linearized_table:
        result = with_indices(result, params, vm, criteria, warn=False, passivity_model=passivity_model)
        result = _with_certificate(result, params, spec, amp_range, criteria, linearization)
    robustness = None
    if setup is not None and isinstance(params, TableParameters) and setup.uncertainty is not None:
        article = lab_article(setup)
        robustness = robust_margins(
            result,
            params,
            vm,
            setup.uncertainty,
            article_impedance(article),
            article.label,
            samples=robust_samples,
            seed=robust_seed,
            criteria=criteria,
            force_sensor=lab_force_sensor(setup.sensors.suite, setup.controller.feedback),
        )
    measured = _measured_checks(result, measured_frf, tm, vm, frf_kw)
    study = _mass_ratio_rows(tm, vs, sets_vs, spec, lin, ratios, form, criteria, fcs[0]) if ratios else []
    written = (
        []
        if plots is None
        else _write_plots(
            plots, params, result, vm, fcs, scan, (form, family, order), criteria, spec, shown, tm
        )
    )
    if output is not None:
        written.append(save_design(result, output))
    doc = result.to_json()
    doc["zpk"] = {
        name: H.to_zpk()
        for name, H in (("H_uz", result.H_uz), ("H_uw", result.H_uw), ("H_ufh", result.H_ufh))
        if H is not None
    }
    doc["fc_choice_reasons"] = reasons
    doc["from_report"] = from_report
    if linearized_table:
        doc["table_model"] = "linearized"  # the virtual table's linearization, with its [dynamics]
    doc["vs_linearization"] = (
        vm.equivalent.to_dict() if vm is not None and vm.equivalent is not None else None
    )
    if study:
        doc["mass_ratio_study"] = study
    if measured:
        doc["measured"] = _measured_doc(frf, measured)
    if robustness is not None and setup is not None and setup.uncertainty is not None:
        doc["robust"] = {**robustness.to_dict(), "uncertainty": setup.uncertainty.to_dict()}
    if json_out:
        print_json(doc, shown)
        return
    _print_human(result, reasons, study, written, measured, shown)
    if robustness is not None:
        console.print("robust: " + robustness.line(), markup=False, highlight=False)


def _robust_lab(
    robust: bool,
    lab: str | None,
    table: Path | None,
    sets: list[str] | None,
    samples: int,
    seed: int,
    other_method: bool,
) -> LabSetup | None:
    """The lab of ``--robust`` (None without it), its ``[uncertainty]`` required; the options checked."""
    if isinstance(samples, bool) or samples < 0:
        raise ConfigError("--robust-samples", "a non-negative whole number of sample points", samples)
    if seed < 0:
        raise ConfigError("--robust-seed", "a non-negative integer", seed)
    if not robust:
        return None
    if other_method:
        raise ConfigError("--robust", "the filter method (without --map-x/--map-y)")
    setup = load_lab(lab, table=table, overrides=parse_overrides(sets)) if lab or table else None
    require_uncertainty(None if setup is None else setup.uncertainty, "--robust")
    return setup


def _parse_amplitude_range(text: str | None) -> tuple[float, float] | None:
    """``"LO:HI"`` (in, or quantities with a length unit) -> ``(A_min, A_max)`` [in]; None without the option."""
    if text is None:
        return None
    parts = text.split(":")
    if len(parts) != 2:
        raise ConfigError(
            "--amplitude-range", "LO:HI, two amplitudes in in or with a unit ('6 mm:100 mm')", text
        )
    lo, hi = (quantity("--amplitude-range", p.strip(), "inch", "positive") for p in parts)
    with option_errors({"amplitude_range": "--amplitude-range"}):
        return check_amplitude_range((lo, hi))


def _with_certificate(result, params, spec: VSSpec | None, amp_range, criteria, linearization: str):
    """``result`` with the amplitude certificate of III over ``amp_range`` [in] (unchanged without a range),
    on the ``--linearization`` model (the DF for ``open-fh``: the real isolator is hysteretic)."""
    if amp_range is None or spec is None:
        return result
    model = linearization if linearization in VS_MODELS else "describing-function"
    cert = amplitude_certificate(result, params, spec.vs, amp_range, criteria=criteria, vs_model=model)
    return with_amplitude_certificate(result, cert)


def _read_frf(path: Path | None, tolerance: str, controller: str, loop_time_s: float) -> FRFTable | None:
    """The FRF table of ``--frf`` (None without it), its options checked and its loop time the table's [s]."""
    if tolerance not in TOLERANCES:
        raise ConfigError("--frf-tolerance", " or ".join(TOLERANCES), tolerance)
    if controller not in CONTROLLER_MODELS:
        raise ConfigError("--frf-controller", " or ".join(CONTROLLER_MODELS), controller)
    if path is None:
        return None
    frf = read_frf_table(path)
    with option_errors({"loop_time": "--frf"}):
        check_loop_time(frf, loop_time_s)
    return frf


def _measured_checks(result, frf: FRFTable | None, tm: TableModel | None, vm, kw: dict[str, Any]) -> tuple:
    """Each cut-off of ``result`` on the measured FRF (the first only without ``tm``); () without ``--frf``."""
    if frf is None:
        return ()
    with option_errors({"loop_time": "--frf"}):
        return design_measured_checks(result, frf, table=tm, vs=vm, **kw)


def _measured_doc(path: Path | None, checks: tuple) -> dict[str, Any]:
    """The ``measured`` block of the JSON: the FRF table file and one entry per cut-off."""
    return {"frf_table": str(path), "constraints": [c.to_dict() for c in checks]}


#: The options of the optimized design's settings (OptimizationSettings' keys).
OPTIMIZED_OPTIONS = {
    "margin": "--margin",
    "margin_band": "--margin-band",
    "basis": "--method",
    "check_per_decade": "--grid",
    "reduce": "--reduce",
}


def _optimization_options(
    margin: float, margin_band: str | None, grid: int, amplitudes: str, reduce: str = "none"
) -> tuple[OptimizationSettings, list[float]]:
    """The optimized design's settings and robust DF amplitudes [in], checked (for any method)."""
    band = _parse_list("--margin-band", margin_band, 2) or []
    with option_errors(OPTIMIZED_OPTIONS):
        settings = OptimizationSettings(
            margin_deg=margin,
            passivity_band_hz=(band[0], band[1]) if band else None,
            check_per_decade=grid,
            reduce=reduce,
        )
    return settings, _parse_list("--robust-amplitudes", amplitudes) or []


def _optimized(params, spec: VSSpec, lin, vm: VirtualModel, fc_hz, criteria, settings, amplitudes):
    """The optimized design (Section 10.4) with the robust set of the CLI options (DF ``amplitudes`` [in])."""
    with option_errors(OPTIMIZED_OPTIONS):
        robust = {}
        if vm.equivalent is not None:
            for a in amplitudes:
                robust[f"DF {a:g} in"] = virtual_model(spec.vs, spec.name, **{**lin, "amplitude_in": a})
        return design_optimized(
            params, vm, robust_vs=robust, fc_hz=fc_hz, criteria=criteria, settings=settings
        )


def _mass_ratio_rows(
    tm: TableModel,
    vs: str | None,
    sets_vs: list[str] | None,
    spec: VSSpec | None,
    lin: dict[str, Any],
    ratios: list[float],
    form: str,
    criteria: DesignCriteria,
    design_fc_hz: float,
) -> list[dict]:
    """The basemat-mass study (Section 9.4.4), coupled with the report's vessel at each of its depths."""
    if spec is None or vs is None:
        raise ConfigError("--mass-ratios", "a VS (--vs) and a form other than tracking")
    vessels = {f"vessel {d} in": FluidVessel(d).impedance() for d in _DESIGN.coupled_water_depths_in}
    overrides = parse_overrides(sets_vs, option="--set-vs")
    cases = mass_ratio_study(
        tm,
        lambda m: virtual_model(resolve(vs, {**overrides, "m_vs": m}).vs, spec.name, **lin),
        ratios,
        form=form,
        criteria=criteria,
        design_fc_hz=design_fc_hz,
        specimens=vessels,
    )
    return [c.to_dict() for c in cases]


def _write_plots(
    plots: Path,
    params: TableDefinition,
    result: ControllerDesign,
    vm: VirtualModel | None,
    fcs: list[float],
    scan: FcScan,
    choice: tuple[str, str, int | None],
    criteria: DesignCriteria,
    spec: VSSpec | None,
    units: UnitSystem,
    tm: TableModel,
) -> list[Path]:
    """Figure 9.31 rows (the cut-offs, or the feasible range's ends and the design's) and the constraints.

    ``tm`` is the design's table model (Eq 4-11, or ``--linearized-table``).

    ``choice`` is (form, filter family, order); each row is annotated with its passivity margins and
    index: the design's own constraint result for its cut-off (the JSON's numbers), the same indices
    computed for the other rows.
    """
    form, family, order = choice
    ends = [scan.feasible_fc_hz[0], scan.feasible_fc_hz[1]] if scan.feasible_fc_hz else []
    rows = fcs if len(fcs) > 1 else sorted({*ends, fcs[0]})
    indices = {float(result.fc_hz): result.constraints[0]}
    for fc in rows:
        if float(fc) not in indices:
            d = design_controller(
                tm,
                vm,
                fc_hz=fc,
                form=form,
                family=family,
                order=order,
                criteria=criteria,
                emit_warnings=False,
            )
            if isinstance(params, TableParameters):
                d = with_indices(d, params, vm, criteria, warn=False)
            indices[float(fc)] = d.constraints[0]
    label = f"{form} controller, {spec.name if spec else 'tracking'}"
    fig = plot_design_rows(
        tm, vm, rows, form=form, family=family, order=order, title=label, units=units, indices=indices
    )
    return [
        save_figure(fig, plots / "design_fig931.png"),
        save_figure(
            plot_constraint_summary(scan.results, criteria, scan.feasible_fc_hz, title=label),
            plots / "design_constraints.png",
        ),
    ]


def _print_human(result, reasons, study, written, measured=(), units: UnitSystem = UnitSystem.US) -> None:
    console.print(
        f"[bold]{result.form}[/] controller, fc = {result.fc_hz:.4g} Hz, {result.filter.family} "
        f"filters of order {result.filter.order_z} (z) / {result.filter.order_w} (w); "
        f"u = H_uz*{result.reference} + H_uw*w" + (" + H_ufh*f_h" if result.H_ufh is not None else "")
    )
    for name, H in (("H_uz", result.H_uz), ("H_uw", result.H_uw), ("H_ufh", result.H_ufh)):
        if H is not None:
            console.print(f"  {name}: num = [{', '.join(f'{c:.4g}' for c in H.num)}]")
            console.print(f"  {' ' * len(name)}  den = [{', '.join(f'{c:.4g}' for c in H.den)}]")
    console.print("  fc [Hz]    I  perf.err   II  effort    III  margin deg (tolerant)")
    for c in result.constraints:
        mark = {True: "ok", False: "NO"}
        console.print(
            f"  {c.fc_hz:8.4g}  {mark[c.I]:>3} {c.performance_error:8.3f}  {mark[c.II]:>3} "
            f"{c.effort_ratio:8.3g}  {mark[c.III]:>3} {c.passivity_margin_deg:8.2f} "
            f"({c.passivity_tolerant_margin_deg:.2f})"
        )
    feas = result.feasible_fc_hz
    console.print("  feasible fc: " + (f"{feas[0]:.4g}-{feas[1]:.4g} Hz" if feas else "none on the grid"))
    for text in reasons:
        console.print(f"  auto: {text}")
    for row in study:
        r = row["feasible_fc_hz"]
        console.print(
            f"  m_vs/m_st = {row['mass_ratio']:g}: feasible fc "
            + (f"{r[0]:.4g}-{r[1]:.4g} Hz" if r else "none")
            + f"; at {row['design_fc_hz']:g} Hz passive: {row['passive_at_design_fc']} "
            f"(margin {row['passivity_margin_deg']:.2f} deg); coupled stable with "
            + ", ".join(
                f"{c['specimen']}: {c['stable']} (zeta {c['hf_damping_ratio']:.3f})" for c in row["coupled"]
            )
        )
    c0 = result.constraints[0] if result.constraints else None
    if c0 is not None and c0.III_sampled is not None:
        damping = display_unit(INDEX_UNIT, units)
        console.print(
            f"  passivity: III on the design model {c0.III_design_model}; on the sampled-data table {c0.III_sampled} "
            f"(margin {c0.passivity_margin_sampled_deg:.2f} deg); passivity index "
            f"{c0.passivity_index * damping.factor:.3g} {damping.name}"
        )
    reduction = (result.optimization or {}).get("reduction")
    if reduction and reduction.get("reduced"):
        before, after, bound = reduction["orders_before"], reduction["orders_after"], reduction["error_bound"]
        console.print(
            "  reduced: "
            + ", ".join(
                f"{k} {before[k]} -> {after[k]} states (bound {bound[k]:.2g})" for k in ("H_uz", "H_uw")
            )
        )
    for checks in measured:
        for line in checks.lines():
            console.print(line, markup=False, highlight=False)
    if result.amplitude_certificate is not None and result.amplitude_certificate["certified"]:
        console.print("  " + summary(result.amplitude_certificate))
    for text in result.warnings:
        console.print(f"[yellow]warning:[/] {text}")
    for path in written:
        console.print(f"wrote {path}")
