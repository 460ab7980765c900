"""Generated C99 against the reference runtime (gcc -std=c99 -O2 -Wall -Wextra -Werror -pedantic)."""

from __future__ import annotations

import ctypes
import shutil
import subprocess

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.implement.c import render_c
from impedance_mil.virtual import presets

from .conftest import FC_HZ, GCC_FLAGS, LOOP_TIME_S, WIDE_LIMITS, broadband_record

#: (prefix, precision, VS preset or None) of every variant compiled, once per session.
VARIANTS = [
    ("ctl_f", "single", None),
    ("ctl_d", "double", None),
    ("sd_d", "double", "SD2"),
    ("lr_d", "double", "LR2"),
    ("fp_d", "double", "FP2"),
    ("sd_f", "single", "SD2"),
    ("fp_f", "single", "FP2"),
    ("lr_f", "single", "LR2"),
    ("tfp_d", "double", "TFP3"),
    ("tfp_f", "single", "TFP3"),
]

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc not available")


@pytest.fixture(scope="session")
def discrete(controller_tfs):
    return discretize(*controller_tfs, LOOP_TIME_S, fc_hz=FC_HZ)


@pytest.fixture(scope="session")
def clib(discrete, tmp_path_factory):
    """All variants compiled into one shared library (one gcc call per session)."""
    d = tmp_path_factory.mktemp("cgen")
    sources = []
    for prefix, precision, preset in VARIANTS:
        vs = presets.get(preset) if preset else None
        render_c(discrete, precision, prefix, vs=vs, limits=WIDE_LIMITS).write(d)
        sources.append(str(d / f"{prefix}.c"))
    lib = d / "libimil_test.so"
    subprocess.run(
        ["gcc", *GCC_FLAGS, "-o", str(lib), *sources, "-lm"], check=True, capture_output=True, text=True
    )
    return ctypes.CDLL(str(lib))


def _c_run(lib, prefix, precision, a, b, mil=False):
    """u (and z_vs) of the compiled step over a record, in normal operation: no guard acts."""
    ct = ctypes.c_float if precision == "single" else ctypes.c_double
    dt = np.float32 if precision == "single" else np.float64
    state = ctypes.create_string_buffer(getattr(lib, f"{prefix}_state_size")())
    getattr(lib, f"{prefix}_init")(state)
    a = np.ascontiguousarray(a, dt)
    b = np.ascontiguousarray(b, dt)
    u = np.zeros(a.size, dt)
    ptr = lambda x: x.ctypes.data_as(ctypes.POINTER(ct))  # noqa: E731
    if mil:
        z = np.zeros(a.size, dt)
        getattr(lib, f"{prefix}_mil_run")(state, ptr(a), ptr(b), ptr(u), ptr(z), ctypes.c_long(a.size))
    else:
        getattr(lib, f"{prefix}_run")(state, ptr(a), ptr(b), ptr(u), ctypes.c_long(a.size))
    assert getattr(lib, f"{prefix}_fault")(state) == 0  # the guards never acted
    return (u, z) if mil else u


@pytest.fixture(scope="module")
def long_record():
    _, a = broadband_record(duration_s=10.0)  # 20,000 loops
    return a, -9.3 * a + 25.0


@pytest.mark.parametrize("prefix,precision", [("ctl_f", "single"), ("ctl_d", "double")])
def test_controller_step_is_bit_identical_to_runtime(clib, discrete, long_record, prefix, precision):
    # Same operations in the same order and precision -> identical, not just close.
    z, w = long_record
    u_c = _c_run(clib, prefix, precision, z, w)
    u_rt = MILRuntime(discrete, precision=precision).run(z, w)
    assert u_c.size == 20000
    np.testing.assert_array_equal(u_c, u_rt)


def test_single_step_entry_point(clib, discrete):
    # P_init + P_step through ctypes with scalar arguments, against MILRuntime.step.
    clib.ctl_f_step.restype = ctypes.c_float
    clib.ctl_f_step.argtypes = [ctypes.c_void_p, ctypes.c_float, ctypes.c_float]
    state = ctypes.create_string_buffer(clib.ctl_f_state_size())
    clib.ctl_f_init(state)
    rt = MILRuntime(discrete, precision="single")
    for k in range(50):
        z, w = 100.0 * np.sin(0.3 * k), 20.0 * np.cos(0.1 * k)
        assert clib.ctl_f_step(state, z, w) == np.float32(rt.step(z, w))


@pytest.mark.parametrize(
    "prefix,preset", [("sd_d", "SD2"), ("lr_d", "LR2"), ("fp_d", "FP2"), ("tfp_d", "TFP3")]
)
def test_mil_step_double_matches_runtime(clib, discrete, long_record, prefix, preset):
    # The C rendering of the VS definition vs the numba kernel generated from it.
    # Tolerance: 1e-12 of the peak (libm pow/exp may differ from LLVM's in the last bit).
    a_g, w = long_record
    u_c, z_c = _c_run(clib, prefix, "double", a_g, w, mil=True)
    tr = MILRuntime(discrete, vs=presets.get(preset), precision="double").run_mil(a_g, w)
    np.testing.assert_allclose(z_c, tr.z_vs, rtol=0, atol=1e-12 * np.max(np.abs(tr.z_vs)))
    np.testing.assert_allclose(u_c, tr.u, rtol=0, atol=1e-12 * np.max(np.abs(tr.u)))


@pytest.mark.parametrize(
    "prefix,preset", [("sd_f", "SD2"), ("lr_f", "LR2"), ("fp_f", "FP2"), ("tfp_f", "TFP3")]
)
def test_mil_step_single_is_bit_identical_to_runtime(clib, discrete, long_record, prefix, preset):
    # Single precision: the C locals take the precision numba gives each value (float for
    # float32 arrays, double where a double literal enters, as listing.value_types infers),
    # and the float math functions where numba uses them, so the generated MIL step
    # reproduces the runtime's float32 kernel bit for bit over 20,000 loops (before the
    # VS definitions, the two differed by up to 5.9e-7 of the peak in z_vs).
    a_g, w = long_record
    u_c, z_c = _c_run(clib, prefix, "single", a_g, w, mil=True)
    tr = MILRuntime(discrete, vs=presets.get(preset), precision="single").run_mil(a_g, w)
    np.testing.assert_array_equal(z_c, tr.z_vs)
    np.testing.assert_array_equal(u_c, tr.u)


def test_user_type_from_its_own_file_renders_and_matches_runtime(discrete, long_record, two_storey, tmp_path):
    # A user's type (examples/vs_types/two_storey.py) is rendered like a built-in one:
    # double precision within 1e-12 of the peak, single precision bit for bit.
    vs = two_storey.example_two_storey()
    a_g, w = long_record
    for prefix, precision in (("iso_d", "double"), ("iso_f", "single")):
        render_c(discrete, precision, prefix, vs=vs, limits=WIDE_LIMITS).write(tmp_path)
    lib = tmp_path / "libiso.so"
    subprocess.run(
        ["gcc", *GCC_FLAGS, "-o", str(lib), str(tmp_path / "iso_d.c"), str(tmp_path / "iso_f.c"), "-lm"],
        check=True,
        capture_output=True,
        text=True,
    )
    clib = ctypes.CDLL(str(lib))
    u_c, z_c = _c_run(clib, "iso_d", "double", a_g, w, mil=True)
    tr = MILRuntime(discrete, vs=vs, precision="double").run_mil(a_g, w)
    np.testing.assert_allclose(z_c, tr.z_vs, rtol=0, atol=1e-12 * np.max(np.abs(tr.z_vs)))
    u_c, z_c = _c_run(clib, "iso_f", "single", a_g, w, mil=True)
    tr = MILRuntime(discrete, vs=vs, precision="single").run_mil(a_g, w)
    np.testing.assert_array_equal(z_c, tr.z_vs)
    np.testing.assert_array_equal(u_c, tr.u)


@pytest.mark.parametrize("bad", ["1abc", "my-ctl", "int", "static", "__x", "_Foo", ""])
def test_invalid_prefix_is_rejected(discrete, bad):
    with pytest.raises(ConfigError, match="prefix"):
        render_c(discrete, "single", bad, limits=WIDE_LIMITS)
