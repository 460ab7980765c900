"""The first run after an install says it compiles the kernels (issue 16, goal 4).

A fresh install is a numba cache directory without the loop's index: a
subprocess with an empty ``NUMBA_CACHE_DIR`` stands for it (the compile itself,
81 s on the CI machine, is not repeated here).  Once the loop has run, the
index exists and no notice is given.
"""

import os
import subprocess
import sys

from impedance_mil.cli import simulate as simulate_module
from impedance_mil.lab import run_mil
from impedance_mil.lab.first_run import COMPILING_NOTICE, cache_index, kernels_need_compiling
from impedance_mil.lab.tick import run_loop
from impedance_mil.plant import TableParameters
from impedance_mil.signals import builtin_motion
from impedance_mil.virtual import presets

from ..cli.test_simulate_cli import imil

PROBE = "from impedance_mil.lab.first_run import kernels_need_compiling as k; print(k())"


def test_an_empty_cache_directory_means_compiling(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    out = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "True"


def test_after_a_run_the_index_exists_and_no_notice_is_due():
    motion = builtin_motion("elcentro").scaled_to_pga(0.1).trimmed(0.0, 0.2)
    run_mil(TableParameters.report_default(), presets.get("SD2"), motion)
    index = cache_index(run_loop)
    assert index is not None and index.is_file()  # the layout this module reads is numba's
    assert not kernels_need_compiling()


def test_simulate_prints_the_notice_before_a_compiling_run(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(simulate_module, "kernels_need_compiling", lambda: True)
    rc, out, err = imil(monkeypatch, capsys, "simulate", "--duration", "1", "-o", tmp_path / "r.h5", "--json")
    assert rc == 0 and COMPILING_NOTICE in err and COMPILING_NOTICE not in out
