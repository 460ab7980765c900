"""``imil design --method both --map-x ... --map-y ...``: the two-method feasibility map (issue 15, item 5).

Known results used (tests/design/test_feasibility_both.py, docs/design.md): SD2 at the
report's basemat (1.25 m_st, period 0.8 s) is feasible with the filter design
(Table 9.5), SD2 at 0.3 m_st with neither method (the optimized design's III binds).
"""

from __future__ import annotations

import json
import sys

import pytest
from typer.testing import CliRunner

from impedance_mil.cli.main import app, run
from impedance_mil.design import table_model, virtual_model
from impedance_mil.design.feasibility import scan_fc
from impedance_mil.plant import TableParameters
from impedance_mil.report_config import report_config
from impedance_mil.virtual.files import resolve

runner = CliRunner()
MAP = ["design", "--vs", "SD2", "--method", "both", "--grid", "100"]


@pytest.mark.parametrize(
    "args, message",
    [
        (["--map-x", "mass_ratio=", "--map-y", "period=0.8"], "--map-x: expected NAME=v1"),  # empty axis
        (["--map-x", "=1,2", "--map-y", "period=0.8"], "--map-x: expected NAME=v1"),
        (["--map-x", "mass_ratio", "--map-y", "period=0.8"], "--map-x: expected NAME=v1"),
        (["--map-x", "mass_ratio=1:2:0", "--map-y", "period=0.8"], "--map-x: expected NAME=v1"),
        (["--map-x", "mass_ratio=1,nan", "--map-y", "period=0.8"], "--map-x: expected NAME=v1"),
        (
            ["--map-x", "bogus=1,2", "--map-y", "period=0.8"],
            "--map-x: expected mass_ratio, period or a VS key",
        ),
        (["--map-x", "mass_ratio=0.01,1", "--map-y", "period=0.8"], "mass_ratio values from 0.05 to 20"),
        (["--map-x", "mass_ratio=0.3,1", "--map-y", "period=50"], "--map-y: expected period values from 0.1"),
        (["--map-x", "mass_ratio=0.3,0.3", "--map-y", "period=0.8"], "distinct values"),
        (["--map-x", "mass_ratio=1,2", "--map-y", "mass_ratio=0.8"], "--map-y: expected another parameter"),
        (["--map-x", "mass_ratio=0.3,1"], "--map-y: expected a second axis"),
        (["--map-x", "c=-1,2", "--map-y", "period=0.8"], "--map-x c=-1 and --map-y period=0.8"),
        (["--map-x", "T_s=1,2", "--map-y", "period=0.8"], "SD parameter or target"),
        (["--map-x", "mass_ratio=1", "--map-y", "period=1", "--fc", "auto"], "--fc"),
        (["--map-x", "mass_ratio=1", "--map-y", "period=1", "--form", "tracking"], "--map-x"),
    ],
)
def test_bad_map_input_is_one_line_exit_2(tmp_path, monkeypatch, capsys, args, message):
    out = tmp_path / "map.png"
    monkeypatch.setattr(sys, "argv", ["imil", *MAP, *args, "-o", str(out)])
    with pytest.raises(SystemExit) as exc:
        run()
    assert exc.value.code == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0] and "Traceback" not in err, err
    assert not out.exists()


@pytest.mark.parametrize(
    "argv, message",
    [
        (["design", "--vs", "SD2", "--method", "both"], "--method: expected filter or optimized, or both"),
        (["design", "--vs", "SD2", "--map-x", "mass_ratio=1", "--map-y", "period=1"], "--method"),
        ([*MAP, "--map-x", "mass_ratio=1", "--map-y", "period=1", "-o", "map.json"], "-o: expected a plot"),
    ],
)
def test_method_both_goes_with_a_map(monkeypatch, capsys, argv, message):
    monkeypatch.setattr(sys, "argv", ["imil", *argv])
    with pytest.raises(SystemExit) as exc:
        run()
    lines = capsys.readouterr().err.strip().splitlines()
    assert exc.value.code == 2 and len(lines) == 1 and message in lines[0]


def test_map_json_classes_axes_units_and_plot(tmp_path):
    pytest.importorskip("cvxpy")
    out = tmp_path / "map.png"
    res = runner.invoke(
        app, [*MAP, "--map-x", "mass_ratio=0.3,1.25", "--map-y", "period=0.8", "--json", "-o", str(out)]
    )
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    assert doc["class_grid"] == [["neither", "filter"]]
    assert doc["classes"] == ["filter", "optimized only", "neither"]
    assert doc["x"]["name"] == "mass_ratio" and doc["x"]["values"] == [0.3, 1.25]
    assert doc["y"]["unit"] == "s" and doc["units"]["points[0].y"] == "s"
    assert "unknown" not in doc["units"].values()
    fc_report = report_config().design.fc_hz  # the optimized design's reference cut-off, from the report
    assert doc["reference_fc_hz"] == fc_report and doc["from_report"]["design.fc"] == fc_report
    neither, filt = doc["points"]
    assert filt["optimized"] is None and "cheap path" in filt["note"] and doc["optimized_runs"] == 1
    assert neither["optimized"]["binding"] == "III" and not neither["optimized"]["meets_all"]
    # The filter point's feasible range is the one an independent scan finds (Table 9.5: 100-250 Hz pass).
    params = TableParameters.report_default()
    spec = resolve("SD2", {"m_vs": 1.25 * params.mass, "f": 1 / 0.8})
    scan = scan_fc(table_model(params), virtual_model(spec.vs, "SD2"), form="standardized")
    assert filt["filter"]["feasible_fc_hz"] == pytest.approx(list(scan.feasible_fc_hz), rel=1e-12)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_map_human_output_cheap_path(tmp_path):
    """A map of filter-feasible points only solves no optimization (fast) and says so."""
    out = tmp_path / "map.svg"
    res = runner.invoke(app, [*MAP, "--map-x", "mass_ratio=1.25", "--map-y", "period=0.8", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert "0 optimized solves" in res.stdout and "filter (f_c" in res.stdout and f"wrote {out}" in res.stdout
    assert out.read_text().lstrip().startswith("<?xml")
