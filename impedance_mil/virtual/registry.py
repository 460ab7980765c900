"""The VS types: the built-in ones (:mod:`impedance_mil.virtual.types`) and a user's, from a file.

A type is a :class:`VSType`: its :class:`~impedance_mil.virtual.definition.VSDefinition`
and, optionally, design targets (a frozen dataclass whose ``build()`` returns
the system, with the units and labels of its fields) and named presets.
The built-in types are the modules of :mod:`impedance_mil.virtual.types`,
found when this module is imported; a user's type is a Python file that
defines ``TYPE`` (a :class:`VSType`) or ``DEFINITION`` (a
:class:`VSDefinition`), loaded with :func:`load_type_file`.
"""

from __future__ import annotations

import importlib
import importlib.util
import pkgutil
import sys
from pathlib import Path

from ..errors import ConfigError, DataFileError
from . import types as package
from .definition import VSDefinition
from .vstype import VSType


def _discover() -> dict[str, VSType]:
    found = []
    for info in pkgutil.iter_modules(package.__path__):
        module = importlib.import_module(f"{package.__name__}.{info.name}")
        found.append((getattr(module, "ORDER", 1000), info.name, module.TYPE))
    return {t.kind: t for _, _, t in sorted(found, key=lambda x: (x[0], x[1]))}


#: The built-in types by kind, in listing order.
BUILTIN: dict[str, VSType] = _discover()


def kinds() -> tuple[str, ...]:
    """Kinds of the built-in types."""
    return tuple(BUILTIN)


def get_type(kind: str) -> VSType:
    """The built-in type ``kind`` (case-insensitive).

    Raises
    ------
    ConfigError
        Unknown kind.
    """
    key = kind.strip().upper() if isinstance(kind, str) else kind
    if key not in BUILTIN:
        raise ConfigError("kind", "one of " + ", ".join(f"'{k}'" for k in BUILTIN), kind)
    return BUILTIN[key]


def load_type_file(path: str | Path) -> VSType:
    """A user's VS type from a Python file defining ``TYPE`` or ``DEFINITION``.

    The file is the user's own code and runs when loaded.

    Raises
    ------
    DataFileError
        Missing file, an error while running it, or neither name defined.
    ConfigError
        An inconsistent definition (raised when it is made; names the symbol).
    """
    p = Path(path)
    if not p.is_file():
        raise DataFileError(p, "no such VS type file")
    name = f"imil_user_vs_{abs(hash(str(p.resolve())))}"
    spec = importlib.util.spec_from_file_location(name, p)
    if spec is None or spec.loader is None:
        raise DataFileError(p, "not a Python file")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except ConfigError:
        raise
    except Exception as exc:  # the user's file: report what went wrong, in one line
        raise DataFileError(p, f"cannot load the VS type ({type(exc).__name__}: {exc})") from None
    found = getattr(module, "TYPE", None) or getattr(module, "DEFINITION", None)
    if isinstance(found, VSDefinition):
        found = VSType(found)
    if not isinstance(found, VSType):
        raise DataFileError(p, "defines neither TYPE (a VSType) nor DEFINITION (a VSDefinition)")
    return found
