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
one-line :class:`~impedance_mil.errors.DataFileError` naming the file;
:func:`parse_json` parses JSON the same way, refusing before parsing what
would make Python's parser recurse 3000 levels or convert a number of
thousands of digits (:data:`MAX_JSON_DEPTH`, :data:`MAX_NUMBER_DIGITS`).

Integrity helpers: :func:`file_sha256` (the checksum recorded with a file
and checked before it is trusted again), :func:`stale_temporaries` /
:func:`remove_stale_temporaries` (what a killed process left behind), and
:func:`folder_lock` (one writer per folder).

This module sits at the bottom of the package (standard library and
:mod:`impedance_mil.errors` only).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import secrets
import shutil
import socket
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from .errors import DataFileError, ImilError

try:  # POSIX; Windows locks with msvcrt
    import fcntl
except ImportError:  # pragma: no cover - not POSIX
    fcntl = None  # type: ignore[assignment]
    import msvcrt

#: Most digits in one run of digits of a number: a double carries 17 significant
#: digits, and Python takes minutes to convert a number of millions of digits.
MAX_NUMBER_DIGITS = 100

#: Deepest nesting of objects and arrays in a JSON file the package reads: design files,
#: run summaries and campaign records nest 5 levels at most.
MAX_JSON_DEPTH = 32

#: What the check before parsing looks at in a JSON text: a string (skipped whole; an
#: unclosed one ends the scan), a bracket (nesting) and a long run of digits (number size).
_JSON_SCAN_RE = re.compile(
    r'"(?:[^"\\\n]|\\.)*"|"|[\[\]{}]|(?<![0-9])[0-9]{' + str(MAX_NUMBER_DIGITS + 1) + ",}"
)

#: Names :func:`temporary_name` makes: ``.<name>.<tag>-<pid>-<8 hex digits>``.
_TEMPORARY_RE = re.compile(r"^\..+\.(tmp|old)-[0-9]+-[0-9a-f]{8}$")


class FolderLockedError(ImilError, BlockingIOError):
    """Another process holds the lock of a folder (:func:`folder_lock`)."""


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


def read_text(path: str | os.PathLike, expected: str = "a text file", max_bytes: int | None = None) -> str:
    """The UTF-8 text of the file at ``path``.

    Parameters
    ----------
    path : str or PathLike
        The file.
    expected : str
        What the file should be, for the message when ``path`` is a folder
        (e.g. ``"a TOML file"``).
    max_bytes : int, optional
        Refuse a file larger than this many bytes, before reading it (a
        configuration file of gigabytes is a mistake, not a configuration).

    Raises
    ------
    DataFileError
        One line naming the file: not found, a directory, permission denied,
        too large, not UTF-8 text, or another read error.
    """
    p = Path(path)
    try:
        with open(p, "rb") as fh:
            size = os.fstat(fh.fileno()).st_size
            if max_bytes is not None and size > max_bytes:
                raise DataFileError(p, f"{size} bytes, larger than {expected} may be ({max_bytes} bytes)")
            data = fh.read() if max_bytes is None else fh.read(max_bytes + 1)
        if max_bytes is not None and len(data) > max_bytes:
            raise DataFileError(p, f"larger than {expected} may be ({max_bytes} bytes)")
        # Universal newlines, as text mode reads them ("\r\n" and "\r" become "\n").
        return data.decode("utf-8").replace("\r\n", "\n").replace("\r", "\n")
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


def parse_json(text: str, where: str | os.PathLike) -> Any:
    """Parse a JSON text, with a one-line :class:`DataFileError` naming ``where`` for every failure.

    Refused before parsing: arrays and objects nested more than
    :data:`MAX_JSON_DEPTH` deep, a run of more than :data:`MAX_NUMBER_DIGITS`
    digits outside strings.  Refused while parsing: ``NaN``, ``Infinity`` and
    numbers that overflow a double (``1e400``): JSON has no such numbers.

    Raises
    ------
    DataFileError
        Not valid JSON, nested too deep, or a number that is not a finite double.

    Examples
    --------
    >>> parse_json('{"a": [1, 2.5]}', "f.json")
    {'a': [1, 2.5]}
    >>> parse_json("[" * 40 + "]" * 40, "f.json")
    Traceback (most recent call last):
    ...
    impedance_mil.errors.DataFileError: f.json: line 1: arrays or objects nested more than 32 deep
    """
    depth = 0
    for match in _JSON_SCAN_RE.finditer(text):
        token = match.group()
        if token in ("[", "{"):
            depth += 1
            if depth > MAX_JSON_DEPTH:
                line = text.count("\n", 0, match.start()) + 1
                raise DataFileError(
                    where, f"line {line}: arrays or objects nested more than {MAX_JSON_DEPTH} deep"
                )
        elif token in ("]", "}"):
            depth = max(depth - 1, 0)
        elif token == '"':
            break  # an unclosed string: the parser reports it
        elif token[0] != '"':
            line = text.count("\n", 0, match.start()) + 1
            raise DataFileError(where, f"line {line}: a number of more than {MAX_NUMBER_DIGITS} digits")
    try:
        return json.loads(text, parse_constant=_no_constant, parse_float=_finite_float)
    except json.JSONDecodeError as exc:
        raise DataFileError(where, f"not valid JSON ({exc.msg} at line {exc.lineno})") from None
    except _NotAJsonNumber as exc:
        raise DataFileError(where, f"not valid JSON ({exc})") from None
    except (RecursionError, ValueError):  # a case the scan above missed
        raise DataFileError(where, "not valid JSON (nested too deep or a number too large)") from None


class _NotAJsonNumber(ValueError):
    """NaN, Infinity or a number beyond the range of a double in a JSON text."""


def _no_constant(name: str) -> float:
    raise _NotAJsonNumber(f"{name} is not a JSON number")


def _finite_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise _NotAJsonNumber(f"{text[:40]} is beyond the range of a double")
    return value


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


def file_sha256(path: str | os.PathLike, chunk_bytes: int = 1 << 20) -> str:
    """Hex SHA-256 of a file's bytes, read in chunks (a run file of gigabytes never sits in memory).

    Raises
    ------
    OSError
        The file cannot be read.

    Examples
    --------
    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "a.bin"
    >>> _ = path.write_bytes(b"abc")
    >>> file_sha256(path)[:16]
    'ba7816bf8f01cfea'
    """
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(chunk_bytes), b""):
            digest.update(block)
    return digest.hexdigest()


def stale_temporaries(folder: str | os.PathLike) -> list[Path]:
    """Temporary files and folders (:func:`temporary_name`) left in ``folder`` and its subfolders.

    Only names of the form ``.<name>.tmp-<pid>-<hex>`` or ``.<name>.old-<pid>-<hex>``
    are listed; they are stale when no process is writing the folder (hold
    :func:`folder_lock` first).
    """
    root = Path(folder)
    if not root.is_dir():
        return []
    found = []
    for dirpath, dirnames, filenames in os.walk(root):
        for name in filenames + dirnames:
            if _TEMPORARY_RE.match(name):
                found.append(Path(dirpath) / name)
        dirnames[:] = [d for d in dirnames if not _TEMPORARY_RE.match(d)]
    return sorted(found)


def remove_stale_temporaries(folder: str | os.PathLike) -> list[Path]:
    """Remove what :func:`stale_temporaries` lists (e.g. after a SIGKILL); return the paths removed."""
    removed = stale_temporaries(folder)
    for path in removed:
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path, ignore_errors=True)
        else:
            path.unlink(missing_ok=True)
    return removed


@contextmanager
def folder_lock(
    folder: str | os.PathLike, name: str = ".lock", holder: str = "another process"
) -> Iterator[Path]:
    """Hold an exclusive lock on ``folder`` for the block; refuse at once if another process holds it.

    The lock is an operating-system lock (``flock`` on POSIX) on the file
    ``folder/name``, which holds the ``host:pid`` of its holder for the
    message.  The system releases it when the holder exits, even by SIGKILL,
    so a crash never leaves the folder locked.  ``holder`` says who the other
    process is, for the message (e.g. ``"another imil campaign run"``).

    Raises
    ------
    FolderLockedError
        Another process holds the lock (one line naming the folder and the holder).
    OSError
        The folder does not exist or is not writable.
    """
    path = Path(folder) / name
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            if fcntl is not None:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            else:  # pragma: no cover - not POSIX
                msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)
        except OSError:
            os.lseek(fd, 0, os.SEEK_SET)
            who = os.read(fd, 200).decode("utf-8", "replace").strip() or "pid unknown"
            raise FolderLockedError(
                f"{folder}: in use by {holder} ({who}); wait for it to finish or use another folder"
            ) from None
        os.ftruncate(fd, 0)
        os.lseek(fd, 0, os.SEEK_SET)
        os.write(fd, f"{socket.gethostname()}:{os.getpid()}\n".encode())
        yield path
    finally:
        os.close(fd)  # closing the descriptor releases the lock
