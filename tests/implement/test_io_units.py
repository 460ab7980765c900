"""I/O units of the generated code (issue 12, "Units out"): the scale at the edges.

The invariant: the generated code fed in the lab's units gives the runtime's
command (the runtime fed in the internal units) in the lab's unit.  Two forms:

* exact: the code rounds each input once, ``x * K`` in its precision (``K`` the
  factor rounded to it), and the command once, ``u * K_u``; the runtime fed with
  those rounded inputs, its command times ``K_u`` in the same precision, is the
  code's output bit for bit;
* within round-off: against the runtime fed with the record in the internal
  units (the SI record is that record converted in double), in single precision
  the outputs differ by the rounding of the inputs, integrated by the
  controller's double integrator (:data:`SINGLE_RTOL`, :data:`DOUBLE_RTOL`, measured).

Reference factors are the definitions: 1 in = 25.4 mm, 1 lbf = 0.45359237 kg
x 9.80665 m/s**2 = 4.4482216152605 N, g0 = 9.80665 m/s**2 (NIST SP 811, B.8).
"""

from __future__ import annotations

import ctypes
import shutil
import subprocess

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.implement import MILRuntime
from impedance_mil.implement.c import render_c
from impedance_mil.implement.export import coefficients_csv, coefficients_document, render
from impedance_mil.implement.io_units import IOUnits
from impedance_mil.implement.safety import Fault
from impedance_mil.implement.st import render_st
from impedance_mil.virtual import presets

from .conftest import GCC_FLAGS, WIDE_LIMITS, broadband_record
from .st_transpiler import STBlock
from .test_codegen_c import _c_run

#: Exact definitions (NIST SP 811, Appendix B.8).
M_PER_IN = 0.0254
N_PER_LBF = 0.45359237 * 9.80665
G0 = 9.80665

#: Largest |code - runtime on the internal record| / peak |u| measured (C over 20,000 loops, ST
#: over 2,000): single precision 2.4e-7 (C controller), 6.6e-7 u and 2.4e-7 z_vs (C MIL step,
#: SD2), 7.6e-8 (ST controller); double precision at most 7.3e-16 (ST MIL block).  Bounds: 3x
#: the largest single and 4x the largest double value.
SINGLE_RTOL = 2e-6
DOUBLE_RTOL = 3e-15


@pytest.fixture(scope="module")
def record():
    """20,000 loops in the internal units (in/s^2, lbf) and the same record in SI (m/s**2, N)."""
    _, a = broadband_record(duration_s=10.0)
    w = -9.3 * a + 25.0
    return a, w, a * M_PER_IN, w * N_PER_LBF


def test_factors_are_the_definitions():
    io = IOUnits.parse("si")
    assert io.accel.to_internal == pytest.approx(1.0 / M_PER_IN, rel=1e-15)
    assert io.accel.from_internal == pytest.approx(M_PER_IN, rel=1e-15)
    assert io.force.to_internal == pytest.approx(1.0 / N_PER_LBF, rel=1e-15)
    assert io.force.from_internal == pytest.approx(N_PER_LBF, rel=1e-15)
    assert io.disp.from_internal == pytest.approx(25.4, rel=1e-15)
    assert io.disp.to_internal == pytest.approx(1.0 / 25.4, rel=1e-15)
    custom = IOUnits.parse("accel=g0,force=kN,disp=m")
    assert custom.accel.to_internal == pytest.approx(G0 / M_PER_IN, rel=1e-15)
    assert custom.force.to_internal == pytest.approx(1000.0 / N_PER_LBF, rel=1e-15)
    assert custom.disp.from_internal == pytest.approx(M_PER_IN, rel=1e-15)
    assert IOUnits.parse("si,force=kN") == IOUnits.parse({"accel": "m/s**2", "force": "kN", "disp": "mm"})


@pytest.mark.parametrize(
    "spec,name",
    [("us", "us"), ("si", "si"), ("accel=in/s**2,force=lbf,disp=in", "us"), ("si,disp=m", "accel=m/s**2")],
)
def test_spec_names_the_units(spec, name):
    assert IOUnits.parse(spec).spec.startswith(name)
    assert IOUnits.parse(spec).is_internal == (name == "us")


@pytest.mark.parametrize(
    "spec,key",
    [
        ("force=mm", "--io-units force"),  # a length for a force
        ("accel=g", "--io-units accel"),  # pint's g is the gram
        ("si,disp=N", "--io-units disp"),
        ("si,disp=1000 mm", "--io-units disp"),  # a factor is not a unit
        ("si,force=5", "--io-units force"),
        ("si,force=", "--io-units force"),
        ("si,force=N*)", "--io-units force"),  # would close the ST comment it is copied into
        ("si,torque=N", "--io-units torque"),
        ("si,force=N,force=kN", "--io-units force"),
        ("accel=m/s**2,force=N", "--io-units disp"),  # no base: every quantity named
        ("metric", "--io-units"),
        ("", "--io-units"),
    ],
)
def test_bad_specifications_name_the_option_and_the_quantity(spec, key):
    with pytest.raises(ConfigError) as err:
        IOUnits.parse(spec)
    assert err.value.key == key
    assert len(str(err.value).splitlines()) == 1


def test_a_factor_the_precision_cannot_hold_is_refused(discrete):
    tiny = IOUnits.parse("si,force=yN")  # 1 yN = 1e-24 N: 1 lbf is 4.4e24 yN, beyond 1e18
    with pytest.raises(ConfigError, match="io_units force"):
        render(discrete, "c", "single", limits=WIDE_LIMITS, io_units=tiny)


@pytest.mark.parametrize("fmt", ["c", "st", "json", "csv"])
def test_default_export_is_unchanged(discrete, fmt):
    # No option, "us" and the internal units spelled out give the same files, and none of
    # them carries an I/O unit artefact (the 22 variants were also compared byte for byte
    # with the renders of the commit before I/O units existed).
    vs = presets.get("SD2") if fmt in ("c", "st") else None
    plain = render(discrete, fmt, "single", vs=vs, limits=WIDE_LIMITS)
    for spec in ("us", "accel=in/s^2,force=lbf,disp=in"):
        assert (
            render(discrete, fmt, "single", vs=vs, limits=WIDE_LIMITS, io_units=IOUnits.parse(spec)) == plain
        )
    text = "".join(plain.values())
    for artefact in ("TO_INTERNAL", "to_internal", "_int ", "io_units", "I/O units"):
        assert artefact not in text


def test_every_io_comment_names_the_io_units(discrete):
    io = IOUnits.parse("accel=g0,force=kN,disp=mm")
    c = render_c(discrete, "single", "rig", vs=presets.get("SD2"), limits=WIDE_LIMITS, io_units=io).files
    header = c["rig.h"]
    assert "return the safe command u [mm] from z_vs [g0] and w [kN]" in header
    assert "Returns u [mm]; writes z_vs [g0]" in header
    assert "#define RIG_ACCEL_TO_INTERNAL" in header and "/* in/s^2 per g0: z_vs, a_g as read */" in header
    # the input ranges in both units (WIDE_LIMITS: 1e6 in/s^2, 1e7 lbf)
    assert "|z_vs|, |a_g| <= 1e+06 in/s^2, |w| <= 1e+07 lbf" in header
    assert f"|z_vs|, |a_g| <= {1e6 * M_PER_IN / G0:.6g} g0, |w| <= {1e7 * N_PER_LBF / 1000:.6g} kN" in header
    st = render_st(discrete, "single", "rig", vs=presets.get("SD2"), limits=WIDE_LIMITS, io_units=io)[
        "rig.st"
    ]
    assert "I/O units (accel=g0,force=kN,disp=mm): z_vs, a_g [g0]; w [kN]; u, u_z, u_w [mm]" in st
    assert "    z_vs : REAL;  (* [g0] *)" in st and "    u : REAL;  (* [mm] *)" in st
    assert f"{1e6 * M_PER_IN / G0:.6g} g0" in st
    doc = coefficients_document(discrete, "single", io)
    assert doc["units"]["z_vs"] == "in/s^2"  # the coefficients stay internal
    assert doc["io_units"]["z_vs"] == {
        "unit": "g0",
        "internal_unit": "in/s^2",
        "to_internal": io.accel.to_internal,
    }
    assert doc["io_units"]["u"]["from_internal"] == pytest.approx(25.4, rel=1e-15)
    assert "# io_units: accel=g0,force=kN,disp=mm: z_vs g0 (x " in coefficients_csv(discrete, "single", io)


# ---------------------------------------------------------------- generated C, compiled

needs_gcc = pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc not available")

#: (prefix, precision, VS preset or None) compiled with --io-units si.
SI_VARIANTS = [("si_f", "single", None), ("si_d", "double", None), ("sisd_f", "single", "SD2")]


@pytest.fixture(scope="module")
def si_lib(discrete, tmp_path_factory):
    d = tmp_path_factory.mktemp("cgen_si")
    for prefix, precision, preset in SI_VARIANTS:
        vs = presets.get(preset) if preset else None
        render_c(discrete, precision, prefix, vs=vs, limits=WIDE_LIMITS, io_units=IOUnits.parse("si")).write(
            d
        )
    lib = d / "libsi.so"
    sources = [str(d / f"{p}.c") for p, _, _ in SI_VARIANTS]
    subprocess.run(["gcc", *GCC_FLAGS, "-o", str(lib), *sources, "-lm"], check=True, capture_output=True)
    return ctypes.CDLL(str(lib))


def _as_the_code_scales(x_si, factor, dtype):
    """An input in the internal unit as the generated code computes it: one product in its precision."""
    return np.asarray(x_si, dtype) * dtype(factor)


def _peak_error(got, ref) -> float:
    return float(np.max(np.abs(got - ref)) / np.max(np.abs(ref)))


@needs_gcc
@pytest.mark.parametrize(
    "prefix,precision,dtype", [("si_f", "single", np.float32), ("si_d", "double", np.float64)]
)
def test_c_in_si_is_the_runtime_in_internal_units(si_lib, discrete, record, prefix, precision, dtype):
    a, w, a_si, w_si = record
    io = IOUnits.parse("si")
    u_mm = _c_run(si_lib, prefix, precision, a_si, w_si)
    rt = MILRuntime(discrete, precision=precision)
    z_int = _as_the_code_scales(a_si, io.accel.to_internal, dtype)
    w_int = _as_the_code_scales(w_si, io.force.to_internal, dtype)
    exact = rt.run(z_int, w_int).astype(dtype) * dtype(io.disp.from_internal)
    np.testing.assert_array_equal(u_mm, exact)
    reference = MILRuntime(discrete, precision=precision).run(a, w) * 25.4  # [mm]
    assert _peak_error(u_mm, reference) < (SINGLE_RTOL if precision == "single" else DOUBLE_RTOL)


@needs_gcc
def test_c_mil_step_in_si_is_the_runtime_in_internal_units(si_lib, discrete, record):
    a, w, a_si, w_si = record
    io = IOUnits.parse("si")
    f32 = np.float32
    u_mm, z_si = _c_run(si_lib, "sisd_f", "single", a_si, w_si, mil=True)
    vs = presets.get("SD2")
    tr = MILRuntime(discrete, vs=vs, precision="single").run_mil(
        _as_the_code_scales(a_si, io.accel.to_internal, f32),
        _as_the_code_scales(w_si, io.force.to_internal, f32),
    )
    np.testing.assert_array_equal(u_mm, tr.u.astype(f32) * f32(io.disp.from_internal))
    np.testing.assert_array_equal(z_si, tr.z_vs.astype(f32) * f32(io.accel.from_internal))
    ref = MILRuntime(discrete, vs=vs, precision="single").run_mil(a, w)
    assert _peak_error(u_mm, ref.u * 25.4) < SINGLE_RTOL
    assert _peak_error(z_si, ref.z_vs * M_PER_IN) < SINGLE_RTOL


@needs_gcc
def test_c_guards_act_on_the_internal_value(si_lib):
    # WIDE_LIMITS: |w| <= 1e7 lbf = 4.448e7 N.  4.4e7 N passes, 4.5e7 N latches INPUT_RANGE
    # and the step returns the held command (0 mm: nothing moved yet).
    step = si_lib.si_d_step
    step.restype, step.argtypes = ctypes.c_double, [ctypes.c_void_p, ctypes.c_double, ctypes.c_double]
    for force_n, latched in ((4.4e7, False), (4.5e7, True)):
        state = ctypes.create_string_buffer(si_lib.si_d_state_size())
        si_lib.si_d_init(state)
        u = step(state, 0.0, force_n)
        assert bool(si_lib.si_d_fault(state) & Fault.INPUT_RANGE) == latched
        assert (u == 0.0) == latched


# ---------------------------------------------------------------- generated ST, transpiled


@pytest.fixture(scope="module")
def short_record(record):
    a, w, a_si, w_si = record
    return a[:2000], w[:2000], a_si[:2000], w_si[:2000]


@pytest.mark.parametrize("precision,dtype", [("single", np.float32), ("double", np.float64)])
def test_st_in_si_is_the_runtime_in_internal_units(discrete, short_record, precision, dtype):
    a, w, a_si, w_si = short_record
    io = IOUnits.parse("si")
    text = render_st(discrete, precision, "imil", limits=WIDE_LIMITS, io_units=io)["imil.st"]
    fb = STBlock(text, "imil_controller", "imil", dtype)
    u_mm = np.array([fb(z_vs=zz, w=ww)["u"] for zz, ww in zip(a_si, w_si, strict=True)], dtype)
    assert fb.env["fault"] == 0
    z_int = _as_the_code_scales(a_si, io.accel.to_internal, dtype)
    w_int = _as_the_code_scales(w_si, io.force.to_internal, dtype)
    rt = MILRuntime(discrete, precision=precision).run(z_int, w_int)
    np.testing.assert_array_equal(u_mm, rt.astype(dtype) * dtype(io.disp.from_internal))
    reference = MILRuntime(discrete, precision=precision).run(a, w) * 25.4
    assert _peak_error(u_mm, reference) < (SINGLE_RTOL if precision == "single" else DOUBLE_RTOL)


def test_st_mil_block_in_si_is_the_runtime_in_internal_units(discrete, short_record):
    # Double precision, as test_codegen_st's MIL test: in single precision the transpiled MIL
    # block differs from the runtime's float32 kernel by round-off with or without I/O units
    # (2.1e-7 of the peak of u over 2,000 loops without them).  Within DOUBLE_RTOL of the
    # runtime, fed the inputs converted or the internal record.
    a, w, a_si, w_si = short_record
    io = IOUnits.parse("si")
    vs = presets.get("SD2")
    text = render_st(discrete, "double", "imil", vs=vs, limits=WIDE_LIMITS, io_units=io)["imil.st"]
    fb = STBlock(text, "imil_mil", "imil", np.float64)
    out = np.array([[fb(a_g=x, w=f)["u"], fb.env["z_vs"]] for x, f in zip(a_si, w_si, strict=True)])
    assert fb.env["fault"] == 0
    tr = MILRuntime(discrete, vs=vs, precision="double").run_mil(
        a_si * io.accel.to_internal, w_si * io.force.to_internal
    )
    assert _peak_error(out[:, 0], tr.u * io.disp.from_internal) < DOUBLE_RTOL
    assert _peak_error(out[:, 1], tr.z_vs * io.accel.from_internal) < DOUBLE_RTOL
    ref = MILRuntime(discrete, vs=vs, precision="double").run_mil(a, w)
    assert _peak_error(out[:, 0], ref.u * 25.4) < DOUBLE_RTOL
    assert _peak_error(out[:, 1], ref.z_vs * M_PER_IN) < DOUBLE_RTOL
