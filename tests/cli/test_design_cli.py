"""`imil design` end to end (typer runner; errors through cli.main.run)."""

import json
import sys

import pytest
from typer.testing import CliRunner

from impedance_mil.cli.main import app, run
from impedance_mil.design import load_design

runner = CliRunner()


def test_json_contract_table_9_5_plots_and_design_file(tmp_path):
    out = tmp_path / "design.json"
    res = runner.invoke(
        app,
        [
            "design",
            "--vs",
            "SD2",
            "--fc",
            "1000,250,100,50",
            "--json",
            "--plots",
            str(tmp_path),
            "-o",
            str(out),
        ],
    )
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    assert doc["form"] == "standardized" and doc["fc_hz"] == 1000.0
    assert set(doc["H_uz"]) == {"num", "den"} and set(doc["H_uw"]) == {"num", "den"}
    verdicts = {c["fc_hz"]: (c["I"], c["II"], c["III"]) for c in doc["constraints"]}
    assert verdicts == {
        1000.0: (True, False, True),
        250.0: (True, True, True),
        100.0: (True, True, True),
        50.0: (False, True, False),
    }  # Table 9.5
    for key in ("performance_error", "effort_ratio", "passivity_margin_deg"):
        assert all(isinstance(c[key], float) for c in doc["constraints"])
    lo, hi = doc["feasible_fc_hz"]
    assert lo <= 100.0 and hi >= 250.0  # Section 9.4.3: 100-250 Hz feasible
    assert any("Nyquist" in w for w in doc["warnings"])  # 1000 Hz with a 2000 Hz loop
    assert any("constraint II" in w for w in doc["warnings"])
    for name in ("design_fig931.png", "design_constraints.png"):
        assert (tmp_path / name).stat().st_size > 10_000
    assert load_design(out).fc_hz == 1000.0


def test_auto_cut_off_with_reasons():
    res = runner.invoke(app, ["design", "--vs", "SD2", "--fc", "auto", "--json"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    lo, hi = doc["feasible_fc_hz"]
    assert lo <= doc["fc_hz"] <= hi
    assert doc["constraints"][0]["I"] and doc["constraints"][0]["II"] and doc["constraints"][0]["III"]
    assert len(doc["fc_choice_reasons"]) >= 2


@pytest.mark.parametrize(
    "args, message",
    [
        (["--vs", "SD2", "--fc", "0"], "--fc"),
        (["--vs", "SD2", "--fc", "-80"], "--fc"),
        (["--vs", "SD2", "--order", "2"], "filter order"),
        (["--vs", "SD2", "--set", "Kp=0.02"], "unstable"),
        (["--vs", "SD9"], "preset"),
        (["--vs", "SD2", "--form", "nope"], "--form"),
        (["--form", "general"], "--vs"),
        (["--vs", "SD2", "--band", "nan,15"], "--band"),  # NaN/inf passed _parse_list before
        (["--vs", "SD2", "--mass-ratios", "1.25,inf"], "--mass-ratios"),
    ],
)
def test_bad_input_is_one_line_exit_2(tmp_path, monkeypatch, capsys, args, message):
    # Through cli.main.run(), the entry point of the `imil` script, in-process (fast).
    out = tmp_path / "d.json"
    monkeypatch.setattr(sys, "argv", ["imil", "design", *args, "-o", str(out)])
    with pytest.raises(SystemExit) as exc:
        run()
    assert exc.value.code == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0] and "Traceback" not in err
    assert not out.exists()


def test_lr_linearization_and_mass_study_with_coupled_stability():
    res = runner.invoke(
        app,
        ["design", "--vs", "LR2", "--fc", "80", "--json", "--amplitude", "1", "--mass-ratios", "1.25,0.7"],
    )
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    assert doc["vs_linearization"]["method"] == "describing-function"
    assert doc["vs_linearization"]["amplitude_in"] == 1.0
    rows = doc["mass_ratio_study"]
    assert [r["mass_ratio"] for r in rows] == [1.25, 0.7]
    assert {c["specimen"] for c in rows[0]["coupled"]} == {
        "vessel 0.0 in",
        "vessel 18.0 in",
        "vessel 30.0 in",
        "vessel 36.0 in",
        "vessel 42.0 in",
    }
    assert all("feasible_fc_hz" in r and "passive_at_design_fc" in r for r in rows)
