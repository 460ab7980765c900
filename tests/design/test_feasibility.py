"""Design aids: feasible f_c range, --fc auto, basemat-mass study (Section 9.4.4), feasibility map."""

import warnings

import numpy as np
import pytest

from impedance_mil.design import design_controller
from impedance_mil.design.adapters import table_model, virtual_model
from impedance_mil.design.feasibility import choose_fc, feasibility_map, mass_ratio_study, scan_fc
from impedance_mil.design.sampling import check_implementable_fc, implementable_fc
from impedance_mil.errors import ConfigError
from impedance_mil.implement.export import controller_from_design
from impedance_mil.plant import TableParameters
from impedance_mil.virtual import presets

from .conftest import MST, sd_model

GRID = np.logspace(np.log10(20.0), 3.0, 16)  # 20 Hz to the 1000 Hz Nyquist frequency


def test_feasible_range_contains_table_9_5_passes(table):
    scan = scan_fc(table, sd_model(m_vs=1.25 * MST), GRID)
    lo, hi = scan.feasible_fc_hz
    # Table 9.5: 100 and 250 Hz satisfy all constraints, 50 and 1000 Hz do not.
    assert 50.0 < lo <= 100.0 and 250.0 <= hi < 1000.0


def test_auto_choice_is_feasible_and_explained(table):
    choice = choose_fc(table, sd_model(m_vs=1.25 * MST), GRID)
    lo, hi = choice.scan.feasible_fc_hz
    assert choice.feasible and lo <= choice.fc_hz <= hi
    assert any("balances" in r for r in choice.reasons)


def test_auto_choice_reports_infeasibility(table):
    choice = choose_fc(table, sd_model(m_vs=0.4 * MST), GRID)
    assert not choice.feasible and "no cut-off" in choice.reasons[0]


def test_basemat_mass_study_shrinks_the_range(table):
    # Section 9.4.4: the smaller m_vs/m_st, the closer the Nyquist plot to the imaginary axis; for
    # m_vs << m_st no filter works (0.4 m_st, Section 9.4.5).
    cases = mass_ratio_study(table, lambda m: sd_model(m_vs=m), [1.25, 1.0, 0.4], GRID)
    assert cases[0].feasible_fc_hz is not None and cases[2].feasible_fc_hz is None
    # The worst passivity margin at fc = 80 Hz decreases monotonically with the mass ratio.
    at80 = [
        min(r.passivity_tolerant_margin_deg for r in scan_fc(table, sd_model(m_vs=k * MST), [80.0]).results)
        for k in (1.25, 1.0, 0.9, 0.7)
    ]
    assert all(a > b for a, b in zip(at80, at80[1:]))


def test_feasibility_map_over_mass_and_stiffness(table):
    grid = np.logspace(np.log10(50.0), np.log10(500.0), 6)
    fmap = feasibility_map(
        table,
        lambda m_vs, k: sd_model(m_vs=m_vs, k=k),
        "m_vs",
        [0.4 * MST, 1.25 * MST],
        "k",
        [300.0, 1800.0],
        grid,
    )
    assert fmap.feasible.shape == (2, 2)
    assert fmap.feasible[:, 1].all() and not fmap.feasible[:, 0].any()  # heavy basemat yes, light no
    assert np.all(fmap.fc_low_hz[fmap.feasible] <= fmap.fc_high_hz[fmap.feasible])
    # Independent route: the ends of each feasible range are cut-offs on the grid at which a design made
    # with design_controller satisfies I, II and III.
    for i, j in zip(*np.nonzero(fmap.feasible)):
        lo, hi = fmap.fc_low_hz[i, j], fmap.fc_high_hz[i, j]
        assert np.isclose(grid, lo, rtol=1e-12).any() and np.isclose(grid, hi, rtol=1e-12).any()
        vs = sd_model(m_vs=fmap.x[j], k=fmap.y[i])
        d = design_controller(table, vs, fc_hz=lo, evaluate_fc_hz=[hi], emit_warnings=False)
        assert all(r.all_satisfied for r in d.constraints)


def test_unstable_vs_is_infeasible_not_an_abort(table):
    fmap = feasibility_map(
        table, lambda m_vs, c: sd_model(m_vs=m_vs, c=c), "m_vs", [1.25 * MST], "c", [-50.0, 57.0], GRID[::3]
    )
    assert fmap.feasible.tolist() == [[False], [True]]


def test_auto_choice_is_always_implementable():
    # The report's table with FP2 (no feasible cut-off): the least bad grid point used to be the
    # 1000 Hz Nyquist frequency itself, which discretize (imil export) refuses.  The choice and the
    # refusal are one rule (design.sampling.implementable_fc).
    tm = table_model(TableParameters.report_default())
    choice = choose_fc(tm, virtual_model(presets.get("FP2"), "FP2"))
    assert choice.scan.results[-1].fc_hz == tm.nyquist_hz  # the grid still ends at Nyquist
    assert implementable_fc(choice.fc_hz, tm.loop_time_s) and choice.fc_hz < tm.nyquist_hz
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        design = design_controller(tm, virtual_model(presets.get("FP2"), "FP2"), fc_hz=choice.fc_hz)
    assert controller_from_design(design).fc_hz == choice.fc_hz  # export accepts it
    assert not implementable_fc(tm.nyquist_hz, tm.loop_time_s)
    with pytest.raises(ConfigError, match=r"^fc_hz: expected a frequency in \(0, 1000\) Hz"):
        check_implementable_fc("fc_hz", tm.nyquist_hz, tm.loop_time_s)
    with pytest.raises(ConfigError, match="fc_grid_hz"):
        choose_fc(tm, None, [tm.nyquist_hz, 2 * tm.nyquist_hz])
