"""Display units and JSON documents in the user's units (issue 12, "Units out").

Reference values are the exact definitions of the US customary units
(1 in = 25.4 mm, 1 lbf = 4.4482216152605 N, 1 psi = 6894.757293168 Pa,
1 in**3 = 16.387064 cm**3) and the invariants of a conversion at the edge:
US output is the internal document unchanged, every SI number is its internal
value times the factor of its unit, and every number has a unit.
"""

from __future__ import annotations

import math

import pytest

from impedance_mil.display import UnitSystem, display_unit, format_value, unit_system
from impedance_mil.errors import ConfigError
from impedance_mil.lab.lab_units import LAB_OBJECTS
from impedance_mil.report.documents import (
    _KEY_PATTERNS,
    TF_COEFFICIENTS,
    UNKNOWN,
    express,
    key_units,
    own_key_units,
    registry_unit,
)
from impedance_mil.virtual.files import UNITS as VS_UNITS

SI, US = UnitSystem.SI, UnitSystem.US
LBF_N = 4.4482216152605
PSI_PA = LBF_N / 0.0254**2


@pytest.mark.parametrize(
    "unit, name, factor",
    [
        ("inch", "mm", 25.4),
        ("inch / second", "mm/s", 25.4),
        ("inch / second**2", "m/s**2", 0.0254),
        ("force_pound", "kN", LBF_N / 1000),
        ("psi", "MPa", PSI_PA / 1e6),
        ("force_pound * second**2 / inch", "kg", LBF_N / 0.0254),
        ("inch**3 / second", "L/s", 0.016387064),
        ("force_pound / inch", "kN/m", LBF_N / 0.0254 / 1000),
        ("volt / psi", "V/MPa", 1e6 / PSI_PA),
        ("volt / inch", "V/mm", 1 / 25.4),
        ("hertz", "Hz", 1.0),
        ("g0", "g0", 1.0),
        ("milliampere", "mA", 1.0),
    ],
)
def test_si_display_units_are_the_exact_conversions(unit, name, factor):
    shown = display_unit(unit, SI)
    assert shown.name == name
    assert shown.factor == pytest.approx(factor, rel=1e-12)
    assert display_unit(unit, US).factor == 1.0  # US is the internal system


def test_format_value_names_the_unit_a_person_reads():
    assert format_value(3.0, "inch", SI) == "76.2 mm"
    assert format_value(3.0, "inch", US) == "3 in"
    assert format_value(0.8, "g0", SI) == "0.8 g"  # g0 in files, g on screen
    assert format_value(None, "inch", SI) == "none"


def test_unit_system_refuses_an_unknown_name_naming_the_option():
    assert unit_system("SI") is SI and unit_system(None) is US
    with pytest.raises(ConfigError, match=r"--units: expected us or si"):
        unit_system("metric")


DOC = {
    "peak_table_disp_in": 3.0,
    "peak_table_accel_g": 0.5,
    "fc_hz": 80.0,
    "nrms_error": 0.1,
    "specimen_weight_lbf": 3600.0,
    "trip": {"limit": "stroke", "time_s": 2.65, "value": -3.0, "unit": "in"},
    "checks": [
        {"name": "flow", "peak": 24.0, "limit": 57.75, "unit": "in^3/s", "ratio": 0.42, "time_s": 1.1},
        {"name": "stroke", "peak": 2.0, "limit": 3.2, "unit": "in", "ratio": 0.6, "time_s": 4.3},
    ],
    "table": {"mid_stroke": 3.2, "mass": 4.14, "valve_poles_hz": [70.0, 110.0]},
    "limits": {"stroke": 3.0, "acceleration": None},
    "H_uz": {"num": [1.0, 2.0], "den": [1.0, 3.0]},
    "comparison": {"peak_table_disp_in": {"measured": 2.0, "predicted": 2.1}},
    "label": "text",
}


def _leaves(doc, path=""):
    """Every numeric field of a document: path -> value (a list of numbers is one field)."""
    out = {}
    for key, value in doc.items():
        here = f"{path}.{key}" if path else key
        if isinstance(value, dict):
            out.update(_leaves(value, here))
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            for i, item in enumerate(value):
                out.update(_leaves(item, f"{here}[{i}]"))
        elif isinstance(value, int | float | list) and not isinstance(value, bool):
            out[here] = value
    return out


def test_us_output_is_the_internal_document_with_a_units_block():
    shown = express(DOC, US)
    assert {k: v for k, v in shown.items() if k not in ("units", "unit_system")} == DOC
    assert shown["unit_system"] == "us"
    assert shown["units"]["peak_table_disp_in"] == "in"
    assert shown["units"]["checks[0].peak"] == "in**3/s"
    assert shown["units"]["trip.value"] == "in"
    assert shown["units"]["limits.acceleration"] == "in/s**2"  # a null limit still has its unit


def test_si_output_converts_every_number_by_its_unit_and_renames_unit_suffixes():
    shown = express(DOC, SI)
    units = shown["units"]
    assert shown["peak_table_disp_mm"] == pytest.approx(76.2, rel=1e-14)
    assert "peak_table_disp_in" not in shown
    assert shown["peak_table_accel_g"] == 0.5 and shown["fc_hz"] == 80.0  # same in both systems
    assert shown["specimen_weight_kn"] == pytest.approx(3600 * LBF_N / 1000, rel=1e-12)
    assert shown["trip"] == {"limit": "stroke", "time_s": 2.65, "value": pytest.approx(-76.2), "unit": "mm"}
    assert shown["checks"][0]["unit"] == "L/s" and shown["checks"][1]["unit"] == "mm"
    assert shown["checks"][0]["ratio"] == 0.42  # a ratio is a pure number
    assert shown["table"]["mass"] == pytest.approx(4.14 * LBF_N / 0.0254, rel=1e-12)
    assert shown["limits"]["stroke"] == pytest.approx(76.2)
    assert shown["comparison"]["peak_table_disp_in"]["measured"] == pytest.approx(50.8)
    assert shown["H_uz"] == DOC["H_uz"] and units["H_uz.num"] == TF_COEFFICIENTS  # stated, not converted
    # every number of the SI document has a unit, and none is unknown
    assert set(_leaves({k: v for k, v in shown.items() if k not in ("units",)})) <= set(units)
    assert UNKNOWN not in units.values()


def test_si_values_are_the_internal_values_times_their_factor():
    us, si = express(DOC, US), express(DOC, SI)
    pairs = zip(sorted(_leaves(us["table"]).items()), sorted(_leaves(si["table"]).items()), strict=True)
    for (key, value), (_, shown_value) in pairs:
        unit = {"mid_stroke": "inch", "mass": "force_pound * second**2 / inch", "valve_poles_hz": "hertz"}[
            key
        ]
        factor = display_unit(unit, SI).factor
        expected = [v * factor for v in value] if isinstance(value, list) else value * factor
        assert shown_value == pytest.approx(expected, rel=1e-14)


def test_a_number_no_rule_names_is_listed_as_unknown():
    assert express({"mystery": 1.0}, SI)["units"] == {"mystery": UNKNOWN}
    assert math.isclose(express({"mystery": 1.0}, SI)["mystery"], 1.0)  # and left as it is


def test_the_vs_registry_and_the_others_name_disjoint_keys():
    # express() reads the VS types' registry only for a key no other registry names (issue 16,
    # start-up): the order matters only where both name a key, so none may.
    assert set(own_key_units()) & set(VS_UNITS) == set()
    for key in {*own_key_units(), *VS_UNITS, "mystery"}:
        assert registry_unit(key) == key_units().get(key), key
    assert registry_unit("Ke") == "volt / inch" and registry_unit("k_s") == VS_UNITS["k_s"]


def test_a_lab_section_is_an_object_as_before_not_a_number_named_by_a_registry():
    # The lab's optional sections (null when absent) pass without the registries: no registry
    # or key pattern names their keys, so the rules gave them no unit before either.
    for path in LAB_OBJECTS:
        key = path.rsplit(".", 1)[-1]
        assert key_units().get(key) is None and not any(p.match(key) for p, _ in _KEY_PATTERNS), key
    doc = {"dynamics": {"platen": None, "stiffness": 1.0}, "calibration": None}
    shown = express(doc, SI)
    assert shown["dynamics"]["platen"] is None and shown["calibration"] is None
    assert set(shown["units"]) == {"dynamics.stiffness"}
