"""Stale compiled kernels: clear numba's cache of this package when the kernels' sources change.

numba caches each compiled function (``@njit(cache=True)``) beside its source
and checks it against the stamp of *that* file only.  The lab's loop inlines
kernels of other modules (the table's physics of ``plant/nonlinear.py`` into
``lab/stepping.py``'s stages and ``lab/tick.py``'s loop), so after an edit of
``plant/nonlinear.py`` -- a ``git pull`` into an editable install -- numba
would load the loop compiled with the *old* physics, silently.  This module
keeps a fingerprint of every kernel-bearing source of the package (the files
that use numba) next to the cache and, when it changes, deletes the package's
cache files (``*.nbi``, ``*.nbc``) before any kernel is loaded: the next run
compiles afresh (and says so, :mod:`impedance_mil.lab.first_run`).

Cost on every start: one ``stat`` per source file (about 330, a few ms); the
files are read and hashed only when a stamp changed.  A package folder that
cannot be written (an installed wheel, where numba caches elsewhere and an
upgrade rewrites every file, so every stamp changes) is left alone.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

#: The package's root folder.
PACKAGE_ROOT = Path(__file__).resolve().parent
#: Where the fingerprint is kept (numba's own cache folder of the package root).
MARKER_NAME = "kernel_sources.json"
#: numba's cache files: the index and the compiled code of each function.
CACHE_SUFFIXES = (".nbi", ".nbc")
#: A source whose text names numba holds or inlines compiled kernels.
KERNEL_MARK = b"numba"


#: Folders of the package that hold no sources (skipped by the walk: the shipped data are large).
_NOT_SOURCES = {"__pycache__", "data"}


def _stamps(root: Path) -> dict[str, list[int]]:
    """Size and modification time [ns] of every source under ``root``, by relative path."""
    out = {}
    # every path os.walk gives starts with the root and a separator: cut it (os.path.relpath
    # costs 8 us a file, most of this function's time on every start)
    prefix = len(os.path.join(str(root), ""))
    for folder, dirs, _ in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d not in _NOT_SOURCES)
        with os.scandir(folder) as entries:
            for entry in entries:
                if entry.name.endswith(".py") and entry.is_file():
                    st = entry.stat()
                    rel = entry.path[prefix:].replace(os.sep, "/")
                    out[rel] = [st.st_size, st.st_mtime_ns]
    return dict(sorted(out.items()))


def _sources(root: Path) -> list[Path]:
    return [root / rel for rel in _stamps(root)]


def kernel_digest(root: Path = PACKAGE_ROOT) -> str:
    """SHA-256 of the path and text of every source under ``root`` that names numba."""
    h = hashlib.sha256()
    for path in _sources(root):
        text = path.read_bytes()
        if KERNEL_MARK in text:
            h.update(path.relative_to(root).as_posix().encode() + b"\0" + text + b"\0")
    return h.hexdigest()


def cache_folders(root: Path = PACKAGE_ROOT) -> list[Path]:
    """Where numba keeps this package's cache: ``__pycache__`` beside the sources, and under ``NUMBA_CACHE_DIR``."""
    folders = [root]
    user = os.environ.get("NUMBA_CACHE_DIR")
    if user:
        # numba mirrors the source folder's absolute path under NUMBA_CACHE_DIR
        folders.append(Path(user) / root.relative_to(root.anchor))
    return folders


def clear_kernel_cache(root: Path = PACKAGE_ROOT) -> int:
    """Delete the numba cache files of ``root``'s sources; the number deleted."""
    removed = 0
    for folder in cache_folders(root):
        if not folder.is_dir():
            continue
        for path in folder.rglob("*"):
            if path.suffix in CACHE_SUFFIXES and path.is_file():
                try:
                    path.unlink()
                    removed += 1
                except FileNotFoundError:  # another process cleared it first
                    pass
    return removed


def refresh_kernel_cache(root: Path = PACKAGE_ROOT) -> bool:
    """Clear the kernel cache if the kernels' sources changed since it was written; True if cleared.

    No fingerprint yet (a first start, or a cache of an older version without
    one) counts as changed.  Nothing happens where ``root/__pycache__`` cannot
    be written.
    """
    folder = root / "__pycache__"
    marker = folder / MARKER_NAME
    try:
        folder.mkdir(exist_ok=True)
    except OSError:
        return False
    if not os.access(folder, os.W_OK):
        return False
    stamps = _stamps(root)
    try:
        known = json.loads(marker.read_text())
    except (OSError, ValueError):
        known = {}
    if known.get("stamps") == stamps:
        return False  # the fast path: no source touched
    digest = kernel_digest(root)
    cleared = known.get("digest") != digest
    if cleared:
        clear_kernel_cache(root)
    tmp = marker.with_name(f"{MARKER_NAME}.{os.getpid()}.tmp")
    try:
        tmp.write_text(json.dumps({"digest": digest, "stamps": stamps}))
        os.replace(tmp, marker)  # atomic: parallel workers never read half a file
    except OSError:
        pass
    return cleared


__all__ = ["clear_kernel_cache", "kernel_digest", "refresh_kernel_cache"]
