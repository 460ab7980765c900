"""Pre-test feasibility check of a ground motion against the table's limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from impedance_mil.errors import ConfigError
from impedance_mil.signals import GroundMotion, TableLimits, builtin_motion, check_motion, required_rated_flow
from impedance_mil.units import G0


def test_report_limits_by_hand():
    # Section 3.4 / 4.3.2: Q = 57.75 in^3/s at 1000 psi, P_s = 3000 psi, A_p = 2.1 in^2, x_m = 3.2 in.
    # v_max = 57.75 * sqrt(3000/1000) / 2.1 = 47.6314 in/s; F = 2.1 * 3000 = 6300 lbf (hand, 1e-12).
    limits = TableLimits.report_default(specimen_weight=1200.0)
    assert limits.velocity_in_s == pytest.approx(57.75 * math.sqrt(3.0) / 2.1, rel=1e-12)
    assert limits.velocity_in_s == pytest.approx(47.6314, abs=1e-4)
    assert limits.force_lbf == pytest.approx(6300.0, rel=1e-12)
    assert limits.stroke_in == 3.2
    assert limits.moving_mass == pytest.approx(2800.0 / G0, rel=1e-12)


def test_from_table_parameters_matches_report_numbers():
    plant = pytest.importorskip("impedance_mil.plant")
    table = plant.TableParameters.report_default()
    from_table = TableLimits.from_table(table, specimen_weight=1200.0)
    ours = TableLimits.report_default(specimen_weight=1200.0)
    # Table 4.1 prints m_st = 4.14 (1600 lb / 386.089 = 4.144): 0.1 % between the two spellings.
    assert from_table.moving_mass == pytest.approx(ours.moving_mass, rel=1e-3)
    for key in ("stroke_in", "velocity_in_s", "force_lbf", "rated_flow"):
        assert getattr(from_table, key) == pytest.approx(getattr(ours, key), rel=1e-12)


def test_report_gm1_fits_only_when_time_compressed():
    # Report Section 8.2: the records are time-compressed by 2 "to prevent the shake-table
    # displacement from exceeding its maximum stroke" for PGA > 0.4 g.  GM1 (El Centro RSN 6 at
    # 0.8 g) with the empty vessel (1200 lb): fits (stroke < 3 in, the report's own figure)
    # after compression, overruns the stroke without it.
    limits = TableLimits.report_default(specimen_weight=1200.0)
    gm1 = builtin_motion("elcentro").time_scaled(2.0).scaled_to_pga(0.8)
    result = check_motion(gm1, limits)
    assert result.ok and result.exceeded == [] and result.suggested_time_scale is None
    assert result.check("stroke").peak < 3.0
    unscaled = check_motion(builtin_motion("elcentro").scaled_to_pga(0.8), limits)
    assert not unscaled.ok and "stroke" in unscaled.exceeded
    assert 1.0 < unscaled.suggested_time_scale <= 2.0


def test_suggested_time_scale_fixes_and_is_minimal():
    limits = TableLimits.report_default(specimen_weight=1200.0)
    motion = builtin_motion("elcentro-chopra").scaled_to_pga(0.8)
    result = check_motion(motion, limits)
    s = result.suggested_time_scale
    assert s is not None and s > 1
    assert check_motion(motion.time_scaled(s), limits).ok
    assert not check_motion(motion.time_scaled(s - 0.02), limits).ok


def test_time_scaling_laws_of_the_peaks():
    # Compression by s: stroke / s^2, velocity / s, force unchanged, flow / s (module docstring).
    limits = TableLimits.report_default(specimen_weight=2370.0)
    motion = builtin_motion("elcentro").scaled_to_pga(0.6)
    base, fast = check_motion(motion, limits), check_motion(motion.time_scaled(1.7), limits)
    powers = {"stroke": 2, "velocity": 1, "force": 0, "flow": 1}
    for name, power in powers.items():
        assert fast.check(name).peak == pytest.approx(base.check(name).peak / 1.7**power, rel=1e-9)


def test_force_overrun_is_not_fixed_by_time_scaling():
    # 10 000 lb article: max PGA = 6300 / (1600 + 10000) = 0.5431 g (hand).
    limits = TableLimits.report_default(specimen_weight=10000.0)
    motion = builtin_motion("elcentro").time_scaled(2.0).scaled_to_pga(0.8)
    result = check_motion(motion, limits)
    # Peak load pressure 9280 / 2.1 = 4419 psi > P_s while the table pushes: no pressure drop is
    # left across the valve, so the flow demand is infinite too; no time scale can help.
    assert result.exceeded == ["force", "flow"]
    assert math.isinf(result.check("flow").peak) and result.suggested_time_scale is None
    assert result.max_pga_g == pytest.approx(6300.0 / 11600.0, rel=1e-12)
    assert check_motion(motion.scaled_to_pga(0.5), limits).check("force").ok


def test_required_flow_formula_by_hand():
    # Q_eq = A_p |v| sqrt(dP_rated / (P_s - sign(v) F / A_p)); v = 10 in/s, A_p = 2.1 in^2:
    # pushing with P_L = 1000 psi: 21 sqrt(1000/2000) = 14.8492; braking: 21 sqrt(1000/4000) = 10.5;
    # load above supply: infinite; at rest: 0.
    limits = TableLimits.report_default()
    v = np.array([10.0, 10.0, 10.0, 0.0])
    f = np.array([2100.0, -2100.0, 7000.0, 100.0])
    q = required_rated_flow(v, f, limits)
    np.testing.assert_allclose(q[:2], [21 * math.sqrt(0.5), 10.5], rtol=1e-12)
    assert math.isinf(q[2]) and q[3] == 0.0


def test_limit_check_fields_and_units():
    limits = TableLimits.report_default()
    motion = GroundMotion(0.01, 0.1 * G0 * np.sin(2 * np.pi * np.arange(1001) * 0.01))
    result = check_motion(motion, limits)
    assert [c.name for c in result.checks] == ["stroke", "velocity", "force", "flow"]
    assert [c.unit for c in result.checks] == ["in", "in/s", "lbf", "in^3/s"]
    force = result.check("force")
    assert force.peak == pytest.approx(limits.moving_mass * motion.baseline_corrected().pga, rel=1e-12)
    assert force.ratio == pytest.approx(force.peak / 6300.0)
    with pytest.raises(KeyError):
        result.check("pressure")


def test_uncorrected_check_of_a_constant_acceleration_by_hand():
    # a = 10 in/s^2 for 2 s from rest: closed form v(T) = a T = 20 in/s, x(T) = a T^2 / 2 = 20 in,
    # both at the last sample; exact for piecewise-linear integration (tolerance: rounding).
    limits = TableLimits(3.0, 40.0, 5000.0, 5.0)
    motion = GroundMotion(0.01, np.full(201, 10.0))
    raw = check_motion(motion, limits, baseline_correct=False)
    assert raw.check("stroke").peak == pytest.approx(20.0, rel=1e-12)
    assert raw.check("velocity").peak == pytest.approx(20.0, rel=1e-12)
    assert raw.check("stroke").time_s == pytest.approx(2.0) and raw.exceeded == ["stroke"]
    # The default baseline correction removes the drift: the corrected record ends at rest.
    corrected = check_motion(motion, limits)
    assert corrected.check("stroke").peak < 0.1 * raw.check("stroke").peak
    assert raw.check("force").peak == pytest.approx(5.0 * 10.0, rel=1e-12)  # moving mass x a


def test_without_hydraulics_only_three_checks():
    limits = TableLimits(3.0, 40.0, 5000.0, 5.0)
    result = check_motion(builtin_motion("elcentro").time_scaled(2.0), limits)
    assert [c.name for c in result.checks] == ["stroke", "velocity", "force"]


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"stroke_in": -1.0}, "stroke_in"),
        ({"moving_mass": 0.0}, "moving_mass"),
        ({"piston_area": 2.1}, "piston_area"),
    ],
)
def test_invalid_limits(kwargs, key):
    args = {"stroke_in": 3.0, "velocity_in_s": 40.0, "force_lbf": 5000.0, "moving_mass": 5.0} | kwargs
    with pytest.raises(ConfigError, match=key):
        TableLimits(**args)
    with pytest.raises(ConfigError, match="specimen_weight"):
        TableLimits.report_default(specimen_weight=-5.0)


def test_without_the_flow_check_the_other_checks_are_unchanged():
    # flow=False (the pre-test's basemat check) drops the flow check only: same peaks, same times
    gm = builtin_motion("elcentro").time_scaled(2.0).scaled_to_pga(0.8)
    limits = TableLimits.report_default(specimen_weight=1200.0)
    full, kinematic = check_motion(gm, limits), check_motion(gm, limits, flow=False)
    assert [c.name for c in full.checks] == ["stroke", "velocity", "force", "flow"]
    assert kinematic.checks == full.checks[:3]
