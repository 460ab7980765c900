"""Design file round trip and refusals (design/io.py)."""

import json

import pytest

from impedance_mil.design import design_controller, load_design, save_design
from impedance_mil.design.io import FORMAT, design_to_dict
from impedance_mil.errors import DataFileError


@pytest.fixture(scope="module")
def design(table, sd2):
    return design_controller(
        table, sd2, form="standardized", fc_hz=80.0, evaluate_fc_hz=[100.0], emit_warnings=False
    )


def test_round_trip(tmp_path, design):
    path = save_design(design, tmp_path / "design.json")
    assert [p.name for p in tmp_path.iterdir()] == ["design.json"]  # no temporary left behind
    back = load_design(path)
    assert back.form == "standardized" and back.reference == "z_vs" and back.fc_hz == 80.0
    assert back.H_uz.isclose(design.H_uz, rtol=1e-15) and back.H_uw.isclose(design.H_uw, rtol=1e-15)
    assert back.H_ufh is None and back.filter == design.filter
    assert back.constraints == design.constraints
    doc = json.loads(path.read_text())
    assert doc["format"] == FORMAT and doc["version"] == 1
    assert doc["sign_convention"] == "u = H_uz*z_vs + H_uw*w"
    assert doc["vs"]["kind"] == "SD" and doc["table"]["Ke"] == 5.0


@pytest.mark.parametrize(
    "change, message",
    [
        (lambda d: d.update(format="other"), "not an impedance-mil design file"),
        (lambda d: d.update(version=2), "version 2"),
        (lambda d: d.pop("H_uw"), "missing field 'H_uw'"),
        (lambda d: d.update(H_uz={"num": [1, 2, 3], "den": [1]}), "improper"),
        (lambda d: d.update(H_uz={"num": "x"}), "H_uz: expected"),
        # issue 18, finding 7: wrong types and degenerate values get the key, not a traceback
        (lambda d: d.update(constraints="x"), "constraints: expected a list of constraint results"),
        (lambda d: d["constraints"][0].update(I="yes"), r"constraints\[0\]\.I: expected true or false"),
        (lambda d: d["constraints"][0].pop("fc_hz"), r"constraints\[0\]: expected an object with the keys"),
        (lambda d: d.update(H_uz={"num": [1.0], "den": [0.0, 0.0]}), "H_uz.den: expected a denominator with"),
        (lambda d: d.update(H_uw={"num": [True], "den": [1.0, 2.0]}), r"H_uw.num\[0\]: expected a number"),
        (lambda d: d.update(H_uw={"num": [1.0], "den": []}), "H_uw.den: expected a non-empty list"),
        (lambda d: d.update(H_uw={"num": [1.0], "den": [1.0], "gain": 2}), "H_uw: expected null or"),
        (lambda d: d.update(H_uz=None), "H_uz/H_uw: expected transfer functions"),
        (lambda d: d.update(fc_hz="80"), "fc_hz: expected a number"),
        (lambda d: d.update(fc_hz=-80.0), "fc_hz: expected a positive number"),
        (lambda d: d.update(fc_hz=10**400), "line 1: a number of more than 100 digits"),
        (lambda d: d.update(loop_time_s=[0.0005]), "loop_time_s: expected a number"),
        (lambda d: d.update(feasible_fc_hz=[1.0]), "feasible_fc_hz: expected null or a list"),
        (lambda d: d.update(form=["standardized"]), "form: expected one of .* got 'a JSON array'"),
        (lambda d: d.update(reference="a_g"), "reference: expected 'z_vs'"),
        (lambda d: d.update(filter="butterworth"), "filter: expected"),
        (lambda d: d["filter"].update(order_z=2.5), "filter.order_z: expected a whole number"),
        (lambda d: d["filter"].pop("family"), "filter.family: expected present"),
        (lambda d: d.update(warnings="none"), "warnings: expected a list of strings"),
        (lambda d: d.update(warnings=[1]), r"warnings\[0\]: expected a string"),
        (lambda d: d.update(software_version=1), "software_version: expected a string"),
        (lambda d: d.update(vs="SD2"), "vs: expected null or"),
        (lambda d: d["vs"].update(kind=2), "vs.kind: expected a string"),
        (lambda d: d["vs"].update(parameters=[]), "vs.parameters: expected an object"),
        (lambda d: d.update(table=[1]), "table: expected the table parameters"),
        (lambda d: d["table"].update(mass=-1.0), "table.mass"),
        (lambda d: d["table"].update(mass=True), "table.mass: expected a number"),
        (lambda d: d["table"].update(valve_poles_hz=[70.0]), "table.valve_poles_hz: expected a list of 2"),
        # a misspelt table key was ignored, its value lost (issue 18)
        (lambda d: d["table"].update(Kp_gain=0.001), "table.Kp_gain: expected a table parameter: Ke, Kp"),
    ],
)
def test_bad_files_are_refused(tmp_path, design, change, message):
    doc = design_to_dict(design)
    change(doc)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(DataFileError, match=message):
        load_design(path)


@pytest.mark.parametrize(
    "text, message",
    [
        ("[" * 3000 + "]" * 3000, "nested more than 32 deep"),  # was a RecursionError traceback
        ('{"a": ' * 40 + "1" + "}" * 40, "nested more than 32 deep"),
        ('{"fc_hz": ' + "9" * 400 + "}", "a number of more than 100 digits"),
        ('{"fc_hz": ' + "9" * 2_000_000 + "}", "a number of more than 100 digits"),
        ('{"fc_hz": 1e400}', "beyond the range of a double"),
        ('{"fc_hz": NaN}', "NaN is not a JSON number"),
        ('{"fc_hz": -Infinity}', "-Infinity is not a JSON number"),
        ('{"a": "[[[[', "not valid JSON"),  # an unclosed string ends the depth scan
        ("", "not valid JSON"),
    ],
)
def test_hostile_json_is_refused_in_one_line(tmp_path, text, message):
    path = tmp_path / "bad.json"
    path.write_text(text)
    with pytest.raises(DataFileError, match=message) as info:
        load_design(path)
    assert str(path) in str(info.value) and "\n" not in str(info.value) and len(str(info.value)) < 300


def test_brackets_and_digits_inside_strings_are_not_counted(tmp_path, design):
    doc = design_to_dict(design)
    doc["warnings"] = ["[" * 100 + "9" * 200, '"{']
    path = tmp_path / "ok.json"
    path.write_text(json.dumps(doc))
    assert load_design(path).warnings == tuple(doc["warnings"])


def test_unreadable_files(tmp_path):
    with pytest.raises(DataFileError, match="file not found"):
        load_design(tmp_path / "missing.json")
    (tmp_path / "x.json").write_text("{not json")
    with pytest.raises(DataFileError, match="not valid JSON"):
        load_design(tmp_path / "x.json")


def test_write_into_missing_directory_fails_cleanly(tmp_path, design):
    with pytest.raises(DataFileError, match="cannot write"):
        save_design(design, tmp_path / "nope" / "design.json")
