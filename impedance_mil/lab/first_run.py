"""Whether a run will compile the lab's kernels first (the first run after an install).

numba compiles the compiled loop (:data:`impedance_mil.lab.tick.run_loop`) and
the kernels it inlines once, then loads them from its cache: the first run after
an install (or after the cache was cleared, or with a new ``NUMBA_CACHE_DIR``)
takes a minute or more of compiling (81 s wall on the 2-core CI machine under
load, measured with an empty ``NUMBA_CACHE_DIR``), every later run under a second
of loading.  A command says so before it starts, instead of seeming to hang
(issue 16, goal 4).

The test is whether the loop's cache index exists where numba will look for it.
numba exposes no public call for that; the index path is read from the
dispatcher's cache object, and when a numba version lays it out otherwise the
answer is "not known" (False: no notice, nothing breaks).
"""

from __future__ import annotations

from pathlib import Path

from .tick import run_loop

#: What a command prints (on stderr) before a run that compiles the kernels.
COMPILING_NOTICE = (
    "compiling kernels (first run only: about a minute, then cached; later runs start in under a second)"
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
