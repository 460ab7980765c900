"""The reproduction page tells the claim a lab was calibrated on from the claims it predicts."""

from __future__ import annotations

from pathlib import Path

import pytest

import impedance_mil
from impedance_mil.campaign.claims import CLAIMS
from impedance_mil.campaign.summary import SummaryTable
from impedance_mil.errors import ConfigError
from impedance_mil.report.reproduction import CALIBRATED, PREDICTED, claim_role, lab_calibrations

TABLE_4_1 = Path(impedance_mil.__file__).parent / "data" / "tables" / "report_table_4_1.toml"
RECORD = """
[calibration]
claim = "sec8-fc-instability"
parameter = "load-cell delay"
keys = ["sensors.lc.delay"]
value = "1 ms"
reproduced = true
protocol = "p.toml"
"""


def _rows(lab):
    return SummaryTable(
        ("run_id", "study", "status", "lab"), ({"run_id": "a", "study": "s", "status": "ok", "lab": lab},)
    )


def test_roles_follow_the_calibration_record_of_the_lab_the_runs_used(tmp_path):
    lab = tmp_path / "lab.toml"
    lab.write_text(f'[table]\nfile = "{TABLE_4_1.as_posix()}"\n' + RECORD)
    records = lab_calibrations([_rows(str(lab))])
    assert [r.claim for r in records] == ["sec8-fc-instability"]
    by_id = {c.id: c for c in CLAIMS}
    assert claim_role(by_id["sec8-fc-instability"], records) == CALIBRATED
    assert claim_role(by_id["sec9-basemat-mass"], records) == PREDICTED
    # Runs on the report's setup (no lab, or an uncalibrated one): no roles at all.
    assert lab_calibrations([_rows(None), _rows("report")]) == ()
    assert claim_role(by_id["sec9-basemat-mass"], ()) == ""


def test_a_lab_that_cannot_be_read_is_named_not_ignored(tmp_path):
    # Ignoring it would show the claim it was calibrated on as predicted.
    with pytest.raises(ConfigError, match="lab .*gone.toml"):
        lab_calibrations([_rows(str(tmp_path / "gone.toml"))])
