"""FRF estimators with their standard deviation, and the drive files' layouts read back.

* Synchronous averaging (multisine): exact on a noiseless periodic steady state (a
  closed form, ``synthetic.steady_response``), and its standard deviation is that of
  the error: ``|H - H_true|^2 / std^2`` is a unit exponential for a complex Gaussian
  error, mean 1 (measured 1.04 over 800 lines), 95 % below ``ln 20`` (measured 94.5 %).
* Welch H1 (random drive) against the exact response of a discrete filter
  (``scipy.signal.freqz``): Hann leakage bias only without noise (measured 0.53 % at
  most), and the magnitude error within 1.96 of Bendat and Piersol's random error
  (Eq 9.90) at 5 % output noise for 95 % of the lines (measured 93.7 %).
* ``imil identify --segment`` (a random drive, no drive file): the poles of a rational
  table recovered within 3 sigma of their own 95 % intervals at 1 % noise (measured
  errors 0.13 %, 0.001 %, 0.012 %; 3 sigma is 2.5 %, 0.08 %, 0.09 %).
* Drive files: the RMC75E curve layout (two columns, no header) and the CSV layout
  read back to the written samples; an edited data file is refused by its checksum.
"""

from __future__ import annotations

import hashlib
import json

import numpy as np
import pytest
import scipy.signal

from impedance_mil.errors import DataFileError
from impedance_mil.signals.drive import read_drive, read_drive_values
from impedance_mil.signals.frf_estimators import synchronous_frf, welch_frf
from impedance_mil.signals.recordings import ChannelMap, write_recording

from .synthetic import (
    multisine,
    noisy,
    pair,
    random_periodic_response,
    steady_response,
    write_multisine_drive,
    zpk_response,
)

TF = zpk_response(
    pair(30.0, 0.05), [complex(-7.7)] + pair(46.9, 0.15) + pair(67.1, 0.3), 1.0, zeros_at_origin=2
)
RATE = 2000.0


@pytest.fixture(scope="module")
def ms():
    return multisine()


def _synchronous(ms, y):
    return synchronous_frf(ms.signal, y, ms.n_points, ms.sample_rate_hz, ms.lines)


def test_synchronous_average_is_exact_on_a_periodic_steady_state(ms):
    frf = _synchronous(ms, steady_response(ms, TF))
    np.testing.assert_allclose(frf.frequency_hz, ms.lines * RATE / ms.n_points, rtol=1e-15)
    # measured 9e-14 (the FFT's round-off on a 4096-point period)
    np.testing.assert_allclose(frf.response, TF(frf.frequency_hz), rtol=1e-11)
    np.testing.assert_allclose(frf.coherence, 1.0, atol=1e-12)
    assert frf.n_averages == ms.n_periods - 1  # the first period is the transient


def test_synchronous_standard_deviation_is_that_of_the_error(ms):
    ratios = []
    for seed in range(5):
        frf = _synchronous(ms, noisy(steady_response(ms, TF), 0.05, seed))
        ratios.append(np.abs(frf.response - TF(frf.frequency_hz)) ** 2 / frf.std**2)
    r = np.concatenate(ratios)
    # mean of 800 unit exponentials: 1 +- 0.035 (1 sigma), and the smoothed noise estimate
    assert 0.9 < r.mean() < 1.15
    assert 0.92 < np.mean(r < np.log(20)) < 0.975


def _butterworth_record(seed, level, n=2**17):
    b, a = scipy.signal.butter(2, 100.0, fs=RATE)
    rng = np.random.default_rng(seed)
    u = rng.standard_normal(n)
    y = scipy.signal.lfilter(b, a, u)
    y = y + level * np.std(y) * rng.standard_normal(n)
    frf = welch_frf(u, y, RATE, 1024, (1.0, 300.0))
    _, exact = scipy.signal.freqz(b, a, worN=frf.frequency_hz, fs=RATE)
    return frf, exact


def test_welch_h1_without_noise_has_only_the_leakage_bias():
    frf, exact = _butterworth_record(0, 0.0)
    assert frf.n_averages == 255  # 2^17 samples, 1024 per segment, half overlap
    assert np.max(np.abs(frf.response / exact - 1)) < 1e-2
    assert np.min(frf.coherence) > 0.99


def test_welch_standard_deviation_is_that_of_the_magnitude_error():
    inside = []
    for seed in range(3):
        frf, exact = _butterworth_record(seed, 0.05)
        inside.append(np.abs(np.abs(frf.response) - np.abs(exact)) < 1.96 * frf.std)
    share = np.mean(np.concatenate(inside))
    # 459 lines: 95 % +- 1 % (1 sigma); half-overlapped Hann segments are not quite independent
    assert 0.9 < share < 0.98
    # more noise, lower coherence and wider intervals (same seed)
    frf, _ = _butterworth_record(2, 0.05)
    noisier, _ = _butterworth_record(2, 0.2)
    assert np.median(noisier.coherence) < np.median(frf.coherence)
    assert np.median(noisier.std / np.abs(noisier.response)) > 3 * np.median(frf.std / np.abs(frf.response))


def test_identify_a_random_drive_with_welch(tmp_path, imil):
    u, y = random_periodic_response(TF)
    channels = ["u=cmd[mm]", "z=acc[g]"]
    write_recording(
        tmp_path / "rec.csv", {"u": u, "z": noisy(y, 0.01, seed=2)}, ChannelMap.parse(channels, rate=RATE)
    )
    args = [a for c in channels for a in ("--channel", c)]
    out = imil(
        "identify", tmp_path / "rec.csv", "--rate", "2000", *args, "--segment", "4096", "--model", "tf",
        "--order", "5", "--num-order", "2", "--band", "1,100", "-o", tmp_path / "t.toml", "--json",
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout)
    assert got["frf"]["estimator"].startswith("Welch H1") and (tmp_path / "t.toml").is_file()
    for pole, true in zip(got["poles"], [7.7, 46.9, 67.1]):
        lo, hi = pole["ci95_frequency_hz"]
        sigma = np.log(hi / lo) / (2 * 1.959963984540054)
        assert abs(np.log(pole["frequency_hz"] / true)) < 3 * sigma, pole
    lo, hi = got["ci95_dc_gain"]
    assert abs(got["dc_gain"] - 1.0) < 3 * (hi - lo) / (2 * 1.96)
    # the table file it wrote is an LTI table that --table reads (issue 13's layout), with the fit's poles
    table = imil("table", "poles", "--table", tmp_path / "t.toml", "--json")
    assert table.returncode == 0, table.stderr
    read = sorted({round(p["frequency_hz"], 6) for p in json.loads(table.stdout)["poles"]})
    np.testing.assert_allclose(read, sorted(p["frequency_hz"] for p in got["poles"]), rtol=1e-6)


@pytest.mark.parametrize("file_format", ["csv", "rmc75e"])
def test_drive_file_layouts_read_back(tmp_path, ms, file_format):
    drive = write_multisine_drive(tmp_path, ms, file_format=file_format)
    data = tmp_path / "multisine.csv"
    rows = data.read_text().splitlines()
    if file_format == "rmc75e":  # the curve tool's X,Y pairs, no header (docs/measured-data.md)
        assert rows[0].split(",")[0] == "0" and len(rows) == ms.signal.size
    else:
        assert rows[0] == "time_s,u_mm" and len(rows) == ms.signal.size + 1
    last = rows[-1].split(",")
    assert float(last[0]) == pytest.approx((ms.signal.size - 1) / RATE, rel=1e-9)
    assert float(last[1]) == pytest.approx(ms.signal[-1] * 25.4, rel=1e-11)
    assert drive.sha256 == hashlib.sha256(data.read_bytes()).hexdigest()
    back = read_drive(tmp_path / "multisine.json")
    assert back.file_format == file_format
    # written with 12 significant digits, read back in inches
    np.testing.assert_allclose(read_drive_values(back, tmp_path), ms.signal, rtol=1e-11, atol=1e-15)


def test_an_edited_drive_data_file_is_refused(tmp_path, ms):
    write_multisine_drive(tmp_path, ms)
    data = tmp_path / "multisine.csv"
    data.write_text(data.read_text().replace("\n0.0005,", "\n0.0005,1", 1))
    with pytest.raises(DataFileError, match="multisine.csv.*changed since multisine.json"):
        read_drive(tmp_path / "multisine.json")
