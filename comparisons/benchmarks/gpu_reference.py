"""The device check's CPU side, run ahead where there is no GPU: one JSON file for ``gpu-check --cpu-reference``.

    python -m comparisons gpu-reference [--out .whl/agreement.json] [--sample 64] [--duration 20]

``gpu-check``'s agreement compares each member's peak on the GPU with the same member on the CPU, and a member nudged
by NUDGE on the CPU to tell the chaotic ones.  On the lent machine the CPU's batch kernel compiles first (about
four minutes cold), which is device time.  This runs that CPU side here for every case of
:data:`~comparisons.benchmarks.record_members.CASES` and writes each member's peak, nudged peak and steps, the
batch's wall time and threads, and the machine and versions it ran on.  ``.ci/gpu-wheels`` writes it into .whl/
beside the kernels, and ``.ci/gpu-check`` hands it to the check.

A case is keyed by :func:`members_key`: the digest of dem_core's sources, the scene, every member's motion, the
integrator, the duration and the options.  The check takes a case from the file only where its own key is the same,
and runs the CPU side itself otherwise.
"""

import argparse
import json
from importlib import metadata
from pathlib import Path

import numpy as np

from dem_core.analyses.run_identity import code_digest, describe, digest, machine
from dem_core.batch import simulate_batch
from dem_core.cli.arguments import SECONDS, WORKERS

from .record_members import CASES, SCENES, ignore_the_cut_strong_motion, motions

#: a member is not chaotic when its CPU peak moves less than STEADY (relative) as its scale moves by NUDGE
STEADY, NUDGE = 1e-10, 1e-12
#: the agreement's members a case and their duration (s of the record), by default
SAMPLE, DURATION = 64, 20.0
#: the options every agreement batch runs with
OPTIONS = {"stop_at_overturn": True}
#: where .ci/gpu-wheels writes the file and .ci/gpu-check looks for it
DEFAULT_OUT = ".whl/agreement.json"
#: s of the one-member batch that compiles (or loads) the CPU's kernel before a case is timed
WARM_UP = 0.01
#: what :func:`load` requires of the file: of it, of its machine and of each case
REQUIRED = {"file": ("made_on", "cases"), "made_on": ("machine", "numpy", "numba"),
            "case": ("key", "peaks", "nudged", "steps", "wall_time_s", "threads", "device")}


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--out", default=DEFAULT_OUT, help=f"the JSON file written (default {DEFAULT_OUT})")
    parser.add_argument("--sample", type=WORKERS, default=SAMPLE, help=f"members a case (default {SAMPLE})")
    parser.add_argument("--duration", type=SECONDS, default=DURATION, help=f"s of the record (default {DURATION:g})")
    parser.add_argument("--threads", type=WORKERS, default=None,
                        help="the CPU batch's threads (default numba's, at most --sample)")


def members_key(name: str, integrator: str, sample: int, duration: float) -> str:
    """The digest that names one case's CPU side: the code, the scene, the members' motions and nudged motions,
    the integrator, the duration and :data:`OPTIONS`."""
    build, tan_alpha = SCENES[name]
    return digest({"code": code_digest(), "scene": describe(build()), "motions": describe(motions(tan_alpha, sample)),
                   "nudged": describe(motions(tan_alpha, sample, NUDGE)), "integrator": integrator,
                   "duration": duration, "options": describe(OPTIONS)})


def cpu_side(name: str, integrator: str, sample: int, duration: float, threads: int | None = None,
             progress=None) -> dict:
    """One case on the CPU's threads: ``{"peaks", "nudged"}`` (the members' peak |theta| over alpha, (sample,)),
    ``"steps"`` (each member's), ``"wall_time_s"`` and ``"threads"`` of the members' batch, and ``"device"``."""
    import numba

    build, tan_alpha = SCENES[name]
    alpha = float(np.arctan(tan_alpha))
    threads = min(threads or numba.get_num_threads(), sample)
    options = {"integrator": integrator, "device": "cpu", "threads": threads, "progress": progress, **OPTIONS}
    simulate_batch(build(), motions(tan_alpha, 1), WARM_UP, **options)  # the kernel compiled outside the timing
    cpu = simulate_batch(build(), motions(tan_alpha, sample), duration, **options)
    nudged = simulate_batch(build(), motions(tan_alpha, sample, NUDGE), duration, **options)
    return {"peaks": peaks(cpu, alpha).tolist(), "nudged": peaks(nudged, alpha).tolist(),
            "steps": cpu.table["steps"].to_numpy(int).tolist(), "wall_time_s": cpu.wall_time_s,
            "threads": threads, "device": cpu.device}


def peaks(batch, alpha: float) -> np.ndarray:
    """The batch's members' peak |theta| over ``alpha``, (members,)."""
    return batch.table["max_peak_abs_theta_rad"].to_numpy(float) / alpha


def made_on() -> dict:
    """The machine and the versions a CPU side runs with."""
    return {"machine": machine(), **{name: metadata.version(name) for name in ("numpy", "numba")}}


def load(path) -> tuple[dict, dict]:
    """``(cases by members_key, made_on)`` from a file :func:`run` wrote; ``ValueError`` naming the file and what is
    wrong with it where it is not one."""
    try:
        written = json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as error:
        raise ValueError(f"{path} cannot be read ({error.strerror or error})") from None
    except ValueError as error:
        raise ValueError(f"{path} is not JSON ({error})") from None
    lacking = _lacking(written, "file")
    if not lacking:
        lacking = _lacking(written["made_on"], "made_on")
        if not isinstance(written["cases"], list):
            lacking.append("cases as a list")
        else:
            lacking += list(dict.fromkeys(what for case in written["cases"] for what in _lacking(case, "case")))
    if not lacking and not all(isinstance(case["key"], str) for case in written["cases"]):
        lacking.append("case keys as text")
    if lacking:
        raise ValueError(f"{path} is not a CPU reference written by `python -m comparisons gpu-reference`: it lacks "
                         f"{', '.join(lacking)}")
    return {case["key"]: case for case in written["cases"]}, written["made_on"]


def _lacking(thing, part: str) -> list:
    """What ``thing``, the file or a part of it (a key of :data:`REQUIRED`), lacks of what :func:`load` requires."""
    if not isinstance(thing, dict):
        return [f"{part} as a mapping"]
    return [f"{part} {name!r}" for name in REQUIRED[part] if name not in thing]


def run(args: argparse.Namespace) -> None:
    """Run every case of :data:`CASES` on the CPU and write the file."""
    ignore_the_cut_strong_motion()
    cases = []
    for name, integrator in CASES:
        side = cpu_side(name, integrator, args.sample, args.duration, args.threads)
        cases.append({"scene": name, "integrator": integrator, "sample": args.sample, "duration": args.duration,
                      "key": members_key(name, integrator, args.sample, args.duration), **side})
        print(f"{name}, {integrator}: {args.sample} members, {args.duration:g} s each, on {side['device']}: "
              f"{side['wall_time_s']:.1f} s, its longest member {max(side['steps']):,} steps (and as many nudged)",
              flush=True)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"made_on": made_on(), "cases": cases}, indent=1) + "\n", encoding="utf-8")
    print(f"written to {out}")
