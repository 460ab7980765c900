"""GroundMotion: scaling, time scaling, resampling, integration, baseline correction."""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.signals import GroundMotion, builtin_motion
from impedance_mil.units import G0


def _ramp_motion(dt=0.01, n=201, slope=3.0):
    return GroundMotion(dt, slope * np.arange(n) * dt, "ramp", "test")


def test_value_object_is_frozen_and_read_only():
    motion = _ramp_motion()
    with pytest.raises(AttributeError):
        motion.time_step = 1.0
    with pytest.raises(ValueError):
        motion.accel[0] = 1.0


@pytest.mark.parametrize(
    ("dt", "accel", "key"),
    [
        (0.0, [1.0, 2.0], "time_step"),
        (-1.0, [1.0, 2.0], "time_step"),
        (float("nan"), [1, 2], "time_step"),
        (0.01, [1.0], "accel"),
        (0.01, [[1.0, 2.0]], "accel"),
        (0.01, [1.0, float("nan")], "accel"),
    ],
)
def test_invalid_construction(dt, accel, key):
    with pytest.raises(ConfigError, match=key):
        GroundMotion(dt, np.array(accel, dtype=float))


def test_integration_exact_for_ramp():
    # a = c t  =>  v = c t^2 / 2, d = c t^3 / 6 (closed form); the integrator is exact for
    # piecewise-linear acceleration, so only rounding remains (rtol 1e-12).
    motion = _ramp_motion()
    t = motion.time
    np.testing.assert_allclose(motion.velocity(), 3.0 * t**2 / 2, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(motion.displacement(), 3.0 * t**3 / 6, rtol=1e-12, atol=1e-14)


def test_scaled_to_pga_and_report_gm1():
    # Report Table 8.1: GM1 = El Centro time-scaled by 2 and scaled to 0.8 g.
    gm1 = builtin_motion("elcentro").time_scaled(2.0).scaled_to_pga(0.8)
    assert gm1.pga_g == pytest.approx(0.8, rel=1e-12)
    assert gm1.pga == pytest.approx(0.8 * G0, rel=1e-12)
    assert gm1.time_step == pytest.approx(0.005, rel=1e-15)
    with pytest.raises(ConfigError, match="pga"):
        gm1.scaled_to_pga(-0.1)
    with pytest.raises(ConfigError, match="pga"):
        GroundMotion(0.01, np.zeros(10)).scaled_to_pga(0.5)


def test_time_scaling_laws():
    # Compression t' = t/s at the same accelerations: v' = v/s, d' = d/s^2 (exact algebra).
    motion = builtin_motion("elcentro")
    fast = motion.time_scaled(2.0)
    assert fast.duration == pytest.approx(motion.duration / 2, rel=1e-15)
    np.testing.assert_allclose(fast.velocity(), motion.velocity() / 2, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fast.displacement(), motion.displacement() / 4, rtol=1e-12, atol=1e-12)
    with pytest.raises(ConfigError):
        motion.time_scaled(0.0)


def test_resample_upsampling_preserves_band_limited_signal():
    # A 2 Hz sine at 100 Hz upsampled 20x to 2000 Hz equals the sine at the new times; a Hann
    # taper keeps the record ends at zero (resample_poly pads with zeros).  Tolerance 1e-3 of the
    # amplitude: the Kaiser(5) polyphase filter's passband ripple is below that at 2 Hz / 50 Hz.
    dt, n = 0.01, 1001
    t = np.arange(n) * dt
    window = np.sin(np.pi * t / t[-1]) ** 2
    signal = window * np.sin(2 * np.pi * 2.0 * t)
    up = GroundMotion(dt, signal).resampled(0.0005)
    assert up.time_step == pytest.approx(0.0005, rel=1e-12)
    tu = up.time[: (n - 1) * 20 + 1]
    expected = np.sin(np.pi * tu / t[-1]) ** 2 * np.sin(2 * np.pi * 2.0 * tu)
    np.testing.assert_allclose(up.accel[: tu.size], expected, atol=1e-3)


def test_resample_downsampling_is_anti_aliased():
    # 40 Hz sine sampled at 200 Hz, resampled to 50 Hz (Nyquist 25 Hz): without anti-aliasing it
    # would alias to 10 Hz at full amplitude; the filter must remove >= 99 % of it (interior samples).
    dt = 0.005
    t = np.arange(4001) * dt
    down = GroundMotion(dt, np.sin(2 * np.pi * 40.0 * t)).resampled(0.02)
    assert down.time_step == pytest.approx(0.02, rel=1e-12)
    assert np.max(np.abs(down.accel[50:-50])) < 1e-2


def test_resample_refuses_irrational_ratio():
    with pytest.raises(ConfigError, match="time_step"):
        _ramp_motion().resampled(0.01 / np.pi)


@pytest.mark.parametrize("order", [1, 2, 3, 5])
def test_baseline_correction_ends_at_rest(order):
    # Constraint of the method: final velocity and displacement are zero (to rounding).
    raw = builtin_motion("elcentro-chopra")
    offset = GroundMotion(raw.time_step, raw.accel + 0.002 * G0)  # a 2 mg offset drifts ~ metres
    corrected = offset.baseline_corrected(order)
    assert abs(corrected.velocity()[-1]) < 1e-9 * corrected.pgv
    assert abs(corrected.displacement()[-1]) < 1e-9 * corrected.pgd
    # The offset is a degree-0 polynomial, which every order removes exactly: corrected offset
    # record equals corrected raw record (same linear projection).
    np.testing.assert_allclose(corrected.accel, raw.baseline_corrected(order).accel, atol=1e-9 * G0)


def test_baseline_correction_minimises_displacement():
    # Higher orders minimise the displacement RMS over a larger polynomial space: never worse.
    raw = builtin_motion("elcentro-chopra")
    rms = [np.sqrt(np.mean(raw.baseline_corrected(k).displacement() ** 2)) for k in (1, 2, 3, 4)]
    assert all(b <= a * (1 + 1e-9) for a, b in zip(rms[:-1], rms[1:]))
    with pytest.raises(ConfigError, match="order"):
        raw.baseline_corrected(0)


def test_trim():
    motion = _ramp_motion()
    part = motion.trimmed(0.5, 1.0)
    assert part.npts == 51 and part.accel[0] == pytest.approx(1.5)
    with pytest.raises(ConfigError, match="trim"):
        motion.trimmed(1.0, 0.5)
