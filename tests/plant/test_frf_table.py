"""The measured-FRF table file (plant/frf_table.py): units by dimension, both column forms, refusals."""

import numpy as np
import pytest

from impedance_mil.config import read_toml
from impedance_mil.errors import ConfigError, DataFileError
from impedance_mil.plant.frf_table import FRFTable, read_frf_table, write_frf_table

#: SI units of the signals (the conversion the reader must undo).
SI = {"z": "m/s**2", "u": "mm", "w": "kN"}

#: Exact conversion factors (NIST SP 811: 1 in = 0.0254 m, 1 lbf = 4.4482216152605 N).
M_PER_IN, KN_PER_LBF = 0.0254, 4.4482216152605e-3


def small_table(**changes) -> FRFTable:
    f = np.array([0.5, 1.0, 2.0, 4.0])
    kw = dict(
        frequency_hz=f,
        H_zu=(2j * np.pi * f) ** 2 * 0.8,
        H_zw=np.full(4, 0.25 + 0.01j),
        loop_time_s=5e-4,
        coherence_zu=np.array([0.9, 0.95, 1.0, 0.99]),
        coherence_zw=None,
    )
    kw.update(changes)
    return FRFTable(**kw)


def test_si_files_round_trip_to_internal_units(tmp_path):
    table = small_table()
    path = write_frf_table(table, tmp_path / "frf.toml", SI, header=("test table",))
    back = read_frf_table(path)
    np.testing.assert_allclose(back.H_zu, table.H_zu, rtol=1e-14)  # repr() keeps every digit
    np.testing.assert_allclose(back.H_zw, table.H_zw, rtol=1e-14)
    np.testing.assert_array_equal(back.frequency_hz, table.frequency_hz)
    np.testing.assert_array_equal(back.coherence_zu, table.coherence_zu)
    assert back.coherence_zw is None and back.loop_time_s == 5e-4 and back.source == path
    # The CSV really holds SI numbers: H_zw = 0.25 in/s**2 per lbf in (m/s**2) per kN, by hand.
    row = (tmp_path / "frf.csv").read_text().splitlines()[1].split(",")
    assert float(row[3]) == pytest.approx(0.25 * M_PER_IN / KN_PER_LBF, rel=1e-14)
    # H_zu [in/s**2 per in] is the same number in (m/s**2) per m, so 1e-3 of it per mm
    assert float(row[1]) == pytest.approx(table.H_zu[0].real * 1e-3, rel=1e-14)


def test_parsed_document_and_magnitude_phase_columns(tmp_path):
    f = [1.0, 10.0, 100.0]
    lines = ["# an analyser's export", "frequency_hz, H_zu_mag, H_zu_phase_deg, H_zw_re, H_zw_im"]
    lines += [f"{x}, 2.0, -90.0, 0.5, 0.0" for x in f]
    (tmp_path / "m.csv").write_text("\n".join(lines) + "\n")
    toml = tmp_path / "t.toml"
    toml.write_text(
        '[model]\nkind = "frf"\nfile = "m.csv"\nloop_time = "1 ms"\ndelay = "included"\n'
        'units = { z = "in/s**2", u = "in", w = "lbf" }\n'
    )
    table = read_frf_table(toml, read_toml(toml))  # as the --table dispatcher hands it over
    np.testing.assert_allclose(table.H_zu, -2j, atol=1e-15)  # 2 exp(-j 90 deg)
    assert table.loop_time_s == pytest.approx(1e-3, rel=1e-15) and table.range_hz == (1.0, 100.0)
    assert table.nyquist_hz == pytest.approx(500.0, rel=1e-12)


def _files(tmp_path, csv_lines, model=None):
    (tmp_path / "d.csv").write_text("\n".join(csv_lines) + "\n")
    model = model or {
        "kind": '"frf"',
        "file": '"d.csv"',
        "loop_time": '"500 us"',
        "units": '{ z = "m/s**2", u = "mm", w = "kN" }',
    }
    toml = tmp_path / "t.toml"
    toml.write_text("[model]\n" + "".join(f"{k} = {v}\n" for k, v in model.items()))
    return toml


HEADER = "frequency_hz, H_zu_re, H_zu_im, H_zw_re, H_zw_im, coherence_zu, coherence_zw"
GOOD = ["1.0, 1, 0, 1, 0, 0.9, 0.9", "2.0, 1, 0, 1, 0, 0.9, 0.9"]


@pytest.mark.parametrize(
    "rows, message",
    [
        ([HEADER, GOOD[1], GOOD[0]], "line 3: column frequency_hz is not increasing"),
        ([HEADER, GOOD[0], GOOD[0]], "frequency_hz is not increasing"),
        (["frequency_hz, H_zu_re, H_zu_im, H_zw_re", "1, 1, 0, 1"], "missing column 'H_zw_im'"),
        (["H_zu_re, H_zu_im, H_zw_re, H_zw_im", "1, 0, 1, 0"], "missing column 'frequency_hz'"),
        ([HEADER, GOOD[0], "2.0, nan, 0, 1, 0, 0.9, 0.9"], "line 3: column H_zu_re is not finite"),
        ([HEADER, GOOD[0], "2.0, 1, 0, 1, 0, 1.2, 0.9"], "line 3: column coherence_zu is outside [0, 1]"),
        ([HEADER, GOOD[0], "2.0, 1, 0, 1, 0, 0.9, -0.1"], "column coherence_zw is outside [0, 1]"),
        ([HEADER.replace("coherence_zw", "coherence_xx"), *GOOD], "unknown column 'coherence_xx'"),
        ([HEADER + ", H_zu_mag", GOOD[0] + ", 1", GOOD[1] + ", 1"], "both as re/im and as mag/phase"),
        ([HEADER, GOOD[0], "2.0, 1, 0, 1"], "line 3: expected 7 values, got 4"),
        ([HEADER, GOOD[0], "2.0, x, 0, 1, 0, 0.9, 0.9"], "column H_zu_re is not a number"),
        ([HEADER, GOOD[0]], "at least 2 frequencies"),
        ([HEADER], "at least 2 frequencies"),
    ],
)
def test_bad_data_file_is_refused_naming_file_and_column(tmp_path, rows, message):
    with pytest.raises(DataFileError) as exc:
        read_frf_table(_files(tmp_path, rows))
    assert message in str(exc.value) and "d.csv" in str(exc.value)


UNITS = '{ z = "m/s**2", u = "mm", w = "kN" }'


@pytest.mark.parametrize(
    "model, message",
    [
        ({"kind": '"frf"', "file": '"d.csv"', "units": UNITS}, "model.loop_time: expected"),
        ({"kind": '"frf"', "loop_time": '"500 us"', "units": UNITS}, "model.file: expected"),
        ({"kind": '"frf"', "file": '"d.csv"', "loop_time": '"500 us"'}, "model.units: expected"),
        (
            {"kind": '"transfer-function"', "file": '"d.csv"', "loop_time": '"1 ms"', "units": UNITS},
            "model.kind",
        ),
        ({"kind": '"frf"', "file": '"d.csv"', "loop_time": '"500 mm"', "units": UNITS}, "model.loop_time"),
        ({"kind": '"frf"', "file": '"d.csv"', "loop_time": '"0 s"', "units": UNITS}, "model.loop_time"),
        (
            {
                "kind": '"frf"',
                "file": '"d.csv"',
                "loop_time": '"1 ms"',
                "units": '{ z = "m/s", u = "mm", w = "kN" }',
            },
            "model.units.z: expected a quantity with the dimension of inch / second**2, got 'm/s'",
        ),
        (
            {
                "kind": '"frf"',
                "file": '"d.csv"',
                "loop_time": '"1 ms"',
                "units": '{ z = "m/s**2", u = "kg", w = "kN" }',
            },
            "model.units.u",
        ),
        (
            {
                "kind": '"frf"',
                "file": '"d.csv"',
                "loop_time": '"1 ms"',
                "units": '{ z = "m/s**2", u = "mm" }',
            },
            "model.units.w",
        ),
        (
            {
                "kind": '"frf"',
                "file": '"d.csv"',
                "loop_time": '"1 ms"',
                "units": UNITS,
                "delay": '"first-order"',
            },
            "model.delay",
        ),
        (
            {"kind": '"frf"', "file": '"d.csv"', "loop_time": '"1 ms"', "units": UNITS, "gain": "2"},
            "model.gain",
        ),
        (
            {"kind": '"frf"', "file": '"none.csv"', "loop_time": '"1 ms"', "units": UNITS},
            "none.csv: file not found",
        ),
    ],
)
def test_bad_table_file_is_refused_naming_the_key(tmp_path, model, message):
    with pytest.raises(DataFileError) as exc:
        read_frf_table(_files(tmp_path, [HEADER, *GOOD], model))
    assert message in str(exc.value)


def test_no_model_section(tmp_path):
    path = tmp_path / "t.toml"
    path.write_text("[table]\nmass = 1\n")
    with pytest.raises(DataFileError, match=r"t.toml: model: expected a \[model\] table"):
        read_frf_table(path)


@pytest.mark.parametrize(
    "changes, key",
    [
        ({"frequency_hz": np.array([0.5, 0.4, 2.0, 4.0])}, "frequency_hz"),
        ({"frequency_hz": np.array([0.0, 1.0, 2.0, 4.0])}, "frequency_hz"),
        ({"H_zw": np.array([1.0, np.nan, 1.0, 1.0])}, "H_zw"),
        ({"H_zu": np.ones(3)}, "H_zu"),
        ({"coherence_zw": np.array([0.5, 0.5, 1.5, 0.5])}, "coherence_zw"),
        ({"coherence_zu": np.array([0.5, np.nan, 0.5, 0.5])}, "coherence_zu"),
        ({"loop_time_s": 0.0}, "loop_time"),
    ],
)
def test_the_dataclass_refuses_bad_arrays(changes, key):
    with pytest.raises(ConfigError) as exc:
        small_table(**changes)
    assert exc.value.key == key
