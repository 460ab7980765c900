"""Where campaign runs execute: in this process, a local process pool, or a Dask cluster.

All three share one small interface, :class:`RunExecutor` (``submit``,
``as_completed``, ``shutdown``), so the campaign engine has a single code
path.  :func:`make_executor` picks one from the CLI options:

* ``workers = 0``: :class:`InlineExecutor`, runs one after another in this
  process (for debugging; a crash of a run is a crash of the campaign);
* ``workers >= 1``: :class:`LocalExecutor`, a
  :class:`concurrent.futures.ProcessPoolExecutor` (the default, one worker per core);
* ``scheduler = "tcp://host:port"``: :class:`DaskExecutor`, an existing Dask
  distributed cluster (optional extra ``impedance-mil[dask]``).  The workers
  must be able to import :mod:`impedance_mil`.
"""

from __future__ import annotations

import abc
import concurrent.futures as cf
import importlib.util
import multiprocessing
import os
from collections.abc import Callable, Iterable, Iterator
from typing import Any

from ..errors import ConfigError, ImilError
from ..lazy import LazyModule

#: Dask's distributed (optional extra: impedance-mil[dask]), imported when a cluster is used:
#: it takes 0.37 s to import, which every ``imil simulate`` paid through this module (issue 16).
distributed: Any = LazyModule("distributed") if importlib.util.find_spec("distributed") else None

#: Seconds to wait for a Dask scheduler before giving up (``--connect-timeout``).
DEFAULT_CONNECT_TIMEOUT_S = 5.0

#: Modules the fork server imports once, so each worker starts quickly.
_PRELOAD = ("impedance_mil.campaign.engine",)


class SchedulerError(ImilError, ConnectionError):
    """The Dask scheduler is unreachable, or Dask is not installed."""


class RunExecutor(abc.ABC):
    """Runs functions somewhere and hands back their futures as they complete.

    Attributes
    ----------
    workers : int
        Number of runs that may execute at the same time (0 for inline).
    description : str
        One line naming where runs execute, for the CLI.
    """

    workers: int = 1
    description: str = ""

    @abc.abstractmethod
    def submit(self, fn: Callable[..., Any], *args: Any) -> Any:
        """Schedule ``fn(*args)`` and return a future with ``result()`` and ``cancel()``."""

    @abc.abstractmethod
    def as_completed(self, futures: Iterable[Any]) -> Iterator[Any]:
        """Yield the futures as they complete."""

    @abc.abstractmethod
    def shutdown(self, cancel: bool = False) -> None:
        """Release the workers; with ``cancel``, drop runs that have not started.

        A local pool waits for the runs already executing (they record themselves);
        a Dask cluster does not (see ``docs/limits.md``).
        """

    def __enter__(self) -> RunExecutor:
        return self

    def __exit__(self, exc_type: Any, exc: Any, tb: Any) -> None:
        self.shutdown(cancel=exc_type is not None)


class InlineExecutor(RunExecutor):
    """Run each function in this process when its result is asked for (``--workers 0``)."""

    description = "inline (this process)"
    workers = 0

    def __init__(self) -> None:
        self._pending: dict[cf.Future, tuple[Callable[..., Any], tuple[Any, ...]]] = {}

    def submit(self, fn: Callable[..., Any], *args: Any) -> cf.Future:
        future: cf.Future = cf.Future()
        self._pending[future] = (fn, args)
        return future

    def as_completed(self, futures: Iterable[Any]) -> Iterator[Any]:
        for future in list(futures):
            job = self._pending.pop(future, None)
            if job is not None and future.set_running_or_notify_cancel():
                fn, args = job
                try:
                    future.set_result(fn(*args))
                except Exception as exc:  # delivered through the future, like a pool
                    future.set_exception(exc)
                except BaseException as exc:  # an interrupt: the future is done (not left running), then stop
                    future.set_exception(exc)
                    raise
            yield future

    def shutdown(self, cancel: bool = False) -> None:
        for future in self._pending:
            future.cancel()
        self._pending.clear()


class LocalExecutor(RunExecutor):
    """A pool of local worker processes.

    Parameters
    ----------
    workers : int
        Number of worker processes (>= 1).
    """

    def __init__(self, workers: int):
        if workers < 1:
            raise ConfigError("--workers", "a positive number of worker processes", workers)
        methods = multiprocessing.get_all_start_methods()
        method = "forkserver" if "forkserver" in methods else "spawn"
        context = multiprocessing.get_context(method)
        if method == "forkserver":
            context.set_forkserver_preload(list(_PRELOAD))
        self.workers = workers
        self.description = f"{workers} local worker process{'es' if workers > 1 else ''}"
        self._pool = cf.ProcessPoolExecutor(max_workers=workers, mp_context=context)

    def submit(self, fn: Callable[..., Any], *args: Any) -> cf.Future:
        return self._pool.submit(fn, *args)

    def as_completed(self, futures: Iterable[Any]) -> Iterator[Any]:
        return cf.as_completed(list(futures))

    def shutdown(self, cancel: bool = False) -> None:
        # Runs already executing are waited for even when cancelling, so that their records are
        # written while the campaign folder is still locked (after Ctrl-C the workers, in the same
        # process group, are interrupted too and end at once).
        self._pool.shutdown(wait=True, cancel_futures=cancel)


class DaskExecutor(RunExecutor):
    """Runs on an existing Dask distributed cluster.

    Parameters
    ----------
    address : str
        Scheduler address, e.g. ``"tcp://10.0.0.5:8786"``.
    connect_timeout_s : float
        How long to try to reach the scheduler [s].

    Raises
    ------
    SchedulerError
        Dask is not installed, or the scheduler did not answer in time.
    """

    def __init__(self, address: str, connect_timeout_s: float = DEFAULT_CONNECT_TIMEOUT_S):
        if distributed is None:
            raise SchedulerError("--scheduler needs Dask: pip install 'impedance-mil[dask]'")
        try:
            self._client = distributed.Client(address, timeout=connect_timeout_s, set_as_default=False)
        except (OSError, TimeoutError, ValueError) as exc:
            reason = " ".join(str(exc).split()) or type(exc).__name__
            raise SchedulerError(
                f"--scheduler {address}: no Dask scheduler reachable within "
                f"{connect_timeout_s:g} s ({reason[:160]})"
            ) from None
        info = self._client.scheduler_info()
        threads = sum(w.get("nthreads", 1) for w in info.get("workers", {}).values())
        self.workers = max(threads, 1)
        self.description = f"Dask scheduler {address} ({threads} worker threads)"

    def submit(self, fn: Callable[..., Any], *args: Any) -> Any:
        return self._client.submit(fn, *args, pure=False)

    def as_completed(self, futures: Iterable[Any]) -> Iterator[Any]:
        with self._client.as_current():  # this client, not a process-wide default
            yield from distributed.as_completed(list(futures))

    def shutdown(self, cancel: bool = False) -> None:
        self._client.close()


def default_workers() -> int:
    """Number of cores this process may use."""
    try:
        return max(len(os.sched_getaffinity(0)), 1)
    except AttributeError:  # pragma: no cover - not Linux
        return max(os.cpu_count() or 1, 1)


def make_executor(
    workers: int | None = None,
    scheduler: str | None = None,
    connect_timeout_s: float = DEFAULT_CONNECT_TIMEOUT_S,
) -> RunExecutor:
    """Choose an executor from the CLI options.

    Parameters
    ----------
    workers : int, optional
        0 for inline, n >= 1 for n local processes; default: one per core.
        Ignored with ``scheduler`` (the cluster decides).
    scheduler : str, optional
        Address of a Dask scheduler.
    connect_timeout_s : float
        Time allowed to reach the scheduler [s].

    Raises
    ------
    ConfigError
        A negative number of workers.
    SchedulerError
        The scheduler is unreachable or Dask is missing.
    """
    if scheduler:
        return DaskExecutor(scheduler, connect_timeout_s)
    n = default_workers() if workers is None else workers
    if n < 0:
        raise ConfigError("--workers", "0 (inline) or a positive number of processes", n)
    return InlineExecutor() if n == 0 else LocalExecutor(n)
