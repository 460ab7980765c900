"""Passivity margins and index in the Figure 9.31 plots (issue 15, item 3).

The annotation of the design's row must carry the numbers of the design's
JSON (``constraints[0]``), rounded to two decimals, in the unit system asked
for; the index in SI is the US value times 175.127 (1 lbf*s/in = 175.127 N*s/m,
pint).
"""

from __future__ import annotations

import json
import re

import pytest
from typer.testing import CliRunner

from impedance_mil.cli import design_cmd
from impedance_mil.cli.main import app

runner = CliRunner()
NUMBER = r"([+-]\d+\.\d\d)"


def _run(tmp_path, monkeypatch, units: str):
    captured = {}
    save = design_cmd.save_figure

    def keep(fig, path):
        captured[path.name] = fig
        return save(fig, path)

    monkeypatch.setattr(design_cmd, "save_figure", keep)
    res = runner.invoke(app, ["design", "--vs", "SD2", "--plots", str(tmp_path), "--json", "--units", units])
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout), captured


@pytest.mark.parametrize("units,unit_name", [("us", "lbf*s/in"), ("si", "kN*s/m")])
def test_annotation_equals_the_json(tmp_path, monkeypatch, units, unit_name):
    doc, figs = _run(tmp_path, monkeypatch, units)
    assert (tmp_path / "design_fig931.png").stat().st_size > 10_000
    fig = figs["design_fig931.png"]
    c = doc["constraints"][0]
    assert doc["units"]["constraints[0].passivity_index"] == unit_name
    # The design's row (f_c = 80 Hz) among the rows of the feasible range's ends.
    titles = [ax.get_title() for ax in fig.axes]
    k = next(i for i, t in enumerate(titles) if t.startswith("Nyquist") and t.endswith("= 80 Hz"))
    (text,) = [t.get_text() for t in fig.axes[k].texts]
    m = re.search(
        rf"first-order: {NUMBER} deg \(tolerant {NUMBER} deg\)\nmargin sampled-data: {NUMBER} deg\n"
        rf"index min Re\(1/H_vw\): {NUMBER} (\S+)",
        text,
    )
    assert m is not None, text
    expected = (
        c["passivity_margin_deg"],
        c["passivity_tolerant_margin_deg"],
        c["passivity_margin_sampled_deg"],
        c["passivity_index"],
    )
    assert [float(g) for g in m.groups()[:4]] == [round(v, 2) for v in expected]
    assert m.group(5) == unit_name
    # Every row has its annotation and its Re(1/H_vw) panel, whose minimum is marked.
    nyquist = [ax for ax in fig.axes if ax.get_title().startswith("Nyquist")]
    damping = [ax for ax in fig.axes if ax.get_title().startswith("equivalent damping")]
    assert len(nyquist) == len(damping) == 3 and all(len(ax.texts) == 1 for ax in nyquist)


def test_si_index_is_the_us_index_converted(tmp_path, monkeypatch):
    us, _ = _run(tmp_path, monkeypatch, "us")
    si, _ = _run(tmp_path, monkeypatch, "si")
    ratio = si["constraints"][0]["passivity_index"] / us["constraints"][0]["passivity_index"]
    assert ratio == pytest.approx(0.175127, rel=1e-5)  # kN*s/m per lbf*s/in
