"""The floor of the lab's loop: the same tick in plain C against numba's ``run_loop`` (issue 16, goal 3).

``benchmarks/c/tick_floor.c`` transcribes one tick of the default MIL
configuration of ``benchmarks/bench_lab.py`` (El Centro x2 at 0.6 g, SD2,
vessel with 36 in of water as an oscillator bank, nonlinear table, 2 RK4
substeps, Table 7.1 sensors with 16-bit quantization and the pre-drawn noise,
float32 controller, load-cell feedback, the interlocks, every channel
recorded).  This script builds it with the system C compiler at ``-O2`` and at
``-O3 -march=native`` (both without contraction of multiply-adds, as numba),
runs the C loop and ``run_loop`` on fresh copies of the same structures
(:func:`impedance_mil.lab.loop.simulate`'s own), and prints ns per tick, the
ratio numba / C, the real-time factors of the loop alone and how far each
recorded channel of the C loop is from numba's (relative to its peak).  A C
loop whose records differ from numba's by more than :data:`AGREEMENT` of peak
runs another tick: the script says so.

Timing: best of ``--repeats`` calls of the loop alone, in one process pinned
to one core, the records written once beforehand (a fresh record's first
touch costs page faults, ~2 ms per call here, which is not the tick's).
Without a C compiler the script says so and exits 0.

Run: ``.venv/bin/python benchmarks/bench_tick_floor.py [--seconds S] [--repeats R]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

# One BLAS thread, as bench_lab.py: a spinning BLAS thread takes the pinned core.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).with_name("c")))
import tick_floor as floor  # noqa: E402
from cases import bench_case, pin_one_core  # noqa: E402

from impedance_mil.lab.tick import run_loop  # noqa: E402

#: Largest |C - numba| of a channel, relative to its peak, for "the same tick" (the
#: transcription reproduces numba bit for bit on this case: measured 0).
AGREEMENT = 1e-9


def _touched(args: floor.LoopArgs) -> floor.LoopArgs:
    """``args`` with its records written once (their pages mapped before the timed call)."""
    for arr in (*args.log.channels, args.log.vs_states):
        arr.fill(0.0)
    return args


def _time_numba(case, a_g, repeats: int, touch: bool = True) -> float:
    best = np.inf
    for _ in range(repeats):
        args = floor.loop_args(case, a_g)
        if touch:
            args = _touched(args)
        t0 = time.perf_counter()
        run_loop(*args, 0, args.control.a_g.shape[0])
        best = min(best, time.perf_counter() - t0)
    return best


def _time_c(loop: floor.CLoop, case, a_g, repeats: int) -> float:
    best = np.inf
    for _ in range(repeats):
        c_case, channels, vs_states, _keep = loop.prepare(floor.loop_args(case, a_g))
        channels.fill(0.0)
        vs_states.fill(0.0)
        t0 = time.perf_counter()
        loop.call(c_case)
        best = min(best, time.perf_counter() - t0)
    return best


def _motion(case, seconds: float | None) -> np.ndarray:
    """The record, repeated to at least ``seconds`` [s] for steadier timing (None: as it is)."""
    if seconds is None:
        return case.a_g
    n = int(round(seconds / case.loop_time))
    return np.resize(case.a_g, max(n, 1))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--seconds",
        type=float,
        default=None,
        help="simulated seconds (the record repeated); default the record",
    )
    parser.add_argument("--repeats", type=int, default=7, help="timed calls of each loop (best is printed)")
    args = parser.parse_args()
    compiler = floor.c_compiler()
    if compiler is None:
        print("bench_tick_floor: no C compiler (cc, gcc or clang) on PATH: nothing measured")
        return 0
    where = pin_one_core()
    case = bench_case()
    a_g = _motion(case, args.seconds)
    n = a_g.size
    t0 = time.perf_counter()
    reference = floor.run_numba(floor.loop_args(case, a_g))
    compile_s = time.perf_counter() - t0
    print(
        f"bench_tick_floor ({where}; load average {os.getloadavg()[0]:.2f}; compiler {compiler}; "
        f"numba compile/cache load + first run {compile_s:.1f} s)"
    )
    print(
        f"  case: bench_lab.py's (El Centro x2, 0.6 g, SD2, vessel 36 in, "
        f"{reference.done} of {n} loops of {case.loop_time * 1e6:.0f} us, trip: {reference.cause.name}); "
        f"best of {args.repeats}, loop alone, records written beforehand"
    )
    numba_s = _time_numba(case, a_g, args.repeats)
    numba_ns = numba_s / n * 1e9
    fresh_ns = _time_numba(case, a_g, args.repeats, touch=False) / n * 1e9
    lines = [("numba run_loop", numba_ns)]
    verdicts = []
    with tempfile.TemporaryDirectory() as workdir:
        for label, flags in floor.OPT_LEVELS.items():
            loop = floor.CLoop(floor.build(Path(workdir), flags, compiler))
            run = loop.run(floor.loop_args(case, a_g))
            agree = floor.agreement(run, reference)
            name, worst = agree.worst
            same = run.done == reference.done and run.cause == reference.cause and worst <= AGREEMENT
            verdicts.append((label, same, name, worst, agree))
            c_ns = _time_c(loop, case, a_g, args.repeats) / n * 1e9
            lines.append((f"C {label}", c_ns))
    loop_ns = case.loop_time * 1e9
    for label, ns in lines:
        ratio = "" if label.startswith("numba") else f"   numba / C = {numba_ns / ns:.2f}"
        print(f"  {label:24s} {ns:7.1f} ns per tick -> {loop_ns / ns:6.0f} x real time{ratio}")
    print(
        f"  (numba run_loop on fresh records, as simulate allocates them: {fresh_ns:.1f} ns per tick, "
        f"{fresh_ns - numba_ns:+.1f} ns of first-touch page faults)"
    )
    for label, same, name, worst, agree in verdicts:
        exact = sum(1 for v in agree.relative.values() if v == 0.0)
        print(
            f"  agreement C {label}: {exact} of {len(agree.relative)} channels identical to the bit; "
            f"worst {name} {worst:.1e} of its peak"
        )
        if not same:
            print(
                f"  DISAGREE: C {label} records differ from numba's beyond {AGREEMENT:.0e} of peak "
                "(or trip differently): a floor of a different tick is not a floor"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
