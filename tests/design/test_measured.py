"""Design checks on a measured FRF (design/measured.py) against the model-based checks.

The "measurements" are the design's own table model sampled on a log grid
(written in SI units and read back, so the unit conversion is exercised), and
the exact sampled-data table (plant/sampled.py) as a lab would measure it.
Tolerances were measured on the grid of :data:`PER_DECADE` points per decade:
the FRF checks take the worst of the measured points, the model checks refine
the minimum between grid points (design/passivity.py), so the FRF margin is
never below the model's and exceeds it by at most 1.4e-4 deg (SD2, tolerant
margin); e_I peaks at the band edge 15 Hz, which the grid misses by 0.25 %,
so the FRF e_I is below the model's by at most 2.9e-4 (LR2).
"""

import dataclasses

import numpy as np
import pytest

from impedance_mil.design import DesignCriteria, design_controller, table_model, virtual_model
from impedance_mil.design.measured import (
    STABILITY,
    coverage,
    design_measured_checks,
    measured_checks,
)
from impedance_mil.design.optimized import with_indices
from impedance_mil.design.optimized.models import RationalTarget, robust_set
from impedance_mil.errors import ConfigError
from impedance_mil.plant import LinearTable, TableParameters
from impedance_mil.plant.frf_table import FRFTable, read_frf_table, write_frf_table
from impedance_mil.systems import TransferFunction
from impedance_mil.units import TWO_PI
from impedance_mil.virtual import presets

#: Grid of the sampled "measurements" [points per decade], 0.01 Hz to 1000 Hz (the passivity band).
PER_DECADE = 400
#: Largest measured excess of the FRF margin over the model's [deg] on that grid, with headroom.
MARGIN_TOL_DEG = 5e-4
#: Largest measured shortfall of the FRF e_I below the model's on that grid, with headroom.
PERF_TOL = 1e-3


def log_grid(lo_hz=0.01, hi_hz=1000.0):
    n = int(round(PER_DECADE * np.log10(hi_hz / lo_hz))) + 1
    return np.logspace(np.log10(lo_hz), np.log10(hi_hz), n)


@pytest.fixture(scope="module")
def params():
    return TableParameters.report_default()


@pytest.fixture(scope="module")
def model_frf(params, tmp_path_factory):
    """``LinearTable(report_default(), "first-order")`` sampled, through an SI file pair."""
    lt = LinearTable(params, "first-order")
    f = log_grid()
    table = FRFTable(f, lt.tf("z", "u").frequency_response(f), lt.tf("z", "w").frequency_response(f), 5e-4)
    path = write_frf_table(
        table, tmp_path_factory.mktemp("frf") / "model.toml", {"z": "m/s**2", "u": "mm", "w": "kN"}
    )
    return read_frf_table(path)


@pytest.fixture(scope="module")
def sampled_frf(params):
    """The exact sampled-data table as measured: z/u at the sampling instants (the command held),
    z/w from the velocity path with the force's hold divided out (optimized/models.py), times j 2 pi f."""
    (model,) = robust_set(params, {"none": RationalTarget(TransferFunction.constant(0.0))}, ("sampled",))
    f = log_grid(hi_hz=999.0)  # Tustin's warp diverges at the Nyquist frequency
    r = model.responses(f)
    return FRFTable(f, r.P_zu, 1j * TWO_PI * f * r.P_vw, params.loop_time)


@pytest.fixture(scope="module")
def designs(params):
    tm = table_model(params)
    out = {}
    for name in ("SD2", "LR2"):
        vm = virtual_model(presets.get(name), name)
        d = design_controller(tm, vm, fc_hz=80.0, evaluate_fc_hz=[100.0, 250.0], emit_warnings=False)
        out[name] = (with_indices(d, params, vm, warn=False), vm, tm)
    return out


@pytest.mark.parametrize("name", ["SD2", "LR2"])
def test_model_sampled_to_an_frf_agrees_with_the_model_checks(designs, model_frf, name):
    design, vm, tm = designs[name]
    checks = design_measured_checks(design, model_frf, table=tm, vs=vm, tolerance="delay-model")
    assert [c.fc_hz for c in checks] == [c.fc_hz for c in design.constraints]
    for model, frf in zip(design.constraints, checks):
        assert (frf.I, frf.II, frf.III) == (model.I, model.II, model.III)
        assert frf.coverage_I.status == frf.coverage_III.status == "full"
        assert 0 <= model.performance_error - frf.performance_error <= PERF_TOL
        assert 0 <= frf.passivity_margin_deg - model.passivity_margin_deg <= MARGIN_TOL_DEG
        assert 0 <= frf.passivity_tolerant_margin_deg - model.passivity_tolerant_margin_deg <= MARGIN_TOL_DEG
        assert frf.passivity_worst_hz == pytest.approx(model.passivity_worst_hz, rel=0.01)  # grid step 0.58 %
        assert frf.effort_ratio == model.effort_ratio  # copied: II depends on the controller only


def test_issue_values_sd2_passes_lr2_fails(designs, model_frf):
    sd2 = design_measured_checks(designs["SD2"][0], model_frf, vs=designs["SD2"][1], tolerance="delay-model")[
        0
    ]
    assert sd2.I and sd2.II and sd2.III
    lr2 = design_measured_checks(designs["LR2"][0], model_frf, vs=designs["LR2"][1])[0]
    # Issue 13: e_I 0.308, margin -8.8 deg at 9.4 Hz (3 digits as quoted)
    assert (lr2.I, lr2.II, lr2.III) == (False, True, False)
    assert lr2.performance_error == pytest.approx(0.308, abs=5e-4)
    assert lr2.passivity_margin_deg == pytest.approx(-8.8, abs=0.05)
    assert lr2.passivity_worst_hz == pytest.approx(9.4, abs=0.05)


def test_without_the_delay_model_tolerance_sd2_at_80_hz_is_not_passive(designs, model_frf):
    # The design passes III only by crediting the first-order delay model's phase error
    # (raw margin -1.00 deg at 138 Hz, tolerant +0.17); a measurement has no such error.
    design, vm, _ = designs["SD2"]
    frf = design_measured_checks(design, model_frf, vs=vm)[0]
    assert design.constraints[0].III and frf.III is False and frf.passivity_tolerance == "none"
    assert frf.passivity_tolerant_margin_deg == frf.passivity_margin_deg
    assert frf.passivity_margin_deg == pytest.approx(
        design.constraints[0].passivity_margin_deg, abs=MARGIN_TOL_DEG
    )


@pytest.mark.parametrize("name", ["SD2", "LR2"])
def test_extra_tolerance_at_the_margin_flips_the_verdict(designs, model_frf, name):
    design, vm, _ = designs[name]
    margin = design_measured_checks(design, model_frf, vs=vm)[0].passivity_margin_deg
    assert margin < 0  # both are non-passive without a tolerance
    for shift, verdict in ((1e-6, True), (-1e-6, False)):
        c = DesignCriteria(passivity_extra_tolerance_deg=-margin + shift)
        assert design_measured_checks(design, model_frf, vs=vm, criteria=c)[0].III is verdict


@pytest.mark.parametrize(
    "name, sampled_deficit_deg",
    [("SD2", 0.525), ("LR2", 0.943)],  # measured here; issue 13: 0.5-5 deg less passive
)
def test_sampled_data_table_as_a_measurement(designs, model_frf, sampled_frf, name, sampled_deficit_deg):
    design, vm, _ = designs[name]
    first = design.constraints[0]
    frf = design_measured_checks(design, sampled_frf, vs=vm, controller_model="tustin")[0]
    # the same numbers as the design's own sampled-data index (optimized/indices.py)
    assert frf.passivity_margin_deg == pytest.approx(first.passivity_margin_sampled_deg, abs=MARGIN_TOL_DEG)
    assert first.passivity_margin_deg - frf.passivity_margin_deg == pytest.approx(
        sampled_deficit_deg, abs=0.01
    )
    assert (
        frf.III is False
    )  # less passive than the first-order model; SD2's -1.5 deg is beyond any tolerance here


def test_partial_coverage_gives_no_pass_but_keeps_a_failure(designs, params):
    lt = LinearTable(params, "first-order")
    f = log_grid(0.25, 200.0)
    frf = FRFTable(f, lt.tf("z", "u").frequency_response(f), lt.tf("z", "w").frequency_response(f), 5e-4)
    sd2 = design_measured_checks(designs["SD2"][0], frf, vs=designs["SD2"][1], tolerance="delay-model")[0]
    assert sd2.coverage_I.status == "full" and sd2.I is True
    assert sd2.coverage_III.status == "partial" and sd2.coverage_III.covered_hz == pytest.approx(
        (0.25, 200.0)
    )
    assert sd2.holds_on_covered_III is True and sd2.III is None  # not shown to hold from 0.01 Hz to 1000 Hz
    lr2 = design_measured_checks(designs["LR2"][0], frf, vs=designs["LR2"][1])[0]
    assert lr2.coverage_III.status == "partial" and lr2.III is False  # violated where measured
    doc = sd2.to_dict()
    assert doc["coverage"] == {"I": "full", "II": "controller only", "III": "partial"} and doc["III"] is None


def test_a_band_the_data_miss_is_refused(designs, params):
    lt = LinearTable(params, "first-order")
    f = log_grid(20.0, 200.0)  # above the band of interest 0.25-15 Hz
    frf = FRFTable(f, lt.tf("z", "u").frequency_response(f), lt.tf("z", "w").frequency_response(f), 5e-4)
    checks = design_measured_checks(designs["SD2"][0], frf, vs=designs["SD2"][1])[0]
    assert checks.coverage_I.status == "none" and checks.I is None and checks.performance_error is None
    assert checks.to_dict()["performance_error"] is None
    beyond = FRFTable(np.array([1500.0, 2000.0]), np.ones(2), np.ones(2), 5e-4)  # above Nyquist
    c = design_measured_checks(designs["SD2"][0], beyond, vs=designs["SD2"][1])[0]
    assert c.coverage_III.status == "none" and c.III is None and c.passivity_margin_deg is None


def test_tracking_form_and_the_result_document(params, model_frf):
    tm = table_model(params)
    design = design_controller(tm, form="tracking", fc_hz=80.0, emit_warnings=False)
    frf = design_measured_checks(design, model_frf)[0]
    model = design.constraints[0]
    assert 0 <= model.performance_error - frf.performance_error <= PERF_TOL  # e_I = max |H_c/H_zw|
    assert (frf.I, frf.II, frf.III) == (model.I, model.II, model.III)  # the tracking design fails all three
    assert (
        0 <= frf.passivity_margin_deg - model.passivity_margin_deg <= MARGIN_TOL_DEG
    )  # -89.9 deg at 0.01 Hz
    doc = frf.to_dict()
    for key in ("I", "II", "III", "performance_error", "effort_ratio", "passivity_margin_deg"):
        assert key in doc
    assert doc["frequency_range_hz"] == [0.01, 1000.0] and doc["stability"] == STABILITY
    assert "stable" not in doc and all(isinstance(line, str) for line in frf.lines())


def test_coherence_is_reported_over_the_points_used(designs, model_frf):
    n = model_frf.frequency_hz.size
    coh = np.linspace(0.5, 1.0, n)
    frf = dataclasses.replace(model_frf, coherence_zw=coh)
    checks = design_measured_checks(designs["SD2"][0], frf, vs=designs["SD2"][1])[0]
    assert checks.min_coherence_zu is None and checks.min_coherence_zw == pytest.approx(0.5)


def test_refusals(designs, model_frf):
    design, vm, _ = designs["SD2"]
    other = dataclasses.replace(model_frf, loop_time_s=1e-3)
    with pytest.raises(ConfigError) as exc:
        design_measured_checks(design, other, vs=vm)
    assert exc.value.key == "loop_time"
    with pytest.raises(ConfigError) as exc:
        design_measured_checks(design, model_frf)  # SD2's design without its VS
    assert exc.value.key == "vs" and "SD2" in str(exc.value)
    for kw, key in (({"tolerance": "loose"}, "tolerance"), ({"controller_model": "zoh"}, "controller_model")):
        with pytest.raises(ConfigError) as exc:
            measured_checks(model_frf, design, design.constraints[0], form="standardized", vs=vm, **kw)
        assert exc.value.key == key


def test_coverage_edges():
    frf = FRFTable(np.array([1.0, 2.0, 3.0]), np.ones(3), np.ones(3), 5e-4)
    assert coverage(frf, (1.0, 3.0)).status == "full"
    assert coverage(frf, (0.5, 3.0)).status == "partial"
    assert coverage(frf, (1.5, 2.5)).status == "none"  # one point inside: no check
    assert coverage(frf, (1.5, 2.5)).n_points == 1
