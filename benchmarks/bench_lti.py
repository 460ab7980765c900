"""Speed of the one LTI frequency response against the per-frequency loops it replaced.

``StateSpace.frequency_response`` solves ``(sI - A) X = B`` for every frequency
in batches (one LAPACK call per 2048 points).  The five copies it replaced
looped over frequencies in Python (``plant.statespace.resolvent_response``,
``LinearizedTable``, ``ChannelRealization``; ``SpecimenStateSpace`` already
batched).  Printed, measured in this run (best of ``--repeat``): the time of
each on a dense grid for the table of Eq 4-14a with Pade delay (11 states, one
channel) and for the 36 in vessel (one specimen channel), and the speed-up.
Goal: the batched evaluation is not slower than the loop on any case.

    .venv/bin/python benchmarks/bench_lti.py [--points 4000] [--repeat 7]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from impedance_mil.plant import LinearTable, TableParameters
from impedance_mil.specimens import FluidVessel
from impedance_mil.units import TWO_PI


def loop_response(A, b, c, d, f_hz) -> np.ndarray:
    """The replaced form: one ``numpy.linalg.solve`` per frequency, in a Python loop."""
    eye = np.eye(A.shape[0])
    return np.array([c @ np.linalg.solve(1j * TWO_PI * f * eye - A, b) + d for f in f_hz])


def best(fun, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fun()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=4000)
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    f = np.logspace(-1, 3, args.points)
    cases = {
        "table z/u, Pade(6), 11 states": LinearTable(TableParameters.report_default(), delay="pade")
        .state_space()
        .system.channel("z", "u"),
        "vessel 36 in, w/z": FluidVessel(36).state_space().system,
    }
    print(f"{args.points} frequencies, best of {args.repeat}")
    worst = np.inf
    for label, sys in cases.items():
        A, b, c, d = sys.A, sys.B[:, 0], sys.C[0], float(sys.D[0, 0])
        gap = np.max(np.abs(sys.frequency_response(f) - loop_response(A, b, c, d, f)))
        t_new = best(lambda sys=sys: sys.frequency_response(f), args.repeat)
        t_old = best(lambda A=A, b=b, c=c, d=d: loop_response(A, b, c, d, f), args.repeat)
        worst = min(worst, t_old / t_new)
        print(
            f"  {label:32s} batched {1e3 * t_new:7.2f} ms   loop {1e3 * t_old:7.2f} ms   "
            f"speed-up {t_old / t_new:5.2f}x   max difference {gap:.1e}"
        )
    print(f"goal: speed-up >= 1 on every case: {'met' if worst >= 1 else 'NOT met'} (worst {worst:.2f}x)")


if __name__ == "__main__":
    main()
