"""The TOML writer: what it writes reads back as the same data (independent reader: tomllib)."""

from __future__ import annotations

import math
import tomllib

import pytest

from impedance_mil.config import read_toml
from impedance_mil.errors import ConfigError
from impedance_mil.lab.labfile import REPORT_CONFIG_PATH
from impedance_mil.tomlwrite import toml_text


def test_round_trip_of_nested_tables_arrays_and_quoted_keys():
    data = {
        "units": "si",
        "table": {"file": "a b.toml", "mid_stroke": "150 mm", "K_e": 5.0, "n": 3, "on": True},
        "sensors": {"clipping": "warn", "LC-03": {"share": -0.25, "delay": "0.5 ms"}, "x y": {"q": 'a"b'}},
        "dynamics": {"platen": {"frequency": "80 Hz"}, "valve": {"rates": [1.5, 2, "3 Hz"]}},
        "uncertainty": {"d": {"min": 9e4, "max": "1.1e5 psi/s/mA"}},
    }
    assert tomllib.loads(toml_text(data, "a header\n\nline two")) == data


def test_the_report_lab_reads_back_unchanged():
    data = read_toml(REPORT_CONFIG_PATH)
    assert tomllib.loads(toml_text(data)) == data


def test_a_value_toml_cannot_hold_is_refused_naming_the_key():
    with pytest.raises(ConfigError, match="table.x"):
        toml_text({"table": {"x": math.nan}})
    with pytest.raises(ConfigError, match="table.y"):
        toml_text({"table": {"y": object()}})
