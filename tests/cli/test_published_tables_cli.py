"""`imil table info | poles --table FILE` on the tables from cited public sources.

The published numbers and their sources: tests/plant/test_published_tables.py and
impedance_mil/data/PROVENANCE.md (section ``tables/``). Here the same numbers must come out
of the command line, in its JSON contract.
"""

import json
from importlib import resources

import numpy as np
import pytest
from typer.testing import CliRunner

from impedance_mil.cli.main import app
from impedance_mil.plant import LinearTable
from impedance_mil.plant.table_files import read_table_file

TABLES = resources.files("impedance_mil") / "data" / "tables"
LNEC = str(TABLES / "lnec_st1d_tekeste_2021.toml")
RTHS = str(TABLES / "rths_benchmark_plant.toml")
runner = CliRunner()


def _json(args: list[str]) -> dict:
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


def _poles(data: dict) -> np.ndarray:
    return np.sort_complex(np.array([complex(r["real"], r["imag"]) for r in data["poles"]]))


def test_info_of_the_first_order_valve_table():
    # Tekeste (2021): tau_sv = 24.6 ms; the oil column from the printed K_h (Henrique 2026:
    # 45213171683, 1e3 times 4 beta_e A^2 / V_t in N/m) and m_p = 1975.1 kg is 24.0801 Hz.
    data = _json(["table", "info", "--table", LNEC, "--json"])
    par = data["parameters"]
    assert par["valve"] == "first-order" and par["valve_time_constant"] == pytest.approx(0.0246, rel=1e-15)
    f_from_print = np.sqrt(45213171683.0 * 1e-3 / 1975.1) / (2.0 * np.pi)
    assert par["f_oil_hz"] == pytest.approx(f_from_print, rel=1e-10)
    assert data["units"]["parameters.f_oil_hz"] == "Hz"


def test_poles_of_the_first_order_valve_table():
    # The file's loop_time is 0 (the source's continuous model): four closed-loop poles, a
    # pair at 4.63 Hz (rigid body with the valve) and the oil column at 23.71 Hz, zeta 0.175,
    # equal to the library's (1e-12).
    data = _json(["table", "poles", "--table", LNEC, "--json"])
    assert data["stable"] is True and len(data["poles"]) == 4
    ref = np.sort_complex(LinearTable(read_table_file(LNEC)).poles())
    np.testing.assert_allclose(_poles(data), ref, rtol=1e-12)
    oil = max(data["poles"], key=lambda r: r["frequency_hz"])
    assert oil["frequency_hz"] == pytest.approx(23.71, abs=0.005)


def test_info_and_poles_of_the_transfer_function_table():
    # Li, Actuator_id.m: printed "a = DC*c; % 53529" with c = 54516. The JSON's x/u DC gain
    # reproduces it; no force path; five poles (7.68, 46.87, 46.87, 67.18, 67.18 Hz) equal the
    # library's (1e-12).
    info = _json(["table", "info", "--table", RTHS, "--json"])
    assert info["kind"] == "transfer-function" and info["force_path"] is False
    assert round(info["dc_gains"]["x/u"] * 54516) == 53529
    poles = _json(["table", "poles", "--table", RTHS, "--json"])
    assert poles["stable"] is True
    np.testing.assert_allclose(_poles(poles), np.sort_complex(read_table_file(RTHS).poles()), rtol=1e-12)
    freqs = sorted(round(r["frequency_hz"], 2) for r in poles["poles"])
    assert freqs == [7.68, 46.87, 46.87, 67.18, 67.18]


def test_an_analog_table_designs_without_sampled_indices_and_is_refused_by_the_virtual_lab(imil, tmp_path):
    # loop_time 0 (the LNEC model is continuous): imil design evaluates the continuous
    # constraints and says there is no sampled-data margin (it divided by the loop time);
    # a run needs the controller's loop time and is refused naming it, nothing written.
    doc = _json(["design", "--table", LNEC, "--vs", "SD2", "--fc", "80", "--json"])
    assert doc["constraints"][0]["passivity_margin_sampled_deg"] is None
    assert any("analog table" in w for w in doc["warnings"])
    out = tmp_path / "run.h5"
    for args in (("simulate", "--vs", "SD2"), ("track",), ("frf",)):
        res = imil(*args, "--table", LNEC, "-o", out)
        lines = res.stderr.strip().splitlines()
        assert res.returncode == 2 and len(lines) == 1 and "controller.loop_time" in lines[0], res.stderr
        assert not out.exists()
