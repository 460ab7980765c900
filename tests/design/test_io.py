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
        (lambda d: d.update(H_uz={"num": "x"}), "malformed"),
    ],
)
def test_bad_files_are_refused(tmp_path, design, change, message):
    doc = design_to_dict(design)
    change(doc)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(DataFileError, match=message):
        load_design(path)


def test_unreadable_files(tmp_path):
    with pytest.raises(DataFileError, match="file not found"):
        load_design(tmp_path / "missing.json")
    (tmp_path / "x.json").write_text("{not json")
    with pytest.raises(DataFileError, match="not valid JSON"):
        load_design(tmp_path / "x.json")


def test_write_into_missing_directory_fails_cleanly(tmp_path, design):
    with pytest.raises(DataFileError, match="cannot write"):
        save_design(design, tmp_path / "nope" / "design.json")
