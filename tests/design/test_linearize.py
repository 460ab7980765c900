"""Equivalent linearization of hysteretic VS (design/linearize.py) and the constraints it changes."""

import numpy as np
import pytest

from impedance_mil.design import design_controller, virtual_model
from impedance_mil.design.linearize import equivalent_linearization, harmonic_cycle
from impedance_mil.units import TWO_PI
from impedance_mil.virtual import presets


def test_spring_damper_describing_function_is_exact():
    # A linear isolator F = k x + c v has N = k + j w c exactly (closed form); numerical cycle to 1e-6.
    sd = presets.get("SD2")
    N = harmonic_cycle(sd, 1.0, 2.0).stiffness
    assert N == pytest.approx(sd.k_s + 1j * TWO_PI * 2.0 * sd.c, rel=1e-6)


def test_nothing_changes_for_sd(table):
    # SD is linear: no equivalent is attached and every constraint number is the same.
    sd = presets.get("SD2")
    a = design_controller(table, virtual_model(sd, "SD2"), fc_hz=80.0, emit_warnings=False).constraints[0]
    b = design_controller(
        table, virtual_model(sd, "SD2", linearization="open-fh"), fc_hz=80.0, emit_warnings=False
    ).constraints[0]
    assert virtual_model(sd).equivalent is None and a == b


@pytest.mark.parametrize("D", [0.8, 2.0, 5.0])
def test_bouc_wen_tends_to_the_bilinear_closed_form(D):
    # Bouc-Wen with a large exponent is elastic-perfectly-plastic; its describing function is
    # Caughey's (1960): Re = a k_i + (1-a) k_i (p - sin(2p)/2)/pi, cos p = 1 - 2 u_y/D,
    # Im = 4 q_d (D - u_y)/(pi D^2) (AASHTO's loop area 4 Q_d (D - D_y)), plus w c.
    # Tolerance 1.5% of |N|: the n = 60 loop still rounds its corners over ~u_y/60.
    lr = presets.get("LR2").replace(n=60.0)
    f = 1.0
    p = np.arccos(1 - 2 * lr.u_y / D)
    re = lr.alpha * lr.k_i + (1 - lr.alpha) * lr.k_i * (p - np.sin(2 * p) / 2) / np.pi
    im = 4 * lr.q_d * (D - lr.u_y) / (np.pi * D**2) + TWO_PI * f * lr.c
    N = harmonic_cycle(lr, D, f).stiffness
    assert abs(N - (re + 1j * im)) <= 0.015 * abs(re + 1j * im)


@pytest.mark.parametrize("name", ["LR2", "FP2"])
def test_first_harmonic_of_the_nonlinear_vs_equals_the_equivalent_impedance(name):
    # Time-domain check: drive the nonlinear VS kernel (VirtualSystem.simulate, the report's RK3,
    # 2000 steps per cycle) with the harmonic-balance force for D = 1 in at 9 Hz, where constraint III
    # is decided; the first-harmonic z_vs/w over the last 4 of 12 cycles equals the describing-function
    # impedance at the measured amplitude within 0.2% (observed 0.01-0.03%; higher harmonics of the
    # displacement and the RK3 error are what is left).
    vs = presets.get(name)
    f, D = 9.0, 1.0
    w0 = TWO_PI * f
    W = (harmonic_cycle(vs, D, f).stiffness - vs.m_vs * w0**2) * D
    dt = 1.0 / f / 2000
    t = np.arange(24000) * dt
    r = vs.simulate(np.zeros(t.size), np.real(W * np.exp(1j * w0 * t)), dt=dt, x0=[D, 0.0, 1.0])
    last = slice(16000, None)
    e = np.exp(-1j * w0 * t[last])
    measured = np.mean(r.z_vs[last] * e) / np.mean(r.w[last] * e)
    amplitude = abs(2 * np.mean(r.displacement[last] * e))
    assert amplitude == pytest.approx(D, rel=0.01)
    expected = equivalent_linearization(vs, amplitude).frequency_response(f)
    assert abs(measured / expected - 1) < 2e-3


def test_grid_interpolation_matches_direct_cycles():
    # The describing function is tabulated at 5 points per decade; between grid points the
    # interpolation is within 0.5% of a direct cycle (FP2: the rate-dependent friction).
    vs = presets.get("FP2")
    eq = equivalent_linearization(vs, 1.0)
    for f in (0.013, 0.3, 7.7, 230.0):
        direct = harmonic_cycle(vs, 1.0, f).stiffness
        assert abs(eq.stiffness(f) - direct) <= 5e-3 * abs(direct)


@pytest.mark.parametrize("name", ["LR2", "FP2"])
def test_hysteretic_damping_helps_passivity_but_not_enough_at_80_hz(table, name):
    # Eq 9-2 with the standardized controller contains H_zw^vs, so the isolator's dissipation enters
    # constraint III.  Open f_h (lossless linear part): -11.6 deg near 8.6 Hz.  Describing function at
    # 1 in: the margin improves by more than 2 deg but III still fails (about -8 to -9 deg near 9.5 Hz):
    # rate-independent hysteresis dissipates per cycle, not per unit frequency (docs/design.md).
    vs = presets.get(name)
    open_fh = design_controller(
        table, virtual_model(vs, name, linearization="open-fh"), fc_hz=80.0, emit_warnings=False
    ).constraints[0]
    df = design_controller(table, virtual_model(vs, name), fc_hz=80.0, emit_warnings=False).constraints[0]
    assert open_fh.passivity_margin_deg < -11.0
    assert df.passivity_margin_deg > open_fh.passivity_margin_deg + 2.0
    assert not df.III and 5.0 < df.passivity_worst_hz < 15.0
    # The code method's viscous dashpot (c_eq matched at the effective frequency) credits w/w_eff times
    # more loss at 9 Hz; with it III holds: the verdict rests on that unjustified credit.
    visc = design_controller(
        table, virtual_model(vs, name, linearization="equivalent-viscous"), fc_hz=80.0, emit_warnings=False
    ).constraints[0]
    assert visc.III and visc.passivity_worst_hz > 100.0
