"""Files written whole or not at all, text files read with one-line errors, and JSON-safe values.

Every file the package writes goes through :func:`atomic_path` (or its
shortcuts :func:`atomic_write_text` / :func:`atomic_write_bytes`): the data
are written under a temporary name in the target's folder, flushed to disk
(fsync) and renamed over the target with :func:`os.replace`, which is atomic
on POSIX and Windows for names on one file system.  If anything fails, the
temporary file is removed and an existing target is left untouched, so a
crash or an error never leaves a half-written file under its final name.
:func:`atomic_directory` does the same for a folder of files.

The temporary name is hidden and does not end with the target's suffix
(``.run.h5.tmp-<pid>-<token>``), so a search for ``*.h5`` or ``*.json``
never finds a temporary or left-over file; a library that picks the format
from the suffix (matplotlib) must be told the format.  The file is created
exclusively, with the permissions of the process umask.

:func:`read_text` reads a UTF-8 file and turns every way it can fail into a
one-line :class:`~impedance_mil.errors.DataFileError` naming the file.

This module sits at the bottom of the package (standard library and
:mod:`impedance_mil.errors` only).
"""

from __future__ import annotations

import math
import os
import secrets
import shutil
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from .errors import DataFileError


def temporary_name(path: str | os.PathLike, tag: str = "tmp") -> Path:
    """A new hidden name beside ``path``, ``.<name>.<tag>-<pid>-<random>`` (nothing is created).

    Examples
    --------
    >>> name = temporary_name("out/run.h5")
    >>> name.parent.as_posix(), name.name.startswith(".run.h5.tmp-"), name.suffix == ".h5"
    ('out', True, False)
    """
    target = Path(path)
    return target.with_name(f".{target.name}.{tag}-{os.getpid()}-{secrets.token_hex(4)}")


def _fsync(path: Path) -> None:
    with open(path, "rb") as fh:
        os.fsync(fh.fileno())


@contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary file path beside ``path``; rename it to ``path`` when the block succeeds.

    The temporary file exists (empty) when the block starts; write it in
    place, with any library.  On success it is fsynced and renamed over
    ``path``; on any exception (including KeyboardInterrupt) it is removed and
    ``path`` keeps its old content, if it had one.

    Raises
    ------
    OSError
        The folder of ``path`` does not exist or is not writable (raised
        before the block runs), or the rename fails.

    Examples
    --------
    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> with atomic_path(folder / "a.txt") as tmp:
    ...     _ = tmp.write_text("done")
    >>> (folder / "a.txt").read_text(), sorted(p.name for p in folder.iterdir())
    ('done', ['a.txt'])
    """
    target = Path(path)
    tmp = temporary_name(target)
    with open(tmp, "xb"):
        pass
    try:
        yield tmp
        _fsync(tmp)
        os.replace(tmp, target)
    finally:
        if os.path.lexists(tmp):
            os.unlink(tmp)


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (see :func:`atomic_path`); return the path."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


def atomic_write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` as UTF-8, atomically (see :func:`atomic_path`); return the path."""
    return atomic_write_bytes(path, text.encode("utf-8"))


@contextmanager
def atomic_directory(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a new temporary folder beside ``path``; rename it to ``path`` when the block succeeds.

    An existing folder at ``path`` is replaced only once the new one is
    complete (it is moved aside, the new one renamed in, then the old one
    deleted; if the rename fails the old folder is put back).  On any
    exception the temporary folder and everything in it are removed, so no
    partial folder is left.  Deciding whether an existing folder may be
    replaced is the caller's business.

    Raises
    ------
    OSError
        The parent folder does not exist or is not writable, or ``path`` is a file.
    """
    target = Path(path)
    tmp = temporary_name(target)
    tmp.mkdir()
    try:
        yield tmp
        if target.is_dir():
            old = temporary_name(target, "old")
            target.rename(old)
            try:
                tmp.rename(target)
            except BaseException:
                old.rename(target)
                raise
            shutil.rmtree(old)
        else:
            os.replace(tmp, target)
    finally:
        if tmp.is_dir():
            shutil.rmtree(tmp)


def read_text(path: str | os.PathLike, expected: str = "a text file") -> str:
    """The UTF-8 text of the file at ``path``.

    Parameters
    ----------
    path : str or PathLike
        The file.
    expected : str
        What the file should be, for the message when ``path`` is a folder
        (e.g. ``"a TOML file"``).

    Raises
    ------
    DataFileError
        One line naming the file: not found, a directory, permission denied,
        not UTF-8 text, or another read error.
    """
    p = Path(path)
    try:
        return p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise DataFileError(p, "file not found") from None
    except IsADirectoryError:
        raise DataFileError(p, f"is a directory, expected {expected}") from None
    except PermissionError:
        raise DataFileError(p, "permission denied") from None
    except UnicodeDecodeError:
        raise DataFileError(p, "not a text file") from None
    except OSError as exc:
        raise DataFileError(p, f"unreadable ({exc.strerror or exc})") from None


def json_safe(value: Any) -> Any:
    """A copy of ``value`` that :func:`json.dumps` writes as strict JSON.

    Mappings become dicts with string keys, tuples and lists become lists,
    numpy arrays and scalars (anything with ``tolist``) become Python lists
    and numbers, objects with ``to_dict`` become their dict, and floats that
    are not finite (NaN, +-inf) become ``None`` (JSON has no NaN).  Anything
    else is returned unchanged.

    Examples
    --------
    >>> json_safe({"a": (1.0, float("nan")), 2: float("inf")})
    {'a': [1.0, None], '2': None}
    """
    if isinstance(value, Mapping):
        return {str(k): json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if hasattr(value, "tolist"):
        return json_safe(value.tolist())
    if hasattr(value, "to_dict"):
        return json_safe(value.to_dict())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
