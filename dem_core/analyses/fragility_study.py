"""A fragility study: one scene under a suite of records, each scaled to stripes of an intensity measure, run as
one batch, and a lognormal fragility fitted per damage state (:mod:`dem_core.analyses.fragility`).

Damage is measured by the damage ratio, the largest over the blocks of peak |theta| over the critical angle that
governs the block: its column's (the tilt at which the stack tips as one body, :mod:`dem_core.engine.stacks`) for
a block in a column, its own ``atan(b/h)`` otherwise.  A run exceeds damage state ``s`` below 1 when its damage
ratio reaches ``s`` or it overturned; state 1 is overturning, as the engine's overturn rule finds it
(docs/method.md section 3).
"""

from __future__ import annotations

import json
import math
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..inputs.excitation import GroundMotion, record_name, scaled, unscaled
from ..inputs.records import G_STANDARD
from ..output_files import replacing
from ..simulation import integrator_for, warn_caller
from .damage import critical_angles
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
#: s: the periods of the spectral accelerations a study compares with PGA and PGV (a rocking column has no natural
#: period of its own, so the measure is compared at a few)
DEFAULT_PERIODS = (0.5, 1.0, 2.0)
#: s: the ground velocity is sampled this finely (or finer, for a motion that changes faster) to find its peak
VELOCITY_SAMPLING = 1e-3


@dataclass(frozen=True)
class FragilityStudy:
    """What :func:`fragility_study` returns.

    runs : one row per run: ``record``, ``level`` (the intensity, in the measure's unit), ``scale`` (the factor
        applied to the record) and ``damage_ratio``, then the batch's measures (:func:`dem_core.batch.member_row`).
    fits : {state: :class:`~dem_core.analyses.fragility.Fragility`}.
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
        """One row per damage state: ``state``, ``median`` and ``beta`` (the states fitted together, one common
        beta) with their bootstrap bands (``median_low`` .. ``beta_high``) and what the bootstrap drew again
        (``resampled``), ``records``, ``runs``, ``exceeded``, the IDA-style ``ida_median``, ``ida_beta`` and
        ``ida_records`` (the records that reached the state), and ``note``."""
        rows = []
        for state, fit in self.fits.items():
            (m_low, m_high), (b_low, b_high) = fit.median_band, fit.beta_band
            ida_median, ida_beta, ida_records = self.ida.get(state, (np.nan, np.nan, 0))
            rows.append({"state": state, "median": fit.median, "median_low": m_low, "median_high": m_high,
                         "beta": fit.beta, "beta_low": b_low, "beta_high": b_high, "resampled": fit.resampled,
                         "records": self.runs["record"].nunique(), "runs": int(fit.runs.sum()),
                         "exceeded": int(fit.exceed.sum()), "ida_median": ida_median, "ida_beta": ida_beta,
                         "ida_records": ida_records, "note": fit.note})
        return pd.DataFrame(rows)

    def counts(self) -> pd.DataFrame:
        """One row per stripe and state: ``level``, ``state``, ``runs`` (that finished), ``exceeded`` and
        ``unfinished`` (the stripe's runs that lost stability or were refused, in neither count)."""
        unfinished = (self.runs["status"] != "ok").groupby(self.runs["level"]).sum()
        return pd.DataFrame([{"level": level, "state": state, "runs": int(n), "exceeded": int(z),
                              "unfinished": int(unfinished.get(level, 0))}
                             for state, fit in self.fits.items()
                             for level, n, z in zip(fit.levels, fit.runs, fit.exceed)])

    def intensity_measures(self) -> pd.DataFrame:
        """Which intensity measure predicts the damage best: one row per measure of :attr:`intensities`, the
        states fitted together (:func:`~.nested_fragility.fit_nested`) to every finished run at its own value of
        the measure (its record's value times its scale), with ``beta``, the common dispersion (the smaller, the
        more efficient the measure, Luco and Cornell 2007), and ``median_<state>``; ``runs`` and ``note``."""
        if not self.intensities:
            return pd.DataFrame()
        runs = self.runs[self.runs["status"] == "ok"]
        states = list(self.fits)
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
        """The fits' figure (:func:`~.fragility.fragility_figure`), titled ``title`` over a line that names the
        suite, the duration, the integrator and the step."""
        label, unit = self.measure_label(), INTENSITY_MEASURES[self.im][1]
        fits = {state_label(state): fit for state, fit in self.fits.items()}
        return fragility_figure(fits, intensity=f"{label} ({unit.replace('^2', '$^2$')})",
                                title="\n".join([title or "Fragility", *textwrap.wrap(self.described(), 100)]),
                                median_text=self.median_text)

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
        return (f"{len(names)} records ({suite}) x {self.settings.get('levels', '?')} stripes; "
                f"{'each record whole' if duration is None else f'{duration:g} s of each record'}; "
                f"{self.settings.get('integrator', '?')}, {step}")


def state_label(state: float) -> str:
    """A damage state in words: ``"overturning"`` for 1, ``"peak |theta|/alpha >= 0.3"`` below."""
    return "overturning" if state >= 1.0 else f"peak |theta|/alpha >= {state:g}"


def _check_measure(im: str) -> None:
    if im not in INTENSITY_MEASURES:
        raise ValueError(f"intensity measure must be one of {tuple(INTENSITY_MEASURES)}, got {im!r}")


def intensity(motion: GroundMotion, im: str, period: float | None = None) -> float:
    """The intensity measure ``im`` of ``motion``'s horizontal component: PGA (m/s^2); PGV (m/s), the peak
    |velocity| sampled every :data:`VELOCITY_SAMPLING` s or 1/50 of the motion's shortest time; or Sa(T) (m/s^2),
    the 5%-damped pseudo-spectral acceleration at ``period`` s (:func:`~.spectra.response_spectrum`), refused
    naming the motion outside its usable periods (:func:`check_period`)."""
    _check_measure(im)
    if im == "pga":
        return float(motion.horizontal.peak_acceleration)
    if im == "sa":
        check_period(motion, period)
        return float(response_spectrum(motion, [period]).psa[0])
    end = motion.horizontal.end_time
    if not math.isfinite(end):
        raise ValueError(f"{motion.name}: PGV needs a motion with an end (a record, a pulse)")
    step = min(VELOCITY_SAMPLING, motion.horizontal.time_scale / 50.0)
    t = np.linspace(0.0, end, int(math.ceil(end / step)) + 1)
    return float(np.max(np.abs(motion.horizontal.velocity(t))))


def check_period(motion: GroundMotion, period) -> None:
    """``ValueError`` naming ``motion`` where its spectrum cannot be read at ``period`` s: none given, or outside
    SHORTEST_PERIOD_SAMPLES of its sampling intervals to its length."""
    if period is None or not (isinstance(period, (int, float, np.number)) and math.isfinite(period) and period > 0):
        raise ValueError(f"Sa(T) needs a period, a positive number of seconds; got {period!r}")
    dt, end = getattr(unscaled(motion.horizontal), "dt", None), motion.end_time
    if dt is not None and period < SHORTEST_PERIOD_SAMPLES * dt:
        raise ValueError(f"{record_name(motion)}: a period of {period:g} s is under {SHORTEST_PERIOD_SAMPLES} of its "
                         f"{dt:g} s samples; its usable periods are {SHORTEST_PERIOD_SAMPLES * dt:g} to {end:g} s")
    if math.isfinite(end) and period > end:
        raise ValueError(f"{record_name(motion)}: a period of {period:g} s is longer than the record "
                         f"({end:g} s); its usable periods end there")


def damage_measures(result) -> dict:
    """A run's measures for a study: ``{"damage_ratio": damage_ratio(result)}``."""
    return {"damage_ratio": damage_ratio(result)}


def damage_ratio(result) -> float:
    """The largest over the blocks of peak |theta| / the governing critical angle (:func:`.damage.critical_angles`:
    the column's for a block in a column, else the block's own); nan for a result without critical angles."""
    if result.critical_angle is None:
        return float("nan")
    return float(np.max(result.peak_theta / critical_angles(result)))


def exceeds(ratio, overturned, state: float) -> np.ndarray:
    """Whether runs of damage ``ratio`` that ``overturned`` (arrays of one shape; a missing overturn counts as
    none) exceed damage ``state``: state 1 is overturning; below 1, a ratio of at least ``state``, or an
    overturn."""
    overturned = pd.Series(np.ravel(overturned)).fillna(False).to_numpy(bool).reshape(np.shape(overturned))
    if state >= 1.0:
        return overturned
    return overturned | (np.asarray(ratio, float) >= state)


def stripes(count: int, top: float) -> np.ndarray:
    """``count`` intensity levels evenly spaced from ``top / count`` to ``top``."""
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 2:
        raise ValueError(f"a fragility needs at least 2 intensity levels, got {count!r}")
    if not (math.isfinite(top) and top > 0):
        raise ValueError(f"the highest intensity level must be positive and finite, got {top!r}")
    return top * np.arange(1, count + 1) / count


def fragility_study(scene, records: dict, levels, states=DEFAULT_STATES, *, im: str = "pga",
                    duration: float | None = None, device: str = "auto", threads: int | None = None,
                    progress=None, samples: int | None = None, periods=DEFAULT_PERIODS,
                    period: float | None = None, log=None, scheduler=None, **simulate_options) -> FragilityStudy:
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
    own = {name: intensity(motion, im, period) for name, motion in records.items()}
    for name, value in own.items():
        if not value > 0:
            raise ValueError(f"record {name}: its {INTENSITY_MEASURES[im][0]} is zero; it cannot be scaled")
    plan = [(name, level, level / own[name]) for level in levels for name in records]
    motions = [scaled(records[name], factor) for name, _, factor in plan]
    by_record = [[m for m, (name, _, _) in enumerate(plan) if name == record] for record in records]
    batch = run_members(scene, motions, duration, by_record, log=log, scheduler=scheduler, device=device,
                        threads=threads, progress=progress, measures=damage_measures, **simulate_options)
    runs = pd.concat([pd.DataFrame(plan, columns=["record", "level", "scale"]), batch.table], axis=1)
    outcomes = study_outcomes(runs, list(records), len(levels), states)
    options = {} if samples is None else {"samples": samples}
    fits = dict(zip(states, fit_states(levels, outcomes, **options)))
    ida = {state: ida_estimate(levels, outcomes[:, :, k]) for k, state in enumerate(states)}
    return FragilityStudy(runs, fits, im, batch.device, batch.wall_time_s,
                          {"records": list(records), "levels": len(levels), "states": states, "im": im,
                           **({"period": period} if im == "sa" else {}),
                           "duration": duration, **simulate_options,
                           "integrator": integrator_for(scene if not isinstance(scene, (list, tuple)) else scene[0],
                                                        simulate_options.get("integrator"))},
                          ida, {name: record_intensities(motion, periods) for name, motion in records.items()},
                          batch.resumed)


def record_intensities(motion: GroundMotion, periods=DEFAULT_PERIODS) -> dict:
    """{measure: value} of ``motion`` at unit scale: PGA (m/s^2), PGV (m/s) and the 5%-damped pseudo-spectral
    acceleration Sa(T) (m/s^2) at each of ``periods`` (s) (:func:`~.spectra.response_spectrum`); every one of them
    scales with the motion."""
    found = {"PGA (m/s^2)": intensity(motion, "pga"), "PGV (m/s)": intensity(motion, "pgv")}
    if len(periods):
        spectrum = response_spectrum(motion, np.asarray(periods, float))
        found.update({f"Sa({period:g} s) (m/s^2)": float(sa) for period, sa in zip(spectrum.periods, spectrum.psa)})
    return found


def study_outcomes(runs: pd.DataFrame, records: list, levels: int, states) -> np.ndarray:
    """(R, L, K) per record, level and state of a study's ``runs`` (ordered level by level, the records in
    ``records``' order within each): 1 exceeded, 0 not, nan where the run did not finish."""
    finished = (runs["status"] == "ok").to_numpy()
    outcomes = np.empty((len(records), levels, len(states)))
    for k, state in enumerate(states):
        hit = exceeds(runs["damage_ratio"].to_numpy(), runs["overturned"], state).astype(float)
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
