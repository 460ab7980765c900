"""The first run after an install: compiling the kernels, against a run that loads them cached.

Runs the same short ``imil simulate`` twice in subprocesses sharing a fresh, empty
``NUMBA_CACHE_DIR``: the first compiles every kernel it uses (the first run after an install),
the second loads them from that cache.  Prints both wall-clock times and their ratio, and
whether the first printed the "compiling kernels" notice.  Goal (issue 16, goal 4): kernels
compiled in <= 15 s; the notice on the first run.

    .venv/bin/python benchmarks/bench_first_run.py [--duration 1]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from impedance_mil.lab.first_run import COMPILING_NOTICE

ROOT = Path(__file__).resolve().parents[1]
IMIL = "import sys; from impedance_mil.cli.main import run; sys.argv[0] = 'imil'; run()"
GOAL_S = 15.0


def timed_run(env: dict, folder: Path, duration: float) -> tuple[float, str]:
    """Wall-clock time [s] and stderr of one short ``imil simulate`` run."""
    argv = [sys.executable, "-c", IMIL, "simulate", "--duration", str(duration), "--json", "--overwrite"]
    start = time.perf_counter()
    done = subprocess.run([*argv, "-o", str(folder / "run.h5")], env=env, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if done.returncode not in (0, 3):
        raise SystemExit(f"imil simulate failed ({done.returncode}): {done.stderr.strip()}")
    return elapsed, done.stderr


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=1.0, help="Seconds of motion to run.")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        env = {**os.environ, "NUMBA_CACHE_DIR": str(folder / "cache"), "PYTHONPATH": str(ROOT)}
        cold, cold_err = timed_run(env, folder, args.duration)
        warm, warm_err = timed_run(env, folder, args.duration)
    compile_s = cold - warm
    print(f"first run (compiles)   {cold:7.1f} s   notice shown: {COMPILING_NOTICE in cold_err}")
    print(f"second run (cached)    {warm:7.1f} s   notice shown: {COMPILING_NOTICE in warm_err}")
    print(
        f"compiling: {compile_s:.1f} s = {cold / warm:.1f}x the cached run (goal <= {GOAL_S:g} s: "
        f"{'met' if compile_s <= GOAL_S else 'NOT met'})"
    )


if __name__ == "__main__":
    main()
