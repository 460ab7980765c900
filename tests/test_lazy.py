"""Lazy re-exports of the package ``__init__`` files (impedance_mil/lazy.py, PEP 562)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from impedance_mil.lazy import LazyModule, lazy_attributes, lazy_exports
from impedance_mil.plant import nonlinear, nonlinear_kernels
from impedance_mil.plant.parameters import TableParameters
from impedance_mil.specimens import sensor_kernels, sensors


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


def test_a_lazy_module_is_imported_on_the_first_attribute_read_only():
    # In a fresh interpreter: colorsys is imported by nothing else at start-up.
    probe = (
        "import sys; from impedance_mil.lazy import LazyModule; m = LazyModule('colorsys'); "
        "before = 'colorsys' in sys.modules; m.rgb_to_hsv(0.0, 0.0, 0.0); "
        "print(before, 'colorsys' in sys.modules, repr(m))"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert done.stdout.split() == ["False", "True", "LazyModule('colorsys')"]


def test_a_lazy_module_that_does_not_exist_fails_when_read_not_when_named():
    missing = LazyModule("impedance_mil.no_such_module")
    with pytest.raises(ModuleNotFoundError, match="no_such_module"):
        missing.anything  # noqa: B018


def test_lazy_attributes_read_the_names_from_their_module_and_refuse_others():
    module_getattr = lazy_attributes(
        "impedance_mil.plant.nonlinear", "impedance_mil.plant.nonlinear_kernels", ("orifice",)
    )
    assert module_getattr("orifice") is nonlinear_kernels.orifice
    with pytest.raises(AttributeError, match="'impedance_mil.plant.nonlinear' has no attribute 'port_flows'"):
        module_getattr("port_flows")


@pytest.mark.parametrize(
    ("module", "kernels"),
    [(nonlinear, nonlinear_kernels), (sensors, sensor_kernels)],
    ids=["plant.nonlinear", "specimens.sensors"],
)
def test_the_kernels_moved_out_are_importable_where_they_were(module, kernels):
    for name in module.KERNELS:
        assert getattr(module, name) is getattr(kernels, name)
    with pytest.raises(AttributeError, match="no_such_kernel"):
        module.no_such_kernel  # noqa: B018


def test_the_plain_orifice_law_is_the_compiled_one_to_the_bit():
    # plant.nonlinear builds a table's constants with the Python law (no numba at start-up) and the
    # kernels use it compiled: one definition, so the two agree exactly (no fastmath: IEEE operations).
    rng = np.random.default_rng(16)
    drops = np.concatenate([rng.normal(0.0, 3000.0, 2000), 10.0 ** rng.uniform(-8, 5, 500), [500.0, 1500.0]])
    laminar = np.concatenate([rng.uniform(0.0, 200.0, 2000), 10.0 ** rng.uniform(-8, 3, 500), [20.0, 20.0]])
    for dp, p_lam in zip(drops.tolist(), laminar.tolist(), strict=True):
        assert nonlinear.orifice_law(dp, p_lam) == nonlinear_kernels.orifice(dp, p_lam)
