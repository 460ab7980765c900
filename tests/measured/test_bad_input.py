"""Every bad input of issue 14 is one line naming the file, channel or key, exit 2, nothing written."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from impedance_mil.lab.recorded import sensor_ranges
from impedance_mil.lab.setup import default_sensors
from impedance_mil.signals.recordings import ChannelMap, write_recording
from impedance_mil.units import G0

from .synthetic import multisine, write_multisine_drive

CHANNELS = ["t=time[s]", "u=cmd[mm]", "z=acc[g]"]
MAP = ChannelMap.parse(CHANNELS)


@pytest.fixture()
def lab(tmp_path):
    ms = multisine(n_points=1024, n_lines=40, periods=3)
    write_multisine_drive(tmp_path, ms)
    t = np.arange(ms.signal.size) / ms.sample_rate_hz
    z = 0.01 * np.gradient(np.gradient(ms.signal, t), t)  # well inside the accelerometer range
    return tmp_path, {"t": t, "u": ms.signal, "z": z}


def _write(folder, channels, name="rec.csv", cmap=MAP):
    return write_recording(folder / name, channels, cmap)


def _identify(imil, folder, rec, *extra, channels=CHANNELS):
    args = [a for c in channels for a in ("--channel", c)]
    return imil(
        "identify",
        rec,
        "--drive",
        folder / "multisine.json",
        *args,
        "--order",
        "4",
        "-o",
        folder / "t.toml",
        *extra,
    )


def _refused(out, folder, *words):
    assert out.returncode == 2, out.stdout
    assert out.stderr.startswith("imil: error: ") and out.stderr.count("\n") == 1, out.stderr
    for word in words:
        assert word in out.stderr, out.stderr
    assert not (folder / "t.toml").exists() and not list(folder.glob(".*tmp-*"))


def test_a_column_missing_from_the_recording(imil, lab):
    folder, ch = lab
    rec = _write(folder, ch)
    _refused(
        _identify(imil, folder, rec, channels=["t=time[s]", "u=cmd[mm]", "z=accel[g]"]),
        folder,
        "rec.csv",
        "no column 'accel'",
    )


def test_a_channel_missing_from_the_map(imil, lab):
    folder, ch = lab
    rec = _write(folder, ch)
    _refused(_identify(imil, folder, rec, channels=["t=time[s]", "u=cmd[mm]"]), folder, "--channel", "z")


def test_an_unknown_unit(imil, lab):
    folder, ch = lab
    rec = _write(folder, ch)
    _refused(
        _identify(imil, folder, rec, channels=["t=time[s]", "u=cmd[mm]", "z=acc[furlongs]"]),
        folder,
        "z=acc[furlongs]",
        "unit of acceleration",
    )


def test_unequal_channel_lengths(imil, lab):
    folder, ch = lab
    path = folder / "rec.h5"
    with h5py.File(path, "w") as fh:
        fh["cmd"] = ch["u"] * 25.4
        fh["acc"] = ch["z"][:-5] / G0
    _refused(
        _identify(imil, folder, path, "--rate", "2000", channels=["u=cmd[mm]", "z=acc[g]"]),
        folder,
        "rec.h5",
        "unequal length",
    )


def test_non_uniform_time(imil, lab):
    folder, ch = lab
    ch["t"] = ch["t"].copy()
    ch["t"][100] += 0.3 / 2000
    _refused(_identify(imil, folder, _write(folder, ch)), folder, "rec.csv", "channel t", "non-uniform")


def test_a_gap(imil, lab):
    folder, ch = lab
    ch["t"] = ch["t"].copy()
    ch["t"][200:] += 0.01
    _refused(_identify(imil, folder, _write(folder, ch)), folder, "rec.csv", "gap")


def test_wrong_sample_rate(imil, lab):
    folder, ch = lab
    ch["t"] = ch["t"] * 2  # 1000 Hz
    _refused(_identify(imil, folder, _write(folder, ch)), folder, "rec.csv", "1000 Hz", "multisine.json")


def test_nan_samples(imil, lab):
    folder, ch = lab
    ch["z"] = ch["z"].copy()
    ch["z"][17] = np.nan
    _refused(_identify(imil, folder, _write(folder, ch)), folder, "rec.csv", "channel z", "sample 17")


def test_drive_of_another_length(imil, lab):
    folder, ch = lab
    rec = _write(folder, {k: v[:-1024] for k, v in ch.items()})
    _refused(_identify(imil, folder, rec), folder, "rec.csv", "multisine.json", "samples")


def test_drive_of_other_lines(imil, lab):
    folder, ch = lab
    other = multisine(n_points=1024, n_lines=40, f_min=150.0, f_max=300.0, periods=3)
    _refused(
        _identify(imil, folder, _write(folder, {**ch, "u": other.signal})),
        folder,
        "rec.csv",
        "lines of",
        "multisine.json",
    )


def test_clipped_channel_refused_unless_allowed(imil, lab):
    folder, ch = lab
    ch["z"] = ch["z"].copy()
    ch["z"][300:304] = sensor_ranges(default_sensors())["z"].high
    rec = _write(folder, ch)
    _refused(_identify(imil, folder, rec), folder, "rec.csv", "channel z", "clipped", "--allow-clipped")
    out = _identify(imil, folder, rec, "--allow-clipped", "--json")
    assert out.returncode == 0, out.stderr
    assert '"clipped": [' in out.stdout and '"n_samples": 4' in out.stdout


def test_evaluate_without_the_force_of_a_mil_test(imil, lab, tmp_path):
    folder, ch = lab
    rec = _write(
        folder,
        {"t": ch["t"], "a_g": ch["z"], "z": ch["z"]},
        cmap=ChannelMap.parse(["t=time[s]", "a_g=ag[g]", "z=acc[g]"]),
    )
    out = imil(
        "evaluate",
        rec,
        "--vs",
        "SD2",
        "--channel",
        "t=time[s]",
        "--channel",
        "a_g=ag[g]",
        "--channel",
        "z=acc[g]",
        "-o",
        folder / "e.h5",
    )
    assert out.returncode == 2 and "w=COLUMN[UNIT]" in out.stderr and out.stderr.count("\n") == 1
    assert not (folder / "e.h5").exists()
