"""A run in chunks is the same run; a run file written as the run goes is the file save_run writes.

Invariants (no reference numbers): the compiled loop in chunks of any size gives every channel bit
for bit as the chunk covering the whole run, with a trip too; the streamed run file has the
datasets, values and attributes of ``save_run``'s and loads with its checksum; nothing is left
under the target or the temporary name when the block fails.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from impedance_mil.design import design_controller, table_model, virtual_model
from impedance_mil.errors import ConfigError
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.lab import simulate
from impedance_mil.lab.chunks import chunk_bounds, run_in_chunks
from impedance_mil.lab.results import load_run, save_run
from impedance_mil.lab.run_stream import RunFileStream
from impedance_mil.lab.setup import SafetyLimits
from impedance_mil.lab.trips import TripCause
from impedance_mil.plant.nonlinear import NonlinearTable
from impedance_mil.specimens import FluidVessel
from impedance_mil.virtual import presets

from .conftest import report_parameters

N_LOOPS = 3000


@pytest.fixture(scope="module")
def mil_setup():
    p = report_parameters()
    vs = presets.get("SD2")
    d = design_controller(
        table_model(p), virtual_model(vs), form="standardized", fc_hz=80.0, emit_warnings=False
    )
    controller = discretize(d.H_uz, d.H_uw, p.loop_time, fc_hz=80.0)
    t = np.arange(N_LOOPS) * p.loop_time
    a_g = 300.0 * np.sin(2 * np.pi * 3.0 * t) * np.minimum(t / 0.3, 1.0)
    return NonlinearTable.from_linear(p), controller, vs, a_g


def _mil(setup, **options):
    table, controller, vs, a_g = setup
    runtime = MILRuntime(controller, vs=vs, precision="single")
    return simulate(table, a_g=a_g, runtime=runtime, specimen=FluidVessel.report_default(), **options)


def _assert_same_run(a, b):
    assert a.channels.keys() == b.channels.keys()
    for name in a.channels:
        np.testing.assert_array_equal(a.channels[name], b.channels[name], err_msg=name)
    np.testing.assert_array_equal(a.vs_states, b.vs_states)
    assert a.trip == b.trip


@pytest.mark.parametrize("size", [1, 7, 997, N_LOOPS - 1])
def test_a_run_in_chunks_is_the_same_run_bit_for_bit(mil_setup, size):
    whole = _mil(mil_setup, chunk_loops=N_LOOPS)
    _assert_same_run(_mil(mil_setup, chunk_loops=size), whole)


def test_a_trip_inside_a_chunk_stops_the_run_at_its_loop(mil_setup):
    tight = SafetyLimits(stroke=0.05)  # the SD2 basemat passes 0.05 in within the 1.5 s
    whole = _mil(mil_setup, limits=tight, chunk_loops=N_LOOPS)
    assert whole.trip is not None and whole.trip.cause is TripCause.STROKE
    chunked = _mil(mil_setup, limits=tight, chunk_loops=333)
    _assert_same_run(chunked, whole)
    assert 0 < chunked.n_samples < N_LOOPS and chunked.n_samples % 333 != 0


def test_chunks_are_prepared_before_they_run_and_finished_in_order():
    events = []

    def run_chunk(start, stop):
        events.append(("run", start, stop))
        return stop, TripCause.NONE, 0.0

    done = run_in_chunks(
        run_chunk,
        10,
        prepare=lambda a, b: events.append(("prepare", a, b)),
        finished=lambda a, b: events.append(("finished", a, b)),
        size=4,
    )
    assert done == (10, TripCause.NONE, 0.0)
    for bounds in ((0, 4), (4, 8), (8, 10)):
        assert events.index(("prepare", *bounds)) < events.index(("run", *bounds))
    assert [e[1:] for e in events if e[0] == "finished"] == [(0, 4), (4, 8), (8, 10)]


def test_a_chunk_size_below_one_is_refused():
    with pytest.raises(ConfigError, match="chunk_loops"):
        chunk_bounds(10, 0)
    assert chunk_bounds(0) == [(0, 0)]


def _file_contents(path):
    with h5py.File(path, "r") as f:
        data = {}
        f.visititems(
            lambda name, obj: data.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None
        )
        attrs = {name: dict(obj.attrs) for name, obj in [("/", f), *f.items()] if hasattr(obj, "attrs")}
        attrs["vs_states"] = dict(f["vs_states"].attrs)
        return data, attrs


def _assert_same_file(a, b):
    data_a, attrs_a = _file_contents(a)
    data_b, attrs_b = _file_contents(b)
    assert data_a.keys() == data_b.keys()
    for name in data_a:
        np.testing.assert_array_equal(data_a[name], data_b[name], err_msg=name)
    assert attrs_a.keys() == attrs_b.keys()
    for key in attrs_a:
        assert attrs_a[key].keys() == attrs_b[key].keys()
        for name in attrs_a[key]:
            assert np.array_equal(attrs_a[key][name], attrs_b[key][name]), (key, name)


EXTRAS = dict(
    extra_attrs={"note": "streamed"}, extra_groups={"imil": {"loop": {"force_lbf": np.arange(5.0)}}}
)


@pytest.mark.parametrize("stroke", [None, 0.05])
def test_the_streamed_file_is_the_file_save_run_writes(mil_setup, tmp_path, stroke):
    limits = None if stroke is None else SafetyLimits(stroke=stroke)  # 0.05 in: a trip, written whole
    target = tmp_path / "streamed.h5"
    with RunFileStream(target) as stream:
        run = _mil(mil_setup, limits=limits, sink=stream, chunk_loops=701)
        assert not target.exists()  # in place only when finished
        stream.finish(run, **EXTRAS)
        assert target.exists()
    save_run(run, tmp_path / "whole.h5", **EXTRAS)
    _assert_same_file(target, tmp_path / "whole.h5")
    _assert_same_run(load_run(target), run)  # the checksum written with it holds
    assert sorted(p.name for p in tmp_path.iterdir()) == ["streamed.h5", "whole.h5"]


def test_a_failed_run_leaves_nothing(mil_setup, tmp_path):
    target = tmp_path / "run.h5"

    class Boom(Exception):
        pass

    with pytest.raises(Boom), RunFileStream(target) as stream:
        _mil(mil_setup, sink=stream, chunk_loops=500)
        raise Boom
    assert list(tmp_path.iterdir()) == []


def test_a_stream_left_unfinished_is_an_error_and_leaves_nothing(mil_setup, tmp_path):
    with pytest.raises(RuntimeError, match="not finished"), RunFileStream(tmp_path / "run.h5") as stream:
        _mil(mil_setup, sink=stream)
    assert list(tmp_path.iterdir()) == []
