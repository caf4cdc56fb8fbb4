"""Thresholds of a scene under a family of ground motions: overturning, onset of rocking and of sliding.

* :func:`scan_and_refine`: the search every threshold here uses.  It runs the scene at every scale
  of a fine scan (geometric steps of ``step``, 2% by default, or evenly spaced points when ``scan``
  gives their number), then refines *every* change between neighbouring scales (standing to
  overturned and back) by bisection to ``tolerance``.  The result keeps every run, every window of
  scales where the event happened, and the runs that failed (a run that lost stability is neither a
  survivor nor a collapse).  The scan's scales run in batches (:func:`dem_core.batch.simulate_batch`)
  on every core, each run the one ``simulate`` gives;
* :func:`overturning_threshold`: the smallest scale (PGA, amplitude, record factor: whatever
  ``motion_at(scale)`` takes) at which a block overturns;
* :func:`onset_threshold`: the same for the start of rocking (a rotation above theta_cr / 30,
  docs/method.md section 3) or of sliding (an interface slipping more than ``slip`` m);
* :func:`onset_under_ramp`: both onsets from one run under a monotonic ramp, as ground accelerations.

The response of rocking structures is not monotonic in the scale: under a record a block can
overturn at one PGA and stand at a larger one (Yim, Chopra and Penzien 1980; Makris and
Konstantinidis 2003).  A coarse scan that stops at its first collapse then reports a threshold
above windows it stepped over; hence the fine scan over the whole range, started just below the
uplift acceleration (below which nothing rocks, so nothing overturns).
"""

import functools
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..simulation import SimulationUnstable, simulate
from ..engine.model import compile_model, interface_history, result_states
from ..inputs.excitation import ramp
from ..inputs.number_types import is_real
from ..inputs.scene import Scene
from .study_members import LOST, run_members

ROCKING_FRACTION = 1.0 / 30.0  # rocking starts at theta_cr / 30
SLIP_THRESHOLD = 1e-4  # m
SCAN_STEP = 0.02  # relative step of the scan
TOLERANCE = 0.005  # relative width of a refined change
#: the scan runs this many scales per thread in each batch: the progress shows between batches, and a search
#: that stops at its first event (``first_only``) runs few scales past it
SCALES_PER_THREAD = 4


@dataclass(frozen=True)
class Window:
    """Scales where every completed run had the event: ``first`` and ``last`` of them, and the nearest
    event-free scales run on either side (``below``, ``above``; None where none was run)."""

    first: float
    last: float
    below: float | None
    above: float | None


@dataclass(frozen=True)
class Threshold:
    """Result of a threshold search.

    runs : ((scale, event happened), ...) of the runs that finished, in the order they ran.
    failures : ((scale, message), ...) of the runs that did not (unstable, or another listed failure).
    tolerance : relative width to which each change was refined.
    """

    criterion: str
    runs: tuple = field(default=())
    failures: tuple = field(default=())
    tolerance: float = TOLERANCE

    @property
    def windows(self) -> tuple:
        """The :class:`Window` of every range of scales with the event, lowest first."""
        ordered = sorted(dict(self.runs).items())
        found, start = [], None
        for k, (scale, happened) in enumerate(ordered):
            if happened and start is None:
                start = k
            if start is not None and (not happened or k == len(ordered) - 1):
                end = k if happened else k - 1
                found.append(Window(ordered[start][0], ordered[end][0],
                                    ordered[start - 1][0] if start > 0 else None,
                                    ordered[end + 1][0] if end + 1 < len(ordered) else None))
                start = None
        return tuple(found)

    @property
    def smallest(self) -> float:
        """Smallest scale at which the event happened (NaN if it never did)."""
        windows = self.windows
        return windows[0].first if windows else float("nan")

    @property
    def value(self) -> float:
        """The threshold: the smallest scale with the event, if a smaller scale ran without it (else NaN:
        the event happened already at the smallest scale tried, or never)."""
        windows = self.windows
        return windows[0].first if windows and windows[0].below is not None else float("nan")

    @property
    def below(self) -> float | None:
        """Largest scale without the event below the smallest with it (None if none ran)."""
        windows = self.windows
        if windows:
            return windows[0].below
        return max((s for s, _ in self.runs), default=None)

    @property
    def above(self) -> float | None:
        """Smallest scale with the event (None if it never happened)."""
        windows = self.windows
        return windows[0].first if windows else None

    @property
    def monotonic(self) -> bool:
        """Whether no scale ran without the event above one that had it."""
        windows = self.windows
        return not windows or (len(windows) == 1 and windows[0].above is None)

    @property
    def survives_above_collapse(self) -> bool:
        """The flag of a non-monotonic response: a larger scale left standing what a smaller one toppled."""
        return not self.monotonic


def scan_grid(low: float, high: float, *, step: float = SCAN_STEP, absolute_step: float | None = None,
              scan: int | None = None) -> np.ndarray:
    """Scales of a scan from ``low`` to ``high`` (both included).

    scan : a number of evenly spaced scales; otherwise each next scale is the last times (1 + ``step``),
        the increment capped at ``absolute_step`` (same unit as the scale) when given.
    """
    if not 0 < low < high:
        raise ValueError(f"need 0 < low < high, got low = {low}, high = {high}")
    if scan is not None:
        if scan < 2:
            raise ValueError(f"scan needs at least 2 scales, got {scan}")
        return np.linspace(low, high, int(scan))
    if not step > 0 or (absolute_step is not None and not absolute_step > 0):
        raise ValueError(f"scan steps must be positive, got step = {step}, absolute_step = {absolute_step}")
    grid = [float(low)]
    while grid[-1] < high:
        grid.append(grid[-1] + min(step * grid[-1], absolute_step if absolute_step is not None else np.inf))
    grid[-1] = float(high)
    if len(grid) > 2 and grid[-1] - grid[-2] < 0.25 * (grid[-2] - grid[-3]):
        del grid[-2]  # no sliver of a step at the top
    return np.array(grid)


def scan_and_refine(happens: Callable[[float], bool], low: float, high: float, *, step: float = SCAN_STEP,
                    absolute_step: float | None = None, scan: int | None = None, tolerance: float = TOLERANCE,
                    criterion: str = "", failures: tuple = (SimulationUnstable,),
                    on_run: Callable[[float, bool | None], None] | None = None,
                    first_only: bool = False, happen_at: Callable[[list], list] | None = None,
                    batch: int = 1) -> Threshold:
    """Every scale of :func:`scan_grid` (``low``, ``high``, ``step``, ``absolute_step``, ``scan``), then
    bisection of each change between neighbouring finished runs until its bracket is narrower than
    ``tolerance`` times its upper end.

    first_only : stop the scan at the first scale where the event happens and bisect nothing: its
        ``smallest`` is then the first event to within the scan's step (with ``absolute_step``, windows
        narrower than a relative step are not passed over).

    happens : scale -> whether the event happened; an exception of a type in ``failures`` marks the
        run as failed (kept in :attr:`Threshold.failures`); any other exception propagates.
    on_run : called as ``on_run(scale, happened)`` after each run, ``happened`` None for a failure.
    happen_at : optional, many scales at once -> for each, whether the event happened or the exception its run
        raised; the scan then runs through it ``batch`` scales at a time (the bisections go on one at a time).
    """
    if not tolerance > 0:
        raise ValueError(f"tolerance must be positive, got {tolerance}")
    runs, failed = [], []

    def record(scale, outcome):
        if isinstance(outcome, failures):
            failed.append((scale, f"{type(outcome).__name__}: {outcome}"))
            outcome = None
        elif isinstance(outcome, BaseException):
            raise outcome
        else:
            outcome = bool(outcome)
            runs.append((scale, outcome))
        if on_run is not None:
            on_run(scale, outcome)
        return outcome

    def test(scale):
        try:
            outcome = happens(float(scale))
        except failures as exc:
            outcome = exc
        return record(float(scale), outcome)

    grid = [float(s) for s in scan_grid(low, high, step=step, absolute_step=absolute_step, scan=scan)]
    together = happen_at if happen_at is not None else (lambda scales: [_outcome(happens, s, failures)
                                                                         for s in scales])
    size = max(1, int(batch)) if happen_at is not None else 1
    scanned = []
    for first in range(0, len(grid), size):
        chunk = grid[first:first + size]
        for scale, outcome in zip(chunk, together(chunk)):
            scanned.append((scale, record(scale, outcome)))
            if first_only and scanned[-1][1]:  # the scales past it ran, but the search is the serial one's
                return Threshold(criterion, tuple(runs), tuple(failed), tolerance)
    finished = [(s, o) for s, o in scanned if o is not None]
    for (lo, lo_event), (hi, hi_event) in zip(finished, finished[1:]):
        while lo_event != hi_event and hi - lo > tolerance * hi:
            middle = 0.5 * (lo + hi)
            outcome = test(middle)
            if outcome is None:
                break
            if outcome == lo_event:
                lo = middle
            else:
                hi = middle
    return Threshold(criterion, tuple(runs), tuple(failed), tolerance)


def _outcome(happens, scale: float, failures):
    """``happens(scale)``, or the exception of a type in ``failures`` it raised."""
    try:
        return happens(scale)
    except failures as exc:
        return exc


def batch_outcomes(scene: Scene, motion_at: Callable, scales, event: Callable, *, log=None, scheduler=None,
                   **simulate_options) -> list:
    """For each of ``scales``: ``event(result)`` of the run of ``scene`` under ``motion_at(scale)``, or the error
    of a run that failed (a :class:`SimulationUnstable` with its message and no ``partial``; a ``ValueError``
    naming the scale for a run refused), all the runs one batch (:func:`~.study_members.run_members`: with a
    ``log`` of finished runs to resume from, or on the Dask cluster of ``scheduler``, one run a task; ``event``
    must then be picklable, a module-level function or a partial of one)."""
    motions = [motion_at(s) for s in scales]
    table = run_members(scene, motions, simulate_options.pop("duration", None), [[m] for m in range(len(motions))],
                        log=log, scheduler=scheduler, measures=functools.partial(_event_measure, event),
                        **simulate_options).table
    outcomes = []
    for scale, (_, row) in zip(scales, table.iterrows()):
        if row["status"] == "ok":
            outcomes.append(bool(row["event"]))
        elif row["status"] == "unstable":
            outcomes.append(SimulationUnstable(row["error"], None))
        elif row["status"] == LOST:
            outcomes.append(SimulationUnstable(f"lost on the Dask cluster: {row['error']}", None))
        else:
            outcomes.append(ValueError(f"the run at scale {scale:g} was refused: {row['error']}"))
    return outcomes


def _event_measure(event: Callable, result) -> dict:
    return {"event": bool(event(result))}


def _overturned(result) -> bool:
    return bool(result.overturned)


def _started(scene: Scene, criterion: str, slip: float, result) -> bool:
    """Whether ``criterion`` ("rocking" or "sliding") started in ``result`` (:func:`rocks`, :func:`slides`)."""
    return rocks(scene, result) if criterion == "rocking" else slides(result, slip)


def interface_offsets(scene: Scene, result) -> np.ndarray:
    """(n, n_interfaces) m: each interface's offset from its start at each output of ``result``, the signed
    displacement of one block over the other whose travel is the slip of :func:`interface_slips` (rocking about an
    end of the interface leaves it unchanged), in the order of ``result.interfaces``."""
    model = compile_model(scene)
    return interface_history(model, result_states(model, result))[0]


def interface_slips(result) -> np.ndarray:
    """(n, n_interfaces) m: the slip of each interface touching at the start up to each output, the one measure of
    every engine (``result.slip_history``: the travel of one block over the other measured on their motion,
    airborne phases included; docs/method.md section 3).  ValueError where the result carries none."""
    if result.slip_history is None:
        raise ValueError("this result carries no slip history (result.slip_history is None): sliding cannot be "
                         "judged on it")
    return np.asarray(result.slip_history, dtype=float).reshape(len(result.t), -1)


def rocks(scene: Scene, result) -> bool:
    """Whether any block's rotation passed theta_cr / 30 (theta_cr: the scene's slenderness angle)."""
    return bool(np.max(np.abs(result.theta)) > ROCKING_FRACTION * scene.rocking_slenderness)


def slides(result, slip: float = SLIP_THRESHOLD) -> bool:
    """Whether any interface slipped more than ``slip`` m (:func:`interface_slips`)."""
    slips = interface_slips(result)
    return bool(slips.size and np.max(slips) > slip)


def motion_mode(scene: Scene, result, slip: float = SLIP_THRESHOLD) -> str:
    """``"rest"``, ``"rocking"``, ``"sliding"`` or ``"slide-rock"``: which of :func:`rocks` and
    :func:`slides` (more than ``slip`` m) the run showed."""
    return {(False, False): "rest", (True, False): "rocking", (False, True): "sliding",
            (True, True): "slide-rock"}[(rocks(scene, result), slides(result, slip))]


def overturning_threshold(scene: Scene, motion_at: Callable, low: float, high: float, *, step: float = SCAN_STEP,
                          absolute_step: float | None = None, scan: int | None = None, tolerance: float = TOLERANCE,
                          on_run: Callable[[float, bool | None], None] | None = None, first_only: bool = False,
                          **simulate_options) -> Threshold:
    """Scales at which ``simulate(scene, motion_at(scale))`` overturns a block (:func:`scan_and_refine`).

    motion_at : scale -> GroundMotion, e.g. ``lambda pga: excitation.record("el_centro_1940", pga=pga)``.
    low, high : the range scanned; start ``low`` just below the scene's uplift acceleration.
    step, absolute_step, scan, tolerance, on_run, first_only : as :func:`scan_and_refine`.
    simulate_options : as :func:`dem_core.simulate` takes them (duration, dt, ...), for every run of
        :func:`~dem_core.batch.simulate_batch` (so not ``parallel``; a ``progress`` callback is not passed on:
        ``on_run`` reports each run), and ``log`` and ``scheduler`` as :func:`batch_outcomes` takes them; runs stop
        at the first overturn; a run that loses stability is a failure, not a survivor.
    """
    simulate_options.pop("progress", None)
    options = {**simulate_options, "stop_at_overturn": True}

    def overturned(scales):
        return batch_outcomes(scene, motion_at, scales, _overturned, **options)

    return scan_and_refine(lambda scale: _single(overturned([scale])[0]), low, high, step=step,
                           absolute_step=absolute_step, scan=scan, tolerance=tolerance, criterion="overturning",
                           on_run=on_run, first_only=first_only, happen_at=overturned, batch=_scan_batch())


def onset_threshold(scene: Scene, motion_at: Callable, low: float, high: float, *, criterion: str = "rocking",
                    step: float = SCAN_STEP, absolute_step: float | None = None, scan: int | None = None,
                    tolerance: float = TOLERANCE, slip: float = SLIP_THRESHOLD,
                    on_run: Callable[[float, bool | None], None] | None = None, **simulate_options) -> Threshold:
    """Scales that start ``criterion`` ("rocking": theta above theta_cr/30; "sliding": an interface
    slipping more than ``slip`` m).  Arguments as :func:`overturning_threshold`."""
    if criterion not in ("rocking", "sliding"):
        raise ValueError(f"criterion must be 'rocking' or 'sliding', got {criterion!r}")
    simulate_options.setdefault("output_dt", 1e-3)
    simulate_options.pop("progress", None)

    started = functools.partial(_started, scene, criterion, slip)

    def starts(scales):
        return batch_outcomes(scene, motion_at, scales, started, **simulate_options)

    return scan_and_refine(lambda scale: _single(starts([scale])[0]), low, high, step=step,
                           absolute_step=absolute_step, scan=scan, tolerance=tolerance, criterion=criterion,
                           on_run=on_run, happen_at=starts, batch=_scan_batch())


def _single(outcome):
    """One run's outcome from :func:`batch_outcomes`: the event, or its error raised."""
    if isinstance(outcome, BaseException):
        raise outcome
    return outcome


def _scan_batch() -> int:
    import numba

    return SCALES_PER_THREAD * numba.get_num_threads()


@dataclass(frozen=True)
class RampOnset:
    """Ground accelerations (m/s^2) at which rocking and sliding start under a ramp (NaN: not
    within the run), the overturn acceleration (NaN if none), and the run."""

    rocking: float
    sliding: float
    overturning: float
    result: object


def onset_under_ramp(scene: Scene, rate: float = 0.5, duration: float | None = None, *,
                     slip: float = SLIP_THRESHOLD, peak: float | None = None, **simulate_options) -> RampOnset:
    """Run ``scene`` under a ground acceleration growing at ``rate`` m/s^2 per s and read off the
    accelerations at which it starts rocking, starts sliding and overturns.

    duration : s, default long enough to reach 1 g; peak : cap of the ramp (m/s^2), default none.
    The run goes on after the first overturn only if ``stop_at_overturn=False`` is given.
    """
    if not is_real(rate):
        raise ValueError(f"ramp rate must be a number of m/s^2 per s, got {rate!r}")
    if not 0 < rate < np.inf:
        raise ValueError(f"ramp rate must be positive and finite, got {rate:g} m/s^2 per s")
    duration = duration if duration is not None else scene.gravity / rate
    simulate_options.setdefault("output_dt", 1e-3)
    result = simulate(scene, ramp(rate, peak), duration=duration, **simulate_options)
    acceleration = np.minimum(rate * result.t, peak if peak is not None else np.inf)
    theta = np.max(np.abs(result.theta), axis=1)
    rocking = _first(acceleration, theta > ROCKING_FRACTION * scene.rocking_slenderness)
    slips = interface_slips(result)
    slipping = np.max(slips, axis=1) > slip if slips.size else np.zeros(len(result.t), bool)
    overturn = rate * result.time_of_overturn if result.overturned else float("nan")
    if peak is not None and np.isfinite(overturn):
        overturn = min(overturn, peak)
    return RampOnset(rocking, _first(acceleration, slipping), overturn, result)


def _first(values, mask) -> float:
    hits = np.nonzero(mask)[0]
    return float(values[hits[0]]) if hits.size else float("nan")
