"""``imil drive multisine -o DIR``: the interface of issue 14 writes ``DIR/multisine.csv`` and ``.json``.

A new folder in an existing one is created; a path whose parent does not exist,
or a file, is refused naming ``-o`` with nothing left behind.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import impedance_mil.signals.drive as drive_module
from impedance_mil.signals.drive import read_drive


def test_a_new_output_folder_is_created(imil, tmp_path):
    out = tmp_path / "drive"
    res = imil("drive", "multisine", "--lab", "report", "-o", out, "--json")
    assert res.returncode == 0, res.stderr
    assert sorted(p.name for p in out.iterdir()) == ["multisine.csv", "multisine.json"]
    doc = json.loads(res.stdout)
    drive = read_drive(out / "multisine.json")
    # The metadata read back is the one printed: same sample count, lines and periods.
    assert drive.n_samples == doc["n_samples"]
    assert drive.multisine["lines"] == doc["multisine"]["lines"]
    assert drive.multisine["n_periods"] == doc["multisine"]["n_periods"]


def test_an_output_path_without_a_parent_folder_is_refused(imil, tmp_path):
    out = tmp_path / "missing" / "drive"
    res = imil("drive", "multisine", "--lab", "report", "-o", out)
    assert res.returncode == 2
    assert res.stderr.count("\n") == 1 and "-o" in res.stderr
    assert not (tmp_path / "missing").exists()


def test_a_file_as_output_folder_is_refused(imil, tmp_path):
    out = tmp_path / "drive"
    out.write_text("not a folder")
    res = imil("drive", "multisine", "--lab", "report", "-o", out)
    assert res.returncode == 2 and "-o" in res.stderr
    assert out.read_text() == "not a folder"


def test_a_unit_refused_before_writing_leaves_no_new_folder(imil, tmp_path):
    # A drive unit of the wrong dimension is refused before anything is written.
    out = tmp_path / "drive"
    res = imil("drive", "multisine", "--lab", "report", "--drive-units", "s", "-o", out)
    assert res.returncode == 2
    assert not out.exists()


def test_a_write_that_fails_midway_removes_the_folder_it_made(tmp_path, monkeypatch):
    # The metadata write fails after the data file is written: the data file and the new
    # folder go with it (nothing half-written); an existing folder is kept.
    def failing(path, text):
        if str(path).endswith(".json"):
            raise OSError("disk full")
        return real(path, text)

    real = drive_module.atomic_write_text
    monkeypatch.setattr(drive_module, "atomic_write_text", failing)
    for out, existed in ((tmp_path / "new", False), (tmp_path, True)):
        with pytest.raises(OSError, match="disk full"):
            drive_module.write_drive(out, "multisine", np.zeros(8), sample_rate_hz=2000.0, unit="mm")
        assert out.exists() == existed
        assert not (out / "multisine.csv").exists()
