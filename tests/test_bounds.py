"""Bounded work (issue 18, finding 8): grids, cycles, periods and records refused before allocating.

The audit saw ``imil motion spectrum --periods log:0.01:10:100000000`` climb to
8.9 GB and ``imil vs loops --cycles 1e7`` try to allocate 149 GiB.  Every
bound is in impedance_mil/bounds.py and docs/limits.md; the library checks
it before it allocates, so each request below is refused at once.
"""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.bounds import (
    MAX_MULTISINE_ITERATIONS,
    MAX_RECORD_SAMPLES,
    MAX_SPECTRUM_PERIODS,
    MAX_SPECTRUM_STEPS,
    check_count,
)
from impedance_mil.errors import ConfigError, DataFileError
from impedance_mil.signals import GroundMotion, builtin_motion, read_at2, response_spectrum
from impedance_mil.signals.multisine import design_multisine
from impedance_mil.signals.spectrum import log_periods
from impedance_mil.virtual.excitation import harmonic_ground_motion


def test_check_count_names_the_option_and_the_limit():
    assert check_count("--x", 10, 10, "things") == 10
    for bad in (11, float("inf"), float("nan")):
        with pytest.raises(ConfigError, match=r"^--x: expected at most 10 things \(docs/limits\.md\)"):
            check_count("--x", bad, 10, "things")


def test_spectrum_periods_are_bounded():
    gm = builtin_motion("elcentro")
    with pytest.raises(ConfigError, match=f"^periods: expected at most {MAX_SPECTRUM_PERIODS} periods"):
        response_spectrum(gm.accel, gm.time_step, np.linspace(0.01, 10.0, MAX_SPECTRUM_PERIODS + 1))
    # Periods x samples: 1001 periods of a record of 2e6 samples is 2e9 oscillator steps.
    long = np.zeros(MAX_SPECTRUM_STEPS // 1000 + 1)
    with pytest.raises(ConfigError, match="oscillator steps"):
        response_spectrum(long, 0.001, np.linspace(0.1, 1.0, 1000))
    # log:MIN:MAX:N is refused before numpy allocates the N periods.
    with pytest.raises(ConfigError, match=r"^--periods: expected at most 10000 periods"):
        log_periods(0.01, 10.0, 100_000_000)
    assert log_periods(0.01, 10.0, 100).size == 100


def test_motion_spectrum_command_refuses_a_huge_grid(imil, tmp_path):
    out = imil("motion", "spectrum", "elcentro", "--periods", "log:0.01:10:100000000", "--json", cwd=tmp_path)
    assert out.returncode == 2
    assert out.stderr.strip() == (
        "imil: error: --periods: expected at most 10000 periods (docs/limits.md), got 100000000"
    )


def test_harmonic_cycles_are_bounded():
    # 1e7 cycles of 1 Hz at 0.5 ms: 2e10 samples, 149 GiB per array.
    with pytest.raises(ConfigError, match=f"^cycles: expected at most {MAX_RECORD_SAMPLES} samples"):
        harmonic_ground_motion(100.0, 1.0, cycles=1e7, dt=0.0005)
    n_ok = harmonic_ground_motion(100.0, 1.0, cycles=3.0, dt=0.0005).size
    assert n_ok == 7000  # (3 + 0.5 ramp) cycles of 1 s at 0.5 ms


def test_vs_loops_command_refuses_1e7_cycles(imil, tmp_path):
    out = imil("vs", "loops", "SD2", "-o", tmp_path / "l.png", "--cycles", "1e7")
    assert out.returncode == 2 and out.stderr.startswith(
        "imil: error: cycles: expected at most 4194304 samples"
    )
    # A recorded motion held over 1e7 steps per sample: 5.4e10 samples (400 GiB).
    out = imil("vs", "loops", "SD2", "--motion", "elcentro", "--dt", "1e-9", "-o", tmp_path / "l.png")
    assert out.returncode == 2 and out.stderr.startswith("imil: error: dt: expected at most 4194304 samples")
    assert not list(tmp_path.iterdir())


def test_records_are_bounded():
    with pytest.raises(ConfigError, match=r"^accel: expected at most 4194304 samples in a record"):
        GroundMotion(0.01, np.zeros(MAX_RECORD_SAMPLES + 1))
    gm = GroundMotion(0.01, np.zeros(MAX_RECORD_SAMPLES // 100))
    with pytest.raises(ConfigError, match="^time_step: expected at most 4194304 samples in the resampled"):
        gm.resampled(0.01 / 1000)  # 1000 times more samples


def test_multisine_work_is_bounded():
    with pytest.raises(ConfigError, match=r"^multisine\.n_periods: expected at most 4194304 samples"):
        design_multisine(n_points=1 << 20, n_periods=8, phases="schroeder")
    with pytest.raises(ConfigError, match=r"^multisine\.iterations: expected at most 10000"):
        design_multisine(iterations=MAX_MULTISINE_ITERATIONS + 1)
    with pytest.raises(ConfigError, match=r"^multisine\.n_points: expected a whole number"):
        design_multisine(n_points=8192.5, phases="schroeder")


def test_at2_header_asking_for_too_many_samples_is_refused_before_reading(tmp_path):
    path = tmp_path / "huge.AT2"
    path.write_text(
        "PEER\nrecord\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 100000000, DT= .0100 SEC\n 0.1 0.2\n"
    )
    with pytest.raises(DataFileError, match=r"line 4: NPTS = 100000000 is more than 4194304 samples"):
        read_at2(path)
