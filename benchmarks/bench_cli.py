"""Speed a user feels: start-up of ``imil`` and whole ``imil simulate`` runs (issue 16, goals 1 and 2).

Start-up (``--part startup``): the wall-clock time (best of ``--repeat`` subprocesses each) of
``imil --help``, ``imil table info``, ``imil vs list`` and ``imil lab show``, and its ratio to
the start-up of ``python -c "import numpy, scipy"``.  Goals: ``--help`` within 2x, the
configuration commands within 4x.

Whole runs (``--part run``): ``imil simulate --motion FILE -o run.h5 --json`` (SD2, vessel,
the report's lab) on a 600 s and on a 60 s record, run as recorded (time scale 1), best of
``--repeat`` each; the marginal real-time factor is the 540 s of extra record over the
difference of the two wall times (also printed from the CPU time of the subprocesses, which a
loaded machine disturbs less).  Goal: >= 1000x.  Then, in this process, the post-processing
of the 600 s run read back from its file: the metrics with their spectra
(``lab.metrics.evaluate_run`` with the energy error) and the VS model's loop stored with the
run (``lab.runfile.model_loop``).  Goal: within 0.3 s.

The records are El Centro (RSN 6) baseline-corrected, its displacement tapered (Tukey, 20 %)
so that it starts and ends at rest, zero-padded to 60 s and scaled by 0.5 (0.11 g, so that the
SD2 basemat stays inside the +-3 in interlocks), repeated 1 and 10 times; written as column
files in a temporary folder.

Each command runs as the ``imil`` console script runs it (``impedance_mil.cli.main:run``), from
the checkout holding this file.

    .venv/bin/python benchmarks/bench_cli.py [--repeat 3] [--part startup|run|all]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import NamedTuple

#: The checkout whose ``impedance_mil`` is measured (first on the path of every subprocess, and of this one).
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402
from scipy.signal.windows import tukey  # noqa: E402

from impedance_mil.lab.metrics import evaluate_run  # noqa: E402
from impedance_mil.lab.results import load_run  # noqa: E402
from impedance_mil.lab.runfile import model_loop  # noqa: E402
from impedance_mil.signals import GroundMotion, builtin_motion, read_motion, write_columns  # noqa: E402
from impedance_mil.virtual import presets  # noqa: E402

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


class Timing(NamedTuple):
    """The best of several runs of one subprocess."""

    wall_s: float
    cpu_s: float


#: Whole-run goal: the marginal real-time factor of ``imil simulate``.
RUN_GOAL = 1000.0
#: Post-processing goal for the 600 s record [s].
POST_GOAL_S = 0.3
#: Record lengths of the whole-run pair [s], and the length of one repetition [s].
LONG_S, SHORT_S = 600.0, 60.0
#: Amplitude factor of the repeated record (keeps the SD2 basemat inside the interlocks).
AMPLITUDE = 0.5


def best_of(args: tuple[str, ...], repeat: int, env: dict[str, str]) -> Timing:
    """The shortest wall-clock and CPU times [s] of ``repeat`` runs of ``python *args``; a failure stops.

    Exit status 3 (a run stopped by an interlock) counts as a failure too: the pair must run whole.
    """
    walls, cpus = [], []
    for _ in range(repeat):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        done = subprocess.run([sys.executable, *args], env=env, capture_output=True, text=True)
        walls.append(time.perf_counter() - t0)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
        if done.returncode != 0:
            raise SystemExit(f"{' '.join(args)}: exit status {done.returncode}\n{done.stderr}")
    return Timing(min(walls), min(cpus))


def best_wall_s(args: tuple[str, ...], repeat: int, env: dict[str, str]) -> float:
    """The shortest wall-clock time [s] of ``repeat`` runs of ``python *args``."""
    return best_of(args, repeat, env).wall_s


def startup(repeat: int, env: dict[str, str]) -> None:
    """Goal 1: the start-up ratios."""
    best_wall_s(BASELINE, 1, env)  # untimed: warm the file cache
    base = best_wall_s(BASELINE, repeat, env)
    print(f"best of {repeat}; python -c 'import numpy, scipy': {1e3 * base:6.0f} ms")
    met = True
    for case in CASES:
        wall = best_wall_s(("-c", IMIL, *case.argv), repeat, env)
        ratio = wall / base
        met &= ratio <= case.goal
        verdict = "met" if ratio <= case.goal else "NOT met"
        label = "imil " + " ".join(case.argv)
        print(f"  {label:16s} {1e3 * wall:6.0f} ms  {ratio:5.2f}x   goal <= {case.goal:g}x: {verdict}")
    print(f"goal: --help within 2x, configuration commands within 4x: {'met' if met else 'NOT met'}")


def repeated_record(seconds: float) -> GroundMotion:
    """El Centro at rest at both ends, zero-padded to SHORT_S, scaled by AMPLITUDE, repeated to ``seconds`` [s]."""
    gm = builtin_motion("elcentro").baseline_corrected(3)
    dt = gm.time_step
    disp = gm.displacement() * tukey(gm.npts, 0.2)
    tile = np.zeros(int(round(SHORT_S / dt)))
    tile[: gm.npts] = AMPLITUDE * np.gradient(np.gradient(disp, dt), dt)
    count = int(round(seconds / SHORT_S))
    return GroundMotion(
        dt, np.tile(tile, count), f"elcentro-x{count}", f"El Centro (RSN 6) repeated {count} times"
    )


def simulate_args(motion: Path, out: Path) -> tuple[str, ...]:
    """``imil simulate`` of a column file (g), run as recorded, JSON output."""
    return ("-c", IMIL, "simulate", "--motion", str(motion), "-o", str(out), "--overwrite", "--json")


def post_processing_s(run_file: Path, motion: GroundMotion, repeat: int) -> float:
    """Best time [s] of the metrics (spectra and energy error) and the VS model's loop of a run file."""
    run = load_run(run_file)
    vs = presets.get("SD2")
    ground = motion.resampled(run.loop_time).displacement()
    times = []
    for _ in range(repeat + 1):  # the first loads the cached kernels
        t0 = time.perf_counter()
        evaluate_run(run, vs=vs, ground_displacement=ground)
        model_loop(run, vs)
        times.append(time.perf_counter() - t0)
    return min(times[1:])


def whole_runs(repeat: int, env: dict[str, str]) -> None:
    """Goal 2: the marginal real-time factor of ``imil simulate``, and its post-processing."""
    with tempfile.TemporaryDirectory(prefix="bench_cli_") as tmp:
        folder = Path(tmp)
        timings = {}
        for seconds in (SHORT_S, LONG_S):
            motion = write_columns(repeated_record(seconds), folder / f"record_{seconds:.0f}s.csv")
            best_of(simulate_args(motion, folder / "warm.h5"), 1, env)  # untimed: kernels, file cache
            timings[seconds] = best_of(simulate_args(motion, folder / f"run_{seconds:.0f}s.h5"), repeat, env)
            size = (folder / f"run_{seconds:.0f}s.h5").stat().st_size
            t = timings[seconds]
            print(
                f"  imil simulate, {seconds:3.0f} s record: wall {t.wall_s:6.2f} s, cpu {t.cpu_s:6.2f} s, "
                f"run file {size / 1e6:6.1f} MB"
            )
        extra = LONG_S - SHORT_S
        factor_wall = extra / max(timings[LONG_S].wall_s - timings[SHORT_S].wall_s, 1e-9)
        factor_cpu = extra / max(timings[LONG_S].cpu_s - timings[SHORT_S].cpu_s, 1e-9)
        verdict = "met" if factor_wall >= RUN_GOAL else "NOT met"
        print(
            f"marginal real-time factor ({extra:.0f} s more record): {factor_wall:6.0f}x wall "
            f"({factor_cpu:.0f}x cpu); goal >= {RUN_GOAL:g}x: {verdict}"
        )
        record = read_motion(folder / f"record_{LONG_S:.0f}s.csv")
        post = post_processing_s(folder / f"run_{LONG_S:.0f}s.h5", record, repeat)
        verdict = "met" if post <= POST_GOAL_S else "NOT met"
        print(
            f"metrics and spectra of the {LONG_S:.0f} s run (evaluate_run with the energy error, "
            f"model_loop): {post:5.2f} s; goal <= {POST_GOAL_S:g} s: {verdict}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--part", choices=("startup", "run", "all"), default="all")
    args = parser.parse_args()
    env = environment()
    if args.part in ("startup", "all"):
        startup(args.repeat, env)
    if args.part in ("run", "all"):
        whole_runs(args.repeat, env)


if __name__ == "__main__":
    main()
