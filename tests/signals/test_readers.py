"""Ground-motion readers: PEER AT2, two-column/CSV, built-in records, malformed files."""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from impedance_mil.errors import ConfigError, DataFileError
from impedance_mil.signals import (
    BUILTIN_MOTIONS,
    GroundMotion,
    builtin_motion,
    read_at2,
    read_columns,
    read_motion,
    readers,
    write_columns,
)
from impedance_mil.units import G0

AT2_NGAW2 = """PEER NGA STRONG MOTION DATABASE RECORD
Test record, component 000
ACCELERATION TIME SERIES IN UNITS OF G
NPTS=      7, DT=   .0050 SEC,
   .1000000E-01  -.2000000E-01   .3000000E-01   .4000000E-01  -.5000000E-01
   .6000000E-01   .0000000E+00
"""

AT2_OLD = """PEER STRONG MOTION DATABASE RECORD. PROCESSING BY PACIFIC ENGINEERING.
TEST 01/01/01, STATION, 090
ACCELERATION TIME HISTORY IN UNITS OF G
 7    .00500   NPTS, DT
 .01 -.02 .03 .04
 -.05 .06 0.
"""

SAMPLES_G = np.array([0.01, -0.02, 0.03, 0.04, -0.05, 0.06, 0.0])


def _write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("text", [AT2_NGAW2, AT2_OLD], ids=["ngaw2-header", "old-header"])
def test_at2_both_header_forms(tmp_path, text):
    # Values written in the file (g) times g0 = 386.089 in/s^2; exact up to float rounding.
    motion = read_at2(_write(tmp_path, "rec.AT2", text))
    assert motion.npts == 7
    assert motion.time_step == pytest.approx(0.005, rel=1e-15)
    np.testing.assert_allclose(motion.accel, SAMPLES_G * G0, rtol=1e-15)
    assert motion.pga_g == pytest.approx(0.06, rel=1e-15)


def test_read_motion_detects_at2_without_suffix(tmp_path):
    motion = read_motion(_write(tmp_path, "record.txt", AT2_NGAW2))
    assert motion.npts == 7


def test_at2_crlf_and_d_exponents(tmp_path):
    text = AT2_NGAW2.replace(".1000000E-01", ".1000000D-01").replace("\n", "\r\n")
    path = tmp_path / "crlf.AT2"
    path.write_bytes(text.encode())
    np.testing.assert_allclose(read_at2(path).accel, SAMPLES_G * G0, rtol=1e-15)


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("", "empty file"),
        ("   \n\n", "empty file"),
        ("a\nb\n", "truncated"),
        (AT2_NGAW2.replace("NPTS=      7", "NPTS=      8"), "NPTS = 8 but the file holds 7"),
        (AT2_NGAW2.replace("NPTS=      7", "NPTS=      6"), "NPTS = 6 but the file holds 7"),
        (AT2_NGAW2.replace("DT=   .0050", "DT=   -.0050"), "DT must be positive"),
        (AT2_NGAW2.replace("DT=   .0050", "DT=   .0000"), "DT must be positive"),
        (AT2_NGAW2.replace("-.2000000E-01", "abc"), "line 5: non-numeric token 'abc'"),
        (AT2_NGAW2.replace("-.2000000E-01", "NaN"), "line 5: NaN sample"),
        (AT2_NGAW2.replace("NPTS=      7, DT=   .0050 SEC,", "no numbers here"), "line 4"),
        (AT2_NGAW2.replace("UNITS OF G", "UNITS OF CM/S/S"), "expected accelerations in units of g"),
        (AT2_NGAW2.replace("ACCELERATION", "VELOCITY"), "expected an acceleration"),
    ],
)
def test_malformed_at2_names_file_and_problem(tmp_path, text, needle):
    path = _write(tmp_path, "bad.AT2", text)
    with pytest.raises(DataFileError) as info:
        read_motion(path)
    message = str(info.value)
    assert message.startswith(str(path)) and needle in message
    assert "\n" not in message


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(DataFileError, match="file not found"):
        read_motion(tmp_path / "nope.AT2")
    with pytest.raises(DataFileError, match="is a directory"):
        read_motion(tmp_path)


def test_columns_csv_with_header_and_units(tmp_path):
    rows = "\n".join(f"{0.01 * k:.2f},{a}" for k, a in enumerate(SAMPLES_G * 9.80665))
    path = _write(tmp_path, "rec.csv", "# comment\ntime_s,accel_m_s2\n" + rows + "\n")
    motion = read_columns(path, units="m/s**2")
    # m/s^2 -> in/s^2 is exactly 1/0.0254; the samples were written in full precision.
    np.testing.assert_allclose(motion.accel, SAMPLES_G * G0, rtol=1e-12)
    assert motion.time_step == pytest.approx(0.01, rel=1e-12)


def test_columns_whitespace_without_header_shifted_start(tmp_path):
    rows = "\n".join(f"{1.5 + 0.02 * k:.3f}\t{a}" for k, a in enumerate(SAMPLES_G))
    motion = read_motion(_write(tmp_path, "rec.txt", rows), units="g")
    np.testing.assert_allclose(motion.accel, SAMPLES_G * G0, rtol=1e-15)
    assert motion.time[0] == 0.0 and "t0 = 1.5" in motion.source


def test_columns_rounded_times_are_uniform(tmp_path):
    # dt = 1/300 s printed with 5 decimals: rounding error < 0.2 % of dt, inside the 1 % tolerance.
    rows = "\n".join(f"{k / 300:.5f} {a}" for k, a in enumerate(SAMPLES_G))
    motion = read_motion(_write(tmp_path, "rec.dat", rows), units="g")
    assert motion.time_step == pytest.approx(1 / 300, rel=1e-5)


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("0 0.1\n0.01 0.2\n0.01 0.3\n", "not strictly increasing"),
        ("0 0.1\n0.02 0.2\n0.01 0.3\n", "not strictly increasing"),
        ("0 0.1\n0.01 0.2\n0.03 0.3\n0.04 0.1\n", "not uniformly sampled"),
        ("0 0.1\n0.01 nan\n0.02 0.3\n", "line 2: non-finite"),
        ("0 0.1\n0.01 x\n0.02 0.3\n", "line 2: non-numeric token 'x'"),
        ("0 0.1\n0.01 0.2 0.5\n", "line 2: expected 2 columns"),
        ("time,accel\n", "no data"),
        ("0 0.1\n", "only one sample"),
    ],
)
def test_malformed_columns(tmp_path, text, needle):
    path = _write(tmp_path, "bad.csv", text)
    with pytest.raises(DataFileError) as info:
        read_motion(path)
    assert str(info.value).startswith(str(path)) and needle in str(info.value)


def test_bad_units(tmp_path):
    path = _write(tmp_path, "rec.csv", "0 0.1\n0.01 0.2\n")
    with pytest.raises(ConfigError, match="units"):
        read_motion(path, units="in")  # a length, not an acceleration
    with pytest.raises(ConfigError, match="units"):
        read_motion(_write(tmp_path, "rec.AT2", AT2_NGAW2), units="m/s**2")


@pytest.mark.parametrize(
    ("head", "unit"),
    [
        ("time,accel[g]\n", "g"),
        ("time, acc (m/s**2)\n", "m/s**2"),
        ("time_s,accel_cm/s**2\n", "cm/s**2"),
        ("# units: m/s**2\ntime,accel\n", "m/s**2"),
        ("# unit = g\n", "g"),
        ("time_s,a_g_g\n", "g"),  # as imil drive motion writes it: <channel>_<unit>
    ],
)
def test_columns_stated_unit_is_used(tmp_path, head, unit):
    factor = {"g": 1.0, "m/s**2": 9.80665, "cm/s**2": 980.665}[unit]  # value in `unit` of 1 g (exact)
    rows = "\n".join(f"{0.01 * k:.2f},{a:.17g}" for k, a in enumerate(SAMPLES_G * factor))
    motion = read_motion(_write(tmp_path, "rec.csv", head + rows + "\n"))
    np.testing.assert_allclose(motion.accel, SAMPLES_G * G0, rtol=1e-12)
    # The same unit given again is accepted; another is refused, naming the key and the file's unit.
    assert read_motion(tmp_path / "rec.csv", units=unit).npts == motion.npts
    other = "in/s**2"
    with pytest.raises(ConfigError, match=rf"^--motion-units: expected {re.escape(unit)} as rec.csv states"):
        read_motion(tmp_path / "rec.csv", units=other, key="--motion-units")


def test_columns_without_unit_are_refused_unless_given(tmp_path):
    # A column name that is no unit (accel_m_s2) states none: the reader does not guess g.
    path = _write(tmp_path, "rec.csv", "time_s,accel_m_s2\n0,0.1\n0.01,0.2\n")
    with pytest.raises(
        ConfigError, match=r"^--motion-units: expected the unit of the accelerations of rec.csv"
    ):
        read_motion(path, key="--motion-units")
    assert read_motion(path, units="m/s**2").accel[0] == pytest.approx(0.1 / 0.0254, rel=1e-12)


def test_columns_units_comment_must_be_an_acceleration(tmp_path):
    path = _write(tmp_path, "rec.csv", "# units: parsec\n0,0.1\n0.01,0.2\n")
    with pytest.raises(DataFileError, match="line 1 states 'parsec': not an acceleration unit"):
        read_motion(path, units="g")


def test_builtin_elcentro_matches_report_table_8_1():
    # Report Table 8.1: GM1 seed, Imperial Valley-02 1940 NS (RSN 6), original PGA 0.28 g
    # (printed to 2 digits, so +-0.005 g).  Header of the shipped PEER file: 5372 points at 0.01 s.
    motion = builtin_motion("elcentro")
    assert motion.npts == 5372 and motion.time_step == 0.01
    assert motion.pga_g == pytest.approx(0.28, abs=0.005)
    assert "RSN 6" in motion.name


def test_builtin_chopra_record():
    # Chopra, Dynamics of Structures, Appendix 6: El Centro NS, dt 0.02 s, PGA 0.319 g (3 digits).
    motion = builtin_motion("elcentro-chopra")
    assert motion.time_step == pytest.approx(0.02, rel=1e-9)
    assert motion.pga_g == pytest.approx(0.319, abs=0.0005)


def test_builtin_unknown_name():
    with pytest.raises(ConfigError, match="elcentro"):
        builtin_motion("kobe")
    assert set(BUILTIN_MOTIONS) >= {"elcentro"}


_samples = st.lists(st.floats(-2.0, 2.0, allow_nan=False, allow_subnormal=False), min_size=2, max_size=60)


@settings(max_examples=30, deadline=None)
@given(samples=_samples, dt=st.sampled_from([0.0005, 0.005, 0.01, 0.02, 1 / 3]))
def test_write_read_round_trip(tmp_path_factory, samples, dt):
    # write_columns prints 10 significant digits: values and dt come back to 1e-9 relative.
    motion = GroundMotion(dt, np.array(samples) * G0, "rt", "hypothesis")
    path = tmp_path_factory.mktemp("rt") / "m.csv"
    back = read_motion(write_columns(motion, path))
    assert back.npts == motion.npts and back.time_step == pytest.approx(dt, rel=1e-9)
    np.testing.assert_allclose(back.accel, motion.accel, rtol=1e-9, atol=1e-12)


@settings(max_examples=30, deadline=None)
@given(samples=_samples, per_line=st.integers(1, 8))
def test_at2_any_layout_round_trip(tmp_path_factory, samples, per_line):
    # The AT2 reader ignores line layout: any number of samples per line gives the same record.
    values = np.array(samples)
    lines = [" ".join(f"{v:.7E}" for v in values[i : i + per_line]) for i in range(0, values.size, per_line)]
    text = f"h\nrec\nACCELERATION IN G\nNPTS= {values.size}, DT= .0100 SEC\n" + "\n".join(lines) + "\n"
    path = tmp_path_factory.mktemp("at2") / "r.AT2"
    path.write_text(text)
    np.testing.assert_allclose(
        read_at2(path).accel, np.array([float(f"{v:.7E}") for v in values]) * G0, rtol=1e-15
    )


def test_the_column_reader_parses_at_once_exactly_as_line_by_line(tmp_path):
    # numpy's C reader (the fast path) against the line-by-line parser (Python float):
    # the same values bit for bit, with commas, semicolons, tabs, Fortran D exponents,
    # blank lines, comments and a header.
    rng = np.random.default_rng(3)
    accel = rng.normal(scale=0.3, size=2000)
    lines = ["time [s], accel [g]", "# a comment"]
    for k, a in enumerate(accel):
        sep = (", ", ";", "\t", "  ")[k % 4]
        value = f"{a:.15E}".replace("E", "D") if k % 5 == 0 else repr(float(a))
        lines.append(f"{k * 0.005!r}{sep}{value}")
        if k % 97 == 0:
            lines += ["", "# inside"]
    fast, first = readers._column_rows(tmp_path / "m.csv", lines)
    slow, first_slow = readers._column_rows_by_line(tmp_path / "m.csv", lines)
    assert first == first_slow == 3 and fast.shape == (2000, 2)
    np.testing.assert_array_equal(fast, slow)


@pytest.mark.parametrize(
    "bad, what",
    [("0.01 nan", "non-finite"), ("0.01 2 3", "expected 2 columns"), ("0.01 x", "non-numeric")],
)
def test_a_bad_row_after_the_header_is_named_by_its_line(tmp_path, bad, what):
    # the fast path does not take it; the line-by-line reader names line 4
    lines = ["t a", "0 0.1", "0.005 0.2", bad, "0.015 0.3"]
    with pytest.raises(DataFileError, match=f"line 4: {what}"):
        readers._column_rows(tmp_path / "m.csv", lines)
