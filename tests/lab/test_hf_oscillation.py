"""The high-frequency instability interlock (issue 17, item 4): trip ``hf_oscillation``.

The criterion (:mod:`impedance_mil.lab.oscillation`): the measured table
acceleration, high-passed above 15 Hz, grows by more than 2x from one 0.2 s
window to the next three windows running, starting from a window at least
ten times the accelerometer noise.  Tests: the compiled detector against the
closed form of a growing sinusoid; an unstable table (K_p above the report's
stable range) stopped by this cause while nothing else would stop it; the
cause through the run file, the JSON summary and the campaign claims; the
LTI loop; the configuration checks.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from impedance_mil.campaign.claims import run_stability
from impedance_mil.errors import ConfigError
from impedance_mil.lab.experiments import run_mil, run_tracking
from impedance_mil.lab.kernels import hf_window_history
from impedance_mil.lab.labfile import load_lab
from impedance_mil.lab.loop import simulate
from impedance_mil.lab.lti_plant import virtual_table_for
from impedance_mil.lab.oscillation import default_floor, growth_statistic, highpass_coefficients
from impedance_mil.lab.results import load_run, save_run
from impedance_mil.lab.runfile import trip_summary
from impedance_mil.lab.setup import DEFAULT_NOISE_V, SafetyLimits, accelerometer_noise, default_sensors
from impedance_mil.lab.trips import TripCause
from impedance_mil.plant import LinearTable, default_table_path
from impedance_mil.plant.nonlinear import NonlinearTable
from impedance_mil.signals import builtin_motion
from impedance_mil.specimens import FluidVessel
from impedance_mil.virtual import presets

from .conftest import report_parameters

T = 0.0005  # the report's loop time [s]


@pytest.fixture(scope="module")
def table():
    return NonlinearTable.from_linear(report_parameters())


def _bilinear_response(hp, s: complex) -> complex:
    """H(z) of the high-pass section at z = exp(s T): its response to exp(s t) [-]."""
    z = np.exp(s * T)
    return (hp.b0 + hp.b1 / z + hp.b2 / z**2) / (1.0 + hp.a1 / z + hp.a2 / z**2)


def test_defaults_are_the_stated_ones(table):
    v = SafetyLimits().kernel_values(table)
    # 0.2 s at 500 us: 400 loops; 2x growth, 3 windows; floor 10 x 1 mV x 0.6711 g/V (Table 7.1).
    assert v.hf_filter.window_loops == 400 and v.hf_growth == 2.0 and v.hf_windows == 3
    assert v.hf_floor == pytest.approx(10 * DEFAULT_NOISE_V * 0.6711 * 386.08858, rel=1e-6)
    assert v.hf_floor == default_floor()
    # The section's -3 dB point is the cutoff (prewarped bilinear Butterworth), and it blocks DC.
    hp = v.hf_filter
    assert abs(_bilinear_response(hp, 2j * math.pi * 15.0)) == pytest.approx(1 / math.sqrt(2), rel=1e-12)
    assert hp.b0 + hp.b1 + hp.b2 == pytest.approx(0.0, abs=1e-15)
    assert SafetyLimits(hf_cutoff=None).kernel_values(table).hf_filter.window_loops == 0


def test_a_growing_oscillation_trips_when_the_closed_form_says(table):
    # z = A exp(sigma t) sin(omega t), 40 Hz, sigma = 5 1/s (amplitude x2.72 per 0.2 s window).
    # After its transient the filter's output is |H(s)| A exp(sigma t) sin(omega t + arg H(s)),
    # H at s = sigma + j omega (the steady state of an exponential input).  The window rms of
    # that closed form first reaches the floor in window j0; growth (2.72 > 2) then counts in
    # windows j0+1, j0+2, j0+3: the trip is at the end of window j0 + 3.
    v = SafetyLimits().kernel_values(table)
    hp, n_w = v.hf_filter, v.hf_filter.window_loops
    sigma, omega, amplitude = 5.0, 2 * math.pi * 40.0, 0.01
    t = np.arange(int(4.0 / T)) * T
    z = amplitude * np.exp(sigma * t) * np.sin(omega * t)
    h = _bilinear_response(hp, complex(sigma, omega))
    ideal = abs(h) * amplitude * np.exp(sigma * t) * np.sin(omega * t + np.angle(h))
    windows = ideal[: (t.size // n_w) * n_w].reshape(-1, n_w)
    ideal_rms = np.sqrt(np.mean(windows**2, axis=1))
    j0 = int(np.argmax(ideal_rms >= v.hf_floor))
    rms, count = hf_window_history(v, z)
    j_trip = int(np.argmax(count >= 3))
    assert j_trip == j0 + 3
    # For these numbers: the floor (2.59 in/s**2) is reached in window 6 (1.2-1.4 s), the
    # trip comes at the end of window 9 (2.0 s).
    assert (j0, (j_trip + 1) * n_w * T) == (6, pytest.approx(2.0, abs=1e-12))
    # The compiled filter's window rms against the closed form, once the transient is gone.
    np.testing.assert_allclose(rms[2:12], ideal_rms[2:12], rtol=1e-3)
    # A steady oscillation of any size never trips.
    steady = 500.0 * np.sin(omega * t)
    assert hf_window_history(v, steady)[1].max() == 0


def test_unstable_delta_p_gain_trips_hf_oscillation_and_nothing_else_would(table):
    # K_p = 0.0022 V/psi on the bare table (the report's tuning: 0.001; above about 0.0021
    # the oil-column loop of the virtual table is unstable): from rest, with the sensor
    # noise alone, the 15+ Hz acceleration grows (window rms 0.8, 1.6, 1.5, 5.1, 16, 51,
    # 123 in/s**2) to a limit cycle near 200 in/s**2 rms (0.5 g).  Measured: the detector
    # trips at the end of the 7th window (1.3995 s, the loop before 1.4 s); with it off, no
    # interlock stops the run in 6 s -- not stroke, not divergence, not the valve rules.
    unstable = NonlinearTable.from_linear(dataclasses.replace(report_parameters(), Kp=0.0022))
    u = np.zeros(int(6.0 / T))
    r = simulate(unstable, command=u)
    assert r.trip.cause is TripCause.HF_OSCILLATION and r.trip.unit == "in/s**2"
    assert r.trip.time_s == pytest.approx(1.3995, abs=T / 2)
    assert r.trip.value > 8 * default_floor() and r.n_samples == round(r.trip.time_s / T)
    off = simulate(unstable, command=u, limits=SafetyLimits(hf_cutoff=None))
    assert off.trip is None
    assert np.std(off.z[-4000:]) > 100.0  # the limit cycle the detector stopped [in/s**2]
    # The same table at the report's K_p: no trip in 6 s.
    assert simulate(table, command=u).trip is None


@pytest.mark.parametrize("depth", [0.0, 42.0])
def test_the_reports_stable_tracking_runs_do_not_trip(table, depth):
    # Section 8's tracking, GM1 (El Centro x2 time scale, 0.8 g), the empty vessel and
    # 42 in of water (mass ratios 2.5 and 0.75), the whole 26.9 s.  The ground motion's
    # 15+ Hz content rises at its onset (window rms up to 56 in/s**2), but never doubles
    # three windows running.  Measured statistic (largest smallest ratio of 3 consecutive
    # windows from above the floor, on the recorded true z): 1.37 (0 in) and 1.53 (42 in)
    # against hf_growth = 2; 36 in: 1.49.  With the 1 mV noise added: within 0.02 of these.
    motion = builtin_motion("elcentro").time_scaled(2.0).scaled_to_pga(0.8)
    done = run_tracking(report_parameters(), motion, specimen=FluidVessel(water_depth_in=depth))
    run = done.run
    assert run.trip is None and run.n_samples == done.motion.accel.size
    v = SafetyLimits().kernel_values(table)
    rms, _ = hf_window_history(v, run.z)
    assert 1.0 < growth_statistic(rms, v.hf_windows, v.hf_floor) < v.hf_growth


def test_the_default_mil_run_does_not_trip(table):
    # SD2 with the 36 in vessel (the bench case, El Centro x2 at 0.6 g, 26.9 s): the 15+ Hz
    # window rms stays below 3.6 in/s**2; measured statistic 0.55 against 2.
    motion = builtin_motion("elcentro").time_scaled(2.0).scaled_to_pga(0.6)
    run = run_mil(
        report_parameters(), presets.get("SD2"), motion, specimen=FluidVessel(water_depth_in=36.0)
    ).run
    assert run.trip is None
    v = SafetyLimits().kernel_values(table)
    rms, _ = hf_window_history(v, run.z)
    assert growth_statistic(rms, v.hf_windows, v.hf_floor) < 0.5 * v.hf_growth


def test_the_cause_reaches_the_run_file_the_json_and_the_claims(tmp_path):
    unstable = NonlinearTable.from_linear(dataclasses.replace(report_parameters(), Kp=0.0022))
    r = simulate(unstable, command=np.zeros(int(3.0 / T)))
    summary = trip_summary(r)
    assert summary["aborted"] is True and summary["trip"]["limit"] == "hf_oscillation"
    assert summary["trip"]["time_s"] == r.trip.time_s and summary["trip"]["unit"] == "in/s**2"
    assert "hf_oscillation" in summary["abort_reason"]
    saved = load_run(save_run(r, tmp_path / "r.h5"))
    assert saved.trip == r.trip
    assert run_stability({"status": "aborted", "trip_limit": "hf_oscillation"}) == "unstable"


def test_the_lti_loop_has_the_detector():
    # The table's own linear model at K_p = 0.0025 V/psi has its oil-column poles in the
    # right half-plane; a 1e-4 in step starts the growth.  Measured: the detector trips at
    # 1.3995 s; with it off the actuator-force interlock stops the run only at 1.66 s,
    # when the pressure has reached 95 % of the stall force.
    lti = virtual_table_for(LinearTable(dataclasses.replace(report_parameters(), Kp=0.0025)))
    u = np.full(int(6.0 / T), 1e-4)
    r = simulate(lti, command=u)
    assert r.trip.cause is TripCause.HF_OSCILLATION
    assert r.trip.time_s == pytest.approx(1.3995, abs=T / 2)
    off = simulate(lti, command=u, limits=SafetyLimits(hf_cutoff=None))
    assert off.trip.cause is TripCause.ACTUATOR_FORCE and off.trip.time_s == pytest.approx(1.66, abs=T / 2)


def test_highpass_refuses_a_cutoff_above_nyquist():
    with pytest.raises(ValueError, match="limits.hf_cutoff"):
        highpass_coefficients(1000.0, T, 0.2)
    with pytest.raises(ValueError, match="limits.hf_window"):
        highpass_coefficients(15.0, T, 1e-5)


@pytest.mark.parametrize(
    "key, value",
    [("hf_growth", 1.0), ("hf_windows", 0), ("hf_windows", 2.5), ("hf_window", 0.0), ("hf_floor", -1.0)],
)
def test_bad_detector_settings_are_refused_naming_the_key(key, value):
    with pytest.raises(ValueError, match=f"limits.{key}"):
        SafetyLimits(**{key: value})


def _lab(tmp_path, text: str):
    path = tmp_path / "lab.toml"
    path.write_text(f'[table]\nfile = "{default_table_path()}"\n' + text)
    return path


def test_lab_file_sets_the_detector_or_switches_it_off(tmp_path):
    lab = load_lab(
        _lab(
            tmp_path,
            '[limits]\nhf_cutoff = "20 Hz"\nhf_window = "150 ms"\nhf_growth = 3\nhf_windows = 4\n'
            'hf_floor = "0.05 m/s**2"\n',
        )
    )
    assert (lab.limits.hf_cutoff, lab.limits.hf_window, lab.limits.hf_growth, lab.limits.hf_windows) == (
        pytest.approx(20.0),
        pytest.approx(0.15),
        3.0,
        4,
    )
    assert lab.limits.hf_floor == pytest.approx(0.05 / 0.0254, rel=1e-12)
    shown = lab.to_dict()["limits"]
    assert shown["hf_cutoff"] == pytest.approx(20.0) and shown["hf_floor"] == pytest.approx(0.05 / 0.0254)
    off = load_lab(_lab(tmp_path, '[limits]\nhf_cutoff = "none"\n'))
    assert off.limits.hf_cutoff is None and off.to_dict()["limits"]["hf_floor"] is None
    assert load_lab("report").to_dict()["limits"]["hf_cutoff"] == 15.0


@pytest.mark.parametrize(
    "text, key",
    [
        ('hf_cutoff = "1500 Hz"', "limits.hf_cutoff"),  # above the 1000 Hz Nyquist frequency
        ("hf_growth = 0.5", "limits.hf_growth"),
        ('hf_cutoff = "off"', "limits.hf_cutoff"),
    ],
)
def test_lab_file_refuses_a_bad_detector_setting_naming_the_key(tmp_path, text, key):
    with pytest.raises(ConfigError, match=key):
        load_lab(_lab(tmp_path, f"[limits]\n{text}\n"))


def test_the_floor_follows_a_noisier_accelerometer(table):
    # 10 mV rms on the 0.6711 g/V accelerometer (with its 16-bit quantization, LSB 20 V / 2**16):
    # ten times sqrt(noise^2 + LSB^2/12) x scale; a quieter channel keeps the default floor.
    noisy = default_sensors(noise_rms_v=0.01)
    lsb = 20.0 / 2**16
    expected = 10 * 0.6711 * 386.08858 * math.sqrt(0.01**2 + lsb**2 / 12)
    assert accelerometer_noise(noisy) * 10 == pytest.approx(expected, rel=1e-6)
    assert SafetyLimits().kernel_values(table, accelerometer_noise(noisy)).hf_floor == pytest.approx(
        expected, rel=1e-6
    )
    quiet = accelerometer_noise(default_sensors(noise_rms_v=0.0))
    assert SafetyLimits().kernel_values(table, quiet).hf_floor == default_floor()
