"""`imil export` renders exactly the designed VS (issue 18, finding 2; urgent per the roadmap).

Every VS parameter is changed through ``imil design --set-vs``; the generated C
and ST must carry the changed values (rounded to the export precision), not the
preset's.  Hand edits of a design file's parameters are exported; hand edits of
derived values, unknown kinds and a mismatching ``--vs`` are refused.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from impedance_mil.design import design_controller, save_design, table_model
from impedance_mil.plant import TableParameters
from impedance_mil.virtual import presets


def _c_constants(text: str) -> dict[str, float]:
    return {
        m[1]: float(m[2].rstrip("f"))
        for m in re.finditer(r"static const \w+ imil_vs_(\w+) = ([-+0-9.eE]+f?);", text)
    }


def _st_constants(text: str) -> dict[str, float]:
    return {m[1]: float(m[2]) for m in re.finditer(r"\bp_(\w+) : L?REAL := ([-+0-9.eE]+);", text)}


# Each parameter of each kind, with a changed value (internal units) that keeps the
# VS valid (LR alpha < 1, FP mu_min <= mu_max).
_CASES = [
    (name, key) for name in ("SD2", "LR2", "FP2") for key in presets.get(name).definition.parameter_names
]


@pytest.mark.parametrize("name,key", _CASES)
def test_every_vs_parameter_set_at_design_reaches_c_and_st(imil, tmp_path, name, key):
    base = presets.get(name)
    value = float(getattr(base, key)) * 1.05
    r = imil("design", "--vs", name, "--set-vs", f"{key}={value!r}", "-o", "d.json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    expected_vs = presets.get(name, **{key: value})
    expected = dict(zip(expected_vs.definition.kernel_constants, expected_vs.parameter_array()))
    stock = dict(zip(base.definition.kernel_constants, base.parameter_array()))
    for fmt, reader, prec in (
        ("c", _c_constants, "double"),
        ("st", _st_constants, "double"),
        ("c", _c_constants, "single"),
    ):
        out = tmp_path / f"{fmt}-{prec}"
        r = imil("export", "d.json", "--format", fmt, "--precision", prec, "-o", out, cwd=tmp_path)
        assert r.returncode == 0, r.stderr
        text = "".join(p.read_text() for p in out.iterdir())
        got = reader(text)
        dtype = np.float32 if prec == "single" else np.float64
        for pname, pvalue in expected.items():
            assert got[pname] == float(dtype(pvalue)), (pname, got[pname], pvalue)
        # the changed parameter (or the derived one it feeds, FP's W) differs from the stock value
        assert any(got[p] != float(dtype(stock[p])) for p in expected)
        if fmt == "c":
            assert f"VS {name} ({base.kind})" in text


def test_hand_edited_design_parameter_is_exported(imil, tmp_path):
    assert imil("design", "--vs", "LR2", "-o", "d.json", cwd=tmp_path).returncode == 0
    doc = json.loads((tmp_path / "d.json").read_text())
    doc["vs"]["parameters"]["q_d"] *= 1.5
    # derived values follow the parameters: drop them (a stale derived value is refused below)
    for k in ("k_s", "u_y", "f_y", "f_post_vs"):
        doc["vs"]["parameters"].pop(k)
    (tmp_path / "e.json").write_text(json.dumps(doc))
    r = imil("export", "e.json", "--precision", "double", "-o", "c", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    got = _c_constants((tmp_path / "c" / "imil.c").read_text())
    assert got["q_d"] == doc["vs"]["parameters"]["q_d"]


def _refused(imil, tmp_path, doc, *extra):
    (tmp_path / "bad.json").write_text(json.dumps(doc))
    r = imil("export", "bad.json", *extra, "-o", "out", cwd=tmp_path)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()
    return r.stderr


def test_design_vs_that_cannot_be_rendered_exactly_is_refused(imil, tmp_path):
    assert imil("design", "--vs", "FP2", "-o", "d.json", cwd=tmp_path).returncode == 0
    doc = json.loads((tmp_path / "d.json").read_text())
    stale = json.loads(json.dumps(doc))
    stale["vs"]["parameters"]["W"] = 9999.0  # derived: the parameters give 5600 lbf
    assert "parameters.W" in _refused(imil, tmp_path, stale)
    unknown = json.loads(json.dumps(doc))
    unknown["vs"]["kind"] = "XX"
    assert "kind" in _refused(imil, tmp_path, unknown)
    missing = json.loads(json.dumps(doc))
    missing["vs"]["parameters"].pop("mu_max")
    assert "parameters.mu_max" in _refused(imil, tmp_path, missing)
    assert "designed VS FP2" in _refused(imil, tmp_path, doc, "--vs", "FP1")


def test_design_without_vs_exports_requested_vs_with_a_note(imil, tmp_path):
    design = design_controller(
        table_model(TableParameters.report_default()), form="standardized", fc_hz=80.0, emit_warnings=False
    )
    save_design(design, tmp_path / "d.json")
    r = imil("export", "d.json", "--vs", "SD3", "-o", "c", cwd=tmp_path)
    assert r.returncode == 0 and "not checked" in r.stdout
    r = imil("export", "d.json", "-o", "c2", cwd=tmp_path)
    assert r.returncode == 0 and "no MIL step" in r.stdout
