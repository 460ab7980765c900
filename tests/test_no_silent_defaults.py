"""No silent defaults or truncation (issue 18, finding 9): each case refused with one line naming the key.

The audit's cases: an empty specimen file became the report's vessel;
``n_convective_modes = 2.5`` became 2; ``NPTS= 5372.5`` became 5372;
``--passivity-tol nan`` was accepted; two studies with the same name were
merged; a design file with a boolean numerator or a negative mass exported.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from impedance_mil.campaign import load_campaign
from impedance_mil.design import design_controller, load_design, save_design, table_model
from impedance_mil.design.constraints import DesignCriteria
from impedance_mil.errors import ConfigError, DataFileError
from impedance_mil.plant import TableParameters
from impedance_mil.signals import read_at2
from impedance_mil.specimens import specimen_from_config


def test_an_empty_specimen_file_is_not_the_report_vessel(imil, tmp_path):
    for text in ("", "[specimen]\n"):
        path = tmp_path / "s.toml"
        path.write_text(text)
        out = imil("simulate", "--specimen", path, "-o", tmp_path / "run.h5")
        assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1
        assert (
            out.stderr.startswith("imil: error: s.toml: specimen.type: ")
            and "not an empty table" in out.stderr
        )
        assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]  # nothing written
    with pytest.raises(ConfigError, match=r"^specimen\.type: "):
        specimen_from_config({})


def test_a_fractional_number_of_modes_is_refused():
    with pytest.raises(
        ConfigError, match=r"^specimen\.n_convective_modes: expected a whole number, got 2\.5"
    ):
        specimen_from_config({"type": "vessel", "n_convective_modes": 2.5})
    assert specimen_from_config({"type": "vessel", "n_convective_modes": 2}).n_convective_modes == 2


def test_a_fractional_npts_is_refused(tmp_path):
    samples = " ".join(f"{x:.4f}" for x in np.zeros(5372))
    path = tmp_path / "rec.AT2"
    header = "PEER NGA\nrecord\nACCELERATION TIME SERIES IN UNITS OF G\n"
    path.write_text(header + "NPTS= 5372.5, DT= .0100 SEC\n" + samples + "\n")
    with pytest.raises(DataFileError, match=r"line 4: NPTS must be an integer >= 2, got 5372\.5"):
        read_at2(path)
    path.write_text(header + "NPTS= 5372, DT= .0100 SEC\n" + samples + "\n")
    assert read_at2(path).npts == 5372


def test_a_nan_passivity_tolerance_is_refused(imil, tmp_path):
    for bad in (float("nan"), float("inf"), -1.0):
        with pytest.raises(
            ConfigError, match="^passivity_extra_tolerance_deg: expected a finite non-negative"
        ):
            DesignCriteria(passivity_extra_tolerance_deg=bad)
    out = imil("design", "--passivity-tol", "nan", "-o", tmp_path / "d.json")
    assert out.returncode == 2 and out.stderr.startswith(
        "imil: error: --passivity-tol: expected a finite non-negative"
    )
    assert not (tmp_path / "d.json").exists()


def test_two_studies_with_one_name_are_refused(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text(
        '[campaign]\nname = "c"\nkind = "selftest"\n'
        '[[study]]\nname = "a"\nproduct = { stiffness = [1, 2] }\n'
        '[[study]]\nname = "a"\nproduct = { stiffness = [3] }\n'
    )
    with pytest.raises(ConfigError) as info:
        load_campaign(path)
    assert info.value.key == "study[1].name" and "no other study has" in str(info.value)


@pytest.fixture(scope="module")
def design_doc(tmp_path_factory):
    d = tmp_path_factory.mktemp("design")
    design = design_controller(
        table_model(TableParameters.report_default()), form="standardized", fc_hz=80.0, emit_warnings=False
    )
    return json.loads(save_design(design, d / "design.json").read_text())


@pytest.mark.parametrize(
    "change, message",
    [
        (lambda d: d["H_uz"]["num"].__setitem__(0, True), "H_uz.num[0]: expected a number, got True"),
        (lambda d: d["H_uw"]["den"].__setitem__(1, "2"), "H_uw.den[1]: expected a number, got '2'"),
        (lambda d: d["H_uz"]["den"].__setitem__(1, 10**400), "line 1: a number of more than 100 digits"),
        (lambda d: d["table"].__setitem__("mass", -4.14), "table.mass: expected a positive value, got -4.14"),
        (lambda d: d["table"].__setitem__("mass", True), "table.mass: expected a number"),
        (
            lambda d: d["table"].__setitem__("return_pressure", 3000.0),
            "table.return_pressure: expected a pressure",
        ),
        (lambda d: d["table"].__setitem__("d", 1e-300), "table.d: expected a plausible value"),
    ],
)
def test_a_bad_design_file_does_not_export(imil, tmp_path, design_doc, change, message):
    doc = json.loads(json.dumps(design_doc))
    change(doc)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(DataFileError) as info:
        load_design(path)
    assert message in str(info.value)
    out = imil("export", path, "-o", "out", cwd=tmp_path)
    assert out.returncode == 2 and message in out.stderr and len(out.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()
