"""A small TOML writer for the files the package writes back (a calibrated lab file).

The standard library reads TOML (:mod:`tomllib`) but does not write it, and the
writers on PyPI (tomli-w, tomlkit) would be a core dependency for one file.
Lab files hold only tables, strings, numbers, booleans, arrays of those and
inline tables, so :func:`toml_text` covers exactly that; ``tomllib.loads``
of its output gives back the input (tested in tests/test_tomlwrite.py).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

from .errors import ConfigError

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(name: str) -> str:
    return name if _BARE_KEY.match(name) else _string(name)


def _string(text: str) -> str:
    escaped = text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\t", "\\t")
    return f'"{escaped}"'


def _value(value: Any, where: str) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ConfigError(where, "a finite number (TOML has no NaN in lab files)", value)
        return repr(value)
    if isinstance(value, str):
        return _string(value)
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{_key(k)} = {_value(v, f'{where}.{k}')}" for k, v in value.items()) + " }"
    if isinstance(value, Sequence):
        return "[" + ", ".join(_value(v, where) for v in value) + "]"
    raise ConfigError(where, "a string, number, boolean, array or table", type(value).__name__)


def toml_text(data: Mapping[str, Any], header: str = "") -> str:
    """TOML text of ``data``: top-level scalars first, then one ``[section]`` per nested table.

    A table whose values are all tables (``[sensors.accel]`` under ``[sensors]``) is
    written as sub-sections; a table inside an array is written inline.

    Parameters
    ----------
    data : mapping
        The document.
    header : str
        Comment lines written first (each prefixed with ``# ``).
    """
    lines = [f"# {line}" if line else "#" for line in header.splitlines()]
    _section(data, (), lines)
    return "\n".join(lines).strip("\n") + "\n"


def _section(data: Mapping[str, Any], path: tuple[str, ...], lines: list[str]) -> None:
    scalars = {k: v for k, v in data.items() if not isinstance(v, Mapping)}
    tables = {k: v for k, v in data.items() if isinstance(v, Mapping)}
    if path and (scalars or not tables):
        lines.extend(["", "[" + ".".join(_key(p) for p in path) + "]"])
    for key, value in scalars.items():
        lines.append(f"{_key(key)} = {_value(value, '.'.join((*path, key)))}")
    for key, value in tables.items():
        _section(value, (*path, key), lines)
