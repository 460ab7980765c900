"""The lab file's ``[uncertainty]`` set (issue 17, item 3): parsing by dimension, bad input, sampling.

Reference values are closed-form: a ``±10 %`` range of the report's 27 Hz
oil column is 24.3-29.7 Hz; 0.5 ms is one loop of the report's 500 us loop.
"""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.lab.labfile import load_lab
from impedance_mil.plant import TableParameters, default_table_path
from impedance_mil.plant.uncertainty import parse_uncertainty

P = TableParameters.report_default()


def test_relative_and_absolute_ranges_by_dimension():
    box = parse_uncertainty(
        {
            "f_oil_hz": "±10 %",
            "zeta_oil": {"min": 0.05, "max": "20 %"},
            "d": {"min": "9e4 psi/s/mA", "max": 1.1e5},
            "valve_poles_hz": "+-20 %",
            "extra_delay": {"min": "0 loops", "max": "0.5 ms"},
        },
        P,
    )
    r = {x.key: x for x in box.ranges}
    assert (r["f_oil_hz"].low, r["f_oil_hz"].high) == pytest.approx((24.3, 29.7), rel=1e-12)
    assert (r["zeta_oil"].low, r["zeta_oil"].high) == pytest.approx((0.05, 0.2))
    assert (r["d"].low, r["d"].high) == pytest.approx((9e4, 1.1e5))
    assert (r["extra_delay"].low, r["extra_delay"].high) == (0.0, 1.0)
    table = box.apply(P, {"valve_poles_hz": 0.8, "extra_delay": 1.0})
    assert table.valve_poles_hz == pytest.approx(tuple(0.8 * f for f in P.valve_poles_hz))
    assert table.output_delay_loops == P.output_delay_loops + 1


def test_vertices_and_latin_hypercube():
    box = parse_uncertainty({"f_oil_hz": "±10 %", "zeta_oil": {"min": 0.05, "max": 0.2}}, P)
    assert len(box.vertices()) == 4
    sample = box.latin_hypercube(8, seed=3)
    assert sample == box.latin_hypercube(8, seed=3)  # reproducible from the seed
    for r in box.ranges:  # one point in each of the 8 strata of every range (the LHS invariant)
        u = np.array([(p[r.key] - r.low) / (r.high - r.low) for p in sample])
        assert sorted(np.floor(u * 8).astype(int)) == list(range(8))
    delays = parse_uncertainty({"extra_delay": {"min": 0, "max": 2}}, P).latin_hypercube(9, 0)
    assert sorted({p["extra_delay"] for p in delays}) == [0.0, 1.0, 2.0]  # whole loops, each a third


def test_degenerate_range_is_one_vertex():
    box = parse_uncertainty({"f_oil_hz": {"min": "27 Hz", "max": "27 Hz"}}, P)
    assert box.vertices() == [{"f_oil_hz": P.f_oil_hz}]


@pytest.mark.parametrize(
    ("section", "key", "words"),
    [
        ({"bulk": "±10 %"}, "uncertainty.bulk", "one of the keys"),
        ({"f_oil_hz": {"min": "1 in", "max": "2 in"}}, "uncertainty.f_oil_hz.min", "dimension of hertz"),
        ({"f_oil_hz": {"min": 30, "max": 20}}, "uncertainty.f_oil_hz", "min <= max"),
        ({"f_oil_hz": {"min": 20, "mx": 30}}, "uncertainty.f_oil_hz.mx", "min = ..., max = ..."),
        ({"f_oil_hz": "±100 %"}, "uncertainty.f_oil_hz", "below 100 %"),
        ({"f_oil_hz": "10 %"}, "uncertainty.f_oil_hz", "±10 %"),
        ({"zeta_oil": {"min": 0.5, "max": 1.2}}, "uncertainty.zeta_oil", "below 1"),
        (
            {"extra_delay": {"min": 0, "max": "0.3 ms"}},
            "uncertainty.extra_delay.max",
            "whole number of loops",
        ),
        ({"extra_delay": "±10 %"}, "uncertainty.extra_delay", "loops"),
        ({"valve_poles_hz": {"min": 50, "max": 60}}, "uncertainty.valve_poles_hz", "relative range"),
        ({"valve_damping": "±10 %"}, "uncertainty.valve_damping", "two-pole"),
        ({"f_oil_hz": {"min": 0, "max": 30}}, "uncertainty.f_oil_hz", "valid table"),
    ],
)
def test_bad_ranges_are_refused_naming_the_key(section, key, words):
    with pytest.raises(ConfigError) as err:
        parse_uncertainty(section, P)
    assert err.value.key == key
    assert words in str(err.value)


def test_lab_file_section_and_lab_check(tmp_path, imil):
    lab = tmp_path / "lab.toml"
    lab.write_text(f'[table]\nfile = "{default_table_path()}"\n[uncertainty]\nf_oil_hz = "±5 %"\n')
    setup = load_lab(lab)
    assert setup.uncertainty is not None and setup.uncertainty.keys == ("f_oil_hz",)
    assert load_lab("report").uncertainty is None
    lab.write_text(f'[table]\nfile = "{default_table_path()}"\n[uncertainty]\nf_oil = "±5 %"\n')
    r = imil("lab", "check", lab)
    assert r.returncode == 2
    assert r.stderr.strip().count("\n") == 0 and "uncertainty.f_oil" in r.stderr
    assert "Traceback" not in r.stderr
