"""Where the per-file work of ``gmr convert --batch`` and ``gmr dataset`` runs: in this
process, in ``--jobs N`` local processes, or on a Dask cluster (``--scheduler``).

``--scheduler tcp://HOST:8786`` connects to a running ``dask scheduler`` whose workers have
the package installed and see the same paths; ``--scheduler local:N`` starts a
``distributed.LocalCluster`` of N single-threaded worker processes for the run. Dask comes
with the ``cluster`` extra (``pip install gmr-studio[cluster]``). A task whose worker dies is
run again on another (Dask's own retry of lost tasks, up to ``distributed.scheduler.
allowed-failures`` times); tasks never raise (they return their error), so a bad file is
never retried.

:func:`results` yields results as tasks complete (any order); :func:`ordered_results` in
submission order, keeping at most ``window`` tasks in flight, so a consumer that writes one
stream holds only a few results at a time.
"""

from __future__ import annotations

import contextlib
import os
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from typing import Any

from gmr_studio.core.errors import OperationError

LOCAL_PREFIX = "local:"


def describe(jobs: int, scheduler: str | None) -> str:
    """Words for the summary line: ``2 processes``, ``Dask tcp://...``."""
    if scheduler:
        return f"Dask {scheduler}"
    return f"{jobs} process{'es' if jobs > 1 else ''}"


def _dask():
    try:
        import distributed
    except ImportError:
        raise OperationError("--scheduler needs Dask: pip install 'gmr-studio[cluster]' (dask[distributed])") from None
    return distributed


@contextlib.contextmanager
def dask_client(scheduler: str) -> Iterator[Any]:
    """A ``distributed.Client`` for ``tcp://HOST:PORT`` (or any address Dask takes) or
    ``local:N`` (a LocalCluster of N worker processes, closed afterwards)."""
    distributed = _dask()
    if scheduler.startswith(LOCAL_PREFIX):
        try:
            n_workers = int(scheduler[len(LOCAL_PREFIX) :])
        except ValueError:
            n_workers = 0
        if n_workers < 1:
            raise OperationError(f"--scheduler {scheduler}: expected local:N with N >= 1 workers")
        with (
            distributed.LocalCluster(
                n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=None
            ) as cluster,
            distributed.Client(cluster) as client,
        ):
            yield client
        return
    try:
        client = distributed.Client(scheduler, timeout="20s")
    except OSError as exc:
        raise OperationError(f"cannot reach the Dask scheduler {scheduler}: {exc}") from None
    with client:
        yield client


def results(
    function: Callable, arguments: Sequence[tuple], *, jobs: int = 1, scheduler: str | None = None
) -> Iterator[Any]:
    """``function(*args)`` for every tuple of ``arguments``, yielded as each completes."""
    if scheduler:
        distributed = _dask()
        with dask_client(scheduler) as client:
            futures = [client.submit(function, *args, pure=False) for args in arguments]
            for future in distributed.as_completed(futures):
                yield future.result()
        return
    if jobs <= 1:
        for args in arguments:
            yield function(*args)
        return
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        pending: set[Future] = {pool.submit(function, *args) for args in arguments}
        try:
            while pending:
                finished, pending = wait(pending, return_when=FIRST_COMPLETED)
                for future in finished:
                    yield future.result()
        except BaseException:
            pool.shutdown(wait=True, cancel_futures=True)
            raise


def ordered_results(
    function: Callable, arguments: Iterable[tuple], *, jobs: int = 1, scheduler: str | None = None, window: int = 0
) -> Iterator[Any]:
    """``function(*args)`` for every tuple, yielded in the order given, with at most
    ``window`` (default: twice the workers) tasks submitted and not yet yielded."""
    arguments = iter(arguments)
    if scheduler:
        with dask_client(scheduler) as client:
            n_workers = max(1, len(client.scheduler_info().get("workers", {})))
            yield from _windowed(
                lambda args: client.submit(function, *args, pure=False), arguments, window or 2 * n_workers
            )
        return
    if jobs <= 1:
        for args in arguments:
            yield function(*args)
        return
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        yield from _windowed(lambda args: pool.submit(function, *args), arguments, window or 2 * jobs)


def _windowed(submit: Callable[[tuple], Any], arguments: Iterator[tuple], window: int) -> Iterator[Any]:
    in_flight: deque = deque()
    for args in arguments:
        in_flight.append(submit(args))
        if len(in_flight) >= window:
            yield in_flight.popleft().result()
    while in_flight:
        yield in_flight.popleft().result()


def default_jobs(jobs: int | None, n_tasks: int) -> int:
    """``--jobs``, else every core, never more than the tasks."""
    return max(1, min(jobs or os.cpu_count() or 1, n_tasks))


def file_task(function: Callable, source: str, *args: Any) -> tuple[str, Any]:
    """``function(source, *args)`` for one file of a batch, in a worker: ``("", result)``,
    or ``(error line, None)`` when it fails (a bad file's own ``path:line:col`` line, else
    ``source: message``). Never raises, so one bad file does not stop the batch."""
    from gmr_studio.core.errors import MotionFileError

    try:
        return "", function(source, *args)
    except MotionFileError as exc:
        return str(exc), None
    except (OperationError, OSError, ValueError) as exc:
        return f"{source}: {exc}", None
    except Exception as exc:
        return f"{source}: {type(exc).__name__}: {exc}", None
