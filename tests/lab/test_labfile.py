"""The lab file (issue 12): the report's lab is today's setup, a user's lab is taken as written.

References: the report lab must equal the setup runs used before lab files
existed (SafetyLimits(stroke=3, velocity=40) and the Table 7.1 loop channels,
exact); unit conversions are exact closed forms (150 mm = 5.905... in).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.lab.clipping import clipped_channels
from impedance_mil.lab.lab_units import LAB_OBJECTS
from impedance_mil.lab.labfile import load_lab
from impedance_mil.lab.setup import SafetyLimits, default_sensors
from impedance_mil.plant import TableParameters, default_table_path
from impedance_mil.plausibility import PlausibilityWarning
from impedance_mil.report_config import REPORT_CONFIG_PATH

TABLE = default_table_path()


def _lab(tmp_path, text: str):
    path = tmp_path / "lab.toml"
    path.write_text(f'[table]\nfile = "{TABLE}"\n' + text)
    return path


def test_report_lab_is_the_setup_of_every_earlier_run():
    lab = load_lab("report")
    assert lab.limits == SafetyLimits(stroke=3.0, velocity=40.0)
    assert lab.sensors.suite.sensors == default_sensors().sensors
    assert lab.table == TableParameters.from_toml(TABLE)
    assert lab.is_report


def test_limits_sensors_and_specimen_are_taken_as_written_in_si(tmp_path):
    path = _lab(
        tmp_path,
        '[limits]\nstroke = "50 mm"\nvelocity = "1 m/s"\nacceleration = "2 g0"\npressure = "200 bar"\n'
        '[sensors]\nclipping = "fail"\n'
        '[sensors.lvdt]\nquantity = "displacement"\nrange = "75 mm"\nresolution = "0.01 mm"\n'
        '[sensors.acc]\nquantity = "acceleration"\nrange = "5 g0"\nnoise = "0.01 g0"\n'
        '[sensors.dp]\nquantity = "differential_pressure"\nrange = "250 bar"\n'
        '[sensors.lc]\nquantity = "load_cell"\nrange = "50 kN"\n'
        '[specimen]\nkind = "rigid"\narticle_weight = "2000 kg"\n',
    )
    lab = load_lab(path)
    assert lab.limits.stroke == pytest.approx(50 / 25.4, rel=1e-14)
    assert lab.limits.velocity == pytest.approx(1000 / 25.4, rel=1e-14)
    assert lab.limits.acceleration == pytest.approx(2 * 9.80665 / 0.0254, rel=1e-12)
    assert lab.limits.pressure == pytest.approx(200e5 / 6894.757293168361, rel=1e-12)
    assert lab.sensors.clipping == "fail"
    lvdt = lab.sensors.suite.sensors[0]
    # 0.01 mm over +-75 mm needs 15000 codes: 14 bits.
    assert lvdt.adc_bits == 14
    assert lvdt.value_range[1] == pytest.approx(75 / 25.4, rel=1e-3)
    acc = lab.sensors.suite.sensors[1]
    assert abs(acc.scale) * acc.noise_rms_v == pytest.approx(0.01 * 9.80665 / 0.0254, rel=1e-12)
    assert lab.specimen.article_weight == pytest.approx(2000 / 0.45359237, rel=1e-12)
    assert "limits.stroke" not in lab.defaults and "limits.divergence" in lab.defaults
    json.dumps(lab.to_dict())


def test_a_bare_table_takes_generic_defaults_not_the_reports(tmp_path):
    lab = load_lab(table=TABLE)
    params = TableParameters.from_toml(TABLE)
    assert lab.limits.stroke == params.mid_stroke  # generic: the table's mid-stroke, not 3 in
    dp = params.supply_pressure - params.return_pressure
    assert lab.limits.velocity == pytest.approx(
        params.rated_flow * math.sqrt(dp / params.rated_pressure_drop) / params.piston_area, rel=1e-14
    )
    assert lab.specimen.kind == "none"
    assert "sensors" in lab.defaults and "limits.stroke" in lab.defaults


@pytest.mark.parametrize(
    "text, key",
    [
        ("[limit]\nstroke = 1\n", "[limit]"),
        ("[limits]\nstrok = 1\n", "limits.strok"),
        ('[limits]\nstroke = "-1 in"\n', "limits.stroke"),
        ('[limits]\nstroke = "5 in"\n', "limits.stroke"),  # beyond the 3.2 in mid-stroke
        (
            '[sensors.x]\nquantity = "displacement"\nrange = "1 in"\nresolution = "2 in"\n',
            "sensors.x.resolution",
        ),
        (
            '[sensors.x]\nquantity = "displacement"\nrange = "1 in"\nbandwidth = "-1 kHz"\n',
            "sensors.x.bandwidth",
        ),
        (
            '[sensors.x]\nquantity = "displacement"\nrange = "1 in"\nbandwidth = "1 kHz"\nfilter_order = 4\n',
            "sensors.x.filter_order",
        ),
        (
            '[sensors.x]\nquantity = "displacement"\nrange = "1 in"\nfilter_order = 2\n',
            "sensors.x.filter_order",
        ),
        ('[controller]\noutput_delay = "700 us"\n', "controller.output_delay"),
        ("[controller]\noutput_delay = 0\n", "controller.output_delay"),
        ('[controller]\noutput_delay = "2.5 loops"\n', "controller.output_delay"),
        ('[limits]\nvalve_command = "12 V"\n', "limits.valve_command"),
        ('[specimen]\narticle_weight = "3 in"\n', "specimen.article_weight"),
    ],
)
def test_bad_lab_files_name_the_section_and_key(tmp_path, text, key):
    with pytest.raises(ConfigError) as err:
        load_lab(_lab(tmp_path, text))
    assert key in str(err.value)
    assert "\n" not in str(err.value)


def test_a_channel_beyond_its_range_is_found(tmp_path):
    lab = load_lab(_lab(tmp_path, '[sensors.lc]\nquantity = "load_cell"\nrange = "1000 lbf"\n'))
    t = np.arange(5) * 0.1
    w = np.array([0.0, 500.0, 1200.0, -1500.0, 10.0])
    found = clipped_channels(lab.sensors.suite, {"t": t, "w": w})
    assert [(c.name, c.samples, c.first_time_s, c.peak) for c in found] == [("lc", 2, 0.2, -1500.0)]
    assert clipped_channels(lab.sensors.suite, {"t": t, "w": w / 2}) == []


def test_a_table_file_with_lab_sections_is_read_as_a_lab_not_ignored(tmp_path):
    # Issue 12: "A [limits] section in the table file is silently ignored."
    path = _lab(tmp_path, '[limits]\nstroke = "2 in"\n')
    assert load_lab(table=path).limits.stroke == 2.0
    bogus = _lab(tmp_path, "[bogus]\nx = 1\n")
    with pytest.raises(ConfigError, match=r"\[bogus\]"):
        load_lab(table=bogus)


def test_a_channel_takes_an_anti_alias_filter(tmp_path):
    lab = load_lab(
        _lab(tmp_path, '[sensors.x]\nquantity = "displacement"\nrange = "1 in"\nbandwidth = "0.2 kHz"\n')
    )
    (x,) = lab.sensors.suite.sensors
    assert (x.bandwidth_hz, x.filter_order) == (200.0, 2)
    doc = lab.to_dict()["sensors"]["channels"][0]
    assert (doc["bandwidth"], doc["filter_order"]) == (200.0, 2)
    plain = load_lab(_lab(tmp_path, '[sensors.x]\nquantity = "displacement"\nrange = "1 in"\n'))
    assert plain.sensors.suite.sensors[0].bandwidth_hz is None


def test_a_bandwidth_at_or_above_nyquist_is_a_warning_not_a_refusal(tmp_path):
    # The report's loop of 500 us: Nyquist 1000 Hz.
    text = '[sensors.x]\nquantity = "displacement"\nrange = "1 in"\nbandwidth = "1 kHz"\nfilter_order = 1\n'
    with pytest.warns(
        PlausibilityWarning, match=r"sensors\.x\.bandwidth: 1000 Hz .* Nyquist frequency \(1000 Hz\)"
    ):
        lab = load_lab(_lab(tmp_path, text))
    assert lab.sensors.suite.sensors[0].filter_order == 1


@pytest.mark.parametrize("value, loops", [(2, 2), ('"3 loops"', 3), ('"1 loop"', 1), ('"1.5 ms"', 3)])
def test_the_output_delay_is_a_whole_number_of_loops(tmp_path, value, loops):
    lab = load_lab(_lab(tmp_path, f"[controller]\noutput_delay = {value}\n"))
    assert lab.controller.output_delay == loops
    assert (
        lab.table.output_delay_loops == loops
    )  # the linear models of the lab's table are delayed as its runs


def test_controller_io_units_are_taken_as_written(tmp_path):
    # The units of the exported code (imil export --lab); 1 kN = 1000 / (0.45359237 * 9.80665) lbf.
    lab = load_lab(_lab(tmp_path, '[controller]\nio_units = {accel = "m/s**2", force = "kN", disp = "mm"}\n'))
    io = lab.controller.io_units
    assert io.force.to_internal == pytest.approx(1000 / (0.45359237 * 9.80665), rel=1e-15)
    assert io.disp.from_internal == pytest.approx(25.4, rel=1e-15)
    assert lab.to_dict()["controller"]["io_units"] == "accel=m/s**2,force=kN,disp=mm"
    assert lab.sources["controller.io_units"] == "file"
    assert (
        load_lab(_lab(tmp_path, '[controller]\nio_units = "si"\n')).to_dict()["controller"]["io_units"]
        == "si"
    )
    bare = load_lab(table=TABLE)
    assert bare.controller.io_units.is_internal and "controller.io_units" in bare.defaults
    assert load_lab("report").controller.io_units.is_internal


@pytest.mark.parametrize(
    "value, key",
    [
        ('"si,force=mm"', "controller.io_units force"),
        ('{accel = "g", force = "N", disp = "mm"}', "controller.io_units accel"),
        ('{accel = "m/s**2", force = "N"}', "controller.io_units disp"),
        ("3", "controller.io_units"),
    ],
)
def test_bad_io_units_name_the_key(tmp_path, value, key):
    with pytest.raises(ConfigError) as err:
        load_lab(_lab(tmp_path, f"[controller]\nio_units = {value}\n"))
    assert str(err.value).startswith(f"lab.toml: {key}:")
    assert "\n" not in str(err.value)


def _at(doc, path):
    for part in path.split("."):
        doc = doc[part]
    return doc


def test_lab_objects_are_the_optional_sections_of_the_document(tmp_path):
    # lab_units.LAB_OBJECTS lets the JSON units block pass these paths without the VS registry
    # (issue 16, start-up): each must be an object when the lab has the section, null when not.
    full = load_lab(
        _lab(
            tmp_path,
            '[uncertainty]\nf_oil_hz = "±5 %"\n'
            "[dynamics.platen]\nmodal_mass = 0.2\nfrequency = 150\n"
            "[dynamics.load_cells]\nstiffness = 2e6\n",
        )
    ).to_dict()
    calibrated = load_lab(
        REPORT_CONFIG_PATH.parents[1] / "labs/calibrated-footnote22/calibrated-lab.toml"
    ).to_dict()
    report = load_lab("report").to_dict()
    for path in LAB_OBJECTS:
        given = _at(calibrated if path == "calibration" else full, path)
        assert isinstance(given, dict) and given, path
        assert _at(report, path) is None, path
