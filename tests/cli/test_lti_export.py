"""Issue 13: a table given as a linear model, through design, export (C, ST) and ``simulate --design``.

The LTI table is the report's table as its own linear model (``LinearTable(report,
"first-order").state_space()``), written as a transfer-function, zpk or state-space file
whose ``[capacity]`` states what the physical table implies: its mid-stroke, the valve's
no-load velocity capacity, the stall force A_p (P_S - P_R) and the table mass.  The
generated code's limits then come from that section, and must equal those the physical
table gives (closed form: the same four numbers).
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from impedance_mil.design import design_controller, load_design, save_design, table_model, virtual_model
from impedance_mil.implement.export import controller_from_design
from impedance_mil.implement.safety import command_limits
from impedance_mil.lab.identify import implied_capacity
from impedance_mil.plant import LinearTable, TableParameters
from impedance_mil.plant.capacity import TableCapacity
from impedance_mil.plant.lti_table import LTITable
from impedance_mil.plant.table_files import lti_table_toml, read_table_file
from impedance_mil.virtual.files import resolve

KINDS = ("transfer-function", "zpk", "state-space")


def _lti_file(folder, kind, *, capacity=True, gain=1.0):
    p = TableParameters.report_default()
    # another table: the proportional gain scaled (the closed loop's paths change)
    model = LinearTable(dataclasses.replace(p, Kp=gain * p.Kp), delay="first-order").state_space()
    table = LTITable(
        model,
        p.loop_time,
        "included",
        "state-space",
        capacity=implied_capacity(p) if capacity else TableCapacity(),
    )
    path = folder / f"{kind}{'' if capacity else '-nocap'}{'' if gain == 1.0 else '-other'}.toml"
    path.write_text(lti_table_toml(table, kind))
    return path


def _sd2():
    spec = resolve("SD2")
    return virtual_model(spec.vs, spec.name)


@pytest.mark.parametrize("kind", KINDS)
def test_the_stated_capacity_gives_the_physical_tables_limits(tmp_path, kind):
    # Closed form: the four numbers of [capacity] are those the physical table implies, so the
    # limits are equal (stroke, rate, input ranges; 1e-12, file round trip of 17 digits).
    physical = TableParameters.report_default()
    lti = read_table_file(_lti_file(tmp_path, kind))
    design = design_controller(table_model(lti), _sd2(), fc_hz=80.0, emit_warnings=False)
    assert design.table == {} and set(design.capacity) == {
        "stroke",
        "velocity",
        "force",
        "mass",
        "piston_area",
    }
    got = command_limits(design.table, capacity=design.capacity)
    want = command_limits(physical.to_dict())
    for key in ("stroke_in", "max_rate_in_s", "accel_limit_in_s2", "force_limit_lbf"):
        assert getattr(got, key) == pytest.approx(getattr(want, key), rel=1e-12), key
    assert "capacity.stroke" in got.source("stroke")


def test_the_exported_controller_of_the_lti_design_is_the_physical_designs(tmp_path):
    # The design on the report's model written as a file equals the design on the physical table
    # (measured 2e-15 in the paths): their discrete controllers agree to 1e-9 in response.
    lti = read_table_file(_lti_file(tmp_path, "transfer-function"))
    a = controller_from_design(design_controller(table_model(lti), _sd2(), fc_hz=80.0, emit_warnings=False))
    b = controller_from_design(
        design_controller(
            table_model(TableParameters.report_default()), _sd2(), fc_hz=80.0, emit_warnings=False
        )
    )
    f = np.geomspace(0.1, 999.0, 200)
    for ha, hb in zip(a.frequency_response(f), b.frequency_response(f), strict=True):
        np.testing.assert_allclose(ha, hb, rtol=1e-9)


def test_the_design_file_keeps_the_capacity_and_the_tables_paths(tmp_path):
    lti = read_table_file(_lti_file(tmp_path, "zpk"))
    design = design_controller(table_model(lti), _sd2(), fc_hz=80.0, emit_warnings=False)
    again = load_design(save_design(design, tmp_path / "d.json"))
    assert again.capacity == pytest.approx(design.capacity, rel=1e-15)
    f = np.geomspace(0.1, 999.0, 50)
    for key in ("H_zu", "H_zw"):
        np.testing.assert_allclose(
            again.table_paths[key].frequency_response(f),
            design.table_paths[key].frequency_response(f),
            rtol=1e-13,
        )
    # A physical design's file is as before: neither key.
    physical = design_controller(
        table_model(TableParameters.report_default()), _sd2(), fc_hz=80.0, emit_warnings=False
    )
    doc = json.loads(save_design(physical, tmp_path / "p.json").read_text())
    assert "capacity" not in doc and "table_paths" not in doc


@pytest.mark.parametrize("fmt", ["c", "st"])
def test_export_c_and_st_from_an_lti_table(imil, tmp_path, fmt):
    table = _lti_file(tmp_path, "state-space")
    res = imil("export", "--table", table, "--vs", "SD2", "--fc", "80", "--format", fmt, "-o", tmp_path / fmt)
    assert res.returncode == 0, res.stderr
    text = "".join(p.read_text() for p in (tmp_path / fmt).iterdir())
    assert "capacity.stroke" in text and "capacity.velocity" in text


def test_export_c_without_a_capacity_is_refused_naming_it(imil, tmp_path):
    table = _lti_file(tmp_path, "transfer-function", capacity=False)
    assert (
        imil("design", "--table", table, "--vs", "SD2", "--fc", "80", "-o", tmp_path / "d.json").returncode
        == 0
    )
    res = imil("export", tmp_path / "d.json", "--format", "c", "-o", tmp_path / "out")
    assert res.returncode == 2 and res.stderr.count("\n") == 1
    assert "capacity.stroke" in res.stderr
    assert not (tmp_path / "out").exists()
    # JSON and CSV carry no clamps, and export.
    assert imil("export", tmp_path / "d.json", "--format", "json", "-o", tmp_path / "j").returncode == 0


def test_simulate_design_runs_the_lti_design_on_its_table_in_any_kind_of_file(imil, tmp_path):
    tf, ss = _lti_file(tmp_path, "transfer-function"), _lti_file(tmp_path, "state-space")
    assert (
        imil("design", "--table", tf, "--vs", "SD2", "--fc", "80", "-o", tmp_path / "d.json").returncode == 0
    )
    runs = {}
    for name, args in {
        "design on tf": ("--design", tmp_path / "d.json", "--table", tf),
        "design on ss": ("--design", tmp_path / "d.json", "--table", ss),
        "vs on tf": ("--vs", "SD2", "--table", tf),
    }.items():
        res = imil("simulate", *args, "--duration", "2", "--json", "-o", tmp_path / f"{len(runs)}.h5")
        assert res.returncode == 0, (name, res.stderr)
        runs[name] = json.loads(res.stdout)
    # The design file's controller is the one simulate --vs designs (export's discretization of
    # the same design): the metrics agree to round-off of the file's 17 digits (1e-9).
    for name in ("design on tf", "design on ss"):
        assert runs[name]["nrms_error"] == pytest.approx(runs["vs on tf"]["nrms_error"], rel=1e-9), name


def test_simulate_design_refuses_another_lti_table_naming_the_path(imil, tmp_path):
    tf, other = _lti_file(tmp_path, "transfer-function"), _lti_file(tmp_path, "transfer-function", gain=1.01)
    assert (
        imil("design", "--table", tf, "--vs", "SD2", "--fc", "80", "-o", tmp_path / "d.json").returncode == 0
    )
    res = imil(
        "simulate",
        "--design",
        tmp_path / "d.json",
        "--table",
        other,
        "--duration",
        "1",
        "-o",
        tmp_path / "r.h5",
    )
    assert res.returncode == 2 and res.stderr.count("\n") == 1
    assert "--design" in res.stderr and "H_zu" in res.stderr
    assert not (tmp_path / "r.h5").exists()
