"""The first run after an install says it compiles the kernels (issue 16, goal 4).

A fresh install is a numba cache directory without the loop's index: a
subprocess with an empty ``NUMBA_CACHE_DIR`` stands for it (the compile itself,
about 19 s on the loaded CI machine, is not repeated here; benchmarks/bench_first_run.py
runs it and shows the progress lines).  Once the loop has run, the index exists and
no notice is given.  The progress lines are tested on small kernels of this module,
compiled inside the command.
"""

import os
import subprocess
import sys

from numba import njit

from impedance_mil.cli import simulate as simulate_module
from impedance_mil.lab import first_run, run_mil
from impedance_mil.lab.first_run import (
    COMPILING_NOTICE,
    KERNEL_GROUPS,
    PROGRESS_PREFIX,
    KernelGroup,
    cache_index,
    compile_progress,
    group_of,
    kernels_need_compiling,
)
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


def test_the_simulate_commands_say_compiling_with_progress_per_group_of_kernels(
    tmp_path, monkeypatch, capsys
):
    # The real first run compiles for minutes; here a fresh kernel of this module stands for the
    # lab's, grouped as the progress lines group the lab's, and compiles inside the command.
    inner = njit(lambda x: x * 2.0)
    outer = njit(lambda x: inner(x) + 1.0)  # compiles `inner` within it: one announcement, not two
    groups = (KernelGroup("the test's kernels", (__name__,)), KernelGroup("never compiled", ("nowhere.",)))
    real_progress = first_run.compile_progress
    monkeypatch.setattr(simulate_module, "kernels_need_compiling", lambda: True)
    monkeypatch.setattr(simulate_module, "compile_progress", lambda say: real_progress(say, groups))
    real_check = simulate_module.check

    def check_and_compile(*args, **kwargs):
        assert outer(1.0) == 3.0
        return real_check(*args, **kwargs)

    monkeypatch.setattr(simulate_module, "check", check_and_compile)
    rc, out, err = imil(monkeypatch, capsys, "simulate", "--duration", "1", "-o", tmp_path / "r.h5", "--json")
    assert rc == 0
    lines = [line for line in err.splitlines() if PROGRESS_PREFIX in line]
    assert lines == [f"imil: {PROGRESS_PREFIX} 1/2 the test's kernels ..."]
    assert err.index(COMPILING_NOTICE) < err.index(PROGRESS_PREFIX)
    assert "kernels compiled in" in err and PROGRESS_PREFIX not in out


def test_progress_counts_top_level_compiles_once_per_group_and_nothing_cached():
    said = []
    first = njit(lambda x: x + 1.0)
    second = njit(lambda x: first(x) * 3.0)
    with compile_progress(said.append, (KernelGroup("here", (__name__,)),)) as progress:
        second(1.0)  # compiles second, and first nested in it
        first(2.0)  # already compiled (as second's callee): no event
        first(2)  # a new signature of the same group: compiled, not announced again
    assert said == [f"{PROGRESS_PREFIX} 1/1 here ..."] and progress.announced == [0]
    assert progress.seconds > 0.0
    with compile_progress(said.append, (KernelGroup("here", (__name__,)),)) as progress:
        second(1.0)  # compiled before: nothing to say
    assert len(said) == 1 and progress.announced == [] and progress.seconds == 0.0


def test_the_lab_kernels_fall_in_their_groups():
    # The modules holding the dispatchers a first `imil simulate` compiles (measured with numba's
    # compile events, benchmarks/bench_first_run.py): each has its group, the loop its own.
    labels = [g.label for g in KERNEL_GROUPS]
    where = {
        "imil_vs_sd_82c7a746fbf33ae6": 0,
        "impedance_mil.virtual.kernels": 0,
        "impedance_mil.plant.nonlinear_kernels": 1,
        "impedance_mil.specimens.sensor_kernels": 1,
        "impedance_mil.lab.tick": 2,
        "impedance_mil.signals.spectrum": 3,
        "impedance_mil.implement.kernels": 3,
    }
    assert {m: labels[group_of(m)] for m in where} == {m: labels[i] for m, i in where.items()}
    assert group_of("numpy.linalg") is None and group_of(run_loop.py_func.__module__) == 2
