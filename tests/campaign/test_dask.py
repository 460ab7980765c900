"""The Dask executor: same code path and same results as the local pool; clear errors otherwise."""

from __future__ import annotations

import pytest

from impedance_mil.campaign import InlineExecutor, SchedulerError, executors, load_campaign, run_campaign

distributed = pytest.importorskip("distributed", reason="optional extra impedance-mil[dask] missing")


def test_campaign_on_a_dask_cluster_matches_inline(sd_campaign, tmp_path):
    spec = load_campaign(sd_campaign)
    inline = run_campaign(spec, tmp_path / "inline", InlineExecutor())
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster:
        with executors.make_executor(scheduler=cluster.scheduler_address, connect_timeout_s=10) as pool:
            assert pool.workers == 2 and "Dask scheduler" in pool.description
            dask_result = run_campaign(spec, tmp_path / "dask", pool)
    assert [r.status for r in dask_result.records] == ["ok"] * 3
    drop = lambda rs: [{k: v for k, v in r.metrics.items() if k != "worker_pid"} for r in rs]
    assert drop(dask_result.records) == drop(inline.records)
    assert all((tmp_path / "dask" / r.hdf5).is_file() for r in dask_result.records)


def test_missing_dask_is_a_one_line_error(monkeypatch):
    monkeypatch.setattr(executors, "distributed", None)
    with pytest.raises(
        SchedulerError, match=r"^--scheduler needs Dask: pip install 'impedance-mil\[dask\]'$"
    ):
        executors.make_executor(scheduler="tcp://127.0.0.1:8786")


def test_unreachable_scheduler_fails_within_the_timeout():
    with pytest.raises(SchedulerError, match="no Dask scheduler reachable within 0.5 s"):
        executors.make_executor(scheduler="tcp://127.0.0.1:9", connect_timeout_s=0.5)
