"""``imil design --robust`` and ``imil simulate --robust N`` (issue 17, item 3).

The campaign test trips every run on purpose (a 0.002 in stroke interlock) so
that the fraction unstable is known, 1, and read from the trip cause.
"""

from __future__ import annotations

import json

from impedance_mil.lab.results import load_run
from impedance_mil.plant import default_table_path

LAB = f"""
[table]
file = "{default_table_path()}"
[specimen]
kind = "vessel"
water_depth = "36 in"
[uncertainty]
f_oil_hz = "±10 %"
extra_delay = {{ min = 0, max = "1 loop" }}
"""


def test_design_robust_json_and_human(tmp_path, imil):
    lab = tmp_path / "lab.toml"
    lab.write_text(LAB)
    r = imil(
        "design", "--lab", lab, "--vs", "SD2", "--robust", "--robust-samples", "2", "--json", "--units", "si"
    )
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    rb = doc["robust"]
    assert rb["points_count"] == 1 + 4 + 2
    assert rb["binding"] in ("passivity", "sampled passivity", "coupled stability")
    assert rb["worst"]["passivity_tolerant_margin_deg"] <= rb["nominal"]["passivity_tolerant_margin_deg"]
    assert doc["units"]["robust.worst.passivity_margin_deg"] == "deg"
    assert doc["units"]["robust.worst.parameters.extra_delay_loops"] == "loops"
    assert not [k for k, v in doc["units"].items() if k.startswith("robust") and v == "unknown"]
    human = imil("design", "--lab", lab, "--vs", "SD2", "--robust", "--robust-samples", "2")
    assert "robust: robustly stable" in human.stdout or "robust: NOT robustly stable" in human.stdout


def test_design_robust_without_a_set_is_refused(imil):
    for args in (("--robust",), ("--lab", "report", "--robust"), ("--robust-samples", "-1")):
        r = imil("design", "--vs", "SD2", *args)
        assert r.returncode == 2
        assert r.stderr.count("\n") == 1 and "--robust" in r.stderr and "Traceback" not in r.stderr


def test_simulate_robust_campaign_counts_trips_by_cause(tmp_path, imil):
    lab = tmp_path / "lab.toml"
    lab.write_text(LAB + '[limits]\nstroke = "0.002 in"\n')
    out = tmp_path / "worst.h5"
    r = imil(
        "simulate",
        "--lab",
        lab,
        "--robust",
        "2",
        "--seed",
        "1",
        "--duration",
        "0.5",
        "--force",
        "-o",
        out,
        "--json",
    )
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    rb = doc["robust"]
    assert rb["runs_count"] == 2 and rb["unstable_fraction"] == 1.0
    assert rb["causes"] == {"stroke_count": 2}
    assert rb["worst"]["trip"]["limit"] == "stroke"
    assert "robustly_stable" in doc["pretest"]["robust"]
    run = load_run(out)
    assert run.trip is not None and run.trip.limit == "stroke"
    assert run.loop_time == 0.0005


def test_simulate_robust_needs_the_set(tmp_path, imil):
    r = imil("simulate", "--robust", "2", "--duration", "0.5", "-o", tmp_path / "x.h5")
    assert r.returncode == 2 and "--robust" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "x.h5").exists()
