"""impedance_mil.kernel_cache: a change of a kernel's source clears numba's cache of the package.

numba checks a cached function against its own file; the lab's loop inlines the table's
physics of another file, so without this an edit of plant/nonlinear.py ran the old physics.
"""

from __future__ import annotations

import os

import pytest

from impedance_mil import kernel_cache
from impedance_mil.kernel_cache import MARKER_NAME, PACKAGE_ROOT, refresh_kernel_cache


@pytest.fixture
def package(tmp_path, monkeypatch):
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    root = tmp_path / "pkg"
    (root / "lab" / "__pycache__").mkdir(parents=True)
    (root / "plant").mkdir()
    (root / "plant" / "nonlinear.py").write_text("from numba import njit\n")
    (root / "lab" / "tick.py").write_text("import numba\n")
    (root / "cli.py").write_text("print('no kernels here')\n")
    return root


def _cache(root):
    files = [root / "lab" / "__pycache__" / f"tick.run_loop-10.py311.{s}" for s in ("nbi", "nbc")]
    for f in files:
        f.write_bytes(b"compiled")
    return files


def _touch(path, text):
    path.write_text(text)
    st = path.stat()
    os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))  # a new stamp even on a coarse clock


def test_a_cache_without_a_fingerprint_is_cleared_once(package):
    files = _cache(package)
    assert refresh_kernel_cache(package) is True  # an older version's cache: provenance unknown
    assert not any(f.exists() for f in files)
    assert (package / "__pycache__" / MARKER_NAME).is_file()
    files = _cache(package)
    assert refresh_kernel_cache(package) is False and all(f.exists() for f in files)


def test_an_edit_of_an_inlined_kernel_clears_the_loop_compiled_elsewhere(package):
    refresh_kernel_cache(package)
    files = _cache(package)
    _touch(package / "plant" / "nonlinear.py", "from numba import njit\nK = 2\n")
    assert refresh_kernel_cache(package) is True
    assert not any(f.exists() for f in files)


def test_an_edit_without_kernels_or_a_touch_keeps_the_cache(package):
    refresh_kernel_cache(package)
    files = _cache(package)
    _touch(package / "cli.py", "print('still no kernels')\n")
    _touch(package / "lab" / "tick.py", "import numba\n")  # same text, new stamp
    assert refresh_kernel_cache(package) is False
    assert all(f.exists() for f in files)


def test_the_cache_under_numba_cache_dir_is_cleared_too(package, tmp_path, monkeypatch):
    user = tmp_path / "numba_cache"
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(user))
    mirrored = user / package.relative_to(package.anchor) / "lab"
    mirrored.mkdir(parents=True)
    (mirrored / "tick.run_loop-10.py311.nbi").write_bytes(b"compiled")
    assert refresh_kernel_cache(package) is True
    assert not (mirrored / "tick.run_loop-10.py311.nbi").exists()


def test_a_folder_that_cannot_be_written_is_left_alone(package, monkeypatch):
    files = _cache(package)
    monkeypatch.setattr(kernel_cache.os, "access", lambda *a: False)
    assert refresh_kernel_cache(package) is False and all(f.exists() for f in files)


def test_the_package_kernels_are_fingerprinted():
    # the files the loop is compiled from are among the fingerprinted ones
    sources = {p.relative_to(PACKAGE_ROOT).as_posix() for p in kernel_cache._sources(PACKAGE_ROOT)}
    assert {"plant/nonlinear.py", "lab/stepping.py", "lab/tick.py"} <= sources
    assert all(not s.startswith("data/") for s in sources)
