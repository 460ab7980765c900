"""Campaigns: parameter sweeps over the virtual lab, on local processes or a Dask cluster.

A campaign file names a kind of run (``frf``, ``tracking``, ``mil``,
``design``, ``selftest``), a base configuration and the parameters to vary;
:func:`load_campaign` validates and expands it, :func:`run_campaign` runs the
pending runs resumably and writes a summary table.  See ``docs/campaign.md``.
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_exports

if TYPE_CHECKING:  # what the names are; each is imported on first use (below)
    from .engine import CampaignResult, ProgressEvent, execute_run, run_campaign
    from .executors import (
        DaskExecutor,
        InlineExecutor,
        LocalExecutor,
        RunExecutor,
        SchedulerError,
        make_executor,
    )
    from .kinds import KINDS, Kind, get_kind
    from .params import Param
    from .spec import (
        DEFAULT_MAX_RUNS,
        CampaignSpec,
        RunSpec,
        builtin_campaigns,
        load_campaign,
        resolve_campaign,
    )
    from .store import CampaignStore, RunRecord, run_id_for
    from .summary import SummaryPaths, SummaryTable, load_summary

__all__ = [
    "CampaignResult",
    "CampaignSpec",
    "CampaignStore",
    "DEFAULT_MAX_RUNS",
    "DaskExecutor",
    "InlineExecutor",
    "KINDS",
    "Kind",
    "LocalExecutor",
    "Param",
    "ProgressEvent",
    "RunExecutor",
    "RunRecord",
    "RunSpec",
    "SchedulerError",
    "SummaryPaths",
    "SummaryTable",
    "builtin_campaigns",
    "execute_run",
    "get_kind",
    "load_campaign",
    "make_executor",
    "resolve_campaign",
    "run_campaign",
    "run_id_for",
    "load_summary",
]

# Each name's submodule, imported when the name is first read (PEP 562, impedance_mil/lazy.py):
# ``from impedance_mil.campaign import load_campaign`` does not import dask and the lab.
__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "engine": ("CampaignResult", "ProgressEvent", "execute_run", "run_campaign"),
        "executors": (
            "DaskExecutor",
            "InlineExecutor",
            "LocalExecutor",
            "RunExecutor",
            "SchedulerError",
            "make_executor",
        ),
        "kinds": ("KINDS", "Kind", "get_kind"),
        "params": ("Param",),
        "spec": (
            "DEFAULT_MAX_RUNS",
            "CampaignSpec",
            "RunSpec",
            "builtin_campaigns",
            "load_campaign",
            "resolve_campaign",
        ),
        "store": ("CampaignStore", "RunRecord", "run_id_for"),
        "summary": ("SummaryPaths", "SummaryTable", "load_summary"),
    },
)
