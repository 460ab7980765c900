"""Trip causes are one enumeration: kernel, results, run files, exceptions, JSON."""

from __future__ import annotations

import json

import h5py
import numpy as np
import pytest

from impedance_mil.errors import DataFileError, LimitTripped
from impedance_mil.lab import Trip, load_run, save_run, simulate
from impedance_mil.lab.runfile import flat_summary, run_summary
from impedance_mil.lab.trips import TRIP_LIMIT_KEY, TripCause
from impedance_mil.plant.nonlinear import NonlinearTable

from .conftest import report_parameters

#: Codes and names of the run files written before the enumeration (main at dc9ba1a,
#: lab.kernels.TRIP_NAMES): old files must keep loading.
FILE_NAMES = ("", "stroke", "velocity", "actuator_force", "valve_saturation", "nan", "divergence")
#: Causes added since (issues 18, 12, 17): new codes after the old ones, so the old codes keep their meaning.
NEW_NAMES = (
    "valve_duty",
    "valve_current",
    "command_oscillation",
    "acceleration",
    "pressure",
    "hf_oscillation",
)


@pytest.fixture(scope="module")
def tripped():
    # A ramp to 4 in trips the 3 in stroke interlock (report Section 8.2).
    table = NonlinearTable.from_linear(report_parameters())
    return simulate(table, command=np.linspace(0.0, 4.0, 8000))


def test_codes_and_names_are_those_of_the_run_files():
    assert [int(c) for c in TripCause] == list(range(len(FILE_NAMES) + len(NEW_NAMES)))
    assert [c.label for c in TripCause][1:] == list(FILE_NAMES[1:] + NEW_NAMES)
    assert all(TripCause.from_label(c.label) is c for c in TripCause)
    units = {c.label: c.unit for c in TripCause}
    assert units["stroke"] == "in" and units["velocity"] == "in/s" and units["valve_saturation"] == "V"
    with pytest.raises(ValueError, match="unknown trip cause 'melted'"):
        TripCause.from_label("melted")


def test_a_run_carries_the_cause_and_the_exception_keeps_its_message(tripped):
    trip = tripped.trip
    assert trip.cause is TripCause.STROKE and trip.limit == "stroke" and trip.unit == "in"
    assert trip.to_dict() == {"limit": "stroke", "time_s": trip.time_s, "value": trip.value, "unit": "in"}
    exc = trip.as_exception()
    assert isinstance(exc, LimitTripped) and exc.cause is TripCause.STROKE and exc.value == trip.value
    assert str(exc) == f"limit 'stroke' tripped at t = {trip.time_s:.4f} s: value {trip.value:.6g}"


def test_run_file_stores_name_and_code_and_reads_old_files(tripped, tmp_path):
    path = save_run(tripped, tmp_path / "trip.h5")
    with h5py.File(path, "r") as f:
        stored = json.loads(f.attrs["trip_json"])
    assert stored["limit"] == "stroke" and stored["cause"] == int(TripCause.STROKE)
    # A file of the previous format: the name only.
    with h5py.File(path, "a") as f:
        f.attrs["trip_json"] = json.dumps({k: v for k, v in stored.items() if k != "cause"})
    assert load_run(path).trip == tripped.trip
    # A code that contradicts the name is refused, naming the file.
    with h5py.File(path, "a") as f:
        f.attrs["trip_json"] = json.dumps({**stored, "cause": int(TripCause.VELOCITY)})
    with pytest.raises(DataFileError, match="does not match limit 'stroke'"):
        load_run(path)
    with h5py.File(path, "a") as f:
        f.attrs["trip_json"] = json.dumps({**stored, "limit": "melted"})
    with pytest.raises(DataFileError, match="trip.h5: trip_json: unknown trip cause"):
        load_run(path)


def test_campaign_rows_carry_the_cause_under_the_key_the_claims_read(tripped):
    # The flattened run summary (a campaign summary row) names the cause in the column
    # the claims read (TRIP_LIMIT_KEY), and the JSON summary's trip is Trip.to_dict().
    summary = run_summary(tripped, None)
    assert summary["trip"] == tripped.trip.to_dict()
    assert TripCause.from_label(flat_summary(summary)[TRIP_LIMIT_KEY]) is TripCause.STROKE
    assert summary["abort_reason"].endswith(f"(value {tripped.trip.value:.4g} in)")


def test_trip_is_a_value():
    assert Trip(TripCause.VELOCITY, 0.5, 41.0) == Trip(TripCause.VELOCITY, 0.5, 41.0)
    assert Trip(TripCause.VELOCITY, 0.5, 41.0).detail == "value 41"
