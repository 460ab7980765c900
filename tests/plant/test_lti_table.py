"""LTI tables (issue 13, item 2): transfer-function, zpk and state-space table files.

Reference: the report's table (Table 4.1, Eq 4-14a, first-order delay) as LinearTable builds it
from its physical parameters; each kind of file holding it must give back the same paths.
"""

from pathlib import Path

import control
import numpy as np
import pytest

from impedance_mil.design import design_controller, table_model
from impedance_mil.design.forms import TableModel, ideal_controller
from impedance_mil.errors import ConfigError
from impedance_mil.plant import LinearTable, TableParameters
from impedance_mil.plant.lti_table import LTITable
from impedance_mil.plant.table_files import lti_table_toml, read_lti_table, read_table_file
from impedance_mil.systems import TransferFunction

F = np.geomspace(0.1, 500.0, 60)
TAU = 5e-4
REPORT = LinearTable(TableParameters.report_default())
PATHS = [(o, i) for o in ("z", "x", "dp") for i in ("u", "w")]


def report_lti(delay: str = "included") -> LTITable:
    """The report's table (first-order delay model) as an LTI table, internal units."""
    return LTITable.from_control(REPORT.state_space().system.to_control(), TAU, delay)


def _list(values) -> str:
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def write(tmp_path: Path, text: str, name: str = "t.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("kind", ["state-space", "transfer-function", "zpk"])
def test_each_kind_of_file_gives_back_the_report_table(tmp_path, kind):
    # Written from the state space and read back: every path's response within 1e-9 of
    # LinearTable's (measured 4e-15 tf, 4e-15 zpk, 1e-16 ss); relative degree and the
    # exact zeros at the origin (z/u, z/w: two) kept; the five poles once each.
    table = read_lti_table(write(tmp_path, lti_table_toml(report_lti(), kind)))
    assert table.kind == kind
    for o, i in PATHS:
        H, ref = table.tf(o, i), REPORT.tf(o, i)
        np.testing.assert_allclose(H.frequency_response(F), ref.frequency_response(F), rtol=1e-9)
        assert H.relative_degree == ref.relative_degree
    for i in ("u", "w"):
        assert table.tf("z", i).num[-2:].tolist() == [0.0, 0.0]
    assert table.dcgain("x", "u") == pytest.approx(1.0, rel=1e-12)
    got = np.sort_complex(table.poles())
    np.testing.assert_allclose(got, np.sort_complex(REPORT.poles()), rtol=1e-9)


def test_file_units_are_converted_by_dimension(tmp_path):
    # The same table in m/s**2, mm and kN: z/u scales by 0.0254 / 25.4e-3 ... exactly as pint says.
    H_zu, H_zw = REPORT.tf("z", "u"), REPORT.tf("z", "w")
    a, d, f = 0.0254, 25.4, 4.4482216152605e-3  # m/s**2 per in/s**2, mm per in, kN per lbf
    text = f"""[model]
kind = "transfer-function"
loop_time = "0.5 ms"
delay = "included"
units = {{ z = "m/s**2", u = "mm", w = "kN" }}
H_zu = {{ num = {_list(H_zu.num * a / d)}, den = {_list(H_zu.den)} }}
H_zw = {{ num = {_list(H_zw.num * a / f)}, den = {_list(H_zw.den)} }}
"""
    table = read_lti_table(write(tmp_path, text))
    assert table.loop_time == pytest.approx(TAU, rel=1e-15)
    assert table.outputs == ("z", "x", "v")  # x and v derived: both z paths have s**2
    for o, i in (("z", "u"), ("z", "w"), ("x", "u"), ("x", "w")):
        np.testing.assert_allclose(
            table.tf(o, i).frequency_response(F), REPORT.tf(o, i).frequency_response(F), rtol=1e-12
        )


def test_first_order_and_pade_delays_act_on_the_command_only():
    base, lag, pade = report_lti(), report_lti("first-order"), report_lti("pade")
    s = 2j * np.pi * F
    for o in ("z", "x"):
        ratio = lag.tf(o, "u").frequency_response(F) / base.tf(o, "u").frequency_response(F)
        np.testing.assert_allclose(ratio, 1.0 / (1.0 + s * TAU), rtol=1e-9)
        # Pade order 6 of e^{-s tau}: below 500 Hz (omega tau <= 1.6) its error is < 1e-7
        # (measured 6e-11)
        ratio = pade.tf(o, "u").frequency_response(F) / base.tf(o, "u").frequency_response(F)
        np.testing.assert_allclose(ratio, np.exp(-s * TAU), atol=1e-7)
    np.testing.assert_allclose(
        lag.tf("z", "w").frequency_response(F), base.tf("z", "w").frequency_response(F), rtol=1e-12
    )
    assert len(lag.poles()) == 6 and np.any(np.isclose(lag.poles(), -1.0 / TAU, rtol=1e-12))
    assert lag.state_space() is lag.model and lag.state_space().system.n_states == 5


def test_sampled_command_is_the_held_model_one_loop_late():
    table = report_lti("sampled")
    sampled = table.sampled_command("x")
    assert sampled.dt == TAU and sampled.dcgain() == pytest.approx(1.0, rel=1e-9)
    part = table.state_space().system.channel("x", "u").zoh(TAU)
    z = np.exp(2j * np.pi * F[:20] * TAU)
    np.testing.assert_allclose(sampled.evaluate(z), part.evaluate(z) / z, rtol=1e-9)


def test_python_control_round_trip_and_dict():
    table = report_lti("first-order")
    sys = table.to_control()
    assert isinstance(sys, control.StateSpace) and list(sys.input_labels) == ["u", "w"]
    again = LTITable.from_control(sys, TAU, "first-order")
    for o, i in PATHS:
        assert again.tf(o, i).isclose(table.tf(o, i), rtol=1e-12)
    doc = table.to_dict()
    assert (doc["kind"], doc["delay"], doc["loop_time"]) == ("state-space", "first-order", TAU)
    assert doc["state_space"]["inputs"] == ["u", "w"] and doc["state_space"]["outputs"][0] == "z"


def test_design_of_an_lti_table_equals_the_physical_design():
    # The LTI table with the report's first-order model "included" is the same table:
    # the same controller (coefficients within 1e-9; measured bit-identical).
    lti = design_controller(table_model(report_lti()), form="tracking", fc_hz=80.0, emit_warnings=False)
    ref = design_controller(
        table_model(TableParameters.report_default()), form="tracking", fc_hz=80.0, emit_warnings=False
    )
    assert lti.H_uz.isclose(ref.H_uz, rtol=1e-9) and lti.H_uw.isclose(ref.H_uw, rtol=1e-9)
    assert lti.filter.order_z == ref.filter.order_z == 3  # the relative degree of H_zu


@pytest.mark.parametrize("form", ["standardized", "tracking"])
def test_mil_forms_refuse_a_table_without_force_path(form):
    table = TableModel(REPORT.tf("z", "u"), TransferFunction.constant(0.0), TAU)
    with pytest.raises(ConfigError) as err:
        ideal_controller(form, table)
    assert err.value.key == "H_zw"


def test_a_file_without_force_path_is_read_and_says_so(tmp_path):
    H = REPORT.tf("z", "u")
    text = f"""[model]
kind = "transfer-function"
loop_time = "500 us"
delay = "first-order"
units = {{ z = "in/s**2", u = "in" }}
H_zu = {{ num = {_list(H.num)}, den = {_list(H.den)} }}
"""
    table = read_lti_table(write(tmp_path, text))
    assert not table.has_force_path() and table.tf("z", "w").is_zero
    with pytest.raises(ConfigError, match="H_zw"):
        ideal_controller("standardized", table_model(table))


def _tf_file(**model) -> str:
    base = {
        "kind": '"transfer-function"',
        "loop_time": '"500 us"',
        "delay": '"included"',
        "units": '{ z = "in/s**2", u = "in", w = "lbf" }',
        "H_zu": "{ num = [1.0e4, 0.0, 0.0], den = [1.0, 30.0, 400.0, 3000.0] }",
        "H_zw": "{ num = [0.2, 0.0, 0.0], den = [1.0, 30.0, 400.0, 3000.0] }",
    }
    base.update(model)
    return "[model]\n" + "".join(f"{k} = {v}\n" for k, v in base.items() if v is not None)


def _zpk(poles: str) -> str:
    return f"{{ zeros = [], poles = {poles}, gain = 100.0 }}"


BAD = {
    "improper H_zu": (_tf_file(H_zu="{ num = [1.0, 0.0, 0.0], den = [1.0, 3.0] }"), "model.H_zu"),
    "unstable": (_tf_file(H_zu="{ num = [1.0], den = [1.0, -2.0] }"), "model.allow_unstable"),
    "NaN": (_tf_file(H_zw="{ num = [nan], den = [1.0, 2.0] }"), "model.H_zw.num"),
    "all-zero num": (_tf_file(H_zw="{ num = [0.0, 0.0], den = [1.0, 2.0] }"), "model.H_zw.num"),
    "missing loop_time": (_tf_file(loop_time=None), "model.loop_time"),
    "unknown kind": (_tf_file(kind='"frf-model"'), "model.kind"),
    "wrong dimension": (_tf_file(units='{ z = "in", u = "in", w = "lbf" }'), "model.units.z"),
    "unpaired root": (
        _tf_file(kind='"zpk"', H_zu=_zpk("[-1.0, [-2.0, 3.0]]"), H_zw=None),
        "model.H_zu.poles",
    ),
    "shapes": (
        "[model]\n"
        'kind = "state-space"\nloop_time = "500 us"\ndelay = "included"\n'
        'units = { z = "in/s**2", u = "in", w = "lbf" }\ninputs = ["u", "w"]\noutputs = ["z"]\n'
        "A = [[-1.0, 0.0], [0.0, -2.0]]\nB = [[1.0], [1.0]]\nC = [[1.0, 1.0]]\n",
        "model.B",
    ),
}


@pytest.mark.parametrize("case", list(BAD))
def test_bad_input_is_refused_naming_the_key(tmp_path, case):
    text, key = BAD[case]
    with pytest.raises(ConfigError) as err:
        read_table_file(write(tmp_path, text))
    assert err.value.key == f"t.toml: {key}", str(err.value)
    assert "\n" not in str(err.value)


def test_allow_unstable_accepts_an_unstable_table(tmp_path):
    text = _tf_file(H_zu="{ num = [1.0], den = [1.0, -2.0] }", allow_unstable="true")
    table = read_table_file(write(tmp_path, text))
    assert isinstance(table, LTITable) and not table.is_stable()


def test_a_complex_pair_written_whole_is_accepted(tmp_path):
    # Poles -2 +- 3j: (s + 2)^2 + 9 = s^2 + 4 s + 13, DC gain 100/13.
    text = _tf_file(kind='"zpk"', H_zu=_zpk("[[-2.0, 3.0], [-2.0, -3.0]]"), H_zw=None)
    table = read_table_file(write(tmp_path, text))
    np.testing.assert_allclose(table.tf("z", "u").den, [1.0, 4.0, 13.0], rtol=1e-15)
    assert table.dcgain("z", "u") == pytest.approx(100.0 / 13.0, rel=1e-15)
