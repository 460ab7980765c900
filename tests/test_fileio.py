"""Atomic writes and JSON-safe values (impedance_mil.fileio)."""

import json
import math
import os

import numpy as np
import pytest

from impedance_mil.errors import DataFileError
from impedance_mil.fileio import (
    atomic_directory,
    atomic_path,
    atomic_write_bytes,
    atomic_write_text,
    json_safe,
    read_text,
    temporary_name,
)


class Boom(Exception):
    pass


def names(folder):
    return sorted(p.name for p in folder.iterdir())


def test_atomic_path_renames_on_success(tmp_path):
    target = tmp_path / "out.h5"
    with atomic_path(target) as tmp:
        assert tmp.parent == tmp_path and tmp.is_file()
        assert not list(tmp_path.glob("*.h5"))  # a search by suffix never finds it
        assert not target.exists()  # nothing under the final name yet
        tmp.write_bytes(b"new")
    assert target.read_bytes() == b"new"
    assert names(tmp_path) == ["out.h5"]


def test_atomic_path_failure_keeps_old_file_and_removes_temp(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old")
    with pytest.raises(Boom):
        with atomic_path(target) as tmp:
            tmp.write_text("half")
            raise Boom
    assert target.read_text() == "old"
    assert names(tmp_path) == ["out.txt"]


def test_atomic_path_keyboard_interrupt_leaves_nothing(tmp_path):
    with pytest.raises(KeyboardInterrupt):
        with atomic_path(tmp_path / "new.txt") as tmp:
            tmp.write_text("half")
            raise KeyboardInterrupt
    assert names(tmp_path) == []


def test_atomic_path_missing_folder_raises_before_the_block(tmp_path):
    ran = []
    with pytest.raises(FileNotFoundError):
        with atomic_path(tmp_path / "nope" / "out.txt"):
            ran.append(True)
    assert ran == []


def test_atomic_path_uses_the_umask_permissions(tmp_path):
    mask = os.umask(0o022)
    try:
        atomic_write_text(tmp_path / "a.txt", "x")
    finally:
        os.umask(mask)
    assert (tmp_path / "a.txt").stat().st_mode & 0o777 == 0o644  # not mkstemp's 0600


def test_atomic_write_text_and_bytes(tmp_path):
    assert atomic_write_text(tmp_path / "t.txt", "µ\n") == tmp_path / "t.txt"
    assert (tmp_path / "t.txt").read_bytes() == "µ\n".encode()
    atomic_write_bytes(tmp_path / "t.txt", b"\x00\x01")
    assert (tmp_path / "t.txt").read_bytes() == b"\x00\x01"
    assert names(tmp_path) == ["t.txt"]


def test_temporary_names_differ():
    assert temporary_name("a/b.h5") != temporary_name("a/b.h5")


def test_atomic_directory_success_and_replace(tmp_path):
    target = tmp_path / "out"
    with atomic_directory(target) as tmp:
        (tmp / "a.c").write_text("1")
    assert names(target) == ["a.c"]
    with atomic_directory(target) as tmp:
        (tmp / "b.c").write_text("2")
    assert names(target) == ["b.c"]  # replaced whole, not merged
    assert names(tmp_path) == ["out"]  # no old or temporary folder left


def test_atomic_directory_failure_leaves_no_partial_folder(tmp_path):
    with pytest.raises(Boom):
        with atomic_directory(tmp_path / "new") as tmp:
            (tmp / "a.c").write_text("1")
            raise Boom
    assert names(tmp_path) == []


def test_atomic_directory_failure_keeps_old_folder(tmp_path):
    target = tmp_path / "out"
    target.mkdir()
    (target / "old.c").write_text("old")
    with pytest.raises(Boom):
        with atomic_directory(target) as tmp:
            (tmp / "new.c").write_text("new")
            raise Boom
    assert names(tmp_path) == ["out"] and names(target) == ["old.c"]


def test_json_safe():
    value = {
        "nan": math.nan,
        "inf": -math.inf,
        1: (np.float64(2.5), np.int64(3)),
        "arr": np.array([1.0, np.nan]),
        "ok": [True, None, "s"],
    }
    clean = json_safe(value)
    assert clean == {"nan": None, "inf": None, "1": [2.5, 3], "arr": [1.0, None], "ok": [True, None, "s"]}
    assert type(clean["1"][0]) is float and type(clean["1"][1]) is int
    json.dumps(clean, allow_nan=False)  # strict JSON


def test_json_safe_uses_to_dict():
    class Params:
        def to_dict(self):
            return {"k": np.float32(0.5)}

    assert json_safe([Params()]) == [{"k": 0.5}]


@pytest.mark.parametrize(
    "make, problem",
    [
        (lambda p: None, "file not found"),
        (lambda p: p.mkdir(), "is a directory, expected a TOML file"),
        (lambda p: p.write_bytes(b"\xff\xfe\x00bad"), "not a text file"),
    ],
)
def test_read_text_errors_are_one_line_and_name_the_file(tmp_path, make, problem):
    path = tmp_path / "x.toml"
    make(path)
    with pytest.raises(DataFileError) as exc:
        read_text(path, "a TOML file")
    assert str(exc.value) == f"{path}: {problem}"


def test_read_text_reads_utf8(tmp_path):
    (tmp_path / "a.txt").write_bytes("µs\n".encode())
    assert read_text(tmp_path / "a.txt") == "µs\n"
