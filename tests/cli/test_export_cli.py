"""`imil export`: formats, one-line errors with exit status 2, no partial output."""

from __future__ import annotations

import json

import pytest

from impedance_mil.design import design_controller, save_design, table_model
from impedance_mil.plant import TableParameters, default_table_path


@pytest.fixture(scope="module")
def design_file(tmp_path_factory):
    d = tmp_path_factory.mktemp("design")
    design = design_controller(
        table_model(TableParameters.report_default()), form="standardized", fc_hz=80.0, emit_warnings=False
    )
    return save_design(design, d / "design.json")


def test_export_json_and_csv(imil, design_file, tmp_path):
    r = imil("export", design_file, "--format", "json", "--precision", "double", "-o", "j", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    doc = json.loads((tmp_path / "j" / "imil_coefficients.json").read_text())
    assert doc["loop_time_s"] == 0.0005 and doc["precision"] == "double"
    assert doc["channels"]["H_uz"]["A"]["shape"] == [5, 5]
    assert doc["channels"]["H_uz"]["n_integrators"] == 2 and doc["design"]["form"] == "standardized"
    r = imil("export", design_file, "--format", "csv", "-o", "c", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    rows = [
        ln
        for ln in (tmp_path / "c" / "imil_coefficients.csv").read_text().splitlines()
        if not ln.startswith("#")
    ]
    assert rows[0] == "channel,matrix,row,col,value" and len(rows) == 1 + (25 + 5 + 5 + 1) + (9 + 3 + 3 + 1)


def test_export_c_and_st_with_vs(imil, design_file, tmp_path):
    r = imil(
        "export", design_file, "--format", "c", "--vs", "FP2", "--prefix", "rig1", "-o", "c", cwd=tmp_path
    )
    assert r.returncode == 0, r.stderr
    assert "rig1_mil_step" in (tmp_path / "c" / "rig1.h").read_text()
    r = imil("export", design_file, "--format", "st", "--vs", "LR2", "-o", "s", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "FUNCTION_BLOCK imil_mil" in (tmp_path / "s" / "imil.st").read_text()


def _bad(imil, tmp_path, *args):
    r = imil("export", *args, "-o", "out", cwd=tmp_path)
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1 and "Traceback" not in r.stderr
    assert not (tmp_path / "out").exists()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".out")] == []
    return r.stderr


def test_bad_inputs_one_line_exit_2_nothing_written(imil, design_file, tmp_path):
    doc = json.loads(design_file.read_text())
    other = tmp_path / "v9.json"
    other.write_text(json.dumps({**doc, "version": 9}))
    assert "version" in _bad(imil, tmp_path, other)
    missing = tmp_path / "missing.json"
    missing.write_text(json.dumps({k: v for k, v in doc.items() if k != "H_uz"}))
    assert "H_uz" in _bad(imil, tmp_path, missing)
    assert "loop_time_s" in _bad(imil, tmp_path, design_file, "--loop-time", "0.001")
    assert "prefix" in _bad(imil, tmp_path, design_file, "--prefix", "static")
    assert "prefix" in _bad(imil, tmp_path, design_file, "--format", "st", "--prefix", "VAR")
    assert "prefix" in _bad(imil, tmp_path, design_file, "--prefix", "9lives")
    nyq = tmp_path / "nyq.json"
    nyq.write_text(json.dumps({**doc, "fc_hz": 1000.0}))
    assert "fc_hz" in _bad(imil, tmp_path, nyq)
    assert "--format" in _bad(imil, tmp_path, design_file, "--format", "pdf")


def test_io_units_scale_the_code_and_the_default_is_unchanged(imil, design_file, tmp_path):
    # No option and --io-units us write the same files; si names its units and factors.
    for fmt in ("c", "st", "json"):
        assert imil("export", design_file, "--format", fmt, "-o", f"{fmt}0", cwd=tmp_path).returncode == 0
        r = imil("export", design_file, "--format", fmt, "--io-units", "us", "-o", f"{fmt}1", cwd=tmp_path)
        assert r.returncode == 0, r.stderr
        for f in (tmp_path / f"{fmt}0").iterdir():
            assert f.read_bytes() == (tmp_path / f"{fmt}1" / f.name).read_bytes()
    r = imil("export", design_file, "--io-units", "si", "-o", "si", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "I/O units si: z_vs, a_g in m/s**2, w in N, u in mm" in r.stdout
    header = (tmp_path / "si" / "imil.h").read_text()
    assert "#define IMIL_DISP_FROM_INTERNAL 25.399999618530273f" in header  # 25.4 in float
    r = imil(
        "export",
        design_file,
        "--format",
        "json",
        "--io-units",
        "accel=g0,force=kN,disp=mm",
        "-o",
        "j",
        cwd=tmp_path,
    )
    assert r.returncode == 0, r.stderr
    io = json.loads((tmp_path / "j" / "imil_coefficients.json").read_text())["io_units"]
    # g0 = 9.80665 m/s**2 = 386.0886 in/s^2; 1 kN = 224.8089 lbf (NIST SP 811 B.8)
    assert io["z_vs"]["to_internal"] == pytest.approx(9.80665 / 0.0254, rel=1e-15)
    assert io["w"]["to_internal"] == pytest.approx(1000 / (0.45359237 * 9.80665), rel=1e-15)
    assert io["u"] == {"unit": "mm", "internal_unit": "in", "from_internal": 25.4}


def test_a_lab_file_sets_the_io_units_unless_the_option_does(imil, design_file, tmp_path):
    lab = tmp_path / "lab.toml"
    lab.write_text(
        f'[table]\nfile = "{default_table_path()}"\n[controller]\n'
        'io_units = {accel = "m/s**2", force = "kN", disp = "mm"}\n'
    )
    r = imil("export", design_file, "--lab", lab, "--format", "st", "-o", "a", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "w : REAL;  (* [kN] *)" in (tmp_path / "a" / "imil.st").read_text()
    r = imil(
        "export", design_file, "--lab", lab, "--format", "st", "--io-units", "us", "-o", "b", cwd=tmp_path
    )
    assert r.returncode == 0, r.stderr
    assert "I/O units" not in (tmp_path / "b" / "imil.st").read_text()


def test_bad_io_units_one_line_exit_2_nothing_written(imil, design_file, tmp_path):
    assert "--io-units force" in _bad(
        imil, tmp_path, design_file, "--io-units", "accel=m/s**2,force=mm,disp=mm"
    )
    assert "--io-units accel" in _bad(imil, tmp_path, design_file, "--io-units", "si,accel=g")
    assert "--io-units" in _bad(imil, tmp_path, design_file, "--io-units", "metric")
    bad_lab = tmp_path / "bad.toml"
    bad_lab.write_text(f'[table]\nfile = "{default_table_path()}"\n[controller]\nio_units = "si,disp=N"\n')
    assert "controller.io_units disp" in _bad(imil, tmp_path, design_file, "--lab", bad_lab)
