"""Start-up a user feels: ``imil --help`` and the commands that only read a configuration.

Prints, measured in this run (best of ``--repeat`` subprocesses each), the wall-clock time of
``imil --help``, ``imil table info``, ``imil vs list`` and ``imil lab show``, and its ratio to
the start-up of ``python -c "import numpy, scipy"``.  Each command runs as the ``imil``
console script runs it (``impedance_mil.cli.main:run``), from the checkout holding this file.
Goals (issue 16, goal 1): ``--help`` within 2x, the configuration commands within 4x.

    .venv/bin/python benchmarks/bench_cli.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import NamedTuple

#: The checkout whose ``impedance_mil`` is measured (first on the path of every subprocess).
ROOT = Path(__file__).resolve().parents[1]

#: What the ``imil`` console script does (pyproject.toml, [project.scripts]).
IMIL = "import sys; from impedance_mil.cli.main import run; sys.argv[0] = 'imil'; run()"

#: The yardstick of the goals.
BASELINE = ("-c", "import numpy, scipy")


class Case(NamedTuple):
    """One command line and the ratio it must stay within."""

    argv: tuple[str, ...]
    goal: float


CASES = (
    Case(("--help",), 2.0),
    Case(("table", "info"), 4.0),
    Case(("vs", "list"), 4.0),
    Case(("lab", "show"), 4.0),
)


def environment() -> dict[str, str]:
    """This process's environment with the checkout first on ``PYTHONPATH``."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH", "")) if p)
    return env


def best_wall_s(args: tuple[str, ...], repeat: int, env: dict[str, str]) -> float:
    """The shortest wall-clock time [s] of ``repeat`` runs of ``python *args``; a failure stops."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        done = subprocess.run([sys.executable, *args], env=env, capture_output=True, text=True)
        times.append(time.perf_counter() - t0)
        if done.returncode != 0:
            raise SystemExit(f"{' '.join(args)}: exit status {done.returncode}\n{done.stderr}")
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    env = environment()
    best_wall_s(BASELINE, 1, env)  # untimed: warm the file cache
    base = best_wall_s(BASELINE, args.repeat, env)
    print(f"best of {args.repeat}; python -c 'import numpy, scipy': {1e3 * base:6.0f} ms")
    met = True
    for case in CASES:
        wall = best_wall_s(("-c", IMIL, *case.argv), args.repeat, env)
        ratio = wall / base
        met &= ratio <= case.goal
        verdict = "met" if ratio <= case.goal else "NOT met"
        label = "imil " + " ".join(case.argv)
        print(f"  {label:16s} {1e3 * wall:6.0f} ms  {ratio:5.2f}x   goal <= {case.goal:g}x: {verdict}")
    print(f"goal: --help within 2x, configuration commands within 4x: {'met' if met else 'NOT met'}")


if __name__ == "__main__":
    main()
