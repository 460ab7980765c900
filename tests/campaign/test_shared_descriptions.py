"""The CLI and the campaign kinds run the same experiment descriptions and write the same run files."""

from __future__ import annotations

import json

import h5py
import numpy as np
import pytest

from impedance_mil.campaign import InlineExecutor, load_campaign, run_campaign
from impedance_mil.campaign.claims import AGREE, CLAIMS, evaluate_claims
from impedance_mil.campaign.summary import SummaryTable
from impedance_mil.lab import load_run
from impedance_mil.lab.runfile import SUMMARY_ATTR, read_summary

TRACK = """
[campaign]
name = "same"
kind = "tracking"
[base]
duration = "3 s"
water_depth = "36 in"
feedback = "load_cells"
[[study]]
name = "one"
"""


def test_a_tracking_campaign_run_is_imil_track(imil, tmp_path):
    # GM1 of Table 8.1 (built-in RSN 6, x2, 0.8 g) for 3 s, vessel with 36 in, load cells, seed 0:
    # the campaign (old feedback spelling) and the CLI (defaults) describe the same test.
    (tmp_path / "c.toml").write_text(TRACK)
    result = run_campaign(load_campaign(tmp_path / "c.toml"), tmp_path / "out", InlineExecutor())
    (record,) = result.records
    assert record.status == "ok", record.error
    out = imil("track", "--duration", "3", "-o", tmp_path / "cli.h5", "--json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    campaign_run, cli_run = load_run(result.root / record.hdf5), load_run(tmp_path / "cli.h5")
    for name, values in cli_run.channels.items():
        np.testing.assert_array_equal(campaign_run.channels[name], values, err_msg=name)
    summary, _ = read_summary(result.root / record.hdf5)
    for key in ("spectral_error_0p25_15hz", "spectral_error_15_50hz", "nrms_error", "simulated_s"):
        assert record.metrics[key] == doc[key] == summary[key]
    assert summary["feedback"] == doc["feedback"] == "lc"


def test_an_frf_campaign_run_stores_what_imil_frf_stores(imil, tmp_path):
    # The report's multisine on the bare table (Section 4.5.3), seed 0.
    (tmp_path / "f.toml").write_text('[campaign]\nname = "f"\nkind = "frf"\n[[study]]\nname = "one"\n')
    result = run_campaign(load_campaign(tmp_path / "f.toml"), tmp_path / "out", InlineExecutor())
    (record,) = result.records
    assert record.status == "ok", record.error
    assert imil("frf", "-o", tmp_path / "cli.h5", cwd=tmp_path).returncode == 0
    with h5py.File(result.root / record.hdf5) as a, h5py.File(tmp_path / "cli.h5") as b:
        assert SUMMARY_ATTR in a.attrs and set(a["imil/frf"]) == set(b["imil/frf"])
        for key in b["imil/frf"]:
            np.testing.assert_array_equal(a["imil/frf"][key][()], b["imil/frf"][key][()], err_msg=key)
    summary, _ = read_summary(tmp_path / "cli.h5")
    for key in ("model_error_0p25_100hz", "model_error_10_50hz", "f_oil_hz", "identification_error"):
        assert record.metrics[key] == summary[key]


def _feedback_rows(names):
    # Mean 0.25-15 Hz spectral error at 42 in: 0.05 with u_w, 0.5 without (Section 8.3.2's claim).
    rows = [
        {"run_id": f"r{i}", "study": "feedback", "status": "ok", "feedback": n, "water_depth": 42.0, **m}
        for i, (n, m) in enumerate(names)
    ]
    return SummaryTable(tuple(dict.fromkeys(k for r in rows for k in r)), tuple(rows))


@pytest.mark.parametrize(
    "rows",
    [
        [("lc", {"spectral_error_0p25_15hz": 0.05}), ("none", {"spectral_error_0p25_15hz": 0.5})],
        # A summary written before the names were shared.
        [("load_cells", {"spectral_error_low": 0.05}), ("none", {"spectral_error_low": 0.5})],
    ],
)
def test_the_feedback_claim_reads_old_and_new_summaries(rows):
    (claim,) = [c for c in CLAIMS if c.id == "sec8-feedback"]
    (outcome,) = evaluate_claims([_feedback_rows(rows)], [claim])
    assert outcome.verdict == AGREE, outcome.measured
