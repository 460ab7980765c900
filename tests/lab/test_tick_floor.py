"""The C floor of the loop tick (benchmarks/c/tick_floor.c) runs the same tick as numba's run_loop.

The C file is an independent transcription of the compiled loop's default MIL
configuration (issue 16, goal 3): its records are the reference here, checked
against ``run_loop`` on the structures ``lab.loop.simulate`` builds, on the
first 4 s of the benchmark case (El Centro x2 at 0.6 g, SD2, vessel 36 in).
This is what makes ``benchmarks/bench_tick_floor.py``'s figure a floor of the
same tick.  Skipped without a C compiler.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from impedance_mil.lab.structures import MODE_TRACK

_BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


def _module(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


floor = _module("tick_floor_binding", _BENCHMARKS / "c" / "tick_floor.py")
cases = _module("bench_cases", _BENCHMARKS / "cases.py")

pytestmark = pytest.mark.skipif(floor.c_compiler() is None, reason="no C compiler (cc, gcc or clang)")

#: 4 s of the record: its 0.6 g peak is in them, the table moves 2.3 in (stroke limit 3 in).
N_LOOPS = 8000


@pytest.fixture(scope="module")
def case():
    return cases.bench_case()


@pytest.fixture(scope="module")
def c_loop(tmp_path_factory, case):
    return floor.CLoop(floor.build(tmp_path_factory.mktemp("tick_floor"), ("-O2",)))


@pytest.fixture(scope="module")
def numba_run(case):
    return floor.run_numba(floor.loop_args(case, case.a_g[:N_LOOPS]))


def test_c_tick_records_every_channel_as_numba_to_the_bit(case, c_loop, numba_run):
    # Reference: numba's run_loop.  Tolerance 0: the transcription does the same IEEE
    # operations in the same order (no contraction, no reassociation; sqrt, division and
    # floor are correctly rounded), and the measured difference is 0 on every channel of
    # the full 53 720-loop record too (bench_tick_floor.py).
    args = floor.loop_args(case, case.a_g[:N_LOOPS])
    c_run = c_loop.run(args)
    assert (c_run.done, c_run.cause) == (numba_run.done, numba_run.cause) == (N_LOOPS, floor.TripCause.NONE)
    for name in floor.CHANNELS:
        a, b = c_run.channels[name], numba_run.channels[name]
        differ = np.nonzero(a != b)[0]
        assert differ.size == 0, (
            f"{name} differs first at loop {differ[0]}: C {a[differ[0]]!r}, numba {b[differ[0]]!r}"
        )
    np.testing.assert_array_equal(c_run.vs_states, numba_run.vs_states)
    # The C loop wrote the end state back as run_loop does: the next loop would go on from it.
    assert np.all(args.plant.y != 0.0)


def test_the_comparison_sees_a_different_tick(case, c_loop, numba_run):
    # Invariant: the equality above is not vacuous.  The run moves the table (measured:
    # peak |x| 2.3 in, peak measured acceleration 100 in/s^2), and the same C loop fed
    # the noise of another seed records channels far from numba's (measured: z_meas 2.9e-2
    # of its peak, every channel but t and a_g above 1e-4), not round-off.
    assert np.max(np.abs(numba_run.channels["x"])) > 1.0
    assert np.max(np.abs(numba_run.channels["z_meas"])) > 50.0
    other = c_loop.run(floor.loop_args(case, case.a_g[:N_LOOPS], seed=1))
    agree = floor.agreement(other, numba_run)
    assert agree.relative["z_meas"] > 1e-3
    assert min(v for k, v in agree.relative.items() if k not in ("t", "a_g")) > 1e-5
    assert agree.relative["t"] == 0.0  # the clock does not depend on the noise


def test_a_configuration_the_c_tick_does_not_transcribe_is_refused(case, c_loop):
    args = floor.loop_args(case, case.a_g[:10])
    tracking = args._replace(control=args.control._replace(mode=MODE_TRACK))
    with pytest.raises(floor.UnsupportedCase, match="a MIL run"):
        c_loop.run(tracking)
