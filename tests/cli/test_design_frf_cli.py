"""`imil design --frf`: the design also checked on a measured FRF (a model sampled to files here)."""

import json
import sys

import numpy as np
import pytest
from typer.testing import CliRunner

from impedance_mil.cli.main import app, run
from impedance_mil.plant import LinearTable, TableParameters
from impedance_mil.plant.frf_table import FRFTable, write_frf_table

runner = CliRunner()


@pytest.fixture(scope="module")
def frf_files(tmp_path_factory):
    """The report's first-order table sampled at 200 points/decade, 0.01-1000 Hz and 0.25-200 Hz, in SI."""
    p = TableParameters.report_default()
    lt = LinearTable(p, "first-order")
    folder = tmp_path_factory.mktemp("frf")
    out = {}
    for name, (lo, hi) in {"full": (-2, 3), "part": (np.log10(0.25), np.log10(200.0))}.items():
        f = np.logspace(lo, hi, int(round(200 * (hi - lo))) + 1)
        t = FRFTable(
            f, lt.tf("z", "u").frequency_response(f), lt.tf("z", "w").frequency_response(f), p.loop_time
        )
        out[name] = write_frf_table(t, folder / f"{name}.toml", {"z": "m/s**2", "u": "mm", "w": "kN"})
    return out


def test_json_has_a_measured_block_per_cut_off(frf_files):
    res = runner.invoke(
        app, ["design", "--vs", "SD2", "--fc", "80,100", "--frf", str(frf_files["full"]), "--json"]
    )
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    block = doc["measured"]
    assert block["frf_table"] == str(frf_files["full"]) and len(block["constraints"]) == 2
    for model, frf in zip(doc["constraints"], block["constraints"]):
        assert frf["fc_hz"] == model["fc_hz"] and frf["stability"] == "not judged (model-free)"
        # 200 points/decade: measured 3.5e-5 (80 Hz), 9.6e-5 deg (100 Hz) above the refined model margin
        assert frf["passivity_margin_deg"] == pytest.approx(model["passivity_margin_deg"], abs=5e-4)
        assert frf["coverage"]["III"] == "full" and frf["III"] is False  # raw margin -1.0 / -0.87 deg
    assert not [k for k, v in doc["units"].items() if v == "unknown" and k.startswith("measured")]


def test_text_output_and_delay_model_tolerance(frf_files):
    res = runner.invoke(
        app,
        [
            "design",
            "--vs",
            "SD2",
            "--fc",
            "80",
            "--frf",
            str(frf_files["part"]),
            "--frf-tolerance",
            "delay-model",
        ],
    )
    assert res.exit_code == 0, res.output
    assert "measured FRF at fc = 80 Hz" in res.output
    line = next(x for x in res.output.splitlines() if x.strip().startswith("III"))
    assert (
        "--" in line and "partial" in line
    )  # passes where measured, 0.25-200 Hz of 0.01-1000 Hz: no verdict


def test_optimized_method_is_checked_at_its_cut_off(frf_files):
    res = runner.invoke(
        app,
        [
            "design",
            "--vs",
            "SD2",
            "--fc",
            "80",
            "--method",
            "optimized",
            "--frf",
            str(frf_files["full"]),
            "--json",
        ],
    )
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    assert len(doc["measured"]["constraints"]) == 1


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--frf-tolerance", "loose"], "--frf-tolerance"),
        (["--frf-controller", "zoh"], "--frf-controller"),
        (["--frf", "{missing}"], "missing.toml: file not found"),
        (["--frf", "{bad_column}"], "bad.csv: missing column 'H_zw_im'"),
        (["--frf", "{slow_loop}"], "--frf: expected the design's loop time"),
    ],
)
def test_bad_frf_input_is_one_line_exit_2(tmp_path, monkeypatch, capsys, frf_files, extra, message):
    (tmp_path / "bad.csv").write_text("frequency_hz, H_zu_re, H_zu_im, H_zw_re\n1, 1, 0, 1\n2, 1, 0, 1\n")
    (tmp_path / "bad.toml").write_text(
        '[model]\nkind = "frf"\nfile = "bad.csv"\nloop_time = "500 us"\n'
        'units = { z = "in/s**2", u = "in", w = "lbf" }\n'
    )
    slow = tmp_path / "slow.toml"
    slow.write_text(
        frf_files["full"]
        .read_text()
        .replace("0.0005 s", "0.001 s")
        .replace('"full.csv"', f'"{frf_files["full"].with_suffix(".csv")}"')
    )
    names = {"missing": tmp_path / "missing.toml", "bad_column": tmp_path / "bad.toml", "slow_loop": slow}
    extra = [x.format(**names) for x in extra]
    out = tmp_path / "d.json"
    monkeypatch.setattr(sys, "argv", ["imil", "design", "--vs", "SD2", *extra, "-o", str(out)])
    with pytest.raises(SystemExit) as exc:
        run()
    assert exc.value.code == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0] and "Traceback" not in err
    assert not out.exists()
