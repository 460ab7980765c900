"""Whether a run will compile the lab's kernels first (the first run after an install), and its progress.

numba compiles the compiled loop (:data:`impedance_mil.lab.tick.run_loop`) and
the kernels it inlines once, then loads them from its cache: the first run after
an install (or after the cache was cleared, or with a new ``NUMBA_CACHE_DIR``)
takes seconds to a minute of compiling (11 s on the 2-core CI machine with a
core free, 18 s on one core, measured with an empty ``NUMBA_CACHE_DIR``; 22-25 s
before the changes of docs/lab.md "The first run, session 3", 46-67 s before
the loop's faster inliner, :mod:`impedance_mil.lab.inline_pipeline`), every
later run about a second of loading.  A command says so before it starts, instead of seeming to hang
(issue 16, goal 4), and then says which group of kernels it is compiling
(:func:`compile_progress`: "compiling kernels (first run only): 3/4 the compiled
loop ...").

Where the time goes (``benchmarks/bench_first_run.py``, docs/lab.md, "The first
run"): the compiled loop is about 85 % of it (its LLVM code about half of that);
the spectra's kernels and the loop's compressed-row plant step compile in a
side process meanwhile (:mod:`impedance_mil.lab.compile_aside`).

The test is whether the loop's cache index exists where numba will look for it.
numba exposes no public call for that; the index path is read from the
dispatcher's cache object, and when a numba version lays it out otherwise the
answer is "not known" (False: no notice, nothing breaks).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import NamedTuple

from numba.core import event

from .tick import run_loop

#: What a command prints (on stderr) before a run that compiles the kernels.
COMPILING_NOTICE = (
    "compiling kernels (first run only: up to a minute, then cached; later runs start in under a second)"
)

#: The start of each progress line (then ``k/n label ...``).
PROGRESS_PREFIX = "compiling kernels (first run only):"


class KernelGroup(NamedTuple):
    """Kernels compiled together, named for the progress lines.

    Attributes
    ----------
    label : str
        What the progress line calls them.
    modules : tuple of str
        Prefixes of the module names of their numba dispatchers (the longest
        prefix matching a dispatcher's module picks its group).
    """

    label: str
    modules: tuple[str, ...]


#: The groups a lab run compiles, in the order ``imil simulate`` reaches them (the VS kernels are
#: generated and compiled when the VS is built, the table's physics when the lab sets the table at
#: rest, the loop when it runs, the spectra when its metrics are evaluated).
KERNEL_GROUPS = (
    KernelGroup("the virtual system's kernels", ("imil_vs_", "impedance_mil.virtual.")),
    KernelGroup("the table's physics", ("impedance_mil.plant.", "impedance_mil.specimens.")),
    KernelGroup("the compiled loop (the longest step)", ("impedance_mil.lab.",)),
    KernelGroup("the spectra and other kernels", ("impedance_mil.",)),
)


def cache_index(dispatcher) -> Path | None:
    """The cache index file numba reads for ``dispatcher``, or None when its layout is not the known one."""
    cache_file = getattr(getattr(dispatcher, "_cache", None), "_cache_file", None)
    index = getattr(cache_file, "_index_path", None)
    return Path(index) if isinstance(index, str) else None


def kernels_need_compiling() -> bool:
    """True when the compiled loop has no cache index yet (this run compiles it)."""
    index = cache_index(run_loop)
    return index is not None and not index.is_file()


def group_of(module: str, groups: tuple[KernelGroup, ...] = KERNEL_GROUPS) -> int | None:
    """Index in ``groups`` of the group of a dispatcher defined in ``module`` (longest prefix), or None."""
    best, length = None, -1
    for i, group in enumerate(groups):
        for prefix in group.modules:
            if module.startswith(prefix) and len(prefix) > length:
                best, length = i, len(prefix)
    return best


class CompileProgress(event.Listener):
    """Listens to numba's compile events and says when each group of kernels starts compiling.

    Only a top-level compile counts (the kernels a compile pulls in are part of
    it); a group is announced once.  numba's event API is public
    (``numba.core.event``, "Notes on Numba's event API").

    Parameters
    ----------
    say : callable
        Receives each progress line.
    groups : tuple of KernelGroup
        The groups, in order (the line says ``k/len(groups)``).
    """

    def __init__(self, say: Callable[[str], None], groups: tuple[KernelGroup, ...] = KERNEL_GROUPS) -> None:
        self._say = say
        self._groups = groups
        self._depth = 0
        self._started_at = 0.0
        #: Indices of the groups announced so far.
        self.announced: list[int] = []
        #: Seconds [s] spent in top-level compiles of the groups' kernels.
        self.seconds = 0.0

    def on_start(self, ev: event.Event) -> None:
        self._depth += 1
        if self._depth != 1:
            return
        self._started_at = time.perf_counter()
        dispatcher = (ev.data or {}).get("dispatcher")
        module = getattr(getattr(dispatcher, "py_func", None), "__module__", None) or ""
        index = group_of(module, self._groups)
        if index is not None and index not in self.announced:
            self.announced.append(index)
            self._say(f"{PROGRESS_PREFIX} {index + 1}/{len(self._groups)} {self._groups[index].label} ...")

    def on_end(self, ev: event.Event) -> None:
        self._depth -= 1
        if self._depth == 0:
            self.seconds += time.perf_counter() - self._started_at


@contextmanager
def compile_progress(
    say: Callable[[str], None], groups: tuple[KernelGroup, ...] = KERNEL_GROUPS
) -> Iterator[CompileProgress]:
    """Within the block, say when each group of kernels starts compiling (see :class:`CompileProgress`)."""
    listener = CompileProgress(say, groups)
    with event.install_listener("numba:compile", listener):
        yield listener
