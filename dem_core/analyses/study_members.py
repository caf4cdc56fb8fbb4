"""The members of a study (one scene under many motions) run as batches where they are sent, this machine's cores or
a Dask cluster's workers, with each finished member's row appended to a log that a rerun of the study resumes from.

A member is known in the log by its run digest (:func:`~dem_core.analyses.run_identity.run_digest`: the scene,
the motion's every sample and scale, the settings and the dem_core code) and the measures taken of it, so a rerun
with anything changed runs again what changed and never mixes in rows of other settings.  On this machine the
members run as one batch and each is logged as it ends (:func:`~dem_core.batch.simulate_batch`'s ``finished``):
Ctrl-C or a crash loses only the members running.  On a cluster each group of members (a study's: one record's
stripes) is one task, a batch on the worker's cores or GPU (``device="auto"``), whose rows are logged as it
returns; the members of a task lost on the cluster get the status :data:`LOST` and are not logged, so a rerun runs
them again.
"""

import json
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from ..batch import simulate_batch
from .cluster import completed, dask_client
from .run_identity import describe, digest, run_digest

#: the log of a study's finished members, in the study's output folder
LOG = "members.jsonl"
#: the status of a member whose cluster task was lost (a worker died, the task raised): not logged, so run again
LOST = "lost"


class MembersInterrupted(KeyboardInterrupt):
    """Ctrl-C during a study's members: ``saved`` finished members of ``total`` are in the log (0 without one)."""

    def __init__(self, saved: int, total: int, log: Path | None):
        super().__init__(f"interrupted after {saved} of {total} members")
        self.saved, self.total, self.log = saved, total, log


@dataclass(frozen=True)
class MemberRuns:
    """What :func:`run_members` returns: ``table``, one row per member in the motions' order (the columns of
    :func:`~dem_core.batch.member_row` and the measures); ``device``, where they ran, in words; ``wall_time_s``;
    ``resumed``, the members read from the log instead of run."""

    table: pd.DataFrame
    device: str
    wall_time_s: float
    resumed: int = 0


class MemberLog:
    """Finished members' rows, one JSON line ``{"digest": ..., "row": {...}}`` each, appended as they finish.  A
    line that cannot be read (the torn last line of a crash) is skipped."""

    def __init__(self, path):
        self.path = Path(path)

    def finished(self, digests) -> dict:
        """{digest: row} of the logged members whose digest is among ``digests``."""
        wanted, found = set(digests), {}
        if not self.path.is_file():
            return found
        with open(self.path, encoding="utf-8") as handle:
            for line in handle:
                try:
                    entry = json.loads(line)
                except json.JSONDecodeError:
                    continue
                if isinstance(entry, dict) and entry.get("digest") in wanted:
                    found[entry["digest"]] = entry["row"]
        return found

    def append(self, rows) -> None:
        """Append ``rows``, pairs ``(digest, row)``, and flush them to the file."""
        with open(self.path, "a", encoding="utf-8") as handle:
            handle.writelines(json.dumps({"digest": member_digest, "row": row}, default=_plain) + "\n"
                              for member_digest, row in rows)
            handle.flush()


def _plain(value):
    """JSON for what a member's row holds beside plain numbers and text: numpy scalars, pandas' missing value."""
    if isinstance(value, np.generic):
        return value.item()
    if value is pd.NA:
        return None
    raise TypeError(f"a member's row holds {type(value).__name__}, which the log cannot keep")


def run_members(scene, motions: list, duration, groups: list, *, log=None, scheduler=None, device: str = "auto",
                threads: int | None = None, progress=None, measures=None, **simulate_options) -> MemberRuns:
    """Run ``scene`` under each of ``motions`` (as :func:`~dem_core.batch.simulate_batch` does, with ``duration``,
    ``device``, ``threads``, ``measures`` and ``simulate_options``) and return their rows.

    groups : lists of member indices that partition the members: one cluster task each.
    log : path of a :class:`MemberLog`: members it holds are not run again, and every finished member is appended
        as it ends.
    scheduler : address of a running Dask scheduler, or a ``distributed.Client``; ``measures`` must then be a
        module-level function (it travels to the workers).
    progress : optional ``function(done, total)``.
    Ctrl-C raises :class:`MembersInterrupted` once the finished members are logged.
    """
    started = time.perf_counter()
    log = None if log is None else MemberLog(log)
    settings = {**simulate_options, "duration": duration}
    measured = describe(measures)
    digests = [digest([run_digest(scene, motion, settings), measured]) for motion in motions] if log else []
    rows = _logged(log, digests)
    resumed = len(rows)
    todo = [[m for m in group if m not in rows] for group in groups]
    todo = [group for group in todo if group]
    total = len(motions)

    def finish(found: dict) -> None:
        rows.update(found)
        if log is not None:  # a member lost on the cluster runs again on resuming
            log.append((digests[m], row) for m, row in found.items() if row["status"] != LOST)
        if progress is not None:
            progress(len(rows), total)

    run = {"scene": scene, "motions": motions, "duration": duration, "device": device, "measures": measures,
           "options": simulate_options}
    where = "resumed from the log"
    try:
        if todo and scheduler is not None:
            where = _on_cluster(todo, scheduler, run, finish)
        elif todo:
            where = _here(todo, threads, run, finish)
    except KeyboardInterrupt:
        raise MembersInterrupted(len(rows) if log is not None else 0, total, None if log is None else log.path) \
            from None
    table = pd.DataFrame([{**rows[m], "member": m} for m in sorted(rows)])
    if "overturned" in table:
        table["overturned"] = table["overturned"].astype("boolean")
    return MemberRuns(table, where, time.perf_counter() - started, resumed)


def _logged(log, digests) -> dict:
    """{member: row} of the members the log holds."""
    if log is None:
        return {}
    found = log.finished(digests)
    return {m: found[d] for m, d in enumerate(digests) if d in found}


def _here(groups: list, threads, run: dict, finish) -> str:
    """Run ``groups`` on this machine as one batch, each member's row passed to ``finish`` as the member ends."""
    members = [m for group in groups for m in group]

    def ended(k: int, row: dict) -> None:
        finish({members[k]: {**row, "member": members[k]}})

    return simulate_batch(run["scene"], [run["motions"][m] for m in members], run["duration"], device=run["device"],
                          threads=threads, measures=run["measures"], finished=ended, **run["options"]).device


def _batch_rows(members: list, threads, run: dict, progress=None) -> tuple:
    """``({member: row}, device)`` of one batch of ``members`` (indices into ``run["motions"]``)."""
    batch = simulate_batch(run["scene"], [run["motions"][m] for m in members], run["duration"], device=run["device"],
                           threads=threads, measures=run["measures"], progress=progress, **run["options"])
    found = {members[k]: {**row, "member": members[k]} for k, row in enumerate(batch.table.to_dict("records"))}
    return found, batch.device


def _remote(members: list, run: dict) -> tuple:
    """A cluster task: one group's batch on the worker's cores or GPU."""
    return _batch_rows(members, None, run)


def _on_cluster(groups: list, scheduler, run: dict, finish) -> str:
    """Run each of ``groups`` as one task on the Dask cluster of ``scheduler``; ``finish`` takes each task's rows as
    it returns.  A task lost on the cluster fails its members alone."""
    devices = set()
    with dask_client(scheduler) as client:
        workers = len(client.scheduler_info().get("workers", {}))
        [shared] = client.scatter([run], broadcast=True)
        futures = {client.submit(_remote, group, shared, pure=False): tuple(group) for group in groups}
        try:
            for group, done in completed(futures):
                if isinstance(done, Exception):
                    finish({m: _lost(m, run["motions"][m].name, done) for m in group})
                    continue
                found, device = done
                devices.add(device)
                finish(found)
        finally:
            client.cancel(list(futures))
    ran = ", ".join(sorted(d for d in devices if d)) or "no batch finished"
    return f"Dask cluster of {workers} worker{'s' * (workers != 1)} ({ran} each)"


def _lost(member: int, motion: str, exc: Exception) -> dict:
    """The row of a member whose cluster task failed."""
    return {"member": member, "motion": motion, "status": LOST, "error": f"{type(exc).__name__}: {exc}",
            "wall_time_s": math.nan}
