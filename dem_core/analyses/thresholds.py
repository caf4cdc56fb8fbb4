"""Thresholds of a scene under a family of ground motions: overturning, onset of rocking and of sliding.

* :func:`overturning_threshold`: the smallest scale (PGA, amplitude, record
  factor: whatever ``motion_at(scale)`` takes) at which a block overturns, by
  a scan for the first overturning scale and bisection between it and the
  last surviving one, to a stated tolerance;
* :func:`onset_threshold`: the same for the start of rocking (a rotation
  above theta_cr / 30, docs/method.md section 3) or of sliding (an interface
  slipping more than ``slip`` m);
* :func:`onset_under_ramp`: both onsets from one run under a monotonic ramp,
  as ground accelerations.

The response of rocking structures need not be monotonic in the scale (a
larger motion can leave standing what a smaller one toppled); the scan looks
for the *first* change, and :class:`Threshold` keeps every run so the caller
can see the pattern.
"""

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..inputs.excitation import ramp
from ..inputs.scene import Scene
from ..engine.simulation import simulate

ROCKING_FRACTION = 1.0 / 30.0  # rocking starts at theta_cr / 30
SLIP_THRESHOLD = 1e-4  # m


@dataclass(frozen=True)
class Threshold:
    """Result of a threshold search.

    value : the threshold (midpoint of the final bracket), NaN if the scan never crossed it
        (``below`` is None: it crosses at or below the smallest scale tried; ``above`` is None:
        not even at the largest).
    below, above : the final bracket: largest scale without the event, smallest with it.
    runs : ((scale, event happened), ...) in the order they ran.
    """

    criterion: str
    value: float
    below: float | None
    above: float | None
    tolerance: float
    runs: tuple = field(default=())

    @property
    def monotonic(self) -> bool:
        """Whether every run below the bracket was event-free and every run above it had the event."""
        if self.above is None or self.below is None:
            return True
        return all(happened == (scale >= self.above) for scale, happened in self.runs)


def bracket_and_bisect(happens: Callable[[float], bool], low: float, high: float, *, tolerance: float = 0.02,
                       scan: int = 6, criterion: str = "",
                       on_run: Callable[[float, bool], None] | None = None) -> Threshold:
    """Smallest scale in [low, high] for which ``happens(scale)`` is True.

    Scans ``scan`` evenly spaced scales upwards, stops at the first with the event, then
    bisects between it and the previous one until the bracket is narrower than
    ``tolerance`` times its upper end.  ``on_run(scale, event happened)`` is called after
    every run (a progress report).
    """
    if not 0 < low < high:
        raise ValueError(f"need 0 < low < high, got low = {low}, high = {high}")
    if scan < 2:
        raise ValueError(f"scan needs at least 2 scales, got {scan}")
    runs = []

    def test(scale):
        outcome = bool(happens(scale))
        runs.append((float(scale), outcome))
        if on_run is not None:
            on_run(float(scale), outcome)
        return outcome

    below = above = None
    for scale in np.linspace(low, high, scan):
        if test(scale):
            above = float(scale)
            break
        below = float(scale)
    if above is None or below is None:
        return Threshold(criterion, float("nan"), below, above, tolerance, tuple(runs))
    while above - below > tolerance * above:
        middle = 0.5 * (below + above)
        if test(middle):
            above = middle
        else:
            below = middle
    return Threshold(criterion, 0.5 * (below + above), below, above, tolerance, tuple(runs))


def interface_slip_history(scene: Scene, result) -> dict:
    """{(name_a, name_b): (n,) slip (m)} of every interface touching at the start.

    The slip is the relative displacement, along the interface's initial tangent, of the
    two bodies' material points at the ends of the initial interface, the smaller of the
    two at each time: rocking about either end leaves that end in place, so the measure
    separates sliding from rocking.  For a block that starts tilted on a corner the interface
    is that corner alone, and the measure holds only until it rocks onto another one.
    """
    names = ["base", *result.names]
    angles0 = np.concatenate([[0.0], result.theta[0]])
    centres0 = np.column_stack([np.concatenate([[result.base_x[0]], result.x[0]]),
                                np.concatenate([[result.base_y[0]], result.y[0]])])

    def track(k, point):
        c, s = np.cos(-angles0[k]), np.sin(-angles0[k])
        d = point - centres0[k]
        local = np.array([c * d[0] - s * d[1], s * d[0] + c * d[1]])
        if k == 0:
            return np.column_stack([result.base_x + local[0], result.base_y + local[1]])
        th = result.theta[:, k - 1]
        return np.column_stack([result.x[:, k - 1] + np.cos(th) * local[0] - np.sin(th) * local[1],
                                result.y[:, k - 1] + np.sin(th) * local[0] + np.cos(th) * local[1]])

    slips = {}
    for i, j, contact in scene.touching_pairs():
        ends = []
        for side in (-0.5, 0.5):
            point = contact.centroid + side * contact.length * contact.tangent
            slip = (track(j, point) - track(i, point)) @ contact.tangent
            ends.append(slip - slip[0])
        slips[(names[i], names[j])] = np.where(np.abs(ends[0]) <= np.abs(ends[1]), ends[0], ends[1])
    return slips


def rocks(scene: Scene, result) -> bool:
    """Whether any block's rotation passed theta_cr / 30 (theta_cr: the scene's slenderness angle)."""
    return bool(np.max(np.abs(result.theta)) > ROCKING_FRACTION * scene.rocking_slenderness)


def slides(scene: Scene, result, slip: float = SLIP_THRESHOLD) -> bool:
    """Whether any interface slipped more than ``slip`` m."""
    return any(np.max(np.abs(s)) > slip for s in interface_slip_history(scene, result).values())


def motion_mode(scene: Scene, result, slip: float = SLIP_THRESHOLD) -> str:
    """``"rest"``, ``"rocking"``, ``"sliding"`` or ``"slide-rock"``: which of :func:`rocks` and
    :func:`slides` (more than ``slip`` m) the run showed."""
    return {(False, False): "rest", (True, False): "rocking", (False, True): "sliding",
            (True, True): "slide-rock"}[(rocks(scene, result), slides(scene, result, slip))]


def overturning_threshold(scene: Scene, motion_at: Callable, low: float, high: float, *, tolerance: float = 0.02,
                          scan: int = 6, on_run: Callable[[float, bool], None] | None = None,
                          **simulate_options) -> Threshold:
    """Smallest scale at which ``simulate(scene, motion_at(scale))`` overturns a block.

    motion_at : scale -> GroundMotion, e.g. ``lambda pga: excitation.record("el_centro_1940", pga=pga)``.
    low, high : the range searched; tolerance : relative width of the final bracket.
    on_run : called as ``on_run(scale, overturned)`` after every run (a progress report).
    simulate_options : passed to :func:`dem_core.simulate` (duration, dt, ...); runs stop at the
        first overturn.
    """
    def overturns(scale):
        return simulate(scene, motion_at(scale), stop_at_overturn=True, **simulate_options).overturned

    return bracket_and_bisect(overturns, low, high, tolerance=tolerance, scan=scan, criterion="overturning",
                              on_run=on_run)


def onset_threshold(scene: Scene, motion_at: Callable, low: float, high: float, *, criterion: str = "rocking",
                    tolerance: float = 0.02, scan: int = 6, slip: float = SLIP_THRESHOLD,
                    on_run: Callable[[float, bool], None] | None = None, **simulate_options) -> Threshold:
    """Smallest scale that starts ``criterion`` ("rocking": theta above theta_cr/30; "sliding": an
    interface slipping more than ``slip`` m).  Arguments as :func:`overturning_threshold`."""
    if criterion not in ("rocking", "sliding"):
        raise ValueError(f"criterion must be 'rocking' or 'sliding', got {criterion!r}")
    simulate_options.setdefault("output_dt", 1e-3)

    def starts(scale):
        result = simulate(scene, motion_at(scale), **simulate_options)
        return rocks(scene, result) if criterion == "rocking" else slides(scene, result, slip)

    return bracket_and_bisect(starts, low, high, tolerance=tolerance, scan=scan, criterion=criterion, on_run=on_run)


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
    if not rate > 0:
        raise ValueError(f"rate must be positive, got {rate}")
    duration = duration if duration is not None else scene.gravity / rate
    simulate_options.setdefault("output_dt", 1e-3)
    result = simulate(scene, ramp(rate, peak), duration=duration, **simulate_options)
    acceleration = np.minimum(rate * result.t, peak if peak is not None else np.inf)
    theta = np.max(np.abs(result.theta), axis=1)
    rocking = _first(acceleration, theta > ROCKING_FRACTION * scene.rocking_slenderness)
    slips = interface_slip_history(scene, result).values()
    slipping = np.max(np.abs(np.array(list(slips))), axis=0) > slip if slips else np.zeros(len(result.t), bool)
    overturn = rate * result.time_of_overturn if result.overturned else float("nan")
    if peak is not None and np.isfinite(overturn):
        overturn = min(overturn, peak)
    return RampOnset(rocking, _first(acceleration, slipping), overturn, result)


def _first(values, mask) -> float:
    hits = np.nonzero(mask)[0]
    return float(values[hits[0]]) if hits.size else float("nan")
