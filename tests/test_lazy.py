"""Lazy re-exports of the package ``__init__`` files (impedance_mil/lazy.py, PEP 562)."""

from __future__ import annotations

import pytest

from impedance_mil.lazy import lazy_exports
from impedance_mil.plant.parameters import TableParameters


def test_a_name_is_read_from_its_submodule_and_a_submodule_is_itself():
    exports = lazy_exports("impedance_mil.plant", {"parameters": ("TableParameters",)}, submodules=("valve",))
    assert exports.getattr("TableParameters") is TableParameters
    assert exports.getattr("valve").__name__ == "impedance_mil.plant.valve"
    assert {"TableParameters", "valve"} <= set(exports.dir())


def test_an_unknown_name_is_an_attribute_error_naming_it():
    exports = lazy_exports("impedance_mil.plant", {"parameters": ("TableParameters",)})
    with pytest.raises(AttributeError, match="'impedance_mil.plant' has no attribute 'LinearTable'"):
        exports.getattr("LinearTable")


def test_a_name_of_its_own_submodule_is_refused():
    # Importing implement.discretize binds the package's `discretize` to the module, not the function.
    with pytest.raises(ValueError, match="discretize"):
        lazy_exports("impedance_mil.implement", {"discretize": ("discretize", "with_leak")})
