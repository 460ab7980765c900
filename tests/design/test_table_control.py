"""A table model from a state space or python-control (TableModel.from_control, round-off-safe conversion)."""

import control
import numpy as np
import pytest

from impedance_mil.design import TableModel, design_controller
from impedance_mil.design.forms import check_table
from impedance_mil.errors import ConfigError
from impedance_mil.plant import LinearTable, TableParameters
from impedance_mil.systems import TransferFunction

from .conftest import TAU, closed_form_table

# Both sides are double-precision evaluations of the same model (state space vs the closed
# forms of Eq 4-15); measured agreement 2e-15, bound as in tests/plant/test_linear.py.
RTOL = 1e-9
S2 = TransferFunction([1.0, 0.0, 0.0], [1.0])


def test_acceleration_paths_built_from_displacement_state_space_are_proper():
    # Issue 13: "TransferFunction.from_ss leaves round-off in the polynomials, which then
    # raises 'H_zw is improper (relative degree -1)'".  x/w of Table 4.1 from its state space:
    # scipy.signal.ss2tf gives 9.1e-13 s**4 over a fifth-order denominator (relative degree 1
    # instead of 2), so z/w = s**2 x/w had relative degree -1 and check_table refused the table.
    ss = LinearTable(TableParameters.report_default()).state_space()
    H_xw = TransferFunction.from_ss(ss.A, ss.B_w, ss.C["x"])
    H_xu = TransferFunction.from_ss(ss.A, ss.B_u, ss.C["x"])
    assert (H_xw.relative_degree, H_xu.relative_degree) == (2, 5)
    table = TableModel(S2 * H_xu, S2 * H_xw, TAU)
    check_table(table)  # no "improper (relative degree -1)"
    ref = closed_form_table()
    for H, R in ((table.H_zu, ref.H_zu), (table.H_zw, ref.H_zw)):
        np.testing.assert_allclose(H.num, R.num, rtol=RTOL, atol=0)
        np.testing.assert_allclose(H.den, R.den, rtol=RTOL, atol=0)
    d = design_controller(table, fc_hz=80.0, form="tracking", emit_warnings=False)
    assert d.filter.order_z == 3 and d.H_uz.is_proper


def _control_table():
    """Table 4.1 as a python-control state space with named signals (z/u, z/w of Eq 4-14a)."""
    sys = LinearTable(TableParameters.report_default()).state_space().system
    return sys.to_control()


def test_from_control_state_space_gives_eq_4_15():
    # The state space is converted here, round-off safe: exact double zero at s = 0 and
    # relative degree 3 for z/u (python-control's own ss -> tf leaves 8e-12 s**4 and
    # -0.04 s - 0.003 in it, measured with control 0.10.2).
    table = TableModel.from_control(_control_table(), TAU)
    ref = closed_form_table()
    assert table.loop_time_s == TAU
    assert table.H_zu.relative_degree == 3 and table.H_zu.num[-2:].tolist() == [0.0, 0.0]
    assert table.H_zw.relative_degree == 0 and table.H_zw.num[-2:].tolist() == [0.0, 0.0]
    for H, R in ((table.H_zu, ref.H_zu), (table.H_zw, ref.H_zw)):
        np.testing.assert_allclose(H.num, R.num, rtol=RTOL, atol=0)
        np.testing.assert_allclose(H.den, R.den, rtol=RTOL, atol=0)


def test_to_control_round_trip_through_a_mimo_transfer_function():
    # A transfer function's polynomials are taken as they are (the closed forms here).
    ref = closed_form_table()
    exported = ref.to_control()
    assert exported.input_labels == ["u", "w"] and exported.output_labels == ["z"]
    back = TableModel.from_control(exported, TAU)
    for name in ("H_zu", "H_zw"):
        assert getattr(back, name).isclose(getattr(ref, name), rtol=0)


def test_from_control_refuses_discrete_systems_and_missing_signals():
    with pytest.raises(ConfigError, match="continuous"):
        TableModel.from_control(control.c2d(_control_table(), TAU), TAU)
    with pytest.raises(ConfigError, match="input: expected one of u, w"):
        TableModel.from_control(_control_table(), TAU, command="u_v")
