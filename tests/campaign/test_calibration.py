"""The calibration protocol: its file is validated, its bisection finds the bracket, its lab is written.

The physics is replaced here by a run whose stability is a known step in the parameter
(unstable from 0.6 ms at f_c = 150 Hz and from 1.4 ms at 100 Hz), so the bisection's result
is known in closed form: onsets within the resolution, value = their midpoint.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest

import impedance_mil
from impedance_mil.campaign import calibration
from impedance_mil.campaign.kinds import get_kind
from impedance_mil.config import quantity, read_toml
from impedance_mil.errors import ConfigError
from impedance_mil.lab.labfile import load_lab

ONSET_MS = {150.0: 0.6, 100.0: 1.4}
TABLE_4_1 = Path(impedance_mil.__file__).parent / "data" / "tables" / "report_table_4_1.toml"

LAB = """
[table]
file = "{table}"
[limits]
stroke = "3 in"
[sensors]
[sensors.lc]
quantity = "load_cell"
range = "2000 lbf"
[sensors.accel]
quantity = "acceleration"
range = "4 g0"
[controller]
loop_time = "0.5 ms"
"""

PROTOCOL = """
[calibration]
claim = "sec8-fc-instability"
lab = "base.toml"
why = "test"
[parameter]
name = "force-channel delay"
keys = ["sensors.lc.delay"]
unit = "ms"
min = "0 ms"
max = "{max}"
resolution = "0.01 ms"
source = "a datasheet"
[observation]
kind = "tracking"
set = {{ water_depth = "42 in", motion = "GM1" }}
vary = "f_c"
stable = "100 Hz"
unstable = "150 Hz"
"""


def fake_run(config, out_path):
    # The calibrated key is written into the lab file the run is given; read it back.
    lab = read_toml(config["lab"])
    value_ms = quantity("lc", lab["sensors"]["lc"]["delay"], "ms")
    unstable = value_ms >= ONSET_MS[config["controller"]["fc_hz"]]
    # below the onset the oscillation grows with the value, as it does towards an instability
    return {"hf_ratio": 2.0 if unstable else 0.1 + 0.1 * value_ms, "aborted": False}


@pytest.fixture
def protocol(tmp_path, monkeypatch):
    (tmp_path / "base.toml").write_text(LAB.format(table=TABLE_4_1.as_posix()))
    path = tmp_path / "protocol.toml"
    path.write_text(PROTOCOL.format(max="2 ms"))
    kind = replace(get_kind("tracking"), run=fake_run)
    monkeypatch.setattr(calibration, "get_kind", lambda name: kind)
    return path


def test_bisection_finds_both_onsets_and_takes_their_midpoint(protocol, tmp_path):
    result = calibration.calibrate(calibration.load_protocol(protocol), tmp_path / "out")
    assert result.onset_unstable == pytest.approx(0.6, abs=0.01)
    assert result.onset_stable == pytest.approx(1.4, abs=0.01)
    assert result.value == pytest.approx(1.0, abs=0.01) and result.reproduced
    record = json.loads((tmp_path / "out" / "calibration.json").read_text())
    assert record["claim"] == "sec8-fc-instability" and record["reproduced"] is True
    assert len(record["evaluations"]) == len(result.evaluations) <= 2 * 10 + 4
    # The calibrated lab reads back, names the claim, and holds the value.
    lab = read_toml(tmp_path / "out" / "calibrated-lab.toml")
    assert quantity("v", lab["sensors"]["lc"]["delay"], "ms") == pytest.approx(result.value, rel=1e-5)
    assert lab["calibration"]["claim"] == "sec8-fc-instability"


def test_a_range_that_cannot_reproduce_the_observation_says_so_and_keeps_its_end(protocol, tmp_path):
    protocol.write_text(PROTOCOL.format(max="0.5 ms"))
    result = calibration.calibrate(calibration.load_protocol(protocol), tmp_path / "out")
    # the high end is the nearer to the observation: its hf_ratio (0.15) exceeds the low end's (0.1)
    assert not result.reproduced and result.value == pytest.approx(0.5) and result.onset_unstable is None
    assert "not reproduced" in result.note and "0.15" in result.note


def test_the_calibration_record_is_read_with_the_lab(tmp_path):
    text = (
        'claim = "sec8-fc-instability"\nparameter = "p"\nkeys = ["a.b"]\nvalue = "1 ms"\nreproduced = true\n'
    )
    base = LAB.format(table=TABLE_4_1.as_posix()) + "\n[calibration]\n" + text
    (tmp_path / "lab.toml").write_text(base + 'protocol = "p.toml"\n')
    record = load_lab(tmp_path / "lab.toml").calibration
    assert record is not None and record.claim == "sec8-fc-instability" and record.reproduced
    (tmp_path / "lab.toml").write_text(base)
    with pytest.raises(ConfigError, match="calibration.protocol"):
        load_lab(tmp_path / "lab.toml")


@pytest.mark.parametrize(
    ("old", "new", "key"),
    [
        ('claim = "sec8-fc-instability"', 'claim = "no-such-claim"', "calibration.claim"),
        ('lab = "base.toml"', 'lab = "missing.toml"', "calibration.lab"),
        ('min = "0 ms"', 'min = "0 lbf"', "parameter.min"),
        ('max = "{max}"', 'max = "0 ms"', "parameter.max"),
        ('keys = ["sensors.lc.delay"]', 'keys = ["delay"]', "parameter.keys"),
        ('kind = "tracking"', 'kind = "design"', "observation.kind"),
        ('vary = "f_c"', 'vary = "water_depth"', "observation.vary"),
        ('stable = "100 Hz"', 'stable = "100 in"', "observation.stable"),
    ],
)
def test_a_bad_protocol_is_refused_naming_the_key(protocol, old, new, key):
    protocol.write_text(PROTOCOL.replace(old, new).format(max="2 ms"))
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
        calibration.load_protocol(protocol)


def test_lab_with_creates_tables_below_an_existing_section_only():
    base = {"sensors": {"preset": "table-7.1"}}
    out = calibration.lab_with(base, ("sensors.LC-03.delay", "sensors.LC-06.delay"), "0.3 ms")
    assert out["sensors"]["LC-03"] == {"delay": "0.3 ms"} and out["sensors"]["LC-06"] == {"delay": "0.3 ms"}
    assert base == {"sensors": {"preset": "table-7.1"}}  # a copy
    with pytest.raises(ConfigError, match="dynamics.valve.x"):
        calibration.lab_with(base, ("dynamics.valve.x",), "1")
    with pytest.raises(ConfigError, match="preset"):
        calibration.lab_with(base, ("sensors.preset.x",), "1")
