"""`imil motion`: info, spectrum, check, plot; exit statuses and one-line errors."""

from __future__ import annotations

import importlib.resources
import json
import sys

import numpy as np
import pytest

from impedance_mil.cli.main import run
from impedance_mil.signals import TableLimits, builtin_motion, check_motion, read_motion, response_spectrum


def _imil(monkeypatch, capsys, *args):
    """Run ``imil`` in-process; return (exit status, stdout, stderr)."""
    monkeypatch.setattr(sys, "argv", ["imil", *args])
    code = 0
    try:
        run()
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_info_json_report_gm1(monkeypatch, capsys):
    code, out, _ = _imil(
        monkeypatch, capsys, "motion", "info", "elcentro", "--time-scale", "2", "--pga", "0.8", "--json"
    )
    data = json.loads(out)
    assert code == 0
    # RSN 6 header: 5372 points at 0.01 s; compressed by 2 -> 0.005 s, 26.855 s (exact).
    assert data["npts"] == 5372 and data["dt_s"] == pytest.approx(0.005)
    assert data["duration_s"] == pytest.approx(26.855)
    assert data["pga_g"] == pytest.approx(0.8, rel=1e-12)
    corrected = builtin_motion("elcentro").time_scaled(2).scaled_to_pga(0.8).baseline_corrected()
    assert data["pgd_in"] == pytest.approx(corrected.pgd, rel=1e-12)


def test_info_human_and_list(monkeypatch, capsys):
    code, out, _ = _imil(monkeypatch, capsys, "motion", "info", "elcentro")
    assert code == 0 and "PGA:      0.2808 g" in out and "npts:     5372" in out
    code, out, _ = _imil(monkeypatch, capsys, "motion", "list")
    assert code == 0 and "elcentro" in out


def test_spectrum_json_matches_library(monkeypatch, capsys):
    code, out, _ = _imil(
        monkeypatch,
        capsys,
        "motion",
        "spectrum",
        "elcentro",
        "--damping",
        "0.05",
        "--periods",
        "0.1,0.5,2",
        "--json",
    )
    data = json.loads(out)
    gm = builtin_motion("elcentro")
    spec = response_spectrum(gm.accel, gm.time_step, [0.1, 0.5, 2.0], 0.05)
    assert code == 0 and data["period_s"] == [0.1, 0.5, 2.0]
    np.testing.assert_allclose(data["psa_g"], spec.psa_g, rtol=1e-12)


def test_spectrum_default_periods_and_plot(monkeypatch, capsys, tmp_path):
    target = tmp_path / "spec.png"
    code, out, _ = _imil(
        monkeypatch,
        capsys,
        "motion",
        "spectrum",
        "elcentro",
        "--json",
        "--periods",
        "log:0.05:5:12",
        "-o",
        str(target),
    )
    assert code == 0 and len(json.loads(out)["psa_g"]) == 12
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["spec.png"]  # no temporary left


def test_check_fits_exit_0_and_exceeds_exit_1(monkeypatch, capsys):
    args = ["motion", "check", "elcentro", "--specimen-weight", "1200", "--pga", "0.8", "--json"]
    code, out, _ = _imil(monkeypatch, capsys, *args, "--time-scale", "2")
    data = json.loads(out)
    assert code == 0 and data["ok"] and data["exceeded"] == []
    code, out, _ = _imil(monkeypatch, capsys, *args)
    data = json.loads(out)
    assert code == 1 and data["exceeded"] == ["stroke"]
    # Same numbers as the library with the table of report Table 4.1 (m_st = 4.14 as printed).
    plant = pytest.importorskip("impedance_mil.plant")
    limits = TableLimits.from_table(plant.TableParameters.report_default(), specimen_weight=1200.0)
    lib = check_motion(builtin_motion("elcentro").scaled_to_pga(0.8), limits)
    assert data["suggested_time_scale"] == lib.suggested_time_scale
    assert data["checks"][0]["peak"] == pytest.approx(lib.check("stroke").peak, rel=1e-12)


def test_check_human_output_names_limit_and_fix(monkeypatch, capsys):
    code, out, _ = _imil(monkeypatch, capsys, "motion", "check", "elcentro", "--pga", "0.8")
    assert code == 1 and "OVER stroke" in out and "--time-scale" in out


def test_check_set_override_and_force_limit(monkeypatch, capsys):
    # A 10 in mid-stroke makes the unscaled record fit the stroke; a 300 lbf force limit is below
    # 1600 lb x 0.281 g = 449 lbf (bare table, record as shipped).
    code, out, _ = _imil(
        monkeypatch, capsys, "motion", "check", "elcentro", "--pga", "0.8", "--set", "mid_stroke=10", "--json"
    )
    assert code == 0 and json.loads(out)["checks"][0]["limit"] == 10.0
    code, out, _ = _imil(
        monkeypatch,
        capsys,
        "motion",
        "check",
        "elcentro",
        "--time-scale",
        "2",
        "--force-limit",
        "300",
        "--json",
    )
    assert code == 1 and json.loads(out)["exceeded"][0] == "force"


def test_column_file_with_units(monkeypatch, capsys, tmp_path):
    path = tmp_path / "rec.csv"
    t = np.arange(201) * 0.01
    np.savetxt(
        path, np.column_stack([t, 2.0 * np.sin(2 * np.pi * t)]), delimiter=",", header="time,accel_m_s2"
    )
    code, out, _ = _imil(
        monkeypatch, capsys, "motion", "info", str(path), "--motion-units", "m/s**2", "--json"
    )
    # 2 m/s^2 = 2 / 9.80665 g = 0.20394 g (the sine peaks exactly on a sample at t = 0.25 s).
    assert code == 0 and json.loads(out)["pga_g"] == pytest.approx(2 / 9.80665, rel=1e-12)


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["motion", "info", "nope.AT2"], "nope.AT2: file not found"),
        (["motion", "info", "elcentro", "--pga", "-1"], "pga"),
        (["motion", "spectrum", "elcentro", "--periods", "a,b"], "--periods"),
        (["motion", "spectrum", "elcentro", "--damping", "-0.5"], "damping"),
        (["motion", "spectrum", "elcentro", "-o", "/nonexistent/dir/x.png"], "existing folder"),
        (["motion", "spectrum", "elcentro", "-o", "x.unknownformat"], "-o"),
        (["motion", "check", "elcentro", "--set", "nokey=3"], "nokey"),
        (["motion", "check", "elcentro", "--specimen-weight", "-3"], "--specimen-weight"),
        (["motion", "info", "fema:farfield:x:a"], "fema"),
    ],
)
def test_bad_input_one_line_exit_2(monkeypatch, capsys, tmp_path, args, needle):
    monkeypatch.chdir(tmp_path)
    code, out, err = _imil(monkeypatch, capsys, *args)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("imil: error:") and needle in err
    assert list(tmp_path.iterdir()) == []


def test_malformed_file_one_line(monkeypatch, capsys, tmp_path):
    path = tmp_path / "bad.AT2"
    path.write_text("h1\nh2\nACCELERATION IN G\nNPTS= 3, DT= .01 SEC\n.1 .2\n")
    code, _, err = _imil(monkeypatch, capsys, "motion", "info", str(path))
    assert code == 2 and "NPTS = 3 but the file holds 2 samples" in err and err.count("\n") == 1


def test_plot_histories(monkeypatch, capsys, tmp_path):
    target = tmp_path / "hist.svg"
    code, _, _ = _imil(monkeypatch, capsys, "motion", "plot", "elcentro", "-o", str(target))
    assert code == 0 and target.read_text().lstrip().startswith("<?xml")


def test_export_for_the_loop_round_trips(monkeypatch, capsys, tmp_path):
    # GM1 at the report's 2000 Hz loop: 0.005 s -> 0.0005 s is 10/1; reading the CSV back gives the
    # same samples (10 significant digits written) and the motion ends at rest (baseline-corrected).
    target = tmp_path / "gm1.csv"
    code, _, _ = _imil(
        monkeypatch,
        capsys,
        "motion",
        "export",
        "elcentro",
        "--time-scale",
        "2",
        "--pga",
        "0.8",
        "--dt",
        "0.0005",
        "-o",
        str(target),
    )
    assert code == 0
    back = read_motion(target)
    expected = (
        builtin_motion("elcentro").time_scaled(2).scaled_to_pga(0.8).resampled(0.0005).baseline_corrected()
    )
    assert back.npts == expected.npts and back.time_step == pytest.approx(0.0005, rel=1e-9)
    np.testing.assert_allclose(back.accel, expected.accel, rtol=1e-9, atol=1e-9 * expected.pga)
    assert abs(back.displacement()[-1]) < 1e-6 * back.pgd
    code, _, err = _imil(
        monkeypatch,
        capsys,
        "motion",
        "export",
        "elcentro",
        "--dt",
        "0.00123456789",
        "-o",
        str(tmp_path / "x.csv"),
    )
    assert code == 2 and "time_step" in err and not (tmp_path / "x.csv").exists()


def test_check_with_table_file_and_units(monkeypatch, capsys, tmp_path):
    # A table file with a bigger actuator: 5 in^2 piston, 6 in stroke, in metric where pint allows.
    # v_max = 57.75 sqrt(3000/1000) / 5 = 20.005 in/s (hand); force 5 x 3000 = 15000 lbf.
    text = (importlib.resources.files("impedance_mil") / "data/tables/report_table_4_1.toml").read_text()
    text = text.replace('piston_area = "2.1 in**2"', 'piston_area = "32.258 cm**2"')
    text = text.replace('mid_stroke = "3.2 in"', 'mid_stroke = "6 in"')
    table = tmp_path / "big.toml"
    table.write_text(text)
    code, out, _ = _imil(
        monkeypatch, capsys, "motion", "check", "elcentro", "--table", str(table), "--pga", "0.8", "--json"
    )
    data = json.loads(out)
    limits = {c["name"]: c["limit"] for c in data["checks"]}
    assert limits["velocity"] == pytest.approx(57.75 * 3**0.5 / 5.0, rel=1e-6)
    assert limits["force"] == pytest.approx(15000.0, rel=1e-6) and limits["stroke"] == 6.0
    # Unscaled GM1: 9.7 in > 6 in, 34.7 in/s > 20.0 in/s, and the flow 5 x 34.7 = 173 in^3/s > 57.75.
    assert code == 1 and data["exceeded"] == ["stroke", "velocity", "flow"]
    code, _, err = _imil(
        monkeypatch, capsys, "motion", "check", "elcentro", "--table", str(tmp_path / "missing.toml")
    )
    assert code == 2 and "missing.toml" in err and err.count("\n") == 1
