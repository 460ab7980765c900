"""Campaign and file integrity (issue 18, findings 6 and 10).

Finding 6: a campaign named ``x/../../../...`` wrote its folder outside ``-o``.
Finding 10: a truncated ``run.h5`` whose record said ok was skipped on resume
(and ``campaign report`` exited 0 over it); SIGKILL left ``.tmp-*`` files
that were never cleaned; after Ctrl-C, outputs existed without records; two
``campaign run`` sessions on one folder each ran every run.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from impedance_mil import fileio
from impedance_mil.campaign import (
    CampaignStore,
    InlineExecutor,
    RunRecord,
    load_campaign,
    load_summary,
    run_campaign,
)
from impedance_mil.errors import ConfigError, DataFileError
from impedance_mil.fileio import FolderLockedError, file_sha256, stale_temporaries

CAMPAIGN = '[campaign]\nname = "{name}"\nkind = "selftest"\n[[study]]\nname = "a"\nproduct = {{ stiffness = [1, 2, 3] }}\n'


def write_campaign(folder: Path, name: str = "t") -> Path:
    path = folder / "c.toml"
    path.write_text(CAMPAIGN.format(name=name))
    return path


def tree(folder: Path) -> set[str]:
    return {p.relative_to(folder).as_posix() for p in folder.rglob("*")}


def outputs(out: Path) -> dict[str, Path]:
    """run_id -> output file present under runs/."""
    return {p.parent.name: p for p in (out / "runs").glob("*/*") if not p.name.startswith(".")}


# ------------------------------------------------------------------ finding 6: names stay inside -o
@pytest.mark.parametrize("name", ["x/../../../escape", "../up", "/abs", ".hidden", "a\\b", "", "x" * 65])
def test_a_campaign_name_that_is_not_one_safe_name_is_refused(tmp_path, name):
    with pytest.raises(ConfigError) as info:
        load_campaign(write_campaign(tmp_path, name))
    assert info.value.key == "campaign.name"


def test_the_campaign_command_writes_nothing_outside_its_folder(imil, tmp_path):
    work = tmp_path / "a" / "b" / "c"
    work.mkdir(parents=True)
    path = write_campaign(work, "x/../../../escape")
    before = tree(tmp_path)
    for extra in ([], ["-o", "out"]):
        out = imil("campaign", "run", path, "--workers", "0", *extra, cwd=work)
        assert out.returncode == 2 and out.stderr.startswith("imil: error: campaign.name: ")
        assert len(out.stderr.strip().splitlines()) == 1
    assert tree(tmp_path) == before  # nothing written anywhere


def test_a_record_pointing_outside_the_folder_is_not_trusted(tmp_path):
    outside = tmp_path / "outside.h5"
    outside.write_bytes(b"\x89HDF not really")
    store = CampaignStore(tmp_path / "out")
    store.create()
    record = RunRecord("r1", "selftest", (), {}, "ok", hdf5="../outside.h5", sha256=file_sha256(outside))
    store.write_record(record)
    assert store.output_problem(record) == "../outside.h5: outside the campaign folder"
    assert not store.is_done("r1")
    with pytest.raises(ConfigError, match="^run_id: "):
        store.record_path("../../etc/passwd")


# ------------------------------------------------------------------ finding 10: resume verifies outputs
@pytest.fixture
def finished(tmp_path):
    spec = load_campaign(write_campaign(tmp_path))
    result = run_campaign(spec, tmp_path / "out", InlineExecutor())
    assert result.count("ok") == 3
    return spec, tmp_path / "out"


def damage_truncate(path: Path) -> None:
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


def damage_zero_tail(path: Path) -> None:
    # The audit zeroed the last 20 kB of a run file.  A selftest file is 6 kB whose last 4 kB
    # are already zero (free space), so zero everything after its first quarter: same size,
    # some of the data gone.
    data = path.read_bytes()
    damaged = data[: len(data) // 4] + bytes(len(data) - len(data) // 4)
    assert damaged != data and len(damaged) == len(data)
    path.write_bytes(damaged)


@pytest.mark.parametrize("damage", [damage_truncate, damage_zero_tail, lambda p: p.unlink()])
def test_a_damaged_output_is_redone_on_resume_and_not_reported(imil, finished, damage):
    spec, out = finished
    victim = spec.runs[1].run_id
    damage(outputs(out)[victim])
    with pytest.raises(DataFileError, match=f"run {victim}: runs/{victim}/selftest.h5: "):
        load_summary(out)
    report = imil("campaign", "report", out, "-o", out.parent / "r.html")
    assert (
        report.returncode == 2 and f"run {victim}" in report.stderr and not (out.parent / "r.html").exists()
    )
    again = run_campaign(spec, out, InlineExecutor())
    assert again.executed == (victim,) and set(again.skipped) == {r.run_id for r in spec.runs} - {victim}
    assert load_summary(out).column("status") == ["ok", "ok", "ok"]
    record = CampaignStore(out).load_record(victim)
    assert record.sha256 == file_sha256(out / record.hdf5)


def test_a_record_without_checksum_is_redone(finished):
    spec, out = finished
    store = CampaignStore(out)
    victim = spec.runs[0].run_id
    old = json.loads(store.record_path(victim).read_text())
    del old["sha256"]  # a record written before checksums were recorded
    store.record_path(victim).write_text(json.dumps(old))
    assert run_campaign(spec, out, InlineExecutor()).executed == (victim,)


def test_stale_temporaries_are_removed_at_start(finished):
    spec, out = finished
    run_dir = out / "runs" / spec.runs[0].run_id
    stale = [
        run_dir / ".selftest.h5.tmp-99999-0123abcd",
        out / "records" / f".{spec.runs[0].run_id}.json.tmp-99999-89abcdef",
        out / ".summary.csv.tmp-1-deadbeef",
    ]
    for path in stale:
        path.write_bytes(b"left by a killed process")
    (out / "runs" / ".old-folder.old-12-0badf00d").mkdir()
    keep = out / ".keep"
    keep.write_text("not ours")
    assert len(stale_temporaries(out)) == 4
    result = run_campaign(spec, out, InlineExecutor())
    assert result.executed == () and stale_temporaries(out) == [] and keep.exists()


# ------------------------------------------------------------------ Ctrl-C: never an output without a record
def interrupt_at_replace(monkeypatch, out: Path, n: int) -> None:
    """Raise KeyboardInterrupt at the n-th rename into runs/ or records/ (Ctrl-C landing there)."""
    real = os.replace
    calls = []

    def replace(src, dst):
        if out in Path(dst).parents and Path(dst).parent != out:  # runs/<id>/<file> or records/<id>.json
            calls.append(dst)
            if len(calls) == n:
                raise KeyboardInterrupt
        return real(src, dst)

    monkeypatch.setattr(fileio.os, "replace", replace)


@pytest.mark.parametrize("n", range(1, 7))
def test_an_interrupt_at_any_rename_leaves_no_output_without_its_record(monkeypatch, tmp_path, n):
    spec = load_campaign(write_campaign(tmp_path))
    out = tmp_path / "out"
    interrupt_at_replace(monkeypatch, out, n)
    with pytest.raises(KeyboardInterrupt):
        run_campaign(spec, out, InlineExecutor())
    monkeypatch.undo()
    store = CampaignStore(out)
    for run_id, path in outputs(out).items():
        record = store.load_record(run_id)
        assert record is not None, f"output {path.name} of {run_id} has no record"
        assert record.sha256 == file_sha256(path)
    assert stale_temporaries(out) == []
    result = run_campaign(spec, out, InlineExecutor())
    assert result.count("ok") == 3 and all(store.is_done(r.run_id) for r in spec.runs)


def test_an_interrupted_pool_leaves_no_output_without_its_record(tmp_path):
    from impedance_mil.campaign import LocalExecutor

    path = tmp_path / "c.toml"
    path.write_text(
        '[campaign]\nname = "p"\nkind = "selftest"\n[base]\ndelay = "0.05 s"\n'
        '[[study]]\nname = "a"\nproduct = { stiffness = [1, 2, 3, 4, 5, 6, 7, 8] }\n'
    )
    spec, out = load_campaign(path), tmp_path / "out"

    def stop(event):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        with LocalExecutor(2) as pool:
            run_campaign(spec, out, pool, on_progress=stop)
    # The runs in flight at the interrupt finished (the pool waits for them) and recorded themselves.
    store = CampaignStore(out)
    assert len(outputs(out)) >= 2
    assert all(store.load_record(run_id) is not None for run_id in outputs(out))
    assert stale_temporaries(out) == []


# ------------------------------------------------------------------ one session per folder
def test_a_second_session_on_a_folder_is_refused(imil, tmp_path):
    path = write_campaign(tmp_path)
    out = tmp_path / "out"
    store = CampaignStore(out)
    store.create()
    with store.lock():
        with pytest.raises(FolderLockedError, match="in use by another imil campaign run"):
            run_campaign(load_campaign(path), out, InlineExecutor())
        cli = imil("campaign", "run", path, "-o", out, "--workers", "0")
        assert cli.returncode == 2 and len(cli.stderr.strip().splitlines()) == 1
        assert f"in use by another imil campaign run ({os.uname().nodename}:{os.getpid()})" in cli.stderr
    assert tree(out) == {"runs", "records", ".lock"}  # the refused sessions wrote nothing
    assert run_campaign(load_campaign(path), out, InlineExecutor()).count("ok") == 3


def test_the_lock_dies_with_its_holder(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    code = (
        "import sys, time; from impedance_mil.fileio import folder_lock\n"
        "with folder_lock(sys.argv[1]):\n    print('held', flush=True); time.sleep(600)\n"
    )
    holder = subprocess.Popen([sys.executable, "-c", code, str(out)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(FolderLockedError, match=f":{holder.pid}\\)"):
            with fileio.folder_lock(out):
                pass
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait(timeout=30)
    with fileio.folder_lock(out):  # released by the system when the holder died
        pass
