"""A run file written as the run goes: the records chunk by chunk, the rest when the run is done.

:class:`RunFileStream` is a :class:`~impedance_mil.lab.chunks.RecordSink`:
:func:`impedance_mil.lab.loop.simulate` hands it each chunk of records while
the loop computes the next one, so the write of a long run (230 MB for 600 s
at 500 us) costs no wall time beside a loop that runs on the other core.
The file is the one :func:`~impedance_mil.lab.results.save_run` writes (the
same datasets, attributes and checksum, ``tests/lab/test_run_stream.py``):

* the datasets are made at the run's full length on the first chunk and
  filled in place;
* the SHA-256 of the records starts, in a thread, when the last loop arrives;
* :meth:`RunFileStream.finish` writes the attributes and the caller's extras,
  and renames the file into place (:func:`~impedance_mil.fileio.atomic_path`).

A run that stopped early (an interlock) or that was not streamed (a
user-defined VS steps through the plant interface) is written whole by
:meth:`~RunFileStream.finish` instead, under the same temporary name, so its
file has no unused rows.  Anything that fails before ``finish`` (an error, an
interrupt) removes the temporary file: nothing is left half-written.
"""

from __future__ import annotations

from collections.abc import Mapping
from concurrent.futures import Future, ThreadPoolExecutor
from contextlib import ExitStack
from pathlib import Path
from types import TracebackType
from typing import Any

import h5py
import numpy as np

from ..fileio import atomic_path
from .results import RunResult, checked_extras, data_digest, write_records, write_run_attrs


class RunFileStream:
    """The run file at ``path``, written as the run goes (use it as a context manager).

    Parameters
    ----------
    path : str or Path
        The run file (its folder is created when needed); it appears only
        when :meth:`finish` succeeds.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self._stack = ExitStack()
        self._tmp: Path | None = None
        self._file: h5py.File | None = None
        self._datasets: dict[str, h5py.Dataset] = {}
        self._streamed: Mapping[str, np.ndarray] = {}
        self._length = 0
        self._received = 0
        self._digest: Future[str] | None = None
        self._digests = ThreadPoolExecutor(max_workers=1, thread_name_prefix="imil-run-digest")
        self._finished = False

    def __enter__(self) -> RunFileStream:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._stack.callback(self._digests.shutdown)
        self._tmp = self._stack.enter_context(atomic_path(self.path))
        return self

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> bool | None:
        self._close_file()
        if kind is None and not self._finished:  # a caller's bug: say so, and leave no file
            unfinished = RuntimeError(f"{self.path}: the run file was not finished")
            self._stack.__exit__(RuntimeError, unfinished, None)
            raise unfinished
        return self._stack.__exit__(kind, error, trace)

    def receive(
        self, channels: Mapping[str, np.ndarray], vs_states: np.ndarray, start: int, stop: int
    ) -> None:
        """Write loops ``start ... stop - 1`` of the run's records (``channels`` and ``vs_states``: full length)."""
        if self._file is None:
            self._file = h5py.File(self._open_tmp(), "w")
            self._datasets = write_records(self._file, channels, vs_states, shape_only=True)
            self._length = vs_states.shape[0]
            self._streamed = {**channels, "vs_states": vs_states}
        if start != self._received:  # the loop gives its chunks in order; anything else is a bug here
            raise RuntimeError(f"{self.path}: records {start}-{stop} after {self._received}")
        for name, arr in channels.items():
            self._datasets[name][start:stop] = arr[start:stop]
        if vs_states.shape[1]:
            self._datasets["vs_states"][start:stop] = vs_states[start:stop]
        self._received = stop
        if stop == self._length:
            self._digest = self._digests.submit(data_digest, channels, vs_states)

    def finish(
        self,
        result: RunResult,
        extra_attrs: Mapping[str, Any] | None = None,
        extra_groups: Mapping[str, Mapping[str, Any]] | None = None,
    ) -> Path:
        """Complete the file with ``result``'s attributes and the extras (as ``save_run``'s), rename it
        into place and return ``path``."""
        attrs, groups = checked_extras(extra_attrs, extra_groups)
        if not self._streamed_is(result):  # stopped early, or not streamed: write it as save_run does
            self._close_file()
            self._file = h5py.File(self._open_tmp(), "w")
            self._digest = self._digests.submit(data_digest, result.channels, result.vs_states)
            write_records(self._file, result.channels, result.vs_states)
        if self._digest is None or self._file is None:
            raise RuntimeError(f"{self.path}: no records to finish")
        write_run_attrs(self._file, result, self._digest.result(), attrs, groups)
        self._close_file()
        self._stack.close()  # fsync, rename into place
        self._finished = True
        return self.path

    def _streamed_is(self, result: RunResult) -> bool:
        """Whether the streamed records are ``result``'s, whole (the same arrays, every loop)."""
        if self._digest is None or result.n_samples != self._length:
            return False
        mine = {**result.channels, "vs_states": result.vs_states}
        return mine.keys() == self._streamed.keys() and all(
            arr.shape == self._streamed[name].shape
            and (arr.size == 0 or np.may_share_memory(arr, self._streamed[name]))
            for name, arr in mine.items()
        )

    def _open_tmp(self) -> Path:
        if self._tmp is None:
            raise RuntimeError(f"{self.path}: RunFileStream is used outside its with block")
        return self._tmp

    def _close_file(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None
