"""A run file's records are checked when read (issue 18, finding 10): shapes, and a checksum written with them."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math

import h5py
import numpy as np
import pytest

from impedance_mil.errors import DataFileError
from impedance_mil.lab import load_run, save_run, simulate
from impedance_mil.lab.results import data_digest
from impedance_mil.lab.trips import Trip, TripCause
from impedance_mil.plant.nonlinear import NonlinearTable

from .conftest import report_parameters

T = 0.0005


@pytest.fixture(scope="module")
def run():
    table = NonlinearTable.from_linear(report_parameters())
    return simulate(table, command=0.2 * np.sin(2 * np.pi * 2.0 * np.arange(4000) * T))


@pytest.fixture
def saved(run, tmp_path):
    return save_run(run, tmp_path / "run.h5")


def test_a_written_file_reads_back_and_carries_its_checksum(run, saved):
    back = load_run(saved)
    assert back.channels.keys() == run.channels.keys()
    with h5py.File(saved) as f:
        assert f.attrs["data_sha256"] == data_digest(run.channels, run.vs_states)


def test_a_changed_sample_is_refused(saved):
    # One sample rewritten in place: the file is valid HDF5 and decompresses, only the checksum sees it.
    with h5py.File(saved, "r+") as f:
        f["channels"]["x"][100] += 1e-9
    with pytest.raises(DataFileError, match="data_sha256: the records do not match"):
        load_run(saved)


def test_zeroed_tail_is_refused(saved):
    # The audit's case: the last 20 kB of the file zeroed.
    data = bytearray(saved.read_bytes())
    data[-20_000:] = bytes(20_000)
    saved.write_bytes(bytes(data))
    with pytest.raises(DataFileError, match=str(saved.name)):
        load_run(saved)


def test_records_of_unequal_length_are_refused(saved):
    with h5py.File(saved, "r+") as f:
        x = np.asarray(f["channels"]["x"])
        del f["channels"]["x"]
        f["channels"].create_dataset("x", data=x[:-10])
        del f.attrs["data_sha256"]  # as a file written before checksums
    with pytest.raises(DataFileError, match="x: records of unequal length"):
        load_run(saved)


def test_a_file_written_before_checksums_still_reads(run, saved):
    with h5py.File(saved, "r+") as f:
        del f.attrs["data_sha256"]
    np.testing.assert_array_equal(load_run(saved).channels["x"], run.channels["x"])


def test_imil_report_refuses_a_damaged_file_in_one_line(imil, saved, tmp_path):
    with h5py.File(saved, "r+") as f:
        f["channels"]["u_v"][0] = 7.0
    r = imil("report", saved, "-o", tmp_path / "page.html")
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1 and "data_sha256" in r.stderr
    assert not (tmp_path / "page.html").exists()


@pytest.mark.parametrize(
    "attr, text, message",
    [
        ("config_json", "1" + "0" * 400, "config_json: line 1: a number of more than 100 digits"),
        (
            "config_json",
            "[" * 40 + "]" * 40,
            "config_json: line 1: arrays or objects nested more than 32 deep",
        ),
        (
            "trip_json",
            '{"limit": "stroke", "time_s": NaN, "value": 1.0}',
            "trip_json: .*NaN is not a JSON number",
        ),
    ],
)
def test_the_json_attributes_are_read_with_the_caps_of_parse_json(saved, attr, text, message):
    # json.loads read these (a 400-digit integer, deep nesting, NaN) without a word (issue 18).
    with h5py.File(saved, "r+") as f:
        f.attrs[attr] = text
    with pytest.raises(DataFileError, match=message) as info:
        load_run(saved)
    assert str(saved) in str(info.value)


def test_a_trip_with_a_non_finite_value_round_trips_as_nan(run, tmp_path):
    tripped = dataclasses.replace(run, trip=Trip(TripCause.NAN, 1.5, math.nan))
    path = save_run(tripped, tmp_path / "nan.h5")
    with h5py.File(path) as f:
        assert json.loads(f.attrs["trip_json"])["value"] is None  # strict JSON: no NaN
    back = load_run(path).trip
    assert back.cause == TripCause.NAN and back.time_s == 1.5 and math.isnan(back.value)


def _digest_with_copies(channels, vs_states):
    """``data_digest`` as written before issue 16 (``tobytes`` copies): the stored checksums must not change."""
    h = hashlib.sha256()
    for name in sorted(channels):
        arr = np.ascontiguousarray(channels[name])
        h.update(f"{name}:{arr.dtype.str}:{arr.shape}".encode())
        h.update(arr.tobytes())
    states = np.ascontiguousarray(vs_states)
    h.update(f"vs_states:{states.dtype.str}:{states.shape}".encode())
    h.update(states.tobytes())
    return h.hexdigest()


def test_the_checksum_is_the_one_files_already_carry(run):
    channels = {
        **run.channels,
        "strided": run.channels["x"][::2],
        "f32": run.channels["x"].astype(np.float32),
    }
    assert data_digest(channels, run.vs_states) == _digest_with_copies(channels, run.vs_states)
    states = np.ones((run.n_samples, 2))[:, ::-1]  # not C-contiguous
    assert data_digest(run.channels, states) == _digest_with_copies(run.channels, states)


def test_channels_are_written_uncompressed_and_contiguous(saved):
    # Issue 16: the write takes disk speed (docs/lab.md, "Run files" has the measured choices).
    with h5py.File(saved) as f:
        for name, dataset in f["channels"].items():
            assert (name, dataset.compression, dataset.chunks) == (name, None, None)


def test_a_file_with_gzip_channels_still_reads(run, saved):
    # Files written before issue 16 carry gzip-compressed channels; they load to the same records.
    with h5py.File(saved, "r+") as f:
        for name in list(f["channels"]):
            data = np.asarray(f["channels"][name])
            del f["channels"][name]
            f["channels"].create_dataset(name, data=data, compression="gzip", compression_opts=4)
        assert f["channels"]["x"].compression == "gzip"
    back = load_run(saved)
    for name, data in run.channels.items():
        np.testing.assert_array_equal(back.channels[name], data)
