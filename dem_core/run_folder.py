"""The folder of one run, as ``dem-core run`` writes it and a script can: the time history, a row of measures per
block and per interface (:meth:`~dem_core.Result.metrics`, :meth:`~dem_core.Result.interface_metrics`), under a
sequence of ground motions a row per event (:attr:`~dem_core.Result.events`), with connectors a row per connector
and their forces over time (:attr:`~dem_core.Result.connectors`, :meth:`~dem_core.Result.connector_frame`), and
summary.json, each file written
whole or not at all (:func:`~dem_core.output_files.replacing`).

summary.json says whether the folder is whole: ``status`` is "incomplete" from before the first file is written
until the writer marks it "complete", or "stopped" (the run lost stability: the files hold it up to there, and
``stop_reason`` says why); ``files`` lists what was written.
"""

import json
from pathlib import Path

import numpy as np

from .output_files import replacing

#: the files a run writes into its folder (an animation's name is recorded in summary.json)
RUN_FILES = ("summary.json", "scene.json", "time_history.csv", "time_history.parquet", "metrics.csv", "interfaces.csv",
             "events.csv", "connectors.csv", "connector_history.csv", "rotations.png", "displacements.png", "sliding.png",
             "epistyles.png", "snapshots.png")


def run_summary(result, scene: Path, stopped: str, setup: float | None = None) -> dict:
    """What summary.json holds: the scene file, whether the run is complete (``status``: "incomplete" until
    every file is written, then "complete", or "stopped" with ``stop_reason``), its measures and run facts (among
    them ``ended_at_overturn``, where a run that stops at its first overturn ended: no loss of stability);
    ``compile_time_s`` is ``setup``, the seconds this run took to set up and compile its engine (or load it
    from numba's cache), when given."""
    measures = {k: (v.item() if isinstance(v, np.generic) else v) for k, v in result.summary().items()}
    if setup is not None:
        measures["compile_time_s"] = float(setup)
    summary = {"scene": str(scene.resolve()), "status": "incomplete", "stop_reason": stopped or None,
               "end_time_s": float(result.t[-1]), **measures, "blocks": list(result.names)}
    return {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in summary.items()}


def write_summary(out: Path, summary: dict) -> None:
    """summary.json into ``out``."""
    with replacing(out / "summary.json") as tmp:
        tmp.write_text(json.dumps(summary, indent=2))


def write_run(result, out: Path, fmt: str, summary: dict) -> list:
    """summary.json (status "incomplete" until the caller marks it otherwise), the time history in ``fmt`` ("csv"
    or "parquet"), metrics.csv, interfaces.csv and under a sequence of ground motions events.csv into ``out``, each
    whole or not at all; returns the names written."""
    write_summary(out, {**summary, "files": []})
    history = f"time_history.{fmt}"
    with replacing(out / history) as tmp:
        frame = result.to_frame()
        if fmt == "parquet":
            frame.to_parquet(tmp, index=False)
        else:
            frame.to_csv(tmp, index=False)
    with replacing(out / "metrics.csv") as tmp:
        result.metrics().to_csv(tmp, index=False)
    with replacing(out / "interfaces.csv") as tmp:
        result.interface_metrics().to_csv(tmp, index=False)
    written = ["summary.json", history, "metrics.csv", "interfaces.csv"]
    if result.events is not None:
        with replacing(out / "events.csv") as tmp:
            result.events.to_csv(tmp, index=False)
        written.append("events.csv")
    if result.connectors is not None:
        with replacing(out / "connectors.csv") as tmp:
            result.connectors.to_csv(tmp, index=False)
        with replacing(out / "connector_history.csv") as tmp:
            result.connector_frame().to_csv(tmp, index=False)
        written += ["connectors.csv", "connector_history.csv"]
    return written
