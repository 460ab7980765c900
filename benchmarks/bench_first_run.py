"""The first run after an install: compiling the kernels, against a run that loads them cached.

Runs the same short ``imil simulate`` twice in subprocesses sharing a fresh, empty
``NUMBA_CACHE_DIR`` (and kernel-source folder ``IMPEDANCE_MIL_CACHE_DIR``): the first compiles
every kernel it uses (the first run after an install), the second loads them from that cache.
Prints both wall-clock times and their ratio, the first run's progress lines ("compiling kernels
(first run only): k/n ..."), and where the compile time went: every top-level compile of a numba
dispatcher (seconds, from numba's compile events, recorded in the first run's process), and for
the compiled loop the compiler passes that took longest (numba's ``pipeline_times``).  Goal
(issue 16, goal 4): kernels compiled in <= 15 s; the notice, with progress, on the first run.

    .venv/bin/python benchmarks/bench_first_run.py [--duration 1] [--top 8]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from impedance_mil.lab.first_run import COMPILING_NOTICE, PROGRESS_PREFIX

ROOT = Path(__file__).resolve().parents[1]
IMIL = "import sys; from impedance_mil.cli.main import run; sys.argv[0] = 'imil'; run()"
GOAL_S = 15.0

#: The first run, recording numba's top-level compile events and the loop's compiler passes into
#: the file named by argv[1] (then the command's own arguments).
PROFILED = """
import json, sys, time
from numba.core import event
rows, stack = [], []
class Recorder(event.Listener):
    def on_start(self, ev):
        stack.append(time.perf_counter())
    def on_end(self, ev):
        start = stack.pop()
        if not stack:
            fn = getattr((ev.data or {}).get("dispatcher"), "py_func", None)
            name = f"{getattr(fn, '__module__', '?')}.{getattr(fn, '__qualname__', '?')}"
            rows.append([name, time.perf_counter() - start])
out = sys.argv.pop(1)
event.register("numba:compile", Recorder())
from impedance_mil.cli.main import run
sys.argv[0] = "imil"
try:
    run()
finally:
    from impedance_mil.lab.tick import run_loop
    passes = {}
    for cres in run_loop.overloads.values():
        for pipeline in cres.metadata.get("pipeline_times", {}).values():
            for name, t in pipeline.items():
                passes[name] = passes.get(name, 0.0) + t.init + t.run + t.finalize
    with open(out, "w") as f:
        json.dump({"compiles": rows, "loop_passes": passes}, f)
"""


def timed_run(env: dict, folder: Path, duration: float, profile: Path | None = None) -> tuple[float, str]:
    """Wall-clock time [s] and stderr of one short ``imil simulate`` run."""
    head = [sys.executable, "-c", IMIL] if profile is None else [sys.executable, "-c", PROFILED, str(profile)]
    argv = [*head, "simulate", "--duration", str(duration), "--json", "--overwrite"]
    start = time.perf_counter()
    done = subprocess.run([*argv, "-o", str(folder / "run.h5")], env=env, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if done.returncode not in (0, 3):
        raise SystemExit(f"imil simulate failed ({done.returncode}): {done.stderr.strip()}")
    return elapsed, done.stderr


def print_compiles(profile: Path, top: int) -> None:
    """The top-level compiles by time, grouped by dispatcher, and the loop's longest compiler passes."""
    data = json.loads(profile.read_text())
    by_name: dict[str, list[float]] = {}
    for name, seconds in data["compiles"]:
        by_name.setdefault(name, []).append(seconds)
    total = sum(sum(v) for v in by_name.values())
    print(
        f"top-level compiles: {total:.1f} s in {len(data['compiles'])} compiles of {len(by_name)} dispatchers"
    )
    for name, times in sorted(by_name.items(), key=lambda kv: -sum(kv[1]))[:top]:
        print(f"  {sum(times):7.2f} s  {100 * sum(times) / total:5.1f} %  x{len(times)}  {name}")
    passes = sorted(data["loop_passes"].items(), key=lambda kv: -kv[1])[:top]
    loop_total = sum(data["loop_passes"].values())
    print(f"the compiled loop's compiler passes ({loop_total:.1f} s):")
    for name, seconds in passes:
        print(f"  {seconds:7.2f} s  {100 * seconds / loop_total:5.1f} %  {name}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=1.0, help="Seconds of motion to run.")
    parser.add_argument("--top", type=int, default=8, help="Rows of the compile tables.")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        env = {
            **os.environ,
            "NUMBA_CACHE_DIR": str(folder / "cache"),
            "IMPEDANCE_MIL_CACHE_DIR": str(folder / "kernels"),
            "PYTHONPATH": str(ROOT),
        }
        profile = folder / "compiles.json"
        cold, cold_err = timed_run(env, folder, args.duration, profile)
        warm, warm_err = timed_run(env, folder, args.duration)
        compile_s = cold - warm
        print(f"first run (compiles)   {cold:7.1f} s   notice shown: {COMPILING_NOTICE in cold_err}")
        for line in cold_err.splitlines():
            if PROGRESS_PREFIX in line or "kernels compiled in" in line:
                print(f"    {line}")
        print(f"second run (cached)    {warm:7.1f} s   notice shown: {COMPILING_NOTICE in warm_err}")
        print(
            f"compiling: {compile_s:.1f} s = {cold / warm:.1f}x the cached run (goal <= {GOAL_S:g} s: "
            f"{'met' if compile_s <= GOAL_S else 'NOT met'}; load average {os.getloadavg()[0]:.1f})"
        )
        print_compiles(profile, args.top)


if __name__ == "__main__":
    main()
