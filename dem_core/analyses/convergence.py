"""Does the answer depend on the contact stiffness?  Rerun a scene at stiffer contacts and compare.

The penalty contact is a model parameter, not only a numerical one: a softer
contact lifts corners earlier and, under records, its own rocking mode can
amplify the motion (README, known limits).  :func:`stiffness_convergence`
runs the same scene and motion at ``K_n`` times each factor (the automatic
step shrinks as ``K_n^(-1/2)``) and tabulates the scene-level measures and
their change from the stiffest run; :func:`verdicts` judges each measure:
converged when it changes by at most :data:`RELATIVE_TOLERANCE` (5%) of its
value at the stiffest contact, or by less than its absolute floor
(:data:`FLOORS`: 1 mm of sliding, 0.001 rad of rotation, 0.1 s of overturn
time), so that a few millimetres of sliding against a tiny reference do not
count as a large relative change.
"""

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..engine.contact import stiffer
from ..simulation import simulate

MEASURES = ("max_peak_abs_theta_rad", "total_sliding_m", "mean_rocking_rad", "overturn_time_s")
#: what each measure is, in words, and its unit
LABELS = {"max_peak_abs_theta_rad": "peak rotation (the largest peak |theta| of any block)",
          "total_sliding_m": "total sliding (summed over the interfaces)",
          "mean_rocking_rad": "mean rocking (mean |theta| over the blocks and the run)",
          "overturn_time_s": "overturn time"}
UNITS = {"max_peak_abs_theta_rad": "rad", "total_sliding_m": "m", "mean_rocking_rad": "rad", "overturn_time_s": "s"}
#: a measure has converged when it changes by at most this fraction of its value at the stiffest contact ...
RELATIVE_TOLERANCE = 0.05
#: ... or by less than this much (its unit): changes of tiny values are judged against these floors
FLOORS = {"max_peak_abs_theta_rad": 1e-3, "total_sliding_m": 1e-3, "mean_rocking_rad": 1e-3, "overturn_time_s": 0.1}


def stiffness_convergence(scene, excitation, duration=None, factors=(1.0, 10.0, 100.0), *, on_run=None,
                          **simulate_options):
    """Table with one row per stiffness factor: ``kn`` (N/m^2), ``dt_s``, ``run_time_s``, the
    measures of :data:`MEASURES` and, for each, ``change:<measure>``: the relative change from
    the run at the largest factor (for the overturn time, in seconds).  The runs are the explicit core's, whose
    contacts have a stiffness (Moreau-Jean's rigid ones have none: ``integrator="moreau"`` is refused).
    on_run : called as ``on_run(factor, result)`` after every run (a progress report)."""
    if not factors or min(factors) <= 0:
        raise ValueError(f"factors must be positive, got {factors}")
    if simulate_options.setdefault("integrator", "explicit") != "explicit":
        raise ValueError(f"the stiffness check runs the explicit core, whose contacts have a stiffness; "
                         f"integrator={simulate_options['integrator']!r} has none")
    rows = []
    for factor in sorted(factors):
        contact = stiffer(scene.contact, factor)
        result = simulate(scene.replace(contact=contact), excitation, duration, **simulate_options)
        if on_run is not None:
            on_run(factor, result)
        summary = result.summary()
        rows.append({"factor": factor, "kn": contact.kn, "dt_s": result.dt,
                     "run_time_s": result.info["run_time_s"], **{m: summary[m] for m in MEASURES}})
    table = pd.DataFrame(rows)
    stiffest = table.iloc[-1]
    for m in MEASURES:
        if m == "overturn_time_s":
            table[f"change:{m}"] = table[m] - stiffest[m]
        else:
            scale = abs(stiffest[m]) if stiffest[m] else np.nan
            table[f"change:{m}"] = (table[m] - stiffest[m]) / scale
    return table


@dataclass(frozen=True)
class Verdict:
    """How one measure of :func:`stiffness_convergence` depends on the contact stiffness.

    factors, values : the stiffness factors (ascending) and the measure at each (NaN: no overturn, or not
        measured).
    change, difference : relative and absolute change of the measure at the smallest factor from the stiffest.
    converged : whether the smallest factor agrees with the stiffest (:func:`agree`).
    agrees_from : the smallest factor from which every run agrees with the stiffest; the stiffest factor itself
        when even the two stiffest disagree.
    """

    measure: str
    factors: tuple
    values: tuple
    change: float
    difference: float
    converged: bool
    agrees_from: float

    @property
    def label(self) -> str:
        return LABELS.get(self.measure, self.measure)

    @property
    def unit(self) -> str:
        return UNITS.get(self.measure, "")


def agree(measure: str, value: float, reference: float, relative: float = RELATIVE_TOLERANCE,
          floors: dict | None = None) -> bool:
    """Whether ``value`` of ``measure`` agrees with ``reference`` (the stiffest run's): both NaN (no overturn in
    either), or within ``relative`` of the reference or within the measure's floor (:data:`FLOORS`) of it."""
    floor = (FLOORS if floors is None else floors).get(measure, 0.0)
    if np.isnan(value) or np.isnan(reference):
        return bool(np.isnan(value) and np.isnan(reference))
    return bool(abs(value - reference) <= max(relative * abs(reference), floor))


def verdicts(table: pd.DataFrame, relative: float = RELATIVE_TOLERANCE, floors: dict | None = None) -> list:
    """The :class:`Verdict` of each measure of :data:`MEASURES` in ``table`` (:func:`stiffness_convergence`)."""
    table = table.sort_values("factor")
    factors = tuple(float(f) for f in table.factor)
    found = []
    for m in MEASURES:
        values = tuple(float(v) for v in table[m])
        reference = values[-1]
        agreeing = [agree(m, v, reference, relative, floors) for v in values]
        start = len(values) - 1
        while start > 0 and agreeing[start - 1]:
            start -= 1
        difference = values[0] - reference
        change = difference / abs(reference) if reference and np.isfinite(reference) else float("nan")
        found.append(Verdict(m, factors, values, change, difference, agreeing[0], factors[start]))
    return found
