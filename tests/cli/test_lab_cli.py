"""``--lab`` on the command line (issue 12): a non-report lab in SI units trips at its own limits.

Reference values are closed-form unit conversions (50 mm = 1.9685 in) and the
report lab's identity with the default setup.
"""

from __future__ import annotations

import json

import pytest

from impedance_mil.lab.labfile import load_lab
from impedance_mil.plant import default_table_path
from impedance_mil.units import G0

TABLE = default_table_path()

LAB = f"""
[table]
file = "{TABLE}"
mid_stroke = "150 mm"
[limits]
stroke = "50 mm"
velocity = "1 m/s"
[sensors.accel]
quantity = "acceleration"
range = "3 g0"
[sensors.lvdt]
quantity = "displacement"
range = "150 mm"
resolution = "0.01 mm"
[sensors.dp]
quantity = "differential_pressure"
range = "250 bar"
[sensors.lc]
quantity = "load_cell"
range = "500 lbf"
[specimen]
kind = "rigid"
article_weight = "1000 kg"
"""


@pytest.fixture
def lab_file(tmp_path):
    path = tmp_path / "si_lab.toml"
    path.write_text(LAB)
    return path


def test_lab_show_json_names_values_units_and_sources(imil, lab_file):
    res = imil("lab", "show", "--lab", lab_file, "--json")
    assert res.returncode == 0, res.stderr
    doc = json.loads(res.stdout)
    assert doc["limits"]["stroke"] == pytest.approx(50 / 25.4, rel=1e-14)
    assert doc["units"]["limits.stroke"] == "in"
    assert doc["sources"]["limits.stroke"] == "file"
    assert doc["sources"]["limits.divergence"] == "default"
    assert doc["table"]["mid_stroke"] == pytest.approx(150 / 25.4, rel=1e-14)


def test_simulate_trips_at_the_labs_stroke_and_reports_the_clipped_load_cell(imil, lab_file, tmp_path):
    res = imil("simulate", "--lab", lab_file, "--duration", "4", "--force", "--json", "-o", tmp_path / "r.h5")
    assert res.returncode == 3, res.stderr
    doc = json.loads(res.stdout)
    assert doc["lab"] == "si_lab.toml"
    assert doc["trip"]["limit"] == "stroke"
    assert abs(doc["trip"]["value"]) > 50 / 25.4
    assert abs(doc["trip"]["value"]) < 50 / 25.4 + 0.05  # stopped within a loop or two of the limit
    clipped = {c["channel"] for c in doc["sensor_clipping"]}
    assert "lc" in clipped  # a 1000 kg article on a 500 lbf cell
    assert any("sensor lc" in w for w in doc["warnings"])
    assert "lab.limits.divergence" in doc["from_report"]  # the run says which generic defaults it took


def test_clipping_fail_fails_the_run_and_keeps_its_data(imil, lab_file, tmp_path):
    lab_file.write_text(LAB.replace('stroke = "50 mm"', 'stroke = "140 mm"') + "")
    text = lab_file.read_text().replace("[sensors.accel]", '[sensors]\nclipping = "fail"\n[sensors.accel]')
    lab_file.write_text(text)
    out = tmp_path / "r.h5"
    res = imil("track", "--lab", lab_file, "--duration", "2", "--force", "--pga", "0.5", "--json", "-o", out)
    assert res.returncode == 3
    assert "clipping is 'fail'" in res.stderr
    assert out.exists()


def test_report_lab_equals_the_default(imil, tmp_path):
    a = imil("simulate", "--duration", "1", "--json", "-o", tmp_path / "a.h5")
    b = imil("simulate", "--lab", "report", "--duration", "1", "--json", "-o", tmp_path / "b.h5")
    assert a.returncode == b.returncode == 0, (a.stderr, b.stderr)
    da, db = json.loads(a.stdout), json.loads(b.stdout)
    for key in ("nrms_error", "peak_error", "peak_table_accel_g", "peak_table_disp_in"):
        assert da[key] == db[key]  # bit for bit


@pytest.mark.parametrize(
    "text, key",
    [
        ('[limits]\nstroke = "0 mm"\n', "limits.stroke"),
        ('[limits]\nstroke = "200 mm"\n', "limits.stroke"),
        ("[extra]\n", "[extra]"),
        (
            '[sensors.x]\nquantity = "displacement"\nrange = "1 mm"\nresolution = "2 mm"\n',
            "sensors.x.resolution",
        ),
        ('[controller]\nloop_time = "1 ms"\noutput_delay = "1.5 ms"\n', "controller.output_delay"),
    ],
)
def test_bad_lab_files_are_refused_in_one_line_and_nothing_is_written(imil, tmp_path, text, key):
    path = tmp_path / "bad.toml"
    path.write_text(f'[table]\nfile = "{TABLE}"\nmid_stroke = "150 mm"\n' + text)
    for argv in (("lab", "check", path), ("simulate", "--lab", path, "-o", tmp_path / "r.h5")):
        res = imil(*argv)
        assert res.returncode == 2
        assert key in res.stderr and res.stderr.count("\n") == 1 and "Traceback" not in res.stderr
    assert not (tmp_path / "r.h5").exists()


@pytest.mark.parametrize("argv", [("table", "info"), ("design",), ("motion", "check", "elcentro")])
def test_every_table_command_takes_the_lab(imil, lab_file, tmp_path, argv):
    extra = ("-o", tmp_path / "d.json") if argv == ("design",) else ()
    res = imil(*argv, "--lab", lab_file, *extra)
    assert res.returncode in (0, 1), res.stderr  # motion check exits 1 when the motion does not fit


def test_drive_motion_checks_against_the_labs_interlocks_and_article(imil, lab_file, tmp_path):
    # The drive file's pre-test check is the lab's: its 50 mm stroke interlock, its 1000 kg article
    # (1000 kg weighs 1000 / 0.45359237 = 2204.62 lbf), not the report's 3 in and 3600 lbf.
    res = imil(
        "drive", "motion", "elcentro", "--lab", lab_file, "--pga", "0.3", "--force", "-o", tmp_path, "--json"
    )
    assert res.returncode == 0, res.stderr
    doc = json.loads(res.stdout)
    assert doc["provenance"]["interlocks"]["stroke"] == pytest.approx(50 / 25.4, rel=1e-14)
    assert doc["units"]["provenance.interlocks.stroke"] == "in"
    table_weight = load_lab(lab_file).table.mass * G0
    moving = doc["motion"]["pretest"]["moving_weight_lbf"]
    assert moving == pytest.approx(table_weight + 1000 / 0.45359237, rel=1e-12)


@pytest.mark.parametrize("command", ["identify", "evaluate"])
def test_identify_and_evaluate_take_the_lab(imil, lab_file, tmp_path, command):
    # A valid lab is accepted (the missing recording is what is refused); a lab whose stroke is
    # beyond its table's mid-stroke is refused naming the lab's key: the lab file is read.
    res = imil(command, "missing.csv", "--lab", lab_file, "-o", tmp_path / "x.h5")
    assert res.returncode == 2 and "missing.csv" in res.stderr and "--lab" not in res.stderr
    bad = tmp_path / "bad.toml"
    bad.write_text(LAB.replace('stroke = "50 mm"', 'stroke = "200 mm"'))
    res = imil(command, "missing.csv", "--lab", bad, "-o", tmp_path / "x.h5")
    assert res.returncode == 2 and "bad.toml: limits.stroke" in res.stderr and res.stderr.count("\n") == 1
