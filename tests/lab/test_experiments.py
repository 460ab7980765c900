"""Virtual experiments: FRF through the nonlinear table, identification, K_p study,
tracking (Section 8) and MIL (Section 9) runs.

References: the linear model (Eq 4-14b and its exact sampled-data form,
impedance_mil.plant), the report's qualitative claims of Sections 4.5, 8.3
and Appendix C, stated per test.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.signal

from impedance_mil.errors import LimitTripped
from impedance_mil.lab.experiments import kp_study, run_frf, run_mil, run_tracking
from impedance_mil.lab.identification import identify_table
from impedance_mil.lab.loop import simulate
from impedance_mil.lab.metrics import evaluate_run, vs_force_history
from impedance_mil.lab.runfile import MODEL_LOOP_KEYS, model_loop
from impedance_mil.lab.setup import ideal_sensors
from impedance_mil.plant import LinearTable
from impedance_mil.plant.nonlinear import Friction, NonlinearTable
from impedance_mil.signals import builtin_motion
from impedance_mil.signals.frf import estimate_frf
from impedance_mil.signals.multisine import design_multisine
from impedance_mil.specimens import FluidVessel
from impedance_mil.virtual import presets

from .conftest import eq_4_14b, report_parameters, ss_response


@pytest.fixture(scope="module")
def p():
    return report_parameters()


def _short_multisine(peak, rate=2000.0, n_points=4096, n_lines=200, f_max=100.0, periods=3):
    return design_multisine(
        peak=peak,
        n_points=n_points,
        n_lines=n_lines,
        f_max_hz=f_max,
        sample_rate_hz=rate,
        n_periods=periods,
        iterations=20,
    )


def test_small_amplitude_frf_equals_sampled_linear_model(p):
    # Whole pipeline (multisine -> nonlinear table -> H1): with 2e-3 in peak, no
    # friction and exact (unquantized) sensors, z/u equals the exact sampled-data linear model
    # (plant.SampledTable) within 1 % magnitude and 1 deg up to 100 Hz.
    table = NonlinearTable.from_linear(p, friction=Friction.none())
    ms = _short_multisine(2e-3)
    e = run_frf(
        p, table=table, multisine=ms, delay="sampled", identify=False, sensors=ideal_sensors(), quantize=False
    )
    e_run = e.run
    assert e_run.completed
    frf = estimate_frf(e_run.u, e_run.z, ms.n_points, ms.sample_rate_hz, lines=ms.lines)
    ref = LinearTable(p, delay="sampled").sampled().frequency_response("z", "u", frf.frequency_hz)
    assert np.max(np.abs(np.abs(frf.response / ref) - 1)) < 0.01
    assert np.max(np.abs(np.angle(frf.response / ref, deg=True))) < 1.0


def test_fast_loop_frf_approaches_continuous_eq_4_14b(p):
    # With a 10 us loop the digital controller approaches the analog one: the
    # small-amplitude FRF of the nonlinear table equals Eq 4-14b (continuous
    # feedback) within 1 % magnitude up to 100 Hz (feedback delay 15 us ->
    # 0.5 deg at 100 Hz; phase tolerance 1 deg).
    table = NonlinearTable.from_linear(p.replace(loop_time=10e-6), friction=Friction.none())
    ms = _short_multisine(2e-3, rate=1e5, n_points=16384, n_lines=16, f_max=100.0, periods=4)
    run = simulate(table, command=ms.signal, sensors=ideal_sensors(), quantize=False, substeps=1)
    frf = estimate_frf(run.u, run.x, ms.n_points, ms.sample_rate_hz, lines=ms.lines)
    A, B_u, _ = eq_4_14b(p)
    ref = ss_response(A, B_u, np.eye(5)[0], 0.0, frf.frequency_hz)
    assert np.max(np.abs(np.abs(frf.response / ref) - 1)) < 0.01
    assert np.max(np.abs(np.angle(frf.response / ref, deg=True))) < 1.0


def _linear_frf(p, ms, noise, seed=0):
    """z/u FRF of the exact sampled linear model driven by the multisine (+ output noise)."""
    st = LinearTable(p, delay="sampled").sampled()
    sys = scipy.signal.dlti(st.A, st.B_u[:, None], st.C["z"][None, :], [[st.D["z"][0]]], dt=p.loop_time)
    _, y, _ = scipy.signal.dlsim(sys, ms.signal)
    y = y[:, 0]
    if noise:
        y = y + noise * np.std(y) * np.random.default_rng(seed).standard_normal(y.size)
    return estimate_frf(ms.signal, y, ms.n_points, ms.sample_rate_hz, lines=ms.lines)


@pytest.mark.parametrize("noise, tol", [(0.0, 1e-4), (0.05, 0.03)])
def test_identification_recovers_linear_model(p, noise, tol):
    # Data from the sampled linear model with f_oil = 27 Hz, zeta = 0.09, d = 1e5
    # (Table 4.1); start 15 % off; recovered within 1e-4 (noiseless) or 3 %
    # (5 % output noise, 6 averaged periods).
    ms = _short_multisine(0.05, periods=7)
    frf = _linear_frf(p, ms, noise)
    start = p.replace(f_oil_hz=23.0, zeta_oil=0.11, d=0.85e5)
    ident = identify_table(frf, start, delay="sampled")
    for name in ("f_oil_hz", "zeta_oil", "d"):
        assert getattr(ident.parameters, name) == pytest.approx(getattr(p, name), rel=tol)


def test_kp_study_low_gain_fits_worse(p):
    # Sections 4.5.3.1 / 8.3.3: with K_p = 0.0002 V/psi the linear model fits the
    # table worse than with 0.001 V/psi.  Identified with the report's model
    # (first-order delay) and with the exact sampled one; measured misfit ratios
    # 1.22 and 1.4 with the 0.1 in multisine; required: > 1.1.
    ms = _short_multisine(0.1)
    for delay in ("first-order", "sampled"):
        study = kp_study(p, kp_values=(0.0002, 0.001), multisine=ms, delay=delay)
        low, high = study.misfit
        assert low > 1.1 * high, delay


def test_frf_trip_returns_the_data_up_to_the_trip(p):
    # A 3.5 in multisine at up to 100 Hz asks for far more than A_p (P_s - P_R) = 6300 lbf:
    # an interlock stops it; the experiment comes back with the trip and no FRF.
    ms = _short_multisine(3.5)
    e = run_frf(p, multisine=ms)
    assert not e.completed and e.run.trip is not None
    assert e.frf == {} and e.model == {} and e.identification is None
    assert 0 < e.run.n_samples < ms.signal.size
    assert e.run.trip.time_s == pytest.approx(e.run.n_samples * p.loop_time, abs=p.loop_time)
    with pytest.raises(LimitTripped, match=e.run.trip.limit):
        e.model_error("z")
    assert np.isnan(kp_study(p, kp_values=(0.001,), multisine=ms).misfit[0])


def test_frf_with_vessel_model_prediction(p):
    # Section 4.5.4: with the vessel (36 in of water) the prediction
    # H_zu + H_zw W/U from the measured load-cell force follows the measured
    # z/u within 10 % (RMS log error) below 20 Hz, where the linear model holds.
    ms = _short_multisine(0.05)
    e = run_frf(p, multisine=ms, specimen=FluidVessel.report_default(), identify=False)
    assert "w" in e.frf and e.identification is None
    assert e.model_error("z", (0.5, 20.0)) < 0.10


@pytest.fixture(scope="module")
def motion():
    # El Centro (RSN 6), time-scaled by 2 (Section 8.2), 0.4 g, first 6 s.
    return builtin_motion("elcentro").time_scaled(2).scaled_to_pga(0.4).trimmed(0, 6.0)


def test_tracking_heavy_article_needs_u_w(p, motion):
    # Section 8.3.2 / Figures 8.9c,f,i: with 42 in of water (mass ratio 2.5) the
    # interaction term u_w is needed: without it the 0.25-15 Hz spectral error is
    # several times larger (measured 4.5 % vs 17 %).
    heavy = FluidVessel(water_depth_in=42.0)
    with_uw = run_tracking(p, motion, specimen=heavy)
    without = run_tracking(p, motion, specimen=heavy, compensate=False)
    assert with_uw.run.completed and without.run.completed
    assert with_uw.metrics.spectral_error_low < 0.10
    assert without.metrics.spectral_error_low > 2 * with_uw.metrics.spectral_error_low
    assert np.all(without.run.u_w == 0)


@pytest.mark.parametrize("name", ["SD2", "LR2", "FP2"])
def test_mil_runs_imitate_the_vs(p, motion, name):
    # Section 9.3: the table imitates the VS acceleration accurately below ~20 Hz:
    # spectral error 0.25-15 Hz below 10 % (measured 3-5 %); the isolator's
    # dissipated energy is reproduced within 25 % (measured 6-14 %).
    r = run_mil(p, presets.get(name), motion, specimen=FluidVessel.report_default())
    assert r.run.completed and r.run.mode == "mil"
    assert r.metrics.spectral_error_low < 0.10
    assert abs(r.metrics.energy_error) < 0.25
    assert r.run.vs_states.shape == (r.run.n_samples, presets.get(name).n_states)


def test_mil_with_force_equilibrium_feedback(p, motion):
    # Appendix C, case ii): w_FE = m_st z - A_p dP instead of the load cells gives
    # similarly accurate MIL (SD3, high strength/stiffness): spectral errors below
    # 15 Hz within 2 percentage points of case i) (measured 3.47 % vs 3.47 %).
    vessel = FluidVessel.report_default()
    lc = run_mil(p, presets.get("SD3"), motion, specimen=vessel, feedback="lc")
    fe = run_mil(p, presets.get("SD3"), motion, specimen=vessel, feedback="fe")
    assert lc.run.completed and fe.run.completed
    assert abs(fe.metrics.spectral_error_low - lc.metrics.spectral_error_low) < 0.02
    np.testing.assert_array_equal(fe.run.w_used, fe.run.w_fe)
    np.testing.assert_array_equal(lc.run.w_used, lc.run.w_lc)


def test_identification_of_valve_poles(p):
    # Noiseless sampled-model data: the two valve poles (70, 110 Hz, Section 4.3.2)
    # are recovered together with f_oil, zeta_oil and d, within 1e-3.
    ms = _short_multisine(0.05, periods=3)
    frf = _linear_frf(p, ms, 0.0)
    start = p.replace(f_oil_hz=25.0, zeta_oil=0.1, d=0.9e5, valve_poles_hz=(60.0, 125.0))
    ident = identify_table(
        frf, start, delay="sampled", free=("f_oil_hz", "zeta_oil", "d", "valve_pole_1_hz", "valve_pole_2_hz")
    )
    assert ident.parameters.valve_poles_hz == pytest.approx((70.0, 110.0), rel=1e-3)
    assert ident.parameters.f_oil_hz == pytest.approx(27.0, rel=1e-3)


def test_a_mil_run_keeps_the_vs_force_its_energy_error_used(p, motion):
    # Issue 16: the VS model's force along the run is computed once, for the energy error and
    # for the model loop of the run file; both are what they were when each computed it.
    vs = presets.get("SD2")
    r = run_mil(p, vs, motion, specimen=FluidVessel.report_default())
    recomputed = vs_force_history(vs, r.run.vs_states)
    np.testing.assert_array_equal(r.vs_force, recomputed)
    again = evaluate_run(r.run, vs=vs, ground_displacement=r.motion.displacement())
    assert again.energy_error == r.metrics.energy_error
    loop = model_loop(r.run, vs, r.vs_force)
    np.testing.assert_array_equal(loop[MODEL_LOOP_KEYS[1]], model_loop(r.run, vs)[MODEL_LOOP_KEYS[1]])
    assert run_tracking(p, motion).vs_force is None
