"""A fragility study: one scene under a suite of records, each scaled to stripes of an intensity measure, run as
one batch, and a lognormal fragility fitted per damage state (:mod:`dem_core.analyses.fragility`).

Damage is measured by the damage ratio, the largest over the blocks of peak |theta| over the critical angle that
governs the block: its column's (the tilt at which the stack tips as one body, :mod:`dem_core.engine.stacks`) for
a block in a column, its own ``atan(b/h)`` otherwise.  A run exceeds damage state ``s`` below 1 when its damage
ratio reaches ``s`` or it overturned; state 1 is overturning, as the engine's overturn rule finds it
(docs/method.md section 3).
"""

from __future__ import annotations

import functools
import json
import math
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..inputs.excitation import GroundMotion, extended, peak_velocity, record_name, scaled, unscaled
from ..inputs.number_types import is_integer, is_real
from ..inputs.records import G_STANDARD
from ..inputs.text_files import shown
from ..output_files import replacing
from ..simulation import integrator_for, warn_caller
from .damage import residual_dislocation, residual_tilt, still_at_end
from .fragility import fragility_figure
from .nested_fragility import ADVISED_RECORDS, fit_nested, fit_states, ida_estimate
from .spectra import response_spectrum
from .study_members import run_members

#: the intensity measures: name -> (label, unit)
INTENSITY_MEASURES = {"pga": ("PGA", "m/s^2"), "pgv": ("PGV", "m/s"), "sa": ("Sa(T)", "m/s^2")}
#: the highest stripe when none is given: 1 g of PGA, 1 m/s of PGV
DEFAULT_TOP = {"pga": G_STANDARD, "pgv": 1.0, "sa": G_STANDARD}
#: a record's spectrum is read at periods of at least this many of its sampling intervals (twice the shortest period
#: its samples hold) and at most its length
SHORTEST_PERIOD_SAMPLES = 4
DEFAULT_STATES = (0.1, 0.3, 0.5, 1.0)
#: the damage measures a state is set on: key -> (the runs' column, what it is, its unit); a run exceeds a state
#: when it overturned or its measure reached the state's threshold (peak theta/alpha: 1 is overturning itself)
DAMAGE_MEASURES = {"peak": ("damage_ratio", "peak |theta|/alpha", ""),
                   "dislocation": ("residual_dislocation_mm", "residual dislocation", "mm"),
                   "tilt": ("residual_tilt_rad", "residual tilt", "rad")}
#: s of ground at rest after each record when a study measures what the runs leave (residual states) and is given
#: no other: time for a column's rocking to die out
RESIDUAL_REST = 10.0
#: m/s: a run whose blocks all move slower than this at its end left a resting state (``at_rest`` in its row)
STILL_SPEED = 0.01
#: s: the periods of the spectral accelerations a study compares with PGA and PGV (a rocking column has no natural
#: period of its own, so the measure is compared at a few)
DEFAULT_PERIODS = (0.5, 1.0, 2.0)


@dataclass(frozen=True)
class FragilityStudy:
    """What :func:`fragility_study` returns.

    runs : one row per run: ``record``, ``level`` (the intensity, in the measure's unit), ``scale`` (the factor
        applied to the record) and ``damage_ratio``, with residual states ``residual_dislocation_mm``,
        ``residual_tilt_rad`` and ``at_rest``, then the batch's measures (:func:`dem_core.batch.member_row`).
    fits : {state: :class:`~dem_core.analyses.fragility.Fragility`}, a state a peak |theta|/alpha (a float) or a
        residual state ``(measure, threshold)`` (:data:`DAMAGE_MEASURES`; :func:`state_parts`).
    im : the intensity measure's name (a key of :data:`INTENSITY_MEASURES`).
    device, wall_time_s : where the batch ran and how long the study took, s.
    settings : the records' names, the number of levels, the states, the measure, the duration, the integrator
        and the options of :func:`~dem_core.simulate` the study ran with (written into ``study.json``).
    ida : {state: (median, beta, records that reached it)}, the IDA-style estimate
        (:func:`~dem_core.analyses.nested_fragility.ida_estimate`).
    intensities : {record: {measure: value at unit scale}} (:func:`record_intensities`).
    resumed : runs read from the study's log instead of run (:func:`~.study_members.run_members`).
    """

    runs: pd.DataFrame
    fits: dict
    im: str
    device: str = ""
    wall_time_s: float = float("nan")
    settings: dict = field(default_factory=dict)
    ida: dict = field(default_factory=dict)
    intensities: dict = field(default_factory=dict)
    resumed: int = 0

    def table(self) -> pd.DataFrame:
        """One row per damage state: ``measure`` (a key of :data:`DAMAGE_MEASURES`), ``state`` (its threshold),
        ``median`` and ``beta`` (each measure's states fitted together, one common
        beta) with their bootstrap bands (``median_low`` .. ``beta_high``) and what the bootstrap drew again
        (``resampled``), ``records``, ``runs``, ``exceeded``, the IDA-style ``ida_median``, ``ida_beta`` and
        ``ida_records`` (the records that reached the state), and ``note``."""
        rows = []
        for state, fit in self.fits.items():
            (m_low, m_high), (b_low, b_high) = fit.median_band, fit.beta_band
            ida_median, ida_beta, ida_records = self.ida.get(state, (np.nan, np.nan, 0))
            measure, threshold = state_parts(state)
            rows.append({"measure": measure, "state": threshold, "median": fit.median, "median_low": m_low,
                         "median_high": m_high,
                         "beta": fit.beta, "beta_low": b_low, "beta_high": b_high, "resampled": fit.resampled,
                         "records": self.runs["record"].nunique(), "runs": int(fit.runs.sum()),
                         "exceeded": int(fit.exceed.sum()), "ida_median": ida_median, "ida_beta": ida_beta,
                         "ida_records": ida_records, "note": fit.note})
        return pd.DataFrame(rows)

    def counts(self) -> pd.DataFrame:
        """One row per stripe and state: ``level``, ``measure``, ``state``, ``runs`` (that finished), ``exceeded`` and
        ``unfinished`` (the stripe's runs that lost stability or were refused, in neither count)."""
        unfinished = (self.runs["status"] != "ok").groupby(self.runs["level"]).sum()
        return pd.DataFrame([{"level": level, "measure": state_parts(state)[0], "state": state_parts(state)[1],
                              "runs": int(n), "exceeded": int(z), "unfinished": int(unfinished.get(level, 0))}
                             for state, fit in self.fits.items()
                             for level, n, z in zip(fit.levels, fit.runs, fit.exceed)])

    def still_moving(self) -> int:
        """How many finished runs that did not overturn still moved at their end (``at_rest`` false: a study of
        residual states; 0 without)."""
        if "at_rest" not in self.runs:
            return 0
        standing = (self.runs["status"] == "ok") & ~self.runs["overturned"].fillna(False).astype(bool)
        return int((standing & ~self.runs["at_rest"].fillna(False).astype(bool)).sum())

    def intensity_measures(self) -> pd.DataFrame:
        """Which intensity measure predicts the damage best: one row per measure of :attr:`intensities`, the
        states fitted together (:func:`~.nested_fragility.fit_nested`) to every finished run at its own value of
        the measure (its record's value times its scale), with ``beta``, the common dispersion (the smaller, the
        more efficient the measure, Luco and Cornell 2007), and ``median_<state>``; ``runs`` and ``note``.  The
        states of peak |theta|/alpha only."""
        if not self.intensities:
            return pd.DataFrame()
        runs = self.runs[self.runs["status"] == "ok"]
        states = [state for state in self.fits if state_parts(state)[0] == "peak"]
        outcomes = np.column_stack([exceeds(runs["damage_ratio"].to_numpy(), runs["overturned"], state)
                                    for state in states]).astype(np.int64)
        placed = [k for k in range(len(states)) if 0 < outcomes[:, k].sum() < len(runs)]
        rows = []
        for measure in next(iter(self.intensities.values())):
            value = runs["scale"].to_numpy() * runs["record"].map(
                {name: found[measure] for name, found in self.intensities.items()}).to_numpy(float)
            row = {"measure": measure, "runs": len(runs)}
            medians, beta, note = (fit_nested(value, np.ones((len(runs), len(placed)), np.int64),
                                              outcomes[:, placed]) if placed else ([], np.nan, "no state placed"))
            row["beta"] = beta
            for k, state in enumerate(states):
                row[f"median_{state:g}"] = medians[placed.index(k)] if k in placed else np.nan
            rows.append({**row, "note": note})
        return pd.DataFrame(rows)

    def figure(self, title: str = ""):
        """The fits' figure (:func:`~.fragility.fragility_figure`), a panel per damage measure, titled ``title`` over
        a line that names the suite, the duration, the integrator and the step."""
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        label, unit = self.measure_label(), INTENSITY_MEASURES[self.im][1]
        families = {}
        for state, fit in self.fits.items():
            families.setdefault(state_parts(state)[0], {})[state_label(state)] = fit
        figure, axes = plt.subplots(1, len(families), figsize=(7.5 * len(families), 4.8), squeeze=False)
        for ax, (measure, fits) in zip(axes[0], families.items()):
            fragility_figure(fits, intensity=f"{label} ({unit.replace('^2', '$^2$')})", ax=ax,
                             title=f"damage as {DAMAGE_MEASURES[measure][1]}" if len(families) > 1 else "",
                             median_text=self.median_text)
        figure.suptitle("\n".join([title or "Fragility", *textwrap.wrap(self.described(), 100 * len(families))]),
                        fontsize=9)
        figure.tight_layout()
        return figure

    def measure_label(self) -> str:
        """The intensity measure's name: PGA, PGV, or Sa(T) with its period."""
        if self.im == "sa":
            return f"Sa({self.settings.get('period', float('nan')):g} s)"
        return INTENSITY_MEASURES[self.im][0]

    def median_text(self, median: float) -> str:
        """A median in its measure's unit, and for an acceleration in g."""
        unit = INTENSITY_MEASURES[self.im][1]
        in_g = f" ({median / G_STANDARD:.3g} g)" if unit == "m/s^2" else ""
        return f"{median:.3g} {unit.replace('^2', '$^2$')}{in_g}"

    def described(self) -> str:
        """The suite, the duration, the integrator and the step in a line."""
        names = list(dict.fromkeys(self.runs["record"]))
        suite = ", ".join(names) if len(names) <= 4 else f"{', '.join(names[:3])} and {len(names) - 3} more"
        duration = self.settings.get("duration")
        steps = sorted(set(np.round(self.runs["dt_s"].dropna(), 12))) if "dt_s" in self.runs else []
        step = (f"dt {steps[0]:.3g} s" if len(steps) == 1 else
                f"dt {steps[0]:.3g} to {steps[-1]:.3g} s" if steps else "dt unknown")
        rest = self.settings.get("rest", 0.0)
        whole = "each record whole" if duration is None else f"{duration:g} s of each record"
        return (f"{len(names)} records ({suite}) x {self.settings.get('levels', '?')} stripes; "
                f"{whole}{f' then {rest:g} s at rest' if rest else ''}; "
                f"{self.settings.get('integrator', '?')}, {step}")


def state_parts(state) -> tuple:
    """``(measure, threshold)`` of a study's damage state: a float is a peak |theta|/alpha, a pair a residual state
    (:data:`DAMAGE_MEASURES`)."""
    return state if isinstance(state, tuple) else ("peak", float(state))


def state_label(state) -> str:
    """A damage state in words: ``"overturning"`` for a peak |theta|/alpha of 1, ``"peak |theta|/alpha >= 0.3"``
    below, ``"residual dislocation >= 5 mm"`` for a residual state."""
    measure, threshold = state_parts(state)
    if measure == "peak" and threshold >= 1.0:
        return "overturning"
    _, what, unit = DAMAGE_MEASURES[measure]
    return f"{what} >= {threshold:g}{f' {unit}' if unit else ''}"


def _check_measure(im: str) -> None:
    if im not in INTENSITY_MEASURES:
        raise ValueError(f"intensity measure must be one of {tuple(INTENSITY_MEASURES)}, got {im!r}")


def intensity(motion: GroundMotion, im: str, period: float | None = None) -> float:
    """The intensity measure ``im`` of ``motion``'s horizontal component: PGA (m/s^2); PGV (m/s,
    :func:`~dem_core.inputs.excitation.peak_velocity`); or Sa(T) (m/s^2),
    the 5%-damped pseudo-spectral acceleration at ``period`` s (:func:`~.spectra.response_spectrum`), refused
    naming the motion outside its usable periods (:func:`check_period`)."""
    _check_measure(im)
    if im == "pga":
        return float(motion.horizontal.peak_acceleration)
    if im == "sa":
        check_period(motion, period)
        return float(response_spectrum(motion, [period]).psa[0])
    return peak_velocity(motion)


def check_period(motion: GroundMotion, period) -> None:
    """``ValueError`` naming ``motion`` where its spectrum cannot be read at ``period`` s: none given, or outside
    SHORTEST_PERIOD_SAMPLES of its sampling intervals to its length."""
    if not (is_real(period) and math.isfinite(period) and period > 0):
        raise ValueError(f"Sa(T) needs a period, a positive number of seconds; got {period!r}")
    dt, end = getattr(unscaled(motion.horizontal), "dt", None), motion.end_time
    if dt is not None and period < SHORTEST_PERIOD_SAMPLES * dt:
        raise ValueError(f"{record_name(motion)}: a period of {period:g} s is under {SHORTEST_PERIOD_SAMPLES} of its "
                         f"{dt:g} s samples; its usable periods are {SHORTEST_PERIOD_SAMPLES * dt:g} to {end:g} s")
    if math.isfinite(end) and period > end:
        raise ValueError(f"{record_name(motion)}: a period of {period:g} s is longer than the record "
                         f"({end:g} s); its usable periods end there")


def damage_measures(result) -> dict:
    """A run's measures for a study: ``{"damage_ratio": result.damage_ratio}``
    (:attr:`~dem_core.Result.damage_ratio`)."""
    return {"damage_ratio": result.damage_ratio}


def residual_measures(scene, result) -> dict:
    """A run's measures for a study of residual states: :func:`damage_measures`, the residual dislocation (mm) and
    tilt (rad) of :mod:`.damage` (nan where a block overturned: the run exceeds every state), and ``at_rest``
    (:func:`.damage.still_at_end` below :data:`STILL_SPEED`)."""
    fell = bool(np.any(result.overturned))
    return {**damage_measures(result),
            "residual_dislocation_mm": math.nan if fell else 1e3 * residual_dislocation(scene, result),
            "residual_tilt_rad": math.nan if fell else residual_tilt(result),
            "at_rest": still_at_end(result, STILL_SPEED)}


def exceeds(value, overturned, state) -> np.ndarray:
    """Whether runs of damage ``value`` (the state's measure, :data:`DAMAGE_MEASURES`) that ``overturned`` (arrays
    of one shape; a missing overturn counts as none) exceed damage ``state`` (:func:`state_parts`): a peak
    |theta|/alpha of 1 is overturning; any other state, a value of at least its threshold, or an overturn."""
    overturned = pd.Series(np.ravel(overturned)).fillna(False).to_numpy(bool).reshape(np.shape(overturned))
    measure, threshold = state_parts(state)
    if measure == "peak" and threshold >= 1.0:
        return overturned
    return overturned | (np.asarray(value, float) >= threshold)


def stripes(count: int, top: float) -> np.ndarray:
    """``count`` intensity levels evenly spaced from ``top / count`` to ``top``."""
    if not is_integer(count) or count < 2:
        raise ValueError(f"a fragility needs at least 2 intensity levels, got {count!r}")
    if not (math.isfinite(top) and top > 0):
        raise ValueError(f"the highest intensity level must be positive and finite, got {top!r}")
    return top * np.arange(1, count + 1) / count


def fragility_study(scene, records: dict, levels, states=DEFAULT_STATES, *, im: str = "pga",
                    duration: float | None = None, device: str = "auto", threads: int | None = None,
                    progress=None, samples: int | None = None, periods=DEFAULT_PERIODS,
                    period: float | None = None, log=None, scheduler=None, residual: dict | None = None,
                    rest: float | None = None, **simulate_options) -> FragilityStudy:
    """Run ``scene`` under every record of ``records`` ({name: :class:`GroundMotion`}) scaled to each intensity of
    ``levels`` (the measure ``im``), as batches (:func:`~.study_members.run_members`: one on this machine without a
    log), and fit lognormal fragilities to the damage states of ``states`` together (multiple-stripe analysis: each
    level's runs, one per record; :func:`~.nested_fragility.fit_states`).

    A run that does not finish (unstable, refused) counts in no stripe and keeps its row, with its error.
    ``period`` (s): the period of ``im="sa"``, Sa(T) (:func:`intensity`).
    ``periods`` (s): the periods of the spectral accelerations :meth:`FragilityStudy.intensity_measures` compares
    with PGA and PGV.
    ``samples`` : the bootstrap's refits (default that of :func:`fit_fragility`).  ``simulate_options`` go to
    every run, as :func:`~dem_core.simulate` takes them.
    ``log`` : a file where every finished run is saved as it ends and from which a rerun resumes; ``scheduler``: a
    Dask scheduler's address (or client) whose workers run one record's stripes each
    (:func:`~.study_members.run_members`).
    ``residual`` : what the runs leave as damage states too, {"dislocation": (mm, ...), "tilt": (rad, ...)}
    (:data:`DAMAGE_MEASURES`), each measure's states fitted together; ``rest`` (s) of ground at rest follow every
    record (default :data:`RESIDUAL_REST` with residual states, else 0), so that the runs end at rest.
    """
    _check_measure(im)
    if not records:
        raise ValueError("records is empty: a fragility needs at least one record")
    if len(records) < ADVISED_RECORDS:
        warn_caller(f"{len(records)} record(s): the fragility's record-to-record uncertainty is wide (with a "
                    f"dispersion of 0.4, a median's standard error is 0.4/sqrt(n), {0.4 / math.sqrt(len(records)):.0%}"
                    f" here); multiple-stripe analyses take {ADVISED_RECORDS} to 40 records")
    levels = np.asarray(levels, float)
    if levels.ndim != 1 or len(levels) < 2 or not np.all(np.isfinite(levels) & (levels > 0)):
        raise ValueError(f"levels must be at least 2 positive, finite intensities, got {levels}")
    states = sorted(float(s) for s in states)
    if not states or not all(0 < s <= 1 for s in states):
        raise ValueError(f"damage states are fractions of the critical angle above 0 and up to 1 (1 is "
                         f"overturning), got {states}")
    families = {"peak": states, **_residual_states(residual)}
    rest = (RESIDUAL_REST if len(families) > 1 else 0.0) if rest is None else rest
    if not (is_real(rest) and math.isfinite(rest) and rest >= 0):
        raise ValueError(f"rest must be a finite number of seconds, at least 0, got {rest!r}")
    if rest and duration is not None:
        raise ValueError(f"a rest of {rest:g} s follows each whole record: give no duration, or no rest")
    own = {name: intensity(motion, im, period) for name, motion in records.items()}
    for name, value in own.items():
        if not value > 0:
            raise ValueError(f"record {name}: its {INTENSITY_MEASURES[im][0]} is zero; it cannot be scaled")
    plan = [(name, level, level / own[name]) for level in levels for name in records]
    resting = {name: extended(motion, rest) for name, motion in records.items()}
    motions = [scaled(resting[name], factor) for name, _, factor in plan]
    by_record = [[m for m, (name, _, _) in enumerate(plan) if name == record] for record in records]
    first = scene[0] if isinstance(scene, (list, tuple)) else scene
    measures = damage_measures if len(families) == 1 else functools.partial(residual_measures, first)
    batch = run_members(scene, motions, duration, by_record, log=log, scheduler=scheduler, device=device,
                        threads=threads, progress=progress, measures=measures, **simulate_options)
    # the record and scale of the plan, as the suite names and scales it, stand for the batch's own
    runs = pd.concat([pd.DataFrame(plan, columns=["record", "level", "scale"]),
                      batch.table.drop(columns=["record", "scale"], errors="ignore")], axis=1)
    options = {} if samples is None else {"samples": samples}
    fits, ida = {}, {}
    for measure, thresholds in families.items():
        keys = thresholds if measure == "peak" else [(measure, threshold) for threshold in thresholds]
        outcomes = study_outcomes(runs, list(records), len(levels), keys)
        fits.update(zip(keys, fit_states(levels, outcomes, **options)))
        ida.update({key: ida_estimate(levels, outcomes[:, :, k]) for k, key in enumerate(keys)})
    return FragilityStudy(runs, fits, im, batch.device, batch.wall_time_s,
                          {"records": list(records), "levels": len(levels), "states": states, "im": im,
                           **({"period": period} if im == "sa" else {}),
                           **({"residual": {m: t for m, t in families.items() if m != "peak"}} if residual else {}),
                           "duration": duration, "rest": rest, **simulate_options,
                           "integrator": integrator_for(first, simulate_options.get("integrator"))},
                          ida, {name: record_intensities(motion, periods, rocking_scales(first))
                                for name, motion in records.items()},
                          batch.resumed)


def rocking_scales(scene) -> tuple[float, float]:
    """``(g tan alpha m/s^2, p R m/s)`` of ``scene`` as one rigid block, its blocks' bounding box ``2b x 2h``:
    ``alpha = atan(b / h)``, ``R = sqrt(b^2 + h^2)``, ``p = sqrt(3 g / (4 R))`` (Housner 1963), the scales of the
    dimensionless rocking measures PGA / (g tan alpha) and PGV / (p R)."""
    vertices = np.concatenate([block.vertices for block in scene.blocks])
    b, h = np.ptp(vertices, axis=0) / 2.0
    radius = math.hypot(b, h)
    return scene.gravity * b / h, math.sqrt(3.0 * scene.gravity / (4.0 * radius)) * radius


def record_intensities(motion: GroundMotion, periods=DEFAULT_PERIODS, scales: tuple | None = None) -> dict:
    """{measure: value} of ``motion`` at unit scale: PGA (m/s^2), PGV (m/s), with ``scales`` (g tan alpha, p R:
    :func:`rocking_scales`) the dimensionless PGA / (g tan alpha) and PGV / (p R), and the 5%-damped
    pseudo-spectral acceleration Sa(T) (m/s^2) at each of ``periods`` (s) (:func:`~.spectra.response_spectrum`);
    every one of them scales with the motion."""
    found = {"PGA (m/s^2)": intensity(motion, "pga"), "PGV (m/s)": intensity(motion, "pgv")}
    if scales is not None:
        found.update({"PGA/(g tan alpha)": found["PGA (m/s^2)"] / scales[0],
                      "PGV/(p R)": found["PGV (m/s)"] / scales[1]})
    if len(periods):
        spectrum = response_spectrum(motion, np.asarray(periods, float))
        found.update({f"Sa({period:g} s) (m/s^2)": float(sa) for period, sa in zip(spectrum.periods, spectrum.psa)})
    return found


def _residual_states(residual) -> dict:
    """{measure: sorted thresholds} of a study's residual states, or ValueError naming what is wrong."""
    found = {}
    for measure, thresholds in (residual or {}).items():
        if measure not in DAMAGE_MEASURES or measure == "peak":
            raise ValueError(f"residual states are set on {' or '.join(m for m in DAMAGE_MEASURES if m != 'peak')}, "
                             f"got {measure!r}")
        sequence = isinstance(thresholds, (list, tuple, np.ndarray))
        given = list(thresholds) if sequence else [thresholds]
        bad = [t for t in given if not (is_real(t) and math.isfinite(t) and t > 0)]
        if not given or bad:
            culprit = ""
            if bad and sequence and shown(thresholds) != repr(thresholds):  # cut where it is shown: name it
                culprit = f"{shown(bad[0].item() if isinstance(bad[0], np.generic) else bad[0])} in "
            raise ValueError(f"residual {measure} states must be positive thresholds in "
                             f"{DAMAGE_MEASURES[measure][2]}, got {culprit}{shown(thresholds)}")
        found[measure] = sorted(float(t) for t in given)
    return found


def study_outcomes(runs: pd.DataFrame, records: list, levels: int, states) -> np.ndarray:
    """(R, L, K) per record, level and state of a study's ``runs`` (ordered level by level, the records in
    ``records``' order within each): 1 exceeded, 0 not, nan where the run did not finish."""
    finished = (runs["status"] == "ok").to_numpy()
    outcomes = np.empty((len(records), levels, len(states)))
    for k, state in enumerate(states):
        column = DAMAGE_MEASURES[state_parts(state)[0]][0]
        hit = exceeds(runs[column].to_numpy(), runs["overturned"], state).astype(float)
        hit[~finished] = np.nan
        outcomes[:, :, k] = hit.reshape(levels, len(records)).T
    return outcomes


#: the files :func:`write_study` writes
STUDY_FILES = ("fragility.csv", "counts.csv", "runs.csv", "intensity_measures.csv", "study.json", "fragility.png")


def write_study(study: FragilityStudy, out, title: str, facts: dict | None = None) -> list:
    """Write ``study`` into the folder ``out``, each file whole or not at all: ``fragility.csv``
    (:meth:`FragilityStudy.table`), ``counts.csv`` (:meth:`FragilityStudy.counts`), ``runs.csv`` (the runs),
    ``intensity_measures.csv`` (:meth:`FragilityStudy.intensity_measures`),
    ``study.json`` (``facts``, the study's settings, the machine, the wall time, the package's version and code
    digest) and ``fragility.png`` (the figure, titled ``title``); returns the files' names."""
    from .run_identity import code_digest, machine, package_version

    out = Path(out)
    described = {**(facts or {}), **{k: v for k, v in study.settings.items() if k not in (facts or {})},
                 "device": study.device, "machine": machine(), "runs": len(study.runs),
                 "wall_time_s": study.wall_time_s, "dem_core": package_version(), "code": code_digest()}
    writers = {"fragility.csv": lambda tmp: study.table().to_csv(tmp, index=False),
               "counts.csv": lambda tmp: study.counts().to_csv(tmp, index=False),
               "runs.csv": lambda tmp: study.runs.to_csv(tmp, index=False),
               "intensity_measures.csv": lambda tmp: study.intensity_measures().to_csv(tmp, index=False),
               "study.json": lambda tmp: tmp.write_text(json.dumps(described, indent=2, default=str)),
               "fragility.png": lambda tmp: _save_png(study.figure(title), tmp)}
    for name in STUDY_FILES:
        with replacing(out / name) as tmp:
            writers[name](tmp)
    return list(STUDY_FILES)


def _save_png(figure, path) -> None:
    import matplotlib.pyplot as plt

    figure.savefig(path, dpi=130, format="png")
    plt.close(figure)
