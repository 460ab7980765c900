"""Plausibility of virtual systems and specimens (issue 18: a VS parameter or a rigid weight of 1e308).

``--set m_vs=1e308``, a VS file's ``k_s = 1e308`` and a specimen file's
``weight = 1e308`` were accepted (the last made ``imil frf`` run its whole
test).  The bounds are impedance_mil/plausibility.py's ``VS_BOUNDS`` (by the
parameter's unit) and ``SPECIMEN_BOUNDS``; docs/limits.md lists them.
"""

from __future__ import annotations

import warnings

import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.plausibility import (
    SPECIMEN_BOUNDS,
    VS_ANY_BOUND,
    VS_BOUNDS,
    PlausibilityWarning,
    check_vs_value,
    vs_bound,
)
from impedance_mil.specimens.factory import specimen_from_config
from impedance_mil.virtual import presets
from impedance_mil.virtual.system import DefinedVS

PRESETS = presets.names()


@pytest.mark.parametrize("name", PRESETS)
def test_every_preset_is_inside_the_bounds(name):
    vs = presets.get(name)
    for p in vs.definition.parameters:
        value = abs(vs.parameters[p.name])
        b = vs_bound(p.unit)
        assert b.error_high is None or value <= b.error_high / 10, (p.name, value)  # a decade of room
        assert value == 0 or b.error_low is None or value >= b.error_low * 10, (p.name, value)


@pytest.mark.parametrize(
    "name, key", [(name, p.name) for name in PRESETS for p in presets.get(name).definition.parameters]
)
def test_every_parameter_of_every_preset_is_refused_at_1e308_naming_it(name, key):
    vs = presets.get(name)
    values = {**vs.parameters, key: 1e308}
    with pytest.raises(ConfigError) as info:
        DefinedVS(vs.definition, values, where="vs.toml: ")
    assert info.value.key == f"vs.toml: {key}"
    check = next(p.check for p in vs.definition.parameters if p.name == key)
    assert ("a fraction in [0, 1)" if check == "fraction" else "a plausible value, at most") in str(
        info.value
    )


def test_bounds_are_by_dimension_spaces_ignored_and_a_fallback_for_other_units():
    assert vs_bound("force_pound * second**2 / inch") is VS_BOUNDS["force_pound*second**2/inch"]
    assert vs_bound("volt") is VS_ANY_BOUND
    with pytest.raises(ConfigError, match="gain: expected a plausible value, at most 1e\\+15"):
        check_vs_value("gain", -1e16, "volt")  # the magnitude: a negative value is bounded too


def test_zero_passes_a_lower_bound_and_a_tiny_mass_does_not():
    assert check_vs_value("c", 0.0, "inch") == 0.0
    with pytest.raises(ConfigError, match="m_vs: expected a plausible value, at least 1e-05"):
        check_vs_value("m_vs", 1e-9, "force_pound * second**2 / inch")


def test_the_command_line_names_the_key(imil, tmp_path):
    r = imil("vs", "describe", "SD2", "--set", "k_s=1e308", cwd=tmp_path)
    assert r.returncode == 2
    assert r.stderr.strip().startswith("imil: error: k_s: expected a plausible value, at most 1e+13 lbf/in")


def test_a_rigid_weight_of_1e308_is_refused_in_the_file_and_a_large_one_warns():
    with pytest.raises(ConfigError) as info:
        specimen_from_config({"type": "rigid_mass", "weight": 1e308}, where="sp.toml: specimen.")
    assert info.value.key == "sp.toml: specimen.weight"
    bound = SPECIMEN_BOUNDS["weight"]
    with pytest.warns(PlausibilityWarning, match="weight = 5e\\+07 lbf is unusually large"):
        specimen_from_config({"type": "rigid_mass", "weight": 5 * bound.warn_high})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        specimen_from_config({"type": "rigid_mass", "weight": "3.6 kip"})  # the report's article


def test_a_storey_weight_is_bounded_too():
    with pytest.raises(ConfigError) as info:
        specimen_from_config(
            {"type": "shear_building", "story_weights": [800, 1e300], "story_stiffness": [2e3, 1e3]}
        )
    assert info.value.key == "specimen.story_weights"
