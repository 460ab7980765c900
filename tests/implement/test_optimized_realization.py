"""Realization of the optimized design with order reduction (issue 15, "Realization").

One design, SD2 at 0.7 m_st (coarse dense grid as in test_optimized.py),
with ``--reduce auto``: measured 20/18 -> 13/10 states with the default
basis at 80 Hz.  Reference values: the a-priori bound ``2 * sum`` of the
removed Hankel singular values (:mod:`impedance_mil.design.optimized.reduce`),
the full design's verdicts, the exact Tustin response of the reduced
realization, and the reference runtime for the generated C.
"""

from __future__ import annotations

import ctypes
import json
import shutil
import subprocess

import numpy as np
import pytest
from typer.testing import CliRunner

from impedance_mil.cli.main import app
from impedance_mil.design import load_design, virtual_model
from impedance_mil.design.optimized import OptimizationSettings, design_optimized
from impedance_mil.design.optimized.certify import StateSpace
from impedance_mil.design.optimized.exchange import log_points
from impedance_mil.errors import ConfigError
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.implement.c import render_c
from impedance_mil.plant import TableParameters
from impedance_mil.report_config import report_config
from impedance_mil.virtual.files import resolve

from .conftest import GCC_FLAGS, WIDE_LIMITS, broadband_record

pytest.importorskip("cvxpy")

PARAMS = TableParameters.report_default()
FC_HZ = report_config().design.fc_hz
runner = CliRunner()


def _sd2_07():
    spec = resolve("SD2", {"m_vs": 0.7 * PARAMS.mass})
    return virtual_model(spec.vs, "SD2")


@pytest.fixture(scope="module")
def reduced():
    return design_optimized(
        PARAMS, _sd2_07(), fc_hz=FC_HZ, settings=OptimizationSettings(check_per_decade=100, reduce="auto")
    )


def _ss(doc) -> StateSpace:
    return StateSpace(np.array(doc["A"]), np.array(doc["B"]), np.array(doc["C"]), doc["D"])


def test_auto_reduces_within_the_bound_and_keeps_the_verdicts(reduced):
    rec = reduced.optimization["reduction"]
    assert rec["orders_before"] == {"H_uz": 20, "H_uw": 18}
    after = rec["orders_after"]
    assert after["H_uz"] < 20 and after["H_uw"] < 18  # measured 13 and 10
    assert reduced.H_uz.order == after["H_uz"] and reduced.H_uw.order == after["H_uw"]
    for name in ("H_uz", "H_uw"):
        # The a-priori H-infinity bound holds on the measured error (measured 0.37 of it).
        assert rec["measured_error"][name]["max_abs"] <= rec["error_bound"][name]
        assert rec["measured_error"][name]["max_relative_to_nyquist"] <= rec["tolerance"]
    assert (
        rec["verdicts_reduced"]
        == rec["verdicts_full"]
        == {"I": True, "II": True, "III": True, "certified": True}
    )
    c = reduced.constraints[0]
    assert c.I and c.II and c.III and reduced.optimization["certified"]
    # The state space in the file is the reduced realization; the transfer functions render it.
    ss = _ss(reduced.optimization["state_space"]["H_uw"])
    assert ss.A.shape == (after["H_uw"], after["H_uw"])
    s = 1j * 2 * np.pi * np.logspace(-1, 2.9, 40)
    assert np.max(np.abs(reduced.H_uw(s) / ss.response(s) - 1)) < 1e-9


def test_reduced_design_discretizes_to_its_exact_tustin_response(reduced):
    dc = discretize(reduced.H_uz, reduced.H_uw, PARAMS.loop_time, fc_hz=reduced.fc_hz)
    f = log_points((0.5, 400.0), 20)
    s_tustin = 1j * (2 / PARAMS.loop_time) * np.tan(np.pi * f * PARAMS.loop_time)
    hz, hw = dc.frequency_response(f)
    for h, name in ((hz, "H_uz"), (hw, "H_uw")):
        exact = _ss(reduced.optimization["state_space"][name]).response(s_tustin)
        assert np.max(np.abs(h / exact - 1)) < 1e-6  # measured 1e-12 .. 1e-10


@pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc not available")
@pytest.mark.parametrize("precision", ["single", "double"])
def test_reduced_controller_in_generated_c_is_bit_identical_to_runtime(reduced, precision, tmp_path):
    dc = discretize(reduced.H_uz, reduced.H_uw, PARAMS.loop_time, fc_hz=reduced.fc_hz)
    render_c(dc, precision, "opt", limits=WIDE_LIMITS).write(tmp_path)
    lib = tmp_path / "libopt.so"
    subprocess.run(
        ["gcc", *GCC_FLAGS, "-o", str(lib), str(tmp_path / "opt.c"), "-lm"], check=True, capture_output=True
    )
    c = ctypes.CDLL(str(lib))
    ct = ctypes.c_float if precision == "single" else ctypes.c_double
    dt = np.float32 if precision == "single" else np.float64
    _, a = broadband_record(duration_s=5.0)
    z = np.ascontiguousarray(0.01 * a, dt)  # a displacement-sized record [in]
    w = np.ascontiguousarray(-9.3 * a + 25.0, dt)
    u = np.zeros(z.size, dt)
    state = ctypes.create_string_buffer(c.opt_state_size())
    c.opt_init(state)
    ptr = lambda x: x.ctypes.data_as(ctypes.POINTER(ct))  # noqa: E731
    c.opt_run(state, ptr(z), ptr(w), ptr(u), ctypes.c_long(z.size))
    assert c.opt_fault(state) == 0  # no guard acted
    np.testing.assert_array_equal(u, MILRuntime(dc, precision=precision).run(z, w))
    assert np.max(np.abs(u)) > 0


def test_cli_reduce_option_records_and_refuses(tmp_path):
    out = tmp_path / "r.json"
    args = ["design", "--vs", "SD2", "--set-vs", f"m_vs={0.7 * PARAMS.mass}", "--method", "optimized"]
    # The larger of the orders auto keeps, then that order asked explicitly for both paths.
    # (Which explicit orders leave every pole below the Nyquist frequency depends on the
    # solver's optimum; the others are refused naming --reduce.)
    auto = runner.invoke(app, [*args, "--grid", "100", "--reduce", "auto", "--json"])
    assert auto.exit_code == 0, auto.output
    orders = json.loads(auto.stdout)["optimization"]["reduction"]["orders_after"]
    n = max(orders.values())
    assert n < 20  # reduced from 20 and 18 states
    res = runner.invoke(app, [*args, "--grid", "100", "--reduce", str(n), "--json", "-o", str(out)])
    assert res.exit_code == 0, res.output
    rec = json.loads(res.stdout)["optimization"]["reduction"]
    assert rec["orders_after"] == {"H_uz": n, "H_uw": n} and rec["request"] == n
    assert load_design(out).H_uz.order == n
    # The virtual lab takes the reduced design file unchanged.
    sim = runner.invoke(
        app, ["simulate", "--design", str(out), "-o", str(tmp_path / "o.h5"), "--duration", "2", "--json"]
    )
    assert sim.exit_code == 0, sim.output
    assert json.loads(sim.stdout)["design_method"] == "optimized"
    # So do the C and ST generators.
    for fmt in ("c", "st"):
        exp = runner.invoke(app, ["export", str(out), "--format", fmt, "-o", str(tmp_path / fmt)])
        assert exp.exit_code == 0, exp.output
        assert any((tmp_path / fmt).iterdir())
    bad = runner.invoke(app, [*args, "--reduce", "few"])
    assert isinstance(bad.exception, ConfigError) and "--reduce" in str(bad.exception)
