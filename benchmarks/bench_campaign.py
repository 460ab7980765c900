"""Campaign speed: the 27-case MIL campaign of Table 9.4, on 1 and on 2 local workers.

Prints the wall-clock time of each (pool start-up included; every run executes,
nothing is resumed) and the speed-up from 1 to 2 workers, measured in this run
after an untimed warm-up run (numba compiles its kernels once, into its cache).
Goal: the 27 cases in under 60 s on a 2-core machine.

Until the ``mil`` kind is registered (it needs ``impedance_mil.lab.experiments``),
the script measures 27 runs of the ``design`` kind instead (nine isolation systems
x three cut-offs) and says so.

    .venv/bin/python benchmarks/bench_campaign.py [--reduced]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import tempfile
import time

from impedance_mil.campaign import KINDS, InlineExecutor, LocalExecutor, load_campaign, run_campaign
from impedance_mil.campaign.executors import default_workers

GOAL_S = 60.0


def table_9_4_campaign(reduced: bool):
    """The runs of study table-9.4 of report-sec9, or a 27-run design stand-in."""
    spec = load_campaign("report-sec9", reduced=reduced)
    runs = tuple(r for r in spec.runs if "table-9.4" in r.studies and r.kind == "mil")
    if runs:
        return dataclasses.replace(spec, runs=runs), "mil (Table 9.4)"
    stand_in = tuple(r for r in spec.runs if "design-table-9.4" in r.studies)
    return dataclasses.replace(spec, runs=stand_in), "design (stand-in: mil kind not available)"


def timed(spec, workers: int) -> tuple[float, int]:
    with tempfile.TemporaryDirectory(prefix="imil-bench-") as folder:
        start = time.perf_counter()
        with LocalExecutor(workers) as pool:
            result = run_campaign(spec, folder, pool)
        return time.perf_counter() - start, result.count("ok") + result.count("aborted")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reduced", action="store_true", help="the reduced (CI) campaign")
    args = parser.parse_args()
    spec, what = table_9_4_campaign(args.reduced)
    print(
        f"campaign: {len(spec.runs)} runs of kind {what}; cores available: {default_workers()}; "
        f"kinds registered: {', '.join(KINDS)}"
    )
    # Warm-up, untimed: one run inline fills numba's on-disk cache, so neither timing pays compilation.
    with tempfile.TemporaryDirectory(prefix="imil-bench-") as folder:
        run_campaign(dataclasses.replace(spec, runs=spec.runs[:1]), folder, InlineExecutor())
    times = {}
    for workers in (1, 2):
        elapsed, done = timed(spec, workers)
        times[workers] = elapsed
        print(
            f"{workers} worker{'s' if workers > 1 else ' '}: {elapsed:7.2f} s for {done} finished runs "
            f"({elapsed / max(len(spec.runs), 1):.2f} s per run)"
        )
    print(
        f"speed-up 1 -> 2 workers: {times[1] / times[2]:.2f}x "
        f"(load average now {os.getloadavg()[0]:.2f}: other processes share the cores)"
    )
    verdict = "meets" if times[2] < GOAL_S else "misses"
    print(f"2 workers: {times[2]:.1f} s, {verdict} the goal of < {GOAL_S:.0f} s")


if __name__ == "__main__":
    main()
