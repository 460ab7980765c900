"""Identification from recordings: known tables recovered, with the estimator's own confidence intervals.

Recordings are the exact periodic steady state of a known linear system driven by
a multisine (``synthetic.py``), written as CSV in lab units and read back; one
round trip goes through the virtual lab (the nonlinear table).
"""

from __future__ import annotations

import numpy as np
import pytest

from impedance_mil.lab.identification import model_response
from impedance_mil.lab.identify import identify_recording
from impedance_mil.plant import TableParameters
from impedance_mil.signals.drive import read_drive
from impedance_mil.signals.recordings import ChannelMap, read_recording, write_recording

from .synthetic import multisine, noisy, pair, steady_response, write_multisine_drive, zpk_response

MAP = ChannelMap.parse(["u=cmd[mm]", "z=acc[g]"], rate=2000.0)
#: A table the physical model cannot express: a real valve pole at 7.7 Hz, an oil column
#: pair at 46.9 Hz (zeta 0.15), a valve pair at 67.1 Hz (zeta 0.3) and a foundation notch
#: at 30 Hz (zeta 0.05); x/u has unit DC gain (z = s^2 x).
TF_POLES = [complex(-7.7)] + pair(46.9, 0.15) + pair(67.1, 0.3)
TF_ZEROS = pair(30.0, 0.05)
TF = zpk_response(TF_ZEROS, TF_POLES, 1.0, zeros_at_origin=2)
TRUE_FREQUENCIES = [7.7, 46.9, 67.1]


def _recording(tmp_path, ms, y, name="rec.csv"):
    path = write_recording(tmp_path / name, {"u": ms.signal, "z": y}, MAP)
    drive = write_multisine_drive(tmp_path, ms, overwrite=True)
    return read_recording(path, MAP), read_drive(tmp_path / "multisine.json"), drive


def _sigma(interval):
    return (np.log(interval[1]) - np.log(interval[0])) / (2 * 1.959963984540054)


@pytest.fixture(scope="module")
def ms():
    return multisine()


def test_rational_model_of_a_table_the_physical_model_cannot_express(tmp_path, ms):
    # Noiseless: poles, dampings, DC gain and the notch recovered to 1e-9 (measured 6e-16).
    rec, drive, _ = _recording(tmp_path, ms, steady_response(ms, TF))
    ident = identify_recording(
        rec, TableParameters.report_default(), drive=drive, order=5, num_order=2, f_range_hz=(1.0, 100.0)
    )
    fit = ident.rational
    assert fit.poles_hz == pytest.approx(TRUE_FREQUENCIES, rel=1e-9)
    assert [p.damping for p in fit.poles] == pytest.approx([1.0, 0.15, 0.3], rel=1e-9)
    assert fit.dc_gain == pytest.approx(1.0, rel=1e-9)
    assert sorted(abs(z) for z in fit.zeros_hz if abs(z) > 0) == pytest.approx([30.0, 30.0], rel=1e-9)
    # the physical model's fixed structure cannot: its misfit is far above the rational one's
    assert ident.physical.rms_log_error > 100 * fit.rms_log_error
    # automatic selection (BIC) finds the same structure
    auto = identify_recording(rec, TableParameters.report_default(), drive=drive, f_range_hz=(1.0, 100.0))
    assert (auto.rational.order, auto.rational.num_order) == (5, 2)


@pytest.mark.parametrize("level", [0.01, 0.05])
def test_rational_fit_within_its_confidence_interval(tmp_path, ms, level):
    # 1 % and 5 % white output noise: each pole frequency and the DC gain lie within
    # 3 standard deviations of the estimator's own 95 % interval (Jacobian covariance),
    # and the weighted residual is noise (reduced chi-square within 0.8-1.25).
    y = noisy(steady_response(ms, TF), level, seed=3)
    rec, drive, _ = _recording(tmp_path, ms, y)
    fit = identify_recording(
        rec, TableParameters.report_default(), drive=drive, order=5, num_order=2, f_range_hz=(1.0, 100.0)
    ).rational
    for pole, true in zip(fit.poles, TRUE_FREQUENCIES):
        assert abs(np.log(pole.frequency_hz / true)) < 3 * _sigma(pole.ci95_frequency_hz)
    lo, hi = fit.ci95_dc_gain
    assert abs(fit.dc_gain - 1.0) < 3 * (hi - lo) / (2 * 1.96)
    assert 0.8 < fit.chi2_reduced < 1.25


def _sampled_table(p):
    return lambda f: model_response(p, "z", f, "sampled")


@pytest.mark.parametrize("level", [0.01, 0.05])
def test_physical_fit_within_its_confidence_interval(tmp_path, ms, level):
    # Data from the exact sampled-data model of a table unlike Table 4.1's; fit with
    # the same delay model from the report's values (10-30 % off): f_oil, zeta_oil and d
    # within 3 standard deviations of their own 95 % intervals.
    true = TableParameters.report_default().replace(f_oil_hz=24.0, zeta_oil=0.12, d=1.3e5)
    y = noisy(steady_response(ms, _sampled_table(true)), level, seed=5)
    rec, drive, _ = _recording(tmp_path, ms, y)
    ident = identify_recording(
        rec, TableParameters.report_default(), drive=drive, delay="sampled", order=5, f_range_hz=(1.0, 100.0)
    ).physical
    intervals = ident.intervals()
    for name in ("f_oil_hz", "zeta_oil", "d"):
        value = ident.fit.parameters[name]
        assert abs(np.log(value / getattr(true, name))) < 3 * _sigma(intervals[name]), name
    assert 0.8 < ident.fit.chi2_reduced < 1.25


def test_interval_width_follows_the_noise(tmp_path, ms):
    # 5x the noise -> 5x the interval (linearized covariance): measured ratio within 4-6.
    widths = []
    for level in (0.01, 0.05):
        rec, drive, _ = _recording(tmp_path, ms, noisy(steady_response(ms, TF), level, seed=8))
        fit = identify_recording(
            rec, TableParameters.report_default(), drive=drive, order=5, num_order=2, f_range_hz=(1.0, 100.0)
        ).rational
        widths.append(np.array([_sigma(p.ci95_frequency_hz) for p in fit.poles]))
    assert np.all((widths[1] / widths[0] > 4) & (widths[1] / widths[0] < 6))
