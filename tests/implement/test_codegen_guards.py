"""The safety layer of the generated C and ST (issue 18, finding 3): guards, clamp, latch, fault word.

The compiled C (ctypes) and the transpiled ST (``st_transpiler``) are driven with
NaN, a bias, steps and huge values.  Reference values:

* the command of a run in which nothing holds is the runtime's raw command
  (:class:`MILRuntime`, no guard) passed through an independent numpy model of
  the clamp and the rate limit (:func:`safe_commands`), in the same precision:
  equal bit for bit, because the guards only compare;
* a latched fault holds the last safe command exactly;
* the limits are those of the report's table (``command_limits``): mid-stroke
  3.2 in, the valve's velocity capacity 47.63 in/s (0.0238 in per 0.5 ms loop),
  input ranges ten times its force capacity (63000 lbf, 15217 in/s^2).
"""

from __future__ import annotations

import ctypes
import shutil
import subprocess

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.implement import MILRuntime, discretize
from impedance_mil.implement.c import render_c
from impedance_mil.implement.export import render
from impedance_mil.implement.safety import Fault, command_limits
from impedance_mil.implement.st import render_st
from impedance_mil.plant import TableParameters
from impedance_mil.systems import TransferFunction
from impedance_mil.virtual import presets

from .conftest import FC_HZ, GCC_FLAGS, LOOP_TIME_S, broadband_record
from .st_transpiler import STBlock

LIMITS = command_limits(TableParameters.report_default().to_dict())
HOLD_BITS = Fault.INPUT_NAN | Fault.INPUT_RANGE | Fault.OVERFLOW | Fault.LOOP_TIME
DTYPES = {"single": np.float32, "double": np.float64}
#: (prefix, precision, VS preset) of the compiled variants; "lt" is compiled with
#: LT_HOST_LOOP_TIME_S defined at 1 ms (twice the designed loop time).
VARIANTS = [
    ("g_f", "single", None),
    ("g_d", "double", None),
    ("gm_f", "single", "SD2"),
    ("lt", "single", None),
]


@pytest.fixture(scope="module")
def discrete(controller_tfs):
    return discretize(*controller_tfs, LOOP_TIME_S, fc_hz=FC_HZ)


@pytest.fixture(scope="module")
def runaway():
    """A double integrator of gain 1e12: fed 15000 in/s^2 (within the input range), its raw
    command passes the single-precision value limit 1e18 after about 11.5 s."""
    return discretize(
        TransferFunction([1e12], [1.0, 0.0, 0.0]), TransferFunction([0.0], [1.0]), LOOP_TIME_S, fc_hz=FC_HZ
    )


#: Samples of the runaway runs and their input [in/s^2].
RUNAWAY_N, RUNAWAY_Z = 24000, 15000.0


def first_beyond_value_limit(runaway) -> int:
    """Index of the first raw command of the runaway run beyond 1e18 (the runtime, unguarded)."""
    n, z = RUNAWAY_N, RUNAWAY_Z
    raw = MILRuntime(runaway, precision="single").run(np.full(n, z, np.float32), np.zeros(n, np.float32))
    return int(np.argmax(np.abs(raw) > 1e18))


@pytest.fixture(scope="module")
def lib(discrete, runaway, tmp_path_factory):
    if shutil.which("gcc") is None:
        pytest.skip("gcc not available")
    d = tmp_path_factory.mktemp("guards")
    for prefix, precision, preset in VARIANTS:
        vs = presets.get(preset) if preset else None
        render_c(discrete, precision, prefix, vs=vs, limits=LIMITS).write(d)
    render_c(runaway, "single", "ov_f", limits=LIMITS).write(d)
    sources = [str(d / f"{p}.c") for p, _, _ in VARIANTS] + [str(d / "ov_f.c")]
    so = d / "libguards.so"
    subprocess.run(
        ["gcc", *GCC_FLAGS, "-DLT_HOST_LOOP_TIME_S=0.001", "-o", str(so), *sources, "-lm"], check=True
    )
    return ctypes.CDLL(str(so))


class CStep:
    """One generated C controller, stepped sample by sample through ctypes."""

    def __init__(self, lib, prefix: str, precision: str):
        self.lib, self.prefix = lib, prefix
        self.real = ctypes.c_float if precision == "single" else ctypes.c_double
        self.dtype = DTYPES[precision]
        self.state = ctypes.create_string_buffer(self._f("state_size")())
        for name in ("step", "mil_step"):
            if hasattr(lib, f"{prefix}_{name}"):
                self._f(name).restype = self.real
        self._f("init")(self.state)

    def _f(self, name):
        return getattr(self.lib, f"{self.prefix}_{name}")

    def step(self, z_vs, w) -> float:
        return self._f("step")(self.state, self.real(z_vs), self.real(w))

    def mil_step(self, a_g, w) -> tuple[float, float]:
        z = self.real()
        u = self._f("mil_step")(self.state, self.real(a_g), self.real(w), ctypes.byref(z))
        return u, z.value

    def run(self, z_vs, w) -> np.ndarray:
        return np.array([self.step(a, b) for a, b in zip(z_vs, w)], self.dtype)

    @property
    def fault(self) -> int:
        return self._f("fault")(self.state)

    @property
    def active(self) -> int:
        return self._f("active")(self.state)

    def reset(self) -> None:
        self._f("reset")(self.state)

    def check_loop_time(self, measured_s: float) -> int:
        return self._f("check_loop_time")(self.state, ctypes.c_double(measured_s))


def safe_commands(raw, stroke, du_max, dtype, u0=0.0):
    """The clamp and the rate limit from the command ``u0``, written independently of the
    generators (numpy scalars of ``dtype``)."""
    stroke, du_max, u_safe = dtype(stroke), dtype(du_max), dtype(u0)
    out = np.empty(len(raw), dtype)
    for k, r in enumerate(np.asarray(raw, dtype)):
        u = min(max(r, -stroke), stroke)
        if u - u_safe > du_max:
            u = u_safe + du_max
        elif u - u_safe < -du_max:
            u = u_safe - du_max
        out[k] = u_safe = u
    return out


@pytest.fixture(scope="module")
def biased():
    """4 s of the broadband record (0.35 g) plus a z_vs bias of 1 in/s^2 and a 1000 in/s^2
    pulse from 1.00 to 1.02 s (the raw command jumps 0.57 in in one loop against the rate
    limit's 0.024 in; it passes the stroke later, from the bias); w = -9.3 a + 25 lbf."""
    _, a = broadband_record(duration_s=4.0)
    z = a + 1.0
    z[int(1.0 / LOOP_TIME_S) : int(1.02 / LOOP_TIME_S)] += 1000.0
    return z, -9.3 * a + 25.0


# ---------------------------------------------------------------- C


@pytest.mark.parametrize("prefix,precision", [("g_f", "single"), ("g_d", "double")])
def test_c_clamp_and_rate_limit_are_the_runtime_command_limited(lib, discrete, biased, prefix, precision):
    z, w = biased
    c = CStep(lib, prefix, precision)
    u = c.run(z, w)
    raw = MILRuntime(discrete, precision=precision).run(z, w)
    dtype = DTYPES[precision]
    du = LIMITS.rate_step_in(LOOP_TIME_S)
    np.testing.assert_array_equal(u, safe_commands(raw, LIMITS.stroke_in, du, dtype))
    # the unguarded command leaves the stroke (the bias integrates); the guarded one does not
    assert np.max(np.abs(raw)) > LIMITS.stroke_in
    assert np.max(np.abs(u)) <= dtype(LIMITS.stroke_in)
    # u_safe + du_max is rounded at the command's magnitude (<= the stroke): one spacing there
    assert np.max(np.abs(np.diff(u))) <= dtype(du) + np.spacing(dtype(LIMITS.stroke_in))
    assert c.fault == Fault.CLAMP | Fault.RATE  # sticky, and neither holds


def test_c_bias_over_60_s_stays_within_the_stroke(lib):
    # Issue 18, finding 3: a z_vs bias of 1 in/s^2 integrated to u = 1802 in after 60 s.
    c = CStep(lib, "g_f", "single")
    n = int(round(60.0 / LOOP_TIME_S))
    u = c.run(np.ones(n), np.zeros(n))
    assert np.all(np.isfinite(u)) and np.max(np.abs(u)) == np.float32(LIMITS.stroke_in)
    assert c.fault & Fault.CLAMP and not c.fault & HOLD_BITS


@pytest.mark.parametrize("channel", ["z_vs", "w"])
@pytest.mark.parametrize(
    "value,bit", [(np.nan, Fault.INPUT_NAN), (np.inf, Fault.INPUT_NAN), (1e30, Fault.INPUT_RANGE)]
)
def test_c_bad_input_latches_and_holds_the_last_safe_command(lib, biased, channel, value, bit):
    z, w = (np.array(v[:2000]) for v in biased)
    k = 1500
    (z if channel == "z_vs" else w)[k] = value
    c = CStep(lib, "g_f", "single")
    u = np.empty(z.size, np.float32)
    for i in range(z.size):
        u[i] = c.step(z[i], w[i])
        if i == k:
            assert c.active == bit
    assert np.all(np.isfinite(u))
    np.testing.assert_array_equal(u[k:], u[k - 1])  # held, also after the input is good again
    assert c.fault & HOLD_BITS == bit and c.active == 0


def test_c_input_just_beyond_its_range_holds_and_just_within_does_not(lib):
    c = CStep(lib, "g_f", "single")
    c.step(np.nextafter(np.float32(LIMITS.accel_limit_in_s2), np.float32(0)), 0.0)
    assert not c.fault & HOLD_BITS
    c.step(0.0, np.float32(LIMITS.force_limit_lbf) * np.float32(1.0001))
    assert c.fault & HOLD_BITS == Fault.INPUT_RANGE


def test_c_reset_clears_the_fault_and_ramps_from_the_held_command(lib, discrete):
    c = CStep(lib, "g_f", "single")
    for _ in range(400):
        held = c.step(1000.0, 0.0)  # drives the command to the stroke at the rate limit
    assert held == np.float32(LIMITS.stroke_in)
    c.step(np.nan, 0.0)
    assert c.step(0.0, 0.0) == held and c.fault & Fault.INPUT_NAN
    c.reset()
    assert c.fault == 0
    # controller at rest: its raw command for zero inputs is 0, reached from the held one at the rate limit
    u = c.run(np.zeros(300), np.zeros(300))
    du = np.float32(LIMITS.rate_step_in(LOOP_TIME_S))
    np.testing.assert_array_equal(u, safe_commands(np.zeros(300), LIMITS.stroke_in, du, np.float32, u0=held))
    assert u[0] == np.float32(held) - du and u[-1] == 0.0
    assert c.fault == Fault.RATE


def test_c_runaway_command_latches_overflow_and_holds(lib, runaway):
    c = CStep(lib, "ov_f", "single")
    bits = []
    for _ in range(RUNAWAY_N):
        u = c.step(RUNAWAY_Z, 0.0)
        bits.append(c.active)
    k = first_beyond_value_limit(runaway)
    assert 20000 < k < RUNAWAY_N and bits.index(Fault.OVERFLOW) == k
    assert c.fault & HOLD_BITS == Fault.OVERFLOW and u == np.float32(LIMITS.stroke_in)


def test_c_loop_time_check(lib):
    c = CStep(lib, "g_f", "single")
    assert c.check_loop_time(LOOP_TIME_S * 1.04) == 1 and c.fault == 0
    for off in (LOOP_TIME_S * 1.06, np.nan, 0.0):
        c.reset()
        assert c.check_loop_time(off) == 0 and c.fault == Fault.LOOP_TIME
    u0 = c.step(0.0, 0.0)
    assert c.step(1000.0, 0.0) == u0  # held
    # defined at compile time: the init checks the host's loop time (1 ms against 0.5 ms)
    assert CStep(lib, "lt", "single").fault == Fault.LOOP_TIME


def test_c_mil_step_holds_u_and_z_vs_on_a_bad_input(lib):
    _, a = broadband_record(duration_s=1.0)
    c = CStep(lib, "gm_f", "single")
    out = [c.mil_step(x, -9.3 * x) for x in a[:1000]]
    u_held, z_held = out[-1]
    assert c.fault & HOLD_BITS == 0
    assert c.mil_step(np.nan, 0.0) == (u_held, z_held)
    assert c.mil_step(a[1000], 0.0) == (u_held, z_held) and c.fault & Fault.INPUT_NAN


# ---------------------------------------------------------------- ST (transpiled)


def _st(controller, precision, block="imil_controller", vs=None):
    text = render_st(controller, precision, "imil", vs=vs, limits=LIMITS)["imil.st"]
    return STBlock(text, block, "imil", DTYPES[precision])


def test_st_clamp_and_rate_limit_equal_the_c(lib, discrete, biased):
    # the biased record: the transpiled ST and the compiled C, both single precision
    z, w = biased
    fb = _st(discrete, "single")
    u_st = np.array([fb(z_vs=a, w=b)["u"] for a, b in zip(z, w)], np.float32)
    raw = MILRuntime(discrete, precision="single").run(z, w)
    du = LIMITS.rate_step_in(LOOP_TIME_S)
    np.testing.assert_array_equal(u_st, safe_commands(raw, LIMITS.stroke_in, du, np.float32))
    np.testing.assert_array_equal(u_st, CStep(lib, "g_f", "single").run(z, w))
    assert fb.env["fault"] == Fault.CLAMP | Fault.RATE


@pytest.mark.parametrize(
    "value,bit", [(np.nan, Fault.INPUT_NAN), (-np.inf, Fault.INPUT_NAN), (1e30, Fault.INPUT_RANGE)]
)
def test_st_bad_input_latches_holds_and_resets(discrete, value, bit):
    fb = _st(discrete, "single")
    for _ in range(300):
        held = fb(z_vs=1000.0, w=0.0)["u"]
    assert fb(z_vs=0.0, w=value)["active"] == bit
    for _ in range(5):
        assert fb(z_vs=0.0, w=0.0)["u"] == held and fb.env["active"] == 0
    assert fb.env["fault"] & HOLD_BITS == bit
    out = fb(z_vs=0.0, w=0.0, reset=True)
    assert out["fault"] == Fault.RATE and out["u"] == held - np.float32(LIMITS.rate_step_in(LOOP_TIME_S))
    fb.env["reset"] = False
    assert all(np.isfinite(fb(z_vs=0.0, w=0.0)["u"]) for _ in range(10))


def test_st_overflow_and_loop_time(runaway, discrete):
    fb = _st(runaway, "single")
    bits = [fb(z_vs=RUNAWAY_Z, w=0.0)["active"] for _ in range(RUNAWAY_N)]
    assert bits.index(Fault.OVERFLOW) == first_beyond_value_limit(runaway)
    assert fb.env["fault"] & HOLD_BITS == Fault.OVERFLOW and fb.env["u"] == np.float32(LIMITS.stroke_in)
    fb = _st(discrete, "single")
    assert fb(z_vs=0.0, w=0.0, loop_time_s=LOOP_TIME_S * 1.04)["fault"] == 0
    assert fb(z_vs=0.0, w=0.0, loop_time_s=LOOP_TIME_S * 1.06)["fault"] == Fault.LOOP_TIME


def test_st_mil_block_holds_u_and_z_vs(discrete):
    _, a = broadband_record(duration_s=0.5)
    fb = _st(discrete, "single", "imil_mil", vs=presets.get("SD2"))
    for x in a:
        out = fb(a_g=x, w=-9.3 * x)
    held = (out["u"], out["z_vs"])
    assert fb.env["fault"] & HOLD_BITS == 0
    out = fb(a_g=np.nan, w=0.0)
    assert (out["u"], out["z_vs"]) == held and out["fault"] & Fault.INPUT_NAN


# ---------------------------------------------------------------- export refuses what it cannot render


def test_a_coefficient_beyond_the_precision_is_refused(discrete):
    # Issue 18, finding 3: a 1e308 coefficient exported "inf.0f" with exit 0.
    big = discretize(
        TransferFunction([1e30], [1.0, 10.0]), TransferFunction([0.0], [1.0]), LOOP_TIME_S, fc_hz=FC_HZ
    )
    for fmt in ("c", "st", "json", "csv"):
        with pytest.raises(ConfigError, match=r"H_uz: expected discrete coefficients .*single precision"):
            render(big, fmt, "single", limits=LIMITS)
    with pytest.raises(ConfigError, match="limits"):
        render(discrete, "c", "single")
    text = render(big, "c", "double", limits=LIMITS)["imil.c"]  # 1e30 is a double
    assert "inf.0" not in text and "nan" not in text
