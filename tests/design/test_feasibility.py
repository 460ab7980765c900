"""Design aids: feasible f_c range, --fc auto, basemat-mass study (Section 9.4.4), feasibility map."""

import numpy as np

from impedance_mil.design import design_controller
from impedance_mil.design.feasibility import choose_fc, feasibility_map, mass_ratio_study, scan_fc

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
