"""Generated IEC 61131-3 ST: parsed by blark, executed by a small transpiler, vs the runtime."""

from __future__ import annotations

import re

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.implement.io_units import IOUnits
from impedance_mil.implement.st import render_st
from impedance_mil.systems import TransferFunction
from impedance_mil.virtual import presets

from .conftest import FC_HZ, LOOP_TIME_S, WIDE_LIMITS, broadband_record
from .st_transpiler import STBlock

blark = pytest.importorskip("blark")


@pytest.fixture(scope="module")
def discrete(controller_tfs):
    return discretize(*controller_tfs, LOOP_TIME_S, fc_hz=FC_HZ)


@pytest.fixture(scope="module")
def record():
    _, a = broadband_record(duration_s=1.0)  # 2,000 loops
    return a, -9.3 * a + 25.0


@pytest.fixture(scope="module")
def small():
    """A 2-state H_uz (with its double integrator) and 1-state H_uw: same generator paths,
    shorter sums (blark's Earley parser takes ~10 s per full-size controller)."""
    h_uz = TransferFunction([1.0, 30.0, 200.0], [1.0, 0.0, 0.0])
    h_uw = TransferFunction([-0.01], [1.0, 500.0])
    return discretize(h_uz, h_uw, LOOP_TIME_S, fc_hz=FC_HZ)


@pytest.mark.parametrize("preset", ["FP2", "TFP3"])
def test_generated_st_parses_with_blark(small, preset):
    # FP uses EXP, EXPT, ABS, sign, temps and arrays; TFP adds SEL and comparisons.  SD
    # and LR go through the same code paths (their MIL blocks run in the tests below).
    text = render_st(small, "single", "imil", vs=presets.get(preset), limits=WIDE_LIMITS)["imil.st"]
    result = blark.parse_source_code(text)
    assert result.exception is None
    names = re.findall(r"^(?:FUNCTION|FUNCTION_BLOCK) (\w+)", text, re.M)
    assert names == ["imil_sign", "imil_custom_feedback", "imil_controller", "imil_mil"]


@pytest.mark.parametrize("preset", ["SD2", "LR2", "FP2"])
def test_mil_block_declares_each_variable_once(small, preset):
    # IEC 61131-3 forbids a name declared twice in one POU, and VAR CONSTANT entries
    # need an initial value (blark parses both, so it is checked here).
    text = render_st(small, "single", "imil", vs=presets.get(preset), limits=WIDE_LIMITS)["imil.st"]
    src = re.search(r"FUNCTION_BLOCK imil_mil\n(.*?)END_FUNCTION_BLOCK", text, re.S).group(1)
    names = re.findall(r"^    (\w+) : ", src, re.M)  # declarations, not "x := ..."
    assert len(names) == len(set(names)), sorted(n for n in set(names) if names.count(n) > 1)
    constants = re.search(r"VAR CONSTANT\n(.*?)END_VAR", src, re.S).group(1)
    assert all(":=" in line for line in re.findall(r"^    \w+ :.*$", constants, re.M))
    assert {"x_vs", "k1", "u_z", "dt", "p_m_vs", "rk_b3"} <= set(names)


def test_parser_rejects_broken_st(small):
    # The parse test can fail: a missing semicolon is reported by blark.
    text = render_st(small, "single", "imil", limits=WIDE_LIMITS)["imil.st"].replace(
        "u_raw := u_z + u_w;", "u_raw := u_z + u_w"
    )
    assert blark.parse_source_code(text).exception is not None


@pytest.mark.parametrize("precision,dtype", [("single", np.float32), ("double", np.float64)])
def test_st_controller_computes_what_the_runtime_computes(discrete, record, precision, dtype):
    # Bit-identical: same operations, same order, same IEEE precision.
    text = render_st(discrete, precision, "imil", limits=WIDE_LIMITS)["imil.st"]
    fb = STBlock(text, "imil_controller", "imil", dtype)
    z, w = record
    u_st = np.array([fb(z_vs=zz, w=ww)["u"] for zz, ww in zip(z, w)], dtype)
    np.testing.assert_array_equal(u_st, MILRuntime(discrete, precision=precision).run(z, w))
    assert fb.env["fault"] == 0  # no guard acted


@pytest.mark.parametrize("preset", ["SD2", "LR2", "FP2", "TFP3"])
def test_st_mil_block_matches_runtime(discrete, record, preset):
    # Double precision; numpy's exp/pow vs LLVM/libm may differ in the last bit -> 1e-12 of peak.
    vs = presets.get(preset)
    fb = STBlock(
        render_st(discrete, "double", "imil", vs=vs, limits=WIDE_LIMITS)["imil.st"],
        "imil_mil",
        "imil",
        np.float64,
    )
    a_g, w = record
    out = np.array([[fb(a_g=a, w=f)["u"], fb.env["z_vs"]] for a, f in zip(a_g, w)])
    tr = MILRuntime(discrete, vs=vs, precision="double").run_mil(a_g, w)
    assert fb.env["fault"] == 0  # no guard acted
    np.testing.assert_allclose(out[:, 1], tr.z_vs, rtol=0, atol=1e-12 * np.max(np.abs(tr.z_vs)))
    np.testing.assert_allclose(out[:, 0], tr.u, rtol=0, atol=1e-12 * np.max(np.abs(tr.u)))


def test_custom_feedback_of_figure_7_6(discrete):
    # x_st + K_p*dP/K_e with Table 4.1 gains: 0.5 in + 0.001 V/psi * 800 psi / 5 V/in = 0.66 in.
    text = render_st(discrete, "double", "imil", limits=WIDE_LIMITS)["imil.st"]
    body = re.search(r"imil_custom_feedback := (.*);", text).group(1)
    assert eval(body, {"x_st": 0.5, "Kp": 0.001, "dP": 800.0, "Ke": 5.0}) == pytest.approx(0.66)


@pytest.mark.parametrize("bad", ["END_IF", "real", "Real", "a__b", "x_", "1x", "_x", "my-fb"])
def test_invalid_st_prefix_is_rejected(discrete, bad):
    with pytest.raises(ConfigError, match="prefix"):
        render_st(discrete, "single", bad, limits=WIDE_LIMITS)


def test_st_with_io_units_parses_and_declares_each_variable_once(small):
    # The scaled blocks (issue 12, Units out) add factor constants and *_int locals: still
    # valid ST for blark, and no name declared twice in a POU.
    io = IOUnits.parse("accel=g0,force=kN,disp=mm")
    text = render_st(small, "single", "imil", vs=presets.get("FP2"), limits=WIDE_LIMITS, io_units=io)[
        "imil.st"
    ]
    assert blark.parse_source_code(text).exception is None
    for block in ("imil_controller", "imil_mil"):
        src = re.search(rf"FUNCTION_BLOCK {block}\n(.*?)END_FUNCTION_BLOCK", text, re.S).group(1)
        names = re.findall(r"^    (\w+) : ", src, re.M)
        assert len(names) == len(set(names)), block
        assert {"accel_to_internal", "disp_from_internal", "w_int", "u_int"} <= set(names)
