"""``docs/your-lab.md`` is run as written: its lab file is written, its commands run in order.

Each command must succeed (exit 0; ``imil motion check`` may exit 1 when the
motion does not fit, which is what it is for); the lab's stroke interlock of
50 mm must be the one the run and the JSON report.
"""

from __future__ import annotations

import json
import re
import shlex
import shutil
from pathlib import Path

import pytest

from impedance_mil.plant import default_table_path

GUIDE = Path(__file__).resolve().parents[2] / "docs" / "your-lab.md"


def _blocks(kind: str) -> list[str]:
    return re.findall(rf"```{kind}\n(.*?)```", GUIDE.read_text(), flags=re.S)


def test_the_guide_runs_as_written(imil, tmp_path):
    (toml,) = _blocks("toml")
    (tmp_path / "my_lab.toml").write_text(toml)
    shutil.copy(default_table_path(), tmp_path / "report_table_4_1.toml")
    commands = [line for block in _blocks("sh") for line in block.splitlines() if line.strip()]
    assert len(commands) >= 8
    for line in commands:
        argv = shlex.split(line)
        assert argv[0] == "imil"
        res = imil(*argv[1:], cwd=tmp_path)
        allowed = (0, 1) if argv[1:3] == ["motion", "check"] else (0, 3) if argv[1] == "track" else (0,)
        assert res.returncode in allowed, (line, res.stderr)
        if argv[1:] == ["lab", "show", "--lab", "my_lab.toml", "--json"]:
            doc = json.loads(res.stdout)
            assert doc["unit_system"] == "si"  # the lab's units = "si"
            assert doc["limits"]["stroke"] == pytest.approx(50.0, rel=1e-14)
            assert doc["units"]["limits.stroke"] == "mm"
            assert doc["sources"]["limits.stroke"] == "file"
        if argv[1] == "track":
            doc = json.loads(res.stdout)
            assert doc["unit_system"] == "si" and doc["units"]["peak_table_disp_mm"] == "mm"
            if doc["trip"] is not None:  # a trip is the lab's 50 mm stroke, in mm
                assert doc["trip"]["limit"] == "stroke" and doc["trip"]["unit"] == "mm"
                assert 50.0 < abs(doc["trip"]["value"]) < 51.3
        if argv[1:3] == ["table", "info"]:
            assert re.search(r"^mid_stroke\s+150 mm$", res.stdout, flags=re.M)
    assert (tmp_path / "controller").exists() and (tmp_path / "track.h5").exists()
    assert "peak_table_disp_mm [mm]" in (tmp_path / "track.html").read_text()
