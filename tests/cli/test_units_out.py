"""``--units us|si`` and a lab file's ``units = "si"`` on the command line (issue 12, "Units out").

Reference values: the lab file's own SI limits (50 mm, 1 m/s), exact unit
definitions (1 in = 25.4 mm), and the invariant that every number of every
JSON document has a known unit (``tests/report/test_documents.py`` tests the
conversion itself).
"""

from __future__ import annotations

import json

import pytest

from impedance_mil.report.documents import UNKNOWN

from .test_lab_cli import LAB

#: The SI lab of test_lab_cli, printing in SI.
SI_LAB = 'units = "si"\n' + LAB


@pytest.fixture
def si_lab(tmp_path):
    path = tmp_path / "si_lab.toml"
    path.write_text(SI_LAB)
    return path


def _numbers(doc, path=""):
    """Paths of every number (or list of numbers) of a JSON document, as the units block names them."""
    out = set()
    for key, value in doc.items():
        here = f"{path}.{key}" if path else key
        if isinstance(value, dict):
            out |= _numbers(value, here)
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            for i, item in enumerate(value):
                out |= _numbers(item, f"{here}[{i}]")
        elif isinstance(value, int | float | list) and not isinstance(value, bool) and value != []:
            if not isinstance(value, list) or all(not isinstance(v, str) for v in value):
                out.add(here)
    return out


@pytest.mark.parametrize(
    "argv",
    [
        ("table", "info"),
        ("table", "poles"),
        ("table", "tune"),
        ("table", "tf", "--input", "w"),
        ("lab", "show"),
        ("vs", "describe", "FP2"),
        ("vs", "loops", "LR2", "-o", "{tmp}/l.png"),
        ("motion", "info", "elcentro", "--motion-units", "g0"),
        ("motion", "check", "elcentro", "--motion-units", "g0"),
        ("motion", "spectrum", "elcentro", "--motion-units", "g0"),
        ("design", "-o", "{tmp}/d.json"),
        ("design", "--vs", "SD2", "--fc", "80"),  # passivity_index [lbf*s/in] is a number with a VS
        ("drive", "multisine", "-o", "{tmp}"),
        ("campaign", "plan", "report-sec9", "--reduced"),
    ],
)
def test_every_number_of_the_json_has_a_known_unit(imil, tmp_path, argv):
    res = imil(*(a.format(tmp=tmp_path) for a in argv), "--json", "--units", "si")
    assert res.returncode in (0, 1), res.stderr  # motion check exits 1 when the record does not fit
    doc = json.loads(res.stdout)
    assert doc["unit_system"] == "si"
    units = doc.pop("units")
    missing = _numbers(doc) - set(units)
    assert not missing, missing
    assert [k for k, v in units.items() if v == UNKNOWN] == []


def test_a_lab_in_si_prints_si_and_trips_at_its_own_stroke_in_mm(imil, si_lab, tmp_path):
    res = imil("simulate", "--lab", si_lab, "--duration", "4", "--force", "--json", "-o", tmp_path / "r.h5")
    assert res.returncode == 3, res.stderr
    doc = json.loads(res.stdout)
    assert doc["unit_system"] == "si"
    assert doc["trip"]["limit"] == "stroke" and doc["trip"]["unit"] == "mm"
    assert 50.0 < abs(doc["trip"]["value"]) < 50.0 + 0.05 * 25.4  # within a loop or two of 50 mm
    assert doc["units"]["trip.value"] == "mm"
    assert "value -50" in doc["abort_reason"] and " mm)" in doc["abort_reason"]
    assert doc["units"]["peak_table_disp_mm"] == "mm" and "peak_table_disp_in" not in doc
    assert doc["specimen_weight_kn"] == pytest.approx(9.80665, rel=1e-9)  # 1000 kg weighs 9.807 kN
    assert doc["units"]["pretest.input.checks[0].peak"] == "mm"
    assert [k for k, v in doc["units"].items() if v == UNKNOWN] == []
    # --units us overrides the lab's choice: the same run in inches
    us = imil(
        "simulate",
        "--lab",
        si_lab,
        "--duration",
        "4",
        "--force",
        "--json",
        "--units",
        "us",
        "-o",
        tmp_path / "u.h5",
    )
    doc_us = json.loads(us.stdout)
    assert doc_us["trip"]["value"] * 25.4 == pytest.approx(doc["trip"]["value"], rel=1e-12)
    assert doc_us["peak_table_disp_in"] * 25.4 == pytest.approx(doc["peak_table_disp_mm"], rel=1e-12)


def test_run_page_and_text_in_si(imil, si_lab, tmp_path):
    page = tmp_path / "r.html"
    res = imil(
        "track", "--lab", si_lab, "--duration", "2", "--force", "--report", page, "-o", tmp_path / "r.h5"
    )
    assert res.returncode == 3, res.stderr
    assert "(value -50." in res.stdout and "mm)" in res.stdout  # the trip, in the lab's units
    assert "peak table displacement" in res.stdout and "50." in res.stdout
    html = page.read_text()
    assert "peak_table_disp_mm [mm]" in html
    again = tmp_path / "us.html"
    assert imil("report", tmp_path / "r.h5", "-o", again, "--units", "us").returncode == 0
    assert "peak_table_disp_in [in]" in again.read_text()


def test_table_info_text_names_every_unit(imil, si_lab):
    res = imil("table", "info", "--lab", si_lab)
    assert res.returncode == 0, res.stderr
    lines = {line.split()[0]: line.split()[1:] for line in res.stdout.splitlines()}
    assert lines["mid_stroke"] == ["150", "mm"]
    assert lines["Ke"][1] == "V/mm" and lines["mass"][1] == "kg" and lines["supply_pressure"][1] == "MPa"


@pytest.mark.parametrize("argv", [("table", "info", "--units", "metric"), ("lab", "show", "--units", "")])
def test_unknown_unit_systems_are_refused_in_one_line(imil, argv):
    res = imil(*argv)
    assert res.returncode == 2
    assert res.stderr.startswith("imil: error: --units: expected us or si") and res.stderr.count("\n") == 1


def test_a_lab_file_with_an_unknown_unit_system_is_refused(imil, tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(SI_LAB.replace('units = "si"', 'units = "metric"'))
    res = imil("lab", "check", path)
    assert res.returncode == 2
    assert "bad.toml: units: expected us or si" in res.stderr and res.stderr.count("\n") == 1


@pytest.mark.parametrize(
    "limit, text, unit, threshold",
    [
        ("velocity", '"100 mm/s"', "mm/s", 100.0),
        ("acceleration", '"0.1 g0"', "m/s**2", 0.1 * 9.80665),
        ("actuator_force", '"1 kN"', "kN", 1.0),
        ("pressure", '"10 bar"', "MPa", 1.0),
        ("valve_current", '"1 mA"', "mA", 1.0),
    ],
)
def test_each_limit_of_the_lab_trips_the_run_in_the_labs_units(imil, tmp_path, limit, text, unit, threshold):
    # One limit of the lab set low (the others generic); the run stops on it, and the JSON gives
    # the offending value in SI, beyond the limit as the lab file states it.
    lab = tmp_path / "lab.toml"
    lab.write_text(SI_LAB.replace('stroke = "50 mm"\nvelocity = "1 m/s"', f"{limit} = {text}"))
    res = imil(
        "track", "--lab", lab, "--duration", "3", "--pga", "0.3", "--force", "--json", "-o", tmp_path / "r.h5"
    )
    assert res.returncode == 3, res.stderr
    trip = json.loads(res.stdout)["trip"]
    assert (trip["limit"], trip["unit"]) == (limit, unit)
    assert abs(trip["value"]) > threshold
