"""Ensembles: every bundled record at many amplitudes, so that an engine is judged on a distribution of
runs, not on which side of a jump in a chaotic response one run happens to land.

Rocking under a record is sensitive to its amplitude: the rigid rocking equation takes the 1 x 6 m
monolith from 0.163 alpha under El Centro at 2.75 m/s^2 to 0.208 alpha at 2.76 m/s^2.  An
:class:`Ensemble` therefore scales each record (its strong-motion window,
:mod:`comparisons.cases.strong_motion`) to several multiples of the threshold of the motion it studies
(``g tan(alpha)`` for rocking, ``mu g`` for sliding) on two blocks, and each engine's runs are
compared member by member with the reference:

* rocking: the rigid rocking equation with Housner's impact rule
  (:func:`comparisons.references.rocking_equation.rocking_response`);
* sliding: the exact rigid-plastic integration (:func:`comparisons.references.analytical.rigid_plastic_sliding`).

Peak error of a member: ``(peak - reference peak) / max(reference peak, floor)`` with the peak |theta|
of the block (rocking) or its largest |slip| (sliding).  The floor, alpha/30 for rocking (the rocking
criterion of docs/method.md section 3) and 0.1 mm for sliding (the onset criterion of the
``sliding_onset`` case), keeps a member in which the block barely moves from turning noise into a
large relative error.  An overturned engine's peak is alpha (it reached the critical angle); members
whose reference overturns have no peak error (their peak is alpha by definition) and count only in
the agreement on overturning, so that every engine is judged on the same members.  A run an engine
stopped as unstable has an infinite peak error and disagrees on overturning.

Per engine and step: the median and 90th percentile of |peak error|, the share of members on which
it agrees with the reference about overturning, and the median wall time of a run
(:func:`summarise`).  The native core's members run together on the CPU's threads
(:func:`comparisons.harness.engines.simulate_members`), each timed by its own time loop.  :func:`run_ensemble` returns
the tidy table of every run, for the report, a benchmark script or a test.
"""

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from comparisons.cases.case import ENGINES, by_name, declared_band
from comparisons.cases.measures import peak_until_overturn
from comparisons.cases.strong_motion import strong_motion
from comparisons.harness import engines
from comparisons.harness.engines import settings_label
from comparisons.harness.progress import terminal_bar
from comparisons.references import analytical
from comparisons.references.rocking_equation import rocking_response
from dem_core import records, scenes

#: the floor of the relative peak error: rocking, as a fraction of alpha; sliding, m
ROCKING_FLOOR = 1.0 / 30.0
SLIDING_FLOOR = 1e-4
#: multiples of the threshold from 1.2 to 3: where a block rocks (or slides) without certainly overturning
SCALES = tuple(np.round(np.linspace(1.2, 3.0, 10), 3))
QUICK_SCALES = (1.2, 1.8, 2.4, 3.0)
#: base of the sliding blocks, m: wide enough for the largest slip of any member
SLIDING_BASE = 40.0

#: steps of each engine in the full rocking ensembles (native: divisors of the automatic step; others: s).
#: PyBullet stops at 1e-3 s: its runs cost five times pymunk's, and 5e-4 s would double its share
LADDER = {
    "dem": (1, 4),
    "dem-overlap": (1, 4),
    "dem-moreau": (1, 4, 10),
    "pymunk": (2e-3, 1e-3, 5e-4),
    "pybullet": (2e-3, 1e-3),
    "mujoco": (2e-3, 1e-3, 5e-4),
}


@dataclass(frozen=True)
class Member:
    """One run of an ensemble: a block (width, height in m) under a record scaled to ``scale`` times the
    threshold, i.e. to ``pga`` m/s^2, for the record's strong-motion window (``duration`` s)."""

    block: tuple
    record: str
    scale: float
    pga: float
    duration: float

    @property
    def block_label(self) -> str:
        return f"{self.block[0]:g} x {self.block[1]:g} m"


@dataclass(frozen=True, kw_only=True)
class Ensemble:
    """An ensemble declaration.

    name, title : as for a case.
    kind : ``"rocking"`` or ``"sliding"``.
    blocks : (width, height) of each block, m.
    friction : mu of a sliding block on its base (None: the scenes' default, 0.7, for rocking).
    records : keys of :data:`dem_core.records.BUNDLED`.
    scales : multiples of the threshold (``g tan(alpha)`` or ``mu g``) each record is scaled to.
    bands : ``{metric: {engine: value}}`` at the engine's usual step: an upper bound on
        ``median_error`` and ``p90_error``, a lower bound on ``overturn_agreement``; declared for the
        quick ensembles, which CI runs (the full ones run in the report).
    quick : run by ``--quick`` and CI.
    ladder : ``{engine: steps}`` of the full run (None: :data:`LADDER`); a quick ensemble runs the usual steps.
    """

    name: str
    title: str
    kind: str
    blocks: tuple
    records: tuple = tuple(records.BUNDLED)
    scales: tuple = SCALES
    friction: float | None = None
    bands: dict = field(default_factory=dict)
    quick: bool = False
    ladder: dict | None = None

    def __post_init__(self):
        if self.kind not in ("rocking", "sliding"):
            raise ValueError(f"{self.name}: kind must be 'rocking' or 'sliding', got {self.kind!r}")
        if self.kind == "sliding" and self.friction is None:
            raise ValueError(f"{self.name}: a sliding ensemble needs the friction of its blocks")

    def scene(self, block):
        width, height = block
        if self.kind == "sliding":
            return scenes.block(width, height, friction=self.friction, base_width=SLIDING_BASE)
        return scenes.block(width, height)

    def threshold(self, block) -> float:
        """m/s^2: ``g tan(alpha)`` (rocking) or ``mu g`` (sliding)."""
        if self.kind == "sliding":
            return self.friction * analytical.G
        return analytical.rocking_onset_acceleration(analytical.RockingBlock.from_size(*block))

    def members(self) -> list:
        out = []
        for block in self.blocks:
            for record in self.records:
                for scale in self.scales:
                    pga = float(scale * self.threshold(block))
                    out.append(Member(block, record, float(scale), pga, strong_motion(record, pga).end_time))
        return out

    def band(self, metric: str, engine: str) -> float:
        return declared_band(self.bands, f"ensemble {self.name!r}", metric, engine)


def all_ensembles() -> list:
    """The ensembles of the report, quick ones first.

    Rocking: the 1 x 6 m monolith (tan alpha = 1/6, the thesis' column as one block) and a 1.5 x 6 m
    block (tan alpha = 1/4, the Housner block's slenderness): the same height, hence nearly the same
    frequency parameter p (1.56 and 1.54 rad/s), so that the two differ in slenderness alone.  Both
    are large enough not to overturn under most members (the 0.25 x 1 m block topples under 34 of
    the 40 members of one slenderness).  Sliding: a squat 1 x 0.5 m block (tan alpha = 2) and a
    1 x 1.5 m one (tan alpha = 2/3), both with mu = 0.2 < tan alpha, so that rigid blocks slide
    without ever tipping, and the rigid-plastic reference holds for both.  Sliding is the easy part (on the
    quick ensemble every engine's median error is 0.1% or less, MuJoCo's 1.8%): the full sliding ensemble
    runs each engine at its usual step only.
    """
    every = ENGINES
    # quick (El Centro at 4 amplitudes): 3 of the 4 rocking runs are judged on the peak, one of them at a jump
    # (El Centro at 1.8 g tan(alpha): the engines scatter from -35% to +90%), so the median is the middle one
    # of three; measured dem 7.3%, dem-overlap 36% (its lever arm is short: early, larger rocking),
    # pymunk 2.8%, pybullet 5.0%, mujoco 1.1%, dem-moreau 0.3%; every engine agreed on overturning in all 4 runs
    rocking_bands = {"median_error": {"dem": 0.15, "dem-overlap": 0.6, "dem-moreau": 0.15, "pymunk": 0.15,
                                      "pybullet": 0.15, "mujoco": 0.15},
                     "overturn_agreement": {e: 0.75 for e in every}}
    # measured median 0.04% to 0.08% and 90th percentile 0.11% to 0.14%; mujoco 1.8% and 4.2% (its soft
    # contact creeps while the block sticks); dem-moreau 0.008% and 0.09%
    sliding_bands = {"median_error": {"dem": 0.01, "dem-overlap": 0.01, "dem-moreau": 0.01, "pymunk": 0.01,
                                      "pybullet": 0.01, "mujoco": 0.05},
                     "p90_error": {"dem": 0.01, "dem-overlap": 0.01, "dem-moreau": 0.01, "pymunk": 0.01,
                                   "pybullet": 0.01, "mujoco": 0.10},
                     "overturn_agreement": {e: 1.0 for e in every}}
    return [
        Ensemble(name="rocking_records_quick", title="1 x 6 m monolith under El Centro 1940 at 4 amplitudes "
                 "from 1.2 to 3 g tan(alpha) (rocking equation)", kind="rocking", blocks=((1.0, 6.0),),
                 records=("el_centro_1940",), scales=QUICK_SCALES, bands=rocking_bands, quick=True),
        Ensemble(name="sliding_records_quick", title="1 x 0.5 m block, mu = 0.2, under El Centro 1940 at 4 "
                 "amplitudes from 1.2 to 3 mu g (rigid-plastic sliding)", kind="sliding", blocks=((1.0, 0.5),),
                 friction=0.2, records=("el_centro_1940",), scales=QUICK_SCALES, bands=sliding_bands, quick=True),
        Ensemble(name="rocking_records", title="Rocking under the four bundled records at 10 amplitudes from "
                 "1.2 to 3 g tan(alpha): the 1 x 6 m monolith and a 1.5 x 6 m block (rocking equation)",
                 kind="rocking", blocks=((1.0, 6.0), (1.5, 6.0))),
        Ensemble(name="sliding_records", title="Sliding under the four bundled records at 10 amplitudes from "
                 "1.2 to 3 mu g: 1 x 0.5 m and 1 x 1.5 m blocks, mu = 0.2 (rigid-plastic sliding)",
                 kind="sliding", blocks=((1.0, 0.5), (1.0, 1.5)), friction=0.2,
                 ladder={e: (engines.USUAL_STEP[e],) for e in every}),
    ]


def ensemble(name: str) -> Ensemble:
    """The ensemble declared under ``name``."""
    return by_name(all_ensembles(), name, "ensemble")


@dataclass(frozen=True)
class _Reference:
    peak: float  # rad (rocking) or m (sliding)
    overturned: bool
    floor: float  # same unit as peak
    critical: float  # rad, the peak an overturned block is given


def reference(ens: Ensemble, member: Member) -> _Reference:
    """The reference's peak and overturning for one member."""
    motion = strong_motion(member.record, member.pga)
    if ens.kind == "rocking":
        block = analytical.RockingBlock.from_size(*member.block)
        history = rocking_response(block, motion, member.duration)
        return _Reference(history.peak, history.overturned, ROCKING_FLOOR * block.alpha, block.alpha)
    slip = analytical.rigid_plastic_sliding(motion.horizontal.samples, motion.horizontal.dt, ens.friction,
                                            t_end=member.duration)
    return _Reference(slip.max_slip, False, SLIDING_FLOOR, np.inf)


def _engine_peak(ens: Ensemble, result, critical: float) -> float:
    """Peak |theta| of the block up to its overturn, alpha once overturned (rocking); largest |slip| (sliding)."""
    if ens.kind == "sliding":
        return float(np.max(np.abs(result.relative_x[:, 0] - result.relative_x[0, 0])))
    return min(peak_until_overturn(result, 0), critical)


def _steps(ens, ens_engines, steps, quick):
    plan = {}
    for engine in ens_engines:
        given = (steps or {}).get(engine)
        if given is None:
            given = (engines.USUAL_STEP[engine],) if quick else (ens.ladder or LADDER)[engine]
        plan[engine] = [s if isinstance(s, tuple) else (s, {}) for s in given]
    return plan


def run_ensemble(ens: Ensemble, engine_names=ENGINES, steps: dict | None = None, *, quick: bool | None = None,
                 progress: bool = True) -> pd.DataFrame:
    """Every member of ``ens`` in every engine at every step: the tidy table, one row per run.

    engine_names : the engines to run.
    steps : ``{engine: [step or (step, settings), ...]}`` (native steps are divisors of the automatic
        step); an engine left out runs its usual step when ``quick`` (default: ``ens.quick``), else
        :data:`LADDER`.
    Columns: ensemble, engine, step (label), dt (s), settings, block, record, scale, pga (m/s^2),
    reference_peak, reference_overturned, peak, overturned, error, status, wall_time_s.
    """
    quick = ens.quick if quick is None else quick
    plan = _steps(ens, engine_names, steps, quick)
    members = ens.members()
    references = [reference(ens, m) for m in members]
    motions = [strong_motion(m.record, m.pga) for m in members]
    scene_of = {block: ens.scene(block) for block in ens.blocks}
    member_scenes = [scene_of[m.block] for m in members]
    output_dts = [min(0.005, motion.horizontal.dt / 2) for motion in motions]
    runs = [(engine, step, settings) for engine, ladder in plan.items() for step, settings in ladder]
    rows = []
    bar = terminal_bar(total=len(runs) * len(members), desc=ens.name, unit="run", progress=progress)
    with bar:
        for engine, step, settings in runs:
            done = engines.simulate_members(member_scenes, motions, [m.duration for m in members], engine, step,
                                            settings, output_dts, progress=bar.update)
            for member, ref, run in zip(members, references, done):
                rows.append(_row(ens, member, ref, engine, settings, run))
    return pd.DataFrame(rows)


def _row(ens: Ensemble, member: Member, ref: _Reference, engine: str, settings: dict, run) -> dict:
    """One run's row of :func:`run_ensemble`'s table."""
    if run.status == "ok":
        peak = _engine_peak(ens, run.result, ref.critical)
        overturned = bool(run.result.overturned) if ens.kind == "rocking" else False
        error = (peak - ref.peak) / max(ref.peak, ref.floor) if not ref.overturned else np.nan
    else:
        peak, overturned = np.nan, not ref.overturned
        error = np.inf if not ref.overturned else np.nan
    return {"ensemble": ens.name, "engine": engine, "step": run.label, "dt": run.dt,
            "settings": settings_label(settings), "block": member.block_label, "record": member.record,
            "scale": member.scale, "pga": member.pga, "reference_peak": ref.peak,
            "reference_overturned": ref.overturned, "peak": peak, "overturned": overturned,
            "error": error, "status": run.status, "wall_time_s": run.wall_time_s}


def run_ensembles(quick: bool, engine_names=ENGINES, progress: bool = True) -> pd.DataFrame:
    """The quick ensembles (``quick``) or the full ones, in one tidy table."""
    tables = [run_ensemble(e, engine_names, progress=progress) for e in all_ensembles() if e.quick == quick]
    return pd.concat(tables, ignore_index=True)


def summarise(table: pd.DataFrame) -> pd.DataFrame:
    """Per ensemble, engine and step: members, median and 90th percentile of |peak error| (over the
    members whose reference does not overturn), share agreeing on overturning, median wall time (s)."""
    out = []
    for (name, engine, step), runs in table.groupby(["ensemble", "engine", "step"], sort=False):
        errors = np.abs(runs.error[~runs.reference_overturned].to_numpy(dtype=float))
        out.append({"ensemble": name, "engine": engine, "step": step, "dt": runs["dt"].median(),
                    "members": len(runs), "judged_on_peak": len(errors),
                    "median_error": float(np.median(errors)) if len(errors) else np.nan,
                    "p90_error": float(np.percentile(errors, 90)) if len(errors) else np.nan,
                    "overturn_agreement": float(np.mean(runs.overturned == runs.reference_overturned)),
                    "reference_overturns": int(runs.reference_overturned.sum()),
                    "median_wall_time_s": float(runs.wall_time_s.median()),
                    "stopped": int((runs.status != "ok").sum())})
    return pd.DataFrame(out)
