"""A Dask cluster as the studies reach it: a client for a scheduler's address, or one clear error saying why not."""

from contextlib import contextmanager

#: s a study waits for a scheduler to answer before it says it cannot be reached
CONNECT_TIMEOUT = 10.0


class ClusterError(ValueError):
    """A Dask scheduler that cannot be used; the message names its address and why."""


@contextmanager
def dask_client(scheduler):
    """A ``distributed.Client`` for ``scheduler``: an address (``tcp://host:8786``), connected within
    :data:`CONNECT_TIMEOUT` s and closed on leaving, or a client of the caller's, used as it is.  A scheduler that
    cannot be reached, or a machine without dask.distributed, is :class:`ClusterError` naming it."""
    try:
        from distributed import Client
    except ImportError:
        raise ClusterError("running on a Dask cluster needs dask.distributed: pip install 'dask[distributed]'") \
            from None
    if isinstance(scheduler, Client):
        yield scheduler
        return
    try:
        client = Client(scheduler, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError, ValueError, TypeError) as exc:
        why = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise ClusterError(f"the Dask scheduler {scheduler} cannot be reached within {CONNECT_TIMEOUT:g} s "
                           f"({why}); is it running, and is the address right?") from None
    try:
        yield client
    finally:
        client.close()


#: the Dask setting that turns a worker's statistical profiler off.  Under Python 3.11 the profiler's
#: ``sys._current_frames`` holds the interpreter's thread-list lock while the garbage collector it may run waits
#: for the GIL, and a task starting a thread (a batch's member threads) holds the GIL waiting for that lock: the
#: worker deadlocks (CPython issue 116969; 3.12 runs the collector only between bytecodes)
NO_WORKER_PROFILER = {"distributed.worker.profile.enabled": False}


def local_cluster(workers: int, *, processes: bool = True):
    """A ``distributed.LocalCluster`` of ``workers`` single-threaded workers on this machine (a process each, or
    threads of this one), with no dashboard, the scheduler's HTTP server on a free port (its default, 8787,
    may be held by another cluster, and distributed would take another with a warning) and the workers'
    profiler off (:data:`NO_WORKER_PROFILER`)."""
    import copy

    import dask
    from distributed import LocalCluster

    with dask.config.set(NO_WORKER_PROFILER):
        # a worker process its nanny starts again later takes the nanny's config, not this context's
        nanny = {"config": copy.deepcopy(dask.config.config)} if processes else {}
        return LocalCluster(n_workers=workers, threads_per_worker=1, processes=processes, dashboard_address=None,
                            scheduler_kwargs={"dashboard_address": ":0"}, **nanny)


def completed(futures: dict):
    """``(futures[future], result)`` of each of ``futures`` (Dask or concurrent futures, keyed to what they run) as it
    completes; ``result`` is the exception of a task lost on the cluster (a KilledWorker, an error in the task),
    which fails alone."""
    from concurrent.futures import as_completed as concurrent_completed

    from distributed import Future, as_completed

    waiting = as_completed(futures) if all(isinstance(f, Future) for f in futures) else concurrent_completed(futures)
    for future in waiting:
        try:
            yield futures[future], future.result()
        except Exception as exc:  # noqa: BLE001 - a task lost on the cluster fails alone
            yield futures[future], exc
