"""Physical plausibility of tables (issue 18, finding 5): impossible is an error, odd a warning.

The audit's tables (P_R >= P_S, a mass of 1e308, d = 1e-300, a 1 s loop
time) passed ``design`` and ``table info``.  Bounds are in
impedance_mil/plausibility.py and docs/limits.md.
"""

from __future__ import annotations

import subprocess
import sys
import warnings

import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.plant.parameters import TableParameters
from impedance_mil.plausibility import TABLE_BOUNDS, PlausibilityWarning, table_warnings

REPORT = TableParameters.report_default().to_dict()
#: Values of the general model's keys (issue 13), which the report's table does not have:
#: ordinary values (a 5 ms valve, an 80 Hz valve at 0.7, the lab's friction defaults 8 lbf and
#: 0.5 lbf*s/in, a 300 lbf/in reaction spring), to check that none of them is odd.
GENERAL = {
    "valve_time_constant": 0.005,
    "valve_frequency_hz": 80.0,
    "valve_damping": 0.7,
    "platen_damping": 0.5,
    "coulomb_friction": 8.0,
    "output_gain": 1.0,
    "grounded_stiffness": 300.0,
}


def build(**changes):
    return TableParameters.from_mapping({**REPORT, **changes})


@pytest.mark.parametrize(
    "changes, key, expected",
    [
        ({"return_pressure": 3000.0}, "return_pressure", "below the supply pressure 3000 psi"),
        ({"return_pressure": 3500.0}, "return_pressure", "below the supply pressure"),
        ({"mass": 1e308}, "mass", "at most 1e+07"),
        ({"d": 1e-300}, "d", "at least 0.1"),
        ({"loop_time": 1.0}, "loop_time", "below half the oil-column period, 0.0185185 s"),
        ({"valve_poles_hz": [70.0, 1e308]}, "valve_poles_hz", "at most 1e+06"),
        ({"supply_pressure": 1e9}, "supply_pressure", "at most 100000"),
    ],
)
def test_the_audit_tables_are_refused_naming_the_key(changes, key, expected):
    with pytest.raises(ConfigError) as info:
        build(**changes)
    assert info.value.key == key and expected in str(info.value)


def test_the_report_table_is_plausible_without_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        TableParameters.report_default()
    assert table_warnings(REPORT) == []


@pytest.mark.parametrize("key", sorted(TABLE_BOUNDS))
def test_every_bound_separates_odd_from_impossible(key):
    """Just inside an error bound a value is odd (a warning naming it); just outside it is refused."""
    bound = TABLE_BOUNDS[key]
    report = REPORT[key] if key in REPORT else GENERAL[key]
    assert all(  # the report's own value is neither odd nor impossible
        (bound.warn_low is None or v >= bound.warn_low) and (bound.warn_high is None or v <= bound.warn_high)
        for v in (report if isinstance(report, list) else [report])
    )
    for limit, warn, inside, outside in (
        (bound.error_low, bound.warn_low, 1.01, 0.99),
        (bound.error_high, bound.warn_high, 0.99, 1.01),
    ):
        if limit is None:
            continue
        texts = table_warnings({key: inside * limit})  # one key: the cross-key rules do not apply
        if warn is None:
            assert texts == []
        else:
            assert len(texts) == 1 and texts[0].startswith(f"{key} = "), texts
        with pytest.raises(ConfigError) as info:
            table_warnings({key: outside * limit})
        assert info.value.key == key


def test_odd_values_warn_naming_the_key_and_the_work_goes_on():
    with pytest.warns(PlausibilityWarning, match=r"^Ke = 1000 V/in is unusually large"):
        table = build(Ke=1000.0)
    assert table.Ke == 1000.0
    with pytest.warns(PlausibilityWarning, match=r"^loop_time = 0\.002 s is longer than the shortest valve"):
        build(loop_time=0.002)


def test_a_table_file_and_the_command_line(tmp_path, imil):
    path = tmp_path / "t.toml"
    source = TableParameters.report_default().to_dict()
    lines = [f"{k} = {v!r}" for k, v in source.items() if k != "return_pressure"]
    path.write_text("[table]\n" + "\n".join(lines) + '\nreturn_pressure = "3100 psi"\n')
    with pytest.raises(ConfigError, match="^return_pressure: "):
        TableParameters.from_toml(path)
    for args in (
        ["--table", str(path)],
        ["--set", "mass=1e308"],
        ["--set", "d=1e-300"],
        ["--set", "loop_time=1 s"],
    ):
        out = imil("table", "info", *args)
        assert out.returncode == 2, (args, out.stderr)
        assert out.stderr.startswith("imil: error: ") and len(out.stderr.strip().splitlines()) == 1
    design = imil("design", "--set", "return_pressure=3000 psi", "-o", tmp_path / "d.json")
    assert design.returncode == 2 and "return_pressure" in design.stderr
    assert not (tmp_path / "d.json").exists()


def test_the_warning_is_one_line_on_stderr():
    # In a real process (pytest records warnings instead of printing them).
    odd = subprocess.run(
        [sys.executable, "-m", "impedance_mil.cli.main", "table", "info", "--set", "Ke=1000"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert odd.returncode == 0, odd.stderr
    assert odd.stderr.startswith("imil: warning: Ke = 1000 V/in is unusually large (above 500;")
    assert len(odd.stderr.strip().splitlines()) == 1  # one line, not Python's file:line + source
