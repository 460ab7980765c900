"""Run names from configuration hashes and run records (atomic writes: tests/test_fileio.py)."""

from __future__ import annotations

import hashlib
import json

import pytest

from impedance_mil.campaign import CampaignStore, RunRecord, run_id_for
from impedance_mil.campaign.store import canonical_json


def test_run_id_is_the_sha256_prefix_of_the_canonical_json():
    config = {"b": {"y": 2.0, "x": 1.0}, "a": "GM1"}
    text = '{"config":{"a":"GM1","b":{"x":1.0,"y":2.0}},"kind":"mil"}'  # written out by hand
    assert canonical_json({"kind": "mil", "config": config}) == text
    assert run_id_for("mil", config) == hashlib.sha256(text.encode()).hexdigest()[:12]


def test_run_id_ignores_key_order_and_sees_every_value():
    a = {"table": {"K_p": 0.001, "K_e": 5.0}, "f_c": 80.0}
    b = {"f_c": 80.0, "table": {"K_e": 5.0, "K_p": 0.001}}
    assert run_id_for("mil", a) == run_id_for("mil", b)
    assert run_id_for("mil", a) != run_id_for("tracking", a)
    changed = {"table": {"K_p": 0.0010000001, "K_e": 5.0}, "f_c": 80.0}
    assert run_id_for("mil", a) != run_id_for("mil", changed)


def test_nan_has_no_canonical_form():
    with pytest.raises(ValueError):
        run_id_for("mil", {"x": float("nan")})


def test_record_round_trip_and_nan_metrics_become_null(tmp_path):
    store = CampaignStore(tmp_path)
    store.create()
    record = RunRecord(
        "abc", "selftest", ("s",), {"k": 1.0}, "ok", metrics={"x": 1.5, "bad": float("nan")}, hdf5=""
    )
    store.write_record(record)
    back = store.load_record("abc")
    assert back.metrics == {"x": 1.5, "bad": None}
    assert back.studies == ("s",) and back.done
    assert json.loads(store.record_path("abc").read_text())["status"] == "ok"


def test_unreadable_or_failed_records_mean_the_run_is_redone(tmp_path):
    store = CampaignStore(tmp_path)
    store.create()
    store.record_path("torn").write_text('{"status": "ok", "run_id"')  # a torn write
    assert store.load_record("torn") is None and not store.is_done("torn")
    store.write_record(RunRecord("bad", "selftest", (), {}, "failed", error="x"))
    assert not store.is_done("bad")
    # An ok record whose HDF5 file has gone is not done either.
    store.write_record(RunRecord("gone", "selftest", (), {}, "ok", hdf5="runs/gone/run.h5"))
    assert not store.is_done("gone")
    store.write_record(RunRecord("aborted", "selftest", (), {}, "aborted", error="stroke"))
    assert store.is_done("aborted")


@pytest.mark.parametrize(
    "text",
    ['{"status": "ok", "run_id": ' + "1" * 400 + "}", '{"status": "ok", "x": ' + "[" * 40 + "]" * 40 + "}"],
)
def test_a_record_with_hostile_json_is_unreadable_and_redone(tmp_path, text):
    # json.loads read a 400-digit number or deep nesting; parse_json refuses them (issue 18).
    store = CampaignStore(tmp_path)
    store.create()
    store.record_path("hostile").write_text(text)
    assert store.load_record("hostile") is None and not store.is_done("hostile")


def test_campaign_json_is_read_with_the_caps(tmp_path):
    store = CampaignStore(tmp_path)
    store.create()
    (tmp_path / "campaign.json").write_text('{"runs": NaN}')
    with pytest.raises(ValueError, match="campaign.json: .*NaN is not a JSON number"):
        store.read_json("campaign.json")
