"""The plant/virtual packages and the closed forms used by the design tests agree."""

import numpy as np

from impedance_mil.design import design_controller, table_model, virtual_model
from impedance_mil.plant import LinearTable, TableParameters
from impedance_mil.plant.lti_table import LTITable
from impedance_mil.virtual import presets

from .conftest import sd_model

F = np.logspace(-1, 3, 80)


def test_linear_table_equals_eq_4_15_closed_form(table):
    # Independent routes: LinearTable's state space (Eq 4-14a) vs Eq 4-15a/d coded in conftest.
    tm = table_model(TableParameters.report_default())
    for a, b in ((tm.H_zu, table.H_zu), (tm.H_zw, table.H_zw)):
        np.testing.assert_allclose(a.frequency_response(F), b.frequency_response(F), rtol=1e-9)
    assert tm.loop_time_s == table.loop_time_s


def test_sd2_preset_equals_eq_5_2_with_table_9_1():
    vm = virtual_model(presets.get("SD2"), "SD2")
    ref = sd_model()  # k_s = 894, c = 57 as printed (the preset computes 894.7, 56.96)
    for a, b in ((vm.H_zw, ref.H_zw), (vm.H_zag, ref.H_zag)):
        np.testing.assert_allclose(a.frequency_response(F), b.frequency_response(F), rtol=2e-3)
    assert vm.kind == "SD" and vm.H_zfh is None


def test_design_from_packages_reproduces_eq_6_11(table):
    tm = table_model(TableParameters.report_default())
    a = design_controller(tm, form="standardized", fc_hz=80.0, emit_warnings=False)
    b = design_controller(table, form="standardized", fc_hz=80.0, emit_warnings=False)
    assert a.H_uz.isclose(b.H_uz, rtol=1e-8) and a.H_uw.isclose(b.H_uw, rtol=1e-8)
    assert a.table["Ke"] == 5.0 and a.loop_time_s == 500e-6


def test_table_model_of_an_lti_table_is_its_design_paths():
    # An LTI table (the report's state space, its command delayed by the first-order lag):
    # table_model takes H_zu, H_zw of the design model, the loop time, and no physical parameters.
    ss = LinearTable(TableParameters.report_default(), delay="none").state_space().system
    lti = LTITable.from_control(ss.to_control(), 5e-4, "first-order")
    tm = table_model(lti)
    lag = 1.0 / (1.0 + 2j * np.pi * F * 5e-4)
    ref = LinearTable(TableParameters.report_default(), delay="none")
    np.testing.assert_allclose(
        tm.H_zu.frequency_response(F), ref.tf("z", "u").frequency_response(F) * lag, rtol=1e-9
    )
    np.testing.assert_allclose(
        tm.H_zw.frequency_response(F), ref.tf("z", "w").frequency_response(F), rtol=1e-9
    )
    assert tm.loop_time_s == 5e-4 and dict(tm.parameters) == {}
    assert tm.H_zu.relative_degree == 4  # Eq 4-15a's 3, plus the lag: the filter order follows
    d = design_controller(tm, form="tracking", fc_hz=80.0, emit_warnings=False)
    assert d.filter.order_z == 4
