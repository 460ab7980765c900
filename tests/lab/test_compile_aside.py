"""The first run's side process compiles the spectra's kernels into numba's cache (lab/compile_aside.py).

The side process is run for real once, into an empty ``NUMBA_CACHE_DIR``; a second process then
takes a spectrum of writable accelerations (the types ``imil simulate`` passes) and must load
the kernels instead of compiling any (numba's compile events count the compiles).  Whatever
happens to the side process, the run must go on: a failing, missing or hung one is handled.
"""

import json
import os
import subprocess
import sys

from numba import njit
from numba.core import event

from impedance_mil.lab import compile_aside, run_mil
from impedance_mil.lab.compile_aside import WaitAfterLoop, csr_step_signature, finish, kernels_compiled_aside
from impedance_mil.lab.stepping import advance_csr_called
from impedance_mil.plant import TableParameters
from impedance_mil.signals import builtin_motion
from impedance_mil.virtual import presets

COUNT_COMPILES = """
import json, numpy as np
from numba.core import event
names = []
class Count(event.Listener):
    def on_start(self, ev):
        names.append(ev.data["dispatcher"].py_func.__qualname__)
    def on_end(self, ev):
        pass
event.register("numba:compile", Count())
from impedance_mil.signals import response_spectrum
a = np.cos(np.linspace(0.0, 9.0, 300))
first = response_spectrum(a, 0.02).psa
print(json.dumps({"compiled": names, "finite": bool(np.isfinite(first).all())}))
"""


def _python(code_or_module, env, module=False):
    argv = [sys.executable, "-m", code_or_module] if module else [sys.executable, "-c", code_or_module]
    return subprocess.run(argv, env=env, capture_output=True, text=True, timeout=600)


def test_the_side_process_leaves_the_spectra_kernels_cached_for_the_run(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    cold = json.loads(_python(COUNT_COMPILES, {**env, "NUMBA_CACHE_DIR": str(tmp_path / "other")}).stdout)
    assert "_coefficients" in cold["compiled"]  # the probe does compile in an empty cache
    done = _python("impedance_mil.lab.compile_aside", env, module=True)
    assert done.returncode == 0, done.stderr
    warm = json.loads(_python(COUNT_COMPILES, env).stdout)
    assert warm == {"compiled": [], "finite": True}


def test_a_failed_missing_or_hung_side_process_is_handled():
    assert finish(None, 1.0) is False
    assert finish(subprocess.Popen([sys.executable, "-c", "raise SystemExit(1)"]), 60.0) is False
    assert finish(subprocess.Popen([sys.executable, "-c", "pass"]), 60.0) is True
    hung = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    assert finish(hung, 0.1) is False and hung.returncode is not None


def test_the_run_waits_for_the_side_process_when_a_top_level_compile_of_the_loop_ends(monkeypatch):
    monkeypatch.setattr(compile_aside, "LOOP_MODULE", __name__)  # this module's kernels stand for the loop
    inner = njit(lambda x: x + 1.0)
    outer = njit(lambda x: inner(x) * 2.0)
    waited = []
    monkeypatch.setattr(compile_aside, "finish", lambda process, timeout: waited.append(process) or True)
    listener = WaitAfterLoop("the side process", 5.0)
    with event.install_listener("numba:compile", listener):
        assert outer(1.0) == 4.0  # one top-level compile (inner nested in it): one wait
        inner(2)  # another compile: the side process was waited for already
    assert waited == ["the side process"] and listener.succeeded is True


def test_a_side_process_still_running_at_the_end_is_stopped(monkeypatch):
    hung = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    monkeypatch.setattr(compile_aside, "start", lambda: hung)
    with kernels_compiled_aside() as listener:
        assert hung.poll() is None
    assert hung.returncode is not None and listener.succeeded is None


def test_the_side_process_compiles_the_plant_step_for_the_types_the_loop_passes():
    # numba compiles the loop's callees while it types the loop (whatever the specimen's path):
    # after a run, the signature the side process compiles is among those the loop asked for.
    motion = builtin_motion("elcentro").scaled_to_pga(0.1).trimmed(0.0, 0.2)
    run_mil(TableParameters.report_default(), presets.get("SD2"), motion)
    assert csr_step_signature() in advance_csr_called.signatures


def test_no_side_process_with_a_single_usable_cpu(monkeypatch):
    monkeypatch.setattr(compile_aside, "usable_cpus", lambda: 1)
    assert compile_aside.start() is None
    with kernels_compiled_aside() as listener:
        pass
    assert listener.succeeded is None
