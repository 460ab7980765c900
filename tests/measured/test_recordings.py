"""signals.recordings: every format reads the same samples, units convert by dimension, checks name the channel."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.io

from impedance_mil.errors import ConfigError, DataFileError
from impedance_mil.lab.recorded import sensor_ranges
from impedance_mil.lab.setup import default_sensors
from impedance_mil.signals.recordings import ChannelMap, parse_channel, read_recording, write_recording
from impedance_mil.units import G0

RATE = 1000.0
N = 600


def _columns():
    t = np.arange(N) / RATE
    return {"time": t, "cmd": 2.0 * np.sin(2 * np.pi * 3 * t), "acc": 0.3 * np.cos(2 * np.pi * 5 * t)}


MAP = ChannelMap.parse(["t=time[s]", "u=cmd[mm]", "z=acc[g]"])


def _check(rec):
    cols = _columns()
    # closed forms: 1 mm = 1/25.4 in exactly; g0 = 9.80665 m/s^2 = G0 in/s^2
    np.testing.assert_allclose(rec.channels["u"], cols["cmd"] / 25.4, rtol=1e-15, atol=0)
    np.testing.assert_allclose(rec.channels["z"], cols["acc"] * G0, rtol=1e-15, atol=0)
    assert rec.sample_rate_hz == pytest.approx(RATE, rel=1e-12)
    assert rec.n_samples == N


def test_csv(tmp_path):
    cols = _columns()
    path = tmp_path / "rec.csv"
    lines = ["# recorded by a controller", "time,cmd,acc"]
    lines += [
        f"{float(a)!r},{float(b)!r},{float(c)!r}" for a, b, c in zip(cols["time"], cols["cmd"], cols["acc"])
    ]
    path.write_text("\n".join(lines) + "\n")
    _check(read_recording(path, MAP))


def test_hdf5(tmp_path):
    import h5py

    path = tmp_path / "rec.h5"
    with h5py.File(path, "w") as fh:
        for name, values in _columns().items():
            fh.create_dataset(f"run/{name}", data=values)
    cmap = ChannelMap.parse(["t=run/time[s]", "u=run/cmd[mm]", "z=run/acc[g]"])
    _check(read_recording(path, cmap))


def test_mat_v5_variables_and_struct_fields(tmp_path):
    path = tmp_path / "rec.mat"
    cols = _columns()
    scipy.io.savemat(path, {**{k: v.reshape(-1, 1) for k, v in cols.items()}, "rec": cols})
    _check(read_recording(path, MAP))
    _check(read_recording(path, ChannelMap.parse(["t=rec.time[s]", "u=rec.cmd[mm]", "z=rec.acc[g]"])))


def test_mat_v73_written_by_an_independent_writer(tmp_path):
    hdf5storage = pytest.importorskip("hdf5storage")
    path = tmp_path / "rec.mat"
    hdf5storage.savemat(str(path), {k: v.reshape(-1, 1) for k, v in _columns().items()}, format="7.3")
    assert path.read_bytes()[:10] == b"MATLAB 7.3"
    _check(read_recording(path, MAP))


def test_tdms_rate_from_waveform_increment(tmp_path):
    nptdms = pytest.importorskip("nptdms")
    path = tmp_path / "rec.tdms"
    cols = _columns()
    props = {"wf_increment": 1.0 / RATE}
    channels = [nptdms.ChannelObject("daq", name, cols[name], properties=props) for name in ("cmd", "acc")]
    with nptdms.TdmsWriter(path) as writer:
        writer.write_segment(channels)
    _check(read_recording(path, ChannelMap.parse(["u=daq/cmd[mm]", "z=acc[g]"])))


def test_write_then_read_is_exact(tmp_path):
    # 17 significant digits: a float64 written as CSV reads back bit for bit.
    rng = np.random.default_rng(1)
    channels = {"t": np.arange(N) / RATE, "u": rng.standard_normal(N), "z": rng.standard_normal(N) * 100}
    for suffix in (".csv", ".mat", ".h5"):
        path = write_recording(tmp_path / f"r{suffix}", channels, MAP)
        rec = read_recording(path, MAP)
        for name in ("u", "z"):
            np.testing.assert_allclose(rec.channels[name], channels[name], rtol=2e-16, atol=0)


def test_units_by_dimension():
    assert parse_channel("x=lvdt[mm]").factor == pytest.approx(1 / 25.4, rel=1e-15)
    assert parse_channel("w=lc[kN]").factor == pytest.approx(1000 / 4.4482216152605, rel=1e-12)
    assert parse_channel("dp=p[bar]").factor == pytest.approx(1e5 / 6894.757293168, rel=1e-12)
    for bad in ("z=acc[furlong]", "z=acc[parsec_per_fortnight]", "u=cmd[g]", "w=lc[psi]"):
        with pytest.raises(ConfigError, match="expected a unit of"):
            parse_channel(bad)
    with pytest.raises(ConfigError, match="NAME=COLUMN"):
        parse_channel("z=acc")


def test_clipping_limits_are_the_sensors_readings():
    # Table 7.1: accelerometer 0.6711 g/V + 0.067 g over the 16-bit +-10 V input;
    # load cells 200 lb/V each carrying w/4: w reads up to 4 x 200 x (10 V - 1 LSB).
    ranges = sensor_ranges(default_sensors())
    lsb = 20.0 / 2**16
    assert ranges["z"].high == pytest.approx((0.6711 * (10 - lsb) + 0.067) * G0, rel=1e-12)
    assert ranges["z"].low == pytest.approx((0.6711 * -10 + 0.067) * G0, rel=1e-12)
    assert ranges["w"].high == pytest.approx(4 * 200 * (10 - lsb), rel=1e-12)


def test_clipped_channel_refused_or_recorded(tmp_path):
    ranges = sensor_ranges(default_sensors())
    cols = _columns()
    cols["acc"][100:110] = ranges["z"].high / G0  # 10 samples at the limit
    path = tmp_path / "rec.csv"
    write_recording(path, {"t": cols["time"], "u": cols["cmd"] / 25.4, "z": cols["acc"] * G0}, MAP)
    with pytest.raises(DataFileError, match="channel z .*clipped: 10 samples"):
        read_recording(path, MAP, ranges=ranges)
    rec = read_recording(path, MAP, ranges=ranges, allow_clipped=True)
    assert [(c.channel, c.n_samples) for c in rec.clipped] == [("z", 10)]
    assert rec.clipped[0].first_time_s == pytest.approx(0.1)
