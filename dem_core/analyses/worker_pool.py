"""Worker processes that outlive the death of one of them and die with the process that started them.

:func:`run_tasks` runs ``function(*arguments)`` for each task on a few worker processes, one task at a
time per process, and yields ``(key, outcome, attempts)`` as tasks finish.  A worker killed or crashed while it
runs a task (``kill -9``, the out-of-memory killer, a crash in compiled code) fails only that task: the
task is started again on a new worker up to ``retries`` times and then yielded as a
:class:`WorkerDied`; the other tasks go on.  (``concurrent.futures.ProcessPoolExecutor`` instead
breaks as a whole and fails every pending task.)  Each worker watches the pid of its parent and exits
when the parent is gone, so killing the parent ends its workers too.
"""

import multiprocessing
import os
import signal
import threading
import time
import traceback
from collections import Counter, deque
from multiprocessing.connection import wait

from ..inputs.number_types import is_integer

#: s between a worker's checks that the process that started it is still its parent
PARENT_POLL_S = 0.2
#: s an idle worker is given to exit when asked before it is killed
STOP_TIMEOUT_S = 2.0


class WorkerDied(RuntimeError):
    """The worker process running a task died on every attempt; the message says how."""


class TaskFailed(RuntimeError):
    """The task raised an exception in its worker; the message holds its type, text and traceback."""


def run_tasks(tasks, workers: int, retries: int = 1):
    """Run ``tasks`` (an iterable of ``(key, function, arguments)``; function and arguments picklable)
    on ``workers`` processes; yield ``(key, outcome, attempts)`` in the order tasks finish.

    outcome : the function's return value, a :class:`TaskFailed` if it raised, or a
        :class:`WorkerDied` if its worker died on each of ``1 + retries`` attempts.
    attempts : how many workers the task was started on (more than 1 after a worker died).
    Closing the generator (or an exception in the caller, Ctrl-C) stops every worker.
    ``ValueError`` when ``workers`` is not a whole number of at least 1 (no task could ever start).
    """
    if not is_integer(workers) or workers < 1:
        raise ValueError(f"workers must be a whole number of at least 1, got {workers!r}")
    queue = deque(tasks)
    attempts = Counter()
    context = multiprocessing.get_context()
    idle, busy = [], {}
    try:
        while queue or busy:
            while queue and len(busy) < workers:
                worker = _alive(idle) or _Worker(context)
                task = queue.popleft()
                try:
                    worker.connection.send(task)
                except OSError:  # the worker died while idle: the task never reached it
                    worker.stop()
                    queue.appendleft(task)
                    continue
                except Exception as exc:  # noqa: BLE001 - a task that cannot be pickled fails alone
                    idle.append(worker)
                    yield task[0], TaskFailed(f"cannot send it to a worker process: {type(exc).__name__}: {exc}"), 0
                    continue
                attempts[task[0]] += 1
                busy[worker] = task
            ready = set(wait([w.connection for w in busy] + [w.process.sentinel for w in busy]))
            for worker in [w for w in busy if w.connection in ready or w.process.sentinel in ready]:
                key = busy[worker][0]
                try:
                    outcome = worker.connection.recv()
                except (EOFError, OSError):
                    task = busy.pop(worker)
                    worker.stop()
                    if attempts[key] <= retries:
                        queue.appendleft(task)
                    else:
                        yield key, WorkerDied(f"the worker process running it {_death(worker.process.exitcode)} on "
                                              f"each of {attempts[key]} attempts"), attempts[key]
                    continue
                del busy[worker]
                idle.append(worker)
                yield key, outcome, attempts[key]
    finally:
        for worker in [*busy, *idle]:
            worker.stop(now=worker in busy)


def _alive(idle: list):
    """An idle worker still alive, or None; the dead ones are cleared away."""
    while idle:
        worker = idle.pop()
        if worker.process.is_alive():
            return worker
        worker.stop()
    return None


def _death(exitcode) -> str:
    if exitcode is not None and exitcode < 0:
        try:
            return f"was killed by {signal.Signals(-exitcode).name}"
        except ValueError:
            return f"was killed by signal {-exitcode}"
    return f"exited with code {exitcode} before it answered"


class _Worker:
    """One worker process and the parent's end of the pipe to it."""

    def __init__(self, context):
        self.connection, child = context.Pipe()
        self.process = context.Process(target=_serve, args=(child, os.getpid()), daemon=True, name="dem-core worker")
        self.process.start()
        child.close()

    def stop(self, now: bool = True):
        """End the process: at once (``now``), or asking it first and killing it after a timeout."""
        if not now and self.process.is_alive():
            try:
                self.connection.send(None)
            except OSError:
                pass
            self.process.join(STOP_TIMEOUT_S)
        if self.process.is_alive():
            self.process.kill()
        self.process.join()
        self.connection.close()


def _serve(connection, parent_pid: int) -> None:
    """A worker's life: run the tasks sent until told to stop, or until the parent is gone."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C reaches the whole process group: the parent stops us
    threading.Thread(target=_exit_with_parent, args=(parent_pid,), daemon=True).start()
    while True:
        try:
            task = connection.recv()
        except EOFError:
            return
        if task is None:
            return
        key, function, arguments = task
        try:
            outcome = function(*arguments)
        except Exception as exc:  # noqa: BLE001 - the task's failure is its outcome
            outcome = TaskFailed(f"{type(exc).__name__}: {exc}\n{traceback.format_exc(limit=5)}")
        connection.send(outcome)


def _exit_with_parent(parent_pid: int) -> None:
    while os.getppid() == parent_pid:
        time.sleep(PARENT_POLL_S)
    os._exit(1)
