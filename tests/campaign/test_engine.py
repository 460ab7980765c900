"""The campaign engine: results, failures, resume after an interrupt, summary tables."""

from __future__ import annotations

import csv
import math
import os
import signal
import subprocess
import sys
import time

import h5py
import pyarrow.parquet as pq
import pytest

from impedance_mil.campaign import InlineExecutor, LocalExecutor, load_campaign, load_summary, run_campaign
from impedance_mil.campaign import summary as summary_module
from impedance_mil.campaign.kinds import get_kind
from impedance_mil.design.io import load_design
from impedance_mil.fileio import stale_temporaries

HEAD = '[campaign]\nname = "t"\nkind = "selftest"\n'


def test_selftest_reproduces_the_targets_of_table_9_1(sd_campaign, tmp_path):
    # Table 9.1 gives k_s and c rounded to whole lbf/in and lbf*s/in from the targets
    # f = 0.75/1.25/1.75 Hz and zeta = 0.30/0.25/0.20 with 5600 lb; rounding bounds the
    # error to 0.5 % (f) and 1 % (zeta).
    result = run_campaign(load_campaign(sd_campaign), tmp_path / "out", InlineExecutor())
    assert [r.status for r in result.records] == ["ok", "ok", "ok"]
    freqs = [r.metrics["frequency_hz"] for r in result.records]
    zetas = [r.metrics["damping_ratio"] for r in result.records]
    assert freqs == pytest.approx([0.75, 1.25, 1.75], rel=5e-3)
    assert zetas == pytest.approx([0.30, 0.25, 0.20], rel=1e-2)
    # The HDF5 file holds the poles: |p|^2 = k/m and Re p = -c/(2m), exactly (quadratic roots).
    record = result.records[1]
    with h5py.File(result.root / record.hdf5) as fh:
        re, im = fh["poles_real"][:], fh["poles_imag"][:]
    k, c, m = record.settings["stiffness"], record.settings["damping"], record.settings["mass"]
    assert re == pytest.approx([-c / (2 * m)] * 2, rel=1e-12)
    assert re[0] ** 2 + im[0] ** 2 == pytest.approx(k / m, rel=1e-12)


def test_only_lab_kinds_write_run_files(make_campaign, tmp_path):
    # A design run writes a design file (loadable, same f_c and verdicts as its record), not a
    # "run.h5" that `imil report` would refuse; the selftest writes selftest.h5.
    path = make_campaign(
        '[campaign]\nname = "d"\nkind = "design"\n[[study]]\nname = "fc"\nproduct = { f_c = [60, 80] }\n'
    )
    result = run_campaign(load_campaign(path), tmp_path / "out", InlineExecutor())
    for record in result.records:
        assert record.status == "ok" and record.hdf5.endswith("/design.json")
        design = load_design(result.root / record.hdf5)
        assert design.fc_hz == record.settings["f_c"]
        c = design.constraint_at(design.fc_hz)
        assert (c.I, c.II, c.III) == (record.metrics["I"], record.metrics["II"], record.metrics["III"])
    assert not list((tmp_path / "out").rglob("run.h5"))
    selftest = run_campaign(
        load_campaign(make_campaign(HEAD + '[[study]]\nname = "one"\n', "s.toml")),
        tmp_path / "s",
        InlineExecutor(),
    )
    assert [r.hdf5.rsplit("/", 1)[-1] for r in selftest.records] == ["selftest.h5"]


def test_local_pool_gives_the_same_metrics_as_inline(sd_campaign, tmp_path):
    spec = load_campaign(sd_campaign)
    inline = run_campaign(spec, tmp_path / "a", InlineExecutor())
    with LocalExecutor(2) as pool:
        pooled = run_campaign(spec, tmp_path / "b", pool)
    strip = lambda rs: [{k: v for k, v in r.metrics.items() if k != "worker_pid"} for r in rs]
    assert strip(inline.records) == strip(pooled.records)
    assert {r.metrics["worker_pid"] for r in pooled.records} != {float(os.getpid())}


def test_a_failing_run_is_recorded_and_the_campaign_goes_on(make_campaign, tmp_path):
    path = make_campaign(
        HEAD + '[[study]]\nname = "a"\nproduct = { fail = [false, true], damping = [1, 2] }\n'
    )
    result = run_campaign(load_campaign(path), tmp_path / "out", InlineExecutor())
    assert result.count("ok") == 2 and result.count("failed") == 2
    failed = [r for r in result.records if r.status == "failed"]
    assert all(r.error == "SelftestFailure: selftest run failed on request (fail = true)" for r in failed)
    assert all(r.hdf5 == "" and r.metrics == {} for r in failed)
    # Failed runs are tried again on the next session; the ok ones are not.
    again = run_campaign(load_campaign(path), tmp_path / "out", InlineExecutor())
    assert sorted(again.executed) == sorted(r.run_id for r in failed)


def test_a_run_whose_folder_is_not_writable_fails_with_its_reason(sd_campaign, tmp_path):
    spec = load_campaign(sd_campaign)
    out = tmp_path / "out"
    blocked = spec.runs[1].run_id
    (out / "runs").mkdir(parents=True)
    if os.geteuid() == 0:
        # root ignores permission bits: occupy the run's folder name with a file instead.
        (out / "runs" / blocked).write_text("not a folder")
        reason = "FileExistsError"
    else:
        (out / "runs" / blocked).mkdir()
        os.chmod(out / "runs" / blocked, 0o555)
        reason = "PermissionError"
    result = run_campaign(spec, out, InlineExecutor())
    status = {r.run_id: r for r in result.records}
    assert status[blocked].status == "failed" and status[blocked].error.startswith(reason)
    assert [status[r.run_id].status for r in spec.runs if r.run_id != blocked] == ["ok", "ok"]


def test_read_only_run_folder_as_an_unprivileged_user(sd_campaign, tmp_path):
    """The same check with real permission bits: run the engine as 'nobody' when root."""
    if os.geteuid() != 0:
        pytest.skip("covered by the previous test when not root")
    out = tmp_path / "ro"
    spec = load_campaign(sd_campaign)
    blocked = spec.runs[0].run_id
    (out / "runs" / blocked).mkdir(parents=True)
    for folder in (tmp_path, out, out / "runs"):
        os.chmod(folder, 0o777)
    os.chmod(out / "runs" / blocked, 0o555)
    os.chmod(sd_campaign, 0o644)
    for parent in tmp_path.parents:  # pytest's tmp folders are private to root
        if str(parent).startswith("/tmp/pytest-of"):
            os.chmod(parent, parent.stat().st_mode | 0o011)
    code = (
        "import sys; from impedance_mil.campaign import *; "
        "r = run_campaign(load_campaign(sys.argv[1]), sys.argv[2], InlineExecutor()); "
        "print(';'.join(f'{x.run_id}={x.status}={x.error}' for x in r.records))"
    )
    try:
        proc = subprocess.run(
            [sys.executable, "-c", code, str(sd_campaign), str(out)],
            user=65534,
            capture_output=True,
            text=True,
            timeout=60,
        )
    except PermissionError as exc:
        pytest.skip(f"'nobody' cannot execute this Python ({exc.strerror})")
    if proc.returncode != 0 and "Permission denied" in proc.stderr and "records" not in proc.stderr:
        pytest.skip(f"cannot run as nobody here: {proc.stderr.strip().splitlines()[-1]}")
    assert proc.returncode == 0, proc.stderr
    outcomes = dict(item.split("=", 1) for item in proc.stdout.strip().split(";"))
    assert outcomes[blocked].startswith("failed=PermissionError")
    assert sum(v.startswith("ok=") for v in outcomes.values()) == 2


def _interrupt_after(k):
    def on_progress(event):
        if event.done == k:
            raise KeyboardInterrupt

    return on_progress


def test_interrupted_inline_campaign_resumes_with_only_the_remaining_runs(make_campaign, tmp_path):
    path = make_campaign(HEAD + '[[study]]\nname = "a"\nproduct = { stiffness = [1, 2, 3, 4, 5, 6, 7] }\n')
    spec, out = load_campaign(path), tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_campaign(spec, out, InlineExecutor(), on_progress=_interrupt_after(3))
    first = {p.stem: p.stat().st_mtime_ns for p in (out / "records").iterdir()}
    assert len(first) == 3
    # The summary written at the interrupt lists all seven runs, four of them not run.
    with open(out / "summary.csv") as fh:
        assert [row["status"] for row in csv.DictReader(fh)].count("not run") == 4
    result = run_campaign(spec, out, InlineExecutor())
    assert set(result.skipped) == set(first)
    assert set(result.executed) == {r.run_id for r in spec.runs} - set(first)
    assert {p.stem: p.stat().st_mtime_ns for p in (out / "records").iterdir() if p.stem in first} == first


def test_interrupted_pool_campaign_resumes_with_only_the_remaining_runs(make_campaign, tmp_path):
    path = make_campaign(
        HEAD + '[base]\ndelay = "0.05 s"\n'
        '[[study]]\nname = "a"\nproduct = { stiffness = [1, 2, 3, 4, 5, 6, 7, 8] }\n'
    )
    spec, out = load_campaign(path), tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        with LocalExecutor(2) as pool:
            run_campaign(spec, out, pool, on_progress=_interrupt_after(2))
    done_before = {p.stem for p in (out / "records").iterdir()}
    # Runs in flight at the interrupt are recorded too; pending ones are cancelled.
    assert 2 <= len(done_before) < len(spec.runs)
    with LocalExecutor(2) as pool:
        result = run_campaign(spec, out, pool)
    assert set(result.executed) == {r.run_id for r in spec.runs} - done_before
    assert result.count("ok") == len(spec.runs)


def test_killed_campaign_resumes_with_only_the_remaining_runs(make_campaign, tmp_path):
    """SIGKILL the whole process group mid-campaign, then restart."""
    path = make_campaign(
        HEAD + '[base]\ndelay = "0.3 s"\n'
        '[[study]]\nname = "a"\nproduct = { stiffness = [1, 2, 3, 4, 5, 6, 7, 8] }\n'
    )
    out = tmp_path / "out"
    code = (
        "import sys; from impedance_mil.campaign import *; "
        "run_campaign(load_campaign(sys.argv[1]), sys.argv[2], InlineExecutor())"
    )
    proc = subprocess.Popen([sys.executable, "-c", code, str(path), str(out)], start_new_session=True)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        records = out / "records"
        if records.is_dir() and len(list(records.glob("*.json"))) >= 2:
            break
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait(timeout=10)
    recorded = {p.stem for p in (out / "records").glob("*.json")}
    assert 2 <= len(recorded) < 8
    # A record is written before its output is renamed into place, so the kill may leave a
    # record without its output (that run is redone), never an output without a record.
    spec = load_campaign(path)
    kind_output = get_kind(spec.runs[0].kind).output
    done_before = {r for r in recorded if (out / "runs" / r / kind_output).is_file()}
    outputs = {d.name for d in (out / "runs").iterdir() if (d / kind_output).is_file()}
    assert outputs == done_before and len(recorded - done_before) <= 1
    result = run_campaign(spec, out, InlineExecutor())
    assert set(result.skipped) == done_before
    assert set(result.executed) == {r.run_id for r in spec.runs} - done_before
    assert stale_temporaries(out) == []  # what the kill left is removed when the next session starts


def test_summary_csv_and_parquet_hold_one_row_per_run(make_campaign, tmp_path):
    path = make_campaign(
        HEAD + '[[study]]\nname = "a"\nproduct = { fail = [false, true], damping = [1, 2] }\n'
    )
    spec = load_campaign(path)
    result = run_campaign(spec, tmp_path / "out", InlineExecutor())
    with open(result.summary.csv) as fh:
        rows = list(csv.DictReader(fh))
    table = pq.read_table(result.summary.parquet).to_pylist()
    assert len(rows) == len(table) == 4
    assert list(rows[0])[:8] == ["run_id", "study", "status", "error", "hdf5", "elapsed_s", "fail", "damping"]
    for row, arrow in zip(rows, table):
        assert row["run_id"] == arrow["run_id"] and row["status"] == arrow["status"]
        assert arrow["fail"] is (row["fail"] == "True")
        if row["status"] == "ok":
            assert float(row["frequency_hz"]) == arrow["frequency_hz"]
            assert (tmp_path / "out" / row["hdf5"]).is_file()
        else:
            assert row["frequency_hz"] == "" and arrow["frequency_hz"] is None
    loaded = load_summary(tmp_path / "out")
    assert len(loaded.where(status="ok")) == 2 and len(loaded.where(fail=True)) == 2
    assert all(math.isfinite(v) for v in loaded.values("damping_ratio"))


def test_without_pyarrow_the_summary_is_the_csv_alone(make_campaign, tmp_path, monkeypatch):
    # pyarrow is an extra (`impedance-mil[parquet]`, docs/dependencies.md): a core install has none
    monkeypatch.setattr(summary_module, "parquet", None)
    monkeypatch.setattr(summary_module, "pyarrow", None)
    spec = load_campaign(make_campaign(HEAD + '[[study]]\nname = "a"\nproduct = { damping = [1, 2] }\n'))
    result = run_campaign(spec, tmp_path / "out", InlineExecutor())
    assert result.summary.parquet is None and not (tmp_path / "out" / "summary.parquet").exists()
    assert len(load_summary(tmp_path / "out").rows) == 2
