"""Lazy re-exports for the package ``__init__`` files (PEP 562).

A package ``__init__`` names its public objects and the submodule defining each;
the submodule is imported the first time one of its names is read
(``from impedance_mil.plant import TableParameters`` imports
``plant.parameters``, not ``plant.linear`` and python-control).  The names stay
importable as before; the same imports, under ``typing.TYPE_CHECKING``, tell
readers and type checkers what they are.  This is how a light command (``imil
table info``) stays light (issue 16, goal 1; docs/architecture.md, "The lazy
command registry").

>>> import impedance_mil.plant as plant
>>> plant.TableParameters.__module__
'impedance_mil.plant.parameters'
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping
from typing import Any, NamedTuple


class LazyExports(NamedTuple):
    """A package's module-level ``__getattr__`` and ``__dir__`` (PEP 562)."""

    getattr: Callable[[str], Any]
    dir: Callable[[], list[str]]


def lazy_exports(
    package: str, exports: Mapping[str, tuple[str, ...]], submodules: tuple[str, ...] = ()
) -> LazyExports:
    """The ``__getattr__`` and ``__dir__`` of ``package`` that import its names on first use.

    A name that is also the name of the submodule defining it (``implement.discretize``)
    cannot be lazy: importing the submodule binds the package's attribute to the module.
    The package imports such a name itself, at the top, and leaves it out of ``exports``.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    exports : mapping of str to tuple of str
        Submodule (relative to ``package``, e.g. ``"linear"`` or ``"types.lead_rubber"``) to
        the public names it defines.
    submodules : tuple of str
        Submodules that are public names themselves (``("presets",)``).

    Returns
    -------
    LazyExports
        Bind them in the package: ``__getattr__, __dir__ = lazy_exports(__name__, {...})``.

    Raises
    ------
    ValueError
        If a name of ``exports`` is the name of its own submodule.
    """
    where = {name: module for module, names in exports.items() for name in names}
    shadowed = sorted(name for name, module in where.items() if name == module.rpartition(".")[2])
    if shadowed:
        raise ValueError(f"{package}: {', '.join(shadowed)}: a name of its own submodule cannot be lazy")
    where.update({name: name for name in submodules})

    def module_getattr(name: str) -> Any:
        module_name = where.get(name)
        if module_name is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module = importlib.import_module(f".{module_name}", package)
        return module if name in submodules else getattr(module, name)

    def module_dir() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(where))

    return LazyExports(module_getattr, module_dir)


class LazyModule:
    """A module that is imported when one of its attributes is first read.

    For a heavy dependency that a light module needs in a few functions only (``systems.py``
    converts to and from python-control, which costs 2 s to import, in two methods): the
    module binds ``control = LazyModule("control")`` at the top, where its imports are, and
    ``control.tf(...)`` imports python-control on that first call (:func:`importlib.import_module`);
    each name read is kept on the object, so later reads cost what a module's do.  Unlike
    :class:`importlib.util.LazyLoader` nothing is put in ``sys.modules`` before the first use,
    so ``"control" in sys.modules`` still says whether python-control was loaded.  Not for
    names used at import time (decorators, base classes) or in a hot loop.

    Parameters
    ----------
    name : str
        The absolute name of the module (``"control"``, ``"scipy.signal"``).

    Examples
    --------
    >>> signal = LazyModule("scipy.signal")
    >>> signal.tf2zpk([1.0], [1.0, 1.0])[1]
    array([-1.])
    """

    def __init__(self, name: str) -> None:
        self._name = name

    def __getattr__(self, attribute: str) -> Any:
        # Called only for a name not read before: the value is then kept on this object, so
        # that later reads are plain attribute reads (the fallback to __getattr__ alone costs
        # about 2 us, a tenth of a call of NonlinearTable.derivative).  A module attribute
        # replaced after its first read (a test's monkeypatch) is therefore not seen here.
        if attribute.startswith("__"):
            raise AttributeError(attribute)  # copy, pickle and inspect probe dunders
        value = getattr(importlib.import_module(self._name), attribute)
        setattr(self, attribute, value)
        return value

    def __repr__(self) -> str:
        return f"LazyModule({self._name!r})"


def lazy_attributes(module: str, source: str, names: tuple[str, ...]) -> Callable[[str], Any]:
    """The module-level ``__getattr__`` (PEP 562) of ``module`` that reads ``names`` from ``source``.

    For a module whose compiled kernels moved to a module of their own so that its light part
    does not import numba: ``from impedance_mil.specimens.sensors import measure_kernel`` still
    works, and imports ``specimens.sensor_kernels`` then.

    Parameters
    ----------
    module : str
        The ``__name__`` of the module that binds the result as its ``__getattr__``.
    source : str
        The absolute name of the module defining ``names``.
    names : tuple of str
        The names re-exported.

    Returns
    -------
    callable
        ``__getattr__ = lazy_attributes(__name__, "...", (...))``.
    """
    where = LazyModule(source)

    def module_getattr(name: str) -> Any:
        if name not in names:
            raise AttributeError(f"module {module!r} has no attribute {name!r}")
        return getattr(where, name)

    return module_getattr
