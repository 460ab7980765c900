"""A compiled run in chunks, with the work around the loop done beside it.

The compiled loop (:data:`impedance_mil.lab.tick.run_loop`) keeps every state
in its structures and releases the GIL, so a run of ``n`` loops can be made
of chunks ``0 ... k``, ``k ... 2k``, ... that give the same run, bit for bit.
:func:`run_in_chunks` runs each chunk in a worker thread and, in the calling
thread meanwhile, prepares the next chunk's inputs (the sensor noise) and
hands the finished chunk's records to a :class:`RecordSink` (the run file,
written as the run goes).  On a two-core machine the loop then no longer
waits for the noise draw and the run file's write (issue 16: a 600 s run
writes 230 MB, about 0.5 s on the development VM, as long as the loop).

A chunk is :data:`CHUNK_LOOPS` loops (32.8 s of a 500 us loop, 16 MB of
records): long enough that a thread hand-off (~0.1 ms) is lost in it, short
enough that the first and last chunks, which nothing overlaps, are a small
part of a long run.  A trip ends the run at its loop, as it does in one call.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from concurrent.futures import ThreadPoolExecutor
from typing import Protocol

import numpy as np

from ..errors import ConfigError
from .trips import TripCause

#: Loops per chunk of a run in chunks.
CHUNK_LOOPS = 1 << 16

#: ``run_chunk(start, stop) -> (loops completed, TripCause, value)``: the loop from ``start``.
RunChunk = Callable[[int, int], tuple[int, TripCause, float]]


class RecordSink(Protocol):
    """Receives a run's records as the run goes (the run file, :class:`impedance_mil.lab.results.RunFileStream`)."""

    def receive(
        self, channels: Mapping[str, np.ndarray], vs_states: np.ndarray, start: int, stop: int
    ) -> None:
        """Loops ``start ... stop - 1`` are recorded.

        ``channels`` (one array per channel) and ``vs_states`` are the run's
        whole records, allocated for every loop of the run: only rows
        ``start ... stop - 1`` are new, and they are not written again.
        """


def chunk_bounds(n: int, size: int = CHUNK_LOOPS) -> list[tuple[int, int]]:
    """``[(0, size), (size, 2 size), ..., (.., n)]``; one empty chunk for ``n = 0``."""
    if size < 1:
        raise ConfigError("chunk_loops", "a positive number of loops per chunk", size)
    return [(a, min(a + size, n)) for a in range(0, n, size)] or [(0, 0)]


def run_in_chunks(
    run_chunk: RunChunk,
    n: int,
    *,
    prepare: Callable[[int, int], None] | None = None,
    finished: Callable[[int, int], None] | None = None,
    size: int = CHUNK_LOOPS,
) -> tuple[int, TripCause, float]:
    """Run loops ``0 ... n - 1`` chunk by chunk in a worker thread; return ``(loops completed, cause, value)``.

    ``prepare(start, stop)`` makes a chunk's inputs, in the calling thread,
    before the chunk runs (the first before anything runs, the others while
    the previous chunk runs); ``finished(start, stop)`` is told, in the
    calling thread, of the loops each chunk completed while the next chunk
    runs (the last one after the run).  A trip stops the run at its loop:
    the chunk's completed loops are still handed to ``finished``.
    An exception in a callback or the loop ends the run after the chunk in
    flight and is raised here.
    """
    bounds = chunk_bounds(n, size)
    if prepare is not None:
        prepare(*bounds[0])
    if len(bounds) == 1:  # nothing to do beside it: no thread (a campaign's runs, bench_lab's)
        done, cause, value = run_chunk(*bounds[0])
        if finished is not None:
            finished(bounds[0][0], done)
        return done, cause, value
    with ThreadPoolExecutor(max_workers=1, thread_name_prefix="imil-loop") as worker:
        pending = worker.submit(run_chunk, *bounds[0])
        for i, (start, _) in enumerate(bounds):
            following = bounds[i + 1] if i + 1 < len(bounds) else None
            if following is not None and prepare is not None:
                prepare(*following)
            done, cause, value = pending.result()
            tripped = cause != TripCause.NONE
            if following is not None and not tripped:
                pending = worker.submit(run_chunk, *following)
            if finished is not None:
                finished(start, done)
            if tripped:
                return done, cause, value
    return n, TripCause.NONE, 0.0
