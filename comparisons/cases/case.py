"""What a benchmark case is: a declaration with keyword fields, its reference and its acceptance bands.

A :class:`Case` names a scene, a ground motion and a duration, says where its reference comes from
and how a run is judged, and declares, per metric and per engine, the band its |error| must stay
within at the engine's usual step (the native core's automatic step, 1e-3 s for pymunk, PyBullet
and MuJoCo).  The tests and the report read the bands from the declaration (:meth:`Case.band`), so
each band is written once.

A metric's kind follows from its name (:func:`metric_kind`): a relative error (the default), an
absolute one in the unit its name ends with (``_m``, ``_rad``, ``_J``), or a mismatch (``_mismatch``: 0 when
the run and the reference agree, 1 when they do not).
"""

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

#: the engines the harness judges: the native core under each of its two contact laws, its Moreau-Jean
#: integrator, and the peers
ENGINES = ("dem", "dem-overlap", "dem-moreau", "pymunk", "pybullet", "mujoco")

#: relative errors below this count as exact: the rocking reference converges its peaks to 3e-7 alpha
#: (``comparisons.references.rocking_equation.STEP_TIMES_P``), and no relative error here is asked to be finer
EXACT_RELATIVE = 1e-6
#: absolute errors (m, rad) below this count as exact: 1e-9 m is 1.7e-10 of a 6 m column, round-off
#: of the state over 1e5 to 1e7 steps
EXACT_ABSOLUTE = 1e-9

#: the accuracy a relative measure must reach for an engine to count as right in the verdicts, unless a
#: case asks otherwise (a peak or a period to 3% is what a parametric study of rocking can use)
ACCURACY = 0.03

#: analytical references and their uncertainty (relative): closed forms are exact to round-off; the
#: compiled rocking equation converges to 3e-7 alpha; solve_ivp-based references run at rtol 1e-10
CLOSED_FORM = 1e-12
ROCKING_EQUATION = 1e-6
ODE_SOLVER = 1e-8

REFERENCE_KINDS = {
    "closed form": "a closed-form solution (docs/method.md section 4)",
    "rocking equation": "the rigid rocking equation with Housner's impact rule, integrated exactly "
                        "(comparisons/references/rocking_equation.py)",
    "rigid-plastic": "the exact stick-slip integration of a rigid block (docs/method.md 4.5)",
    "rigid stack": "the equations of motion of two rigid stacked blocks (comparisons/references/stacked_rocking.py)",
    "rest": "the exact answer of a resting stack: nothing moves",
    "consensus": "the converged consensus of the other engines (comparisons/harness/consensus.py)",
}


def metric_kind(metric: str) -> str:
    """``"mismatch"``, ``"absolute"`` (unit in the name: ``_m``, ``_rad``, ``_J``) or ``"relative"``."""
    if metric.endswith("_mismatch"):
        return "mismatch"
    if metric.endswith(("_m", "_rad", "_J")):
        return "absolute"
    return "relative"


def exact_floor(metric: str) -> float:
    """The |error| of ``metric`` below which it counts as exact (0 for a mismatch)."""
    return {"mismatch": 0.0, "absolute": EXACT_ABSOLUTE, "relative": EXACT_RELATIVE}[metric_kind(metric)]


def declared_band(bands: Mapping, declaration: str, metric: str, engine: str) -> float:
    """``bands[metric][engine]`` of a declaration (a case, an ensemble, a spectrum), named in the error
    (``"case 'newmark'"``) when it declares no such band."""
    try:
        return bands[metric][engine]
    except KeyError:
        raise KeyError(f"{declaration} declares no band for {engine} on {metric}") from None


def by_name(declarations, name: str, kind: str):
    """The one of ``declarations`` (cases, ensembles, spectra) called ``name``; KeyError naming ``kind`` if none."""
    for declared in declarations:
        if declared.name == name:
            return declared
    raise KeyError(f"no {kind} named {name!r}")


@dataclass(frozen=True, kw_only=True)
class Case:
    """One benchmark: what to run, what it is measured against, and how close each engine must come.

    name : identifier in tables and file names.
    title : one line for the report.
    scene, motion : builders, called when the case runs (``motion`` returns a ground motion).
    duration : s.
    reference_kind : a key of :data:`REFERENCE_KINDS`.
    reference : computes, once, what ``errors`` compares with (None for a consensus case).
    errors : ``(result, reference) -> {metric: error}`` (analytical references).
    measures : ``result -> {metric: value}`` (consensus cases: the errors come from
        :mod:`comparisons.harness.consensus` once every engine has run).
    bands : ``{metric: {engine: band}}``, |error| at the engine's usual step; an engine missing from a
        metric has no band there (it is reported, not asserted).
    converged_bands : ``{metric: {engine: band}}``, |error| at the engine's finest step of the full ladder
        (:data:`comparisons.harness.case_runs.LADDER`): how close it converges as its step shrinks.
    reference_uncertainty : how far the reference itself may be from the truth, in the metric's unit
        (relative for relative metrics); consensus cases compute theirs from the engines' spread.
    accuracy : the |error| an engine must reach to count as right in the verdict (never taken below the
        reference's uncertainty); a mismatch must be 0.
    output_dt : s between recorded states.
    quick : part of the reduced set of ``--quick`` and CI.
    primary : the metric the report ranks engines by (default: the first one measured).
    note : a caution the report prints with the verdict.
    engines : the engines that can run it (a scene with connectors: the native core's alone).
    """

    name: str
    title: str
    scene: Callable
    motion: Callable
    duration: float
    reference_kind: str
    bands: Mapping[str, Mapping[str, float]] = field(default_factory=dict)
    converged_bands: Mapping[str, Mapping[str, float]] = field(default_factory=dict)
    reference: Callable | None = None
    errors: Callable | None = None
    measures: Callable | None = None
    reference_uncertainty: float = CLOSED_FORM
    accuracy: float = ACCURACY
    output_dt: float = 1e-3
    quick: bool = False
    primary: str | None = None
    note: str = ""
    engines: tuple = ENGINES

    def __post_init__(self):
        if self.reference_kind not in REFERENCE_KINDS:
            raise ValueError(f"{self.name}: unknown reference kind {self.reference_kind!r}")
        if (self.errors is None) == (self.measures is None):
            raise ValueError(f"{self.name}: give errors (against a reference) or measures (for a consensus)")
        if (self.reference_kind == "consensus") != (self.measures is not None):
            raise ValueError(f"{self.name}: a consensus case gives measures, every other case errors")
        for metric, per_engine in [*self.bands.items(), *self.converged_bands.items()]:
            unknown = set(per_engine) - set(self.engines)
            if unknown:
                raise ValueError(f"{self.name}: bands for unknown engines {sorted(unknown)} on {metric}")

    @property
    def by_consensus(self) -> bool:
        return self.reference_kind == "consensus"

    def band(self, metric: str, engine: str) -> float:
        """The band of ``engine`` on ``metric`` (KeyError if none is declared)."""
        return declared_band(self.bands, f"case {self.name!r}", metric, engine)

    def within_band(self, metric: str, engine: str, error: float) -> bool:
        """Whether |error| is within the declared band (a NaN error never is)."""
        return bool(abs(error) <= self.band(metric, engine))

    def verdict_level(self, metric: str) -> float:
        """The |error| that counts as right in the verdicts: 0 for a mismatch, else the larger of the
        case's accuracy and the reference's own uncertainty."""
        if metric_kind(metric) == "mismatch":
            return 0.0
        return max(self.accuracy, self.reference_uncertainty)
