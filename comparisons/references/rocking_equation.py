"""The rocking equation under sampled ground motion, compiled: the reference for records and ensembles.

The rigid block of :class:`comparisons.references.analytical.RockingBlock` on a rigid base, no sliding
(docs/method.md 4.3, in the sign convention of :mod:`comparisons.references.analytical`):

    theta'' = -p^2 [ s (1 + a_v/g) sin(alpha - s theta) - (a_g/g) cos(alpha - s theta) ]

where ``s`` is the corner the block rocks on (+1 left, ``theta > 0``; -1 right).  ``s`` is state:
set at uplift (the sign of ``a_g`` then) and at each impact (the other corner), never read off
the sign of ``theta`` at zero.  The block rests while ``|a_g| <= (g + a_v) tan(alpha)``; at an
impact (``theta = 0``) ``omega -> e omega`` (Housner's restitution unless given); the run stops at
overturning, ``s theta = alpha`` (the project's rule, docs/method.md section 3) or, if asked, at a later angle up
to ``pi/2``, where the block lands on its side: past alpha gravity turns the block further, but the ground
can still bring it back.

Method:

* The ground acceleration (horizontal and vertical) is piecewise linear through knots
  ``(t_i, a_i)``: a record's own samples (zero after the last one, as
  :class:`dem_core.inputs.excitation.Sampled`), or an analytic motion sampled every
  ``sample_dt`` with a double knot at its end, where a pulse jumps to zero.
* Classical fourth-order Runge-Kutta with a fixed step, ``substeps`` steps per knot
  interval, so that the forcing is a polynomial inside every step; by default the fewest
  that make ``p h <= STEP_TIMES_P``.
* Events inside a step are located on the Runge-Kutta map itself (one step of length
  ``sigma`` from the step's start, as a function of ``sigma``) by Newton's method kept inside a
  bracket by bisection: an impact (``theta = 0``), overturning (``s theta`` reaching the overturn angle) and each
  extremum of ``theta`` (``omega = 0``), which gives the peak between samples and catches a
  ``theta`` that dips to zero and back inside one step.
* Rest: after an impact whose rebound speed ``e |omega|`` is below
  ``REST_SPEED_FRACTION p alpha`` the block is at rest (``theta = omega = 0``) until the ground
  lifts a corner again (found exactly: the uplift margin is linear between knots).  This ends
  the chattering, the endless sequence of ever smaller impacts, near the uplift threshold.
* A step budget (steps, partial steps after events and rest intervals, ``max_steps``) raises
  :class:`StepBudgetExceeded` instead of running forever.

Outputs fall on step ends (the default output grid is the step grid) or between them, where
they are the cubic Hermite interpolants of ``theta`` (slopes ``omega``) and of ``omega``
(slopes ``theta''``) over the piece of the step they fall in.

References: Housner (1963) BSSA 53(2): 403-417; docs/method.md 4.3.
"""

import math

import numba as nb
import numpy as np

from dem_core.inputs.excitation import GroundMotion, Sampled, Still

from .analytical import RockingBlock, RockingHistory

#: below this fraction of ``p alpha`` (rad/s) a rebound speed leaves the block at rest
REST_SPEED_FRACTION = 1e-6
#: s, the sampling interval of an analytic ground motion (a pulse, a harmonic): its knots
ANALYTIC_SAMPLE_DT = 1e-4
#: default step: the sample interval divided until ``p h`` is at most this (the peak then converges
#: to within 3e-7 alpha of the step's limit on the bundled records; the error falls as h^4)
STEP_TIMES_P = 0.005
#: default step budget: this many loop passes per regular step of the run
STEP_BUDGET_PER_STEP = 100
#: s, events are located to this width of their bracket
EVENT_TIME_TOLERANCE = 1e-13
EVENT_ITERATIONS = 100

_RUNNING, _OVERTURNED, _OUT_OF_BUDGET = 0, 1, 2
_IMPACT, _OVERTURN, _MAXIMUM, _MINIMUM = 0, 1, 2, 3


class StepBudgetExceeded(RuntimeError):
    """The rocking reference used up its step budget before the end of the run."""


@nb.njit(cache=True)
def _angular_acceleration(theta, a_h, a_v, side, p2, alpha, g):
    """theta'' (rad/s^2) on corner ``side`` under ground accelerations ``a_h``, ``a_v`` (m/s^2)."""
    lever = alpha - side * theta
    return -p2 * (side * (1.0 + a_v / g) * math.sin(lever) - a_h / g * math.cos(lever))


@nb.njit(cache=True)
def _rk4(theta, omega, tau, sigma, forcing, side, p2, alpha, g):
    """One Runge-Kutta step of length ``sigma`` from local time ``tau`` of the knot interval.

    forcing : (a_h, slope of a_h, a_v, slope of a_v) at the interval's first knot (m/s^2, m/s^3).
    Returns ``(theta, omega)`` at ``tau + sigma``.
    """
    ah0, ah1, av0, av1 = forcing[0], forcing[1], forcing[2], forcing[3]
    mid, end = tau + 0.5 * sigma, tau + sigma
    k1t = omega
    k1w = _angular_acceleration(theta, ah0 + ah1 * tau, av0 + av1 * tau, side, p2, alpha, g)
    k2t = omega + 0.5 * sigma * k1w
    k2w = _angular_acceleration(theta + 0.5 * sigma * k1t, ah0 + ah1 * mid, av0 + av1 * mid, side, p2, alpha, g)
    k3t = omega + 0.5 * sigma * k2w
    k3w = _angular_acceleration(theta + 0.5 * sigma * k2t, ah0 + ah1 * mid, av0 + av1 * mid, side, p2, alpha, g)
    k4t = omega + sigma * k3w
    k4w = _angular_acceleration(theta + sigma * k3t, ah0 + ah1 * end, av0 + av1 * end, side, p2, alpha, g)
    return (theta + sigma / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t),
            omega + sigma / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w))


@nb.njit(cache=True)
def _event_function(kind, theta, omega, tau, forcing, side, p2, alpha, g, fall):
    """Value and slope of an event function, positive before the event and zero at it; the block overturns at
    ``s theta = fall``."""
    if kind == _IMPACT:
        return side * theta, side * omega
    if kind == _OVERTURN:
        return fall - side * theta, -side * omega
    acc = _angular_acceleration(theta, forcing[0] + forcing[1] * tau, forcing[2] + forcing[3] * tau,
                                side, p2, alpha, g)
    if kind == _MAXIMUM:
        return side * omega, side * acc
    return -side * omega, -side * acc


@nb.njit(cache=True)
def _locate(kind, lo, hi, theta, omega, tau, forcing, side, p2, alpha, g, fall):
    """Length ``sigma`` in ``(lo, hi]`` of the Runge-Kutta step from ``(theta, omega)`` at ``tau``
    that ends on the event: the function is positive at ``lo`` (or starts at zero there and
    leaves it positive) and not positive at ``hi``.  Newton's method, bisection when Newton
    leaves the bracket."""
    sigma = 0.5 * (lo + hi)
    for _ in range(EVENT_ITERATIONS):
        th, om = _rk4(theta, omega, tau, sigma, forcing, side, p2, alpha, g)
        value, slope = _event_function(kind, th, om, tau + sigma, forcing, side, p2, alpha, g, fall)
        if value > 0.0:
            lo = sigma
        else:
            hi = sigma
        if value == 0.0 or hi - lo <= EVENT_TIME_TOLERANCE:
            return sigma
        newton = sigma - value / slope if slope != 0.0 else lo
        following = newton if lo < newton < hi else 0.5 * (lo + hi)
        if abs(following - sigma) <= EVENT_TIME_TOLERANCE:
            return following
        sigma = following
    return sigma


@nb.njit(cache=True)
def _uplift(tau, tau_end, forcing, g, tan_alpha):
    """First local time in ``[tau, tau_end]`` where ``|a_h| > (g + a_v) tan(alpha)`` and the corner it
    lifts (+1 for ``a_h > 0``); ``(tau_end, 0)`` if the block stays at rest.  Exact: both sides of the
    margin are linear inside a knot interval."""
    best, corner = tau_end, 0
    for side in (1.0, -1.0):
        start = side * (forcing[0] + forcing[1] * tau) - (g + forcing[2] + forcing[3] * tau) * tan_alpha
        end = side * (forcing[0] + forcing[1] * tau_end) - (g + forcing[2] + forcing[3] * tau_end) * tan_alpha
        if start > 0.0:
            return tau, int(side)
        if end > 0.0:
            crossing = min(max(tau + (tau_end - tau) * (-start) / (end - start), tau), tau_end)
            if crossing < best or corner == 0:
                best, corner = crossing, int(side)
    return best, corner


@nb.njit(cache=True)
def _write(out_t, out_theta, out_omega, j, t0, t1, th0, om0, acc0, th1, om1, acc1):
    """Fill the outputs at times in ``(t0, t1]`` (from index ``j``) with the cubic Hermite interpolants
    of ``theta`` and ``omega`` over the piece; returns the next index."""
    span = t1 - t0
    while j < out_t.shape[0] and out_t[j] <= t1:
        u = (out_t[j] - t0) / span if span > 0.0 else 1.0
        u2, u3 = u * u, u * u * u
        h00, h10, h01, h11 = 2.0 * u3 - 3.0 * u2 + 1.0, u3 - 2.0 * u2 + u, 3.0 * u2 - 2.0 * u3, u3 - u2
        out_theta[j] = h00 * th0 + h10 * span * om0 + h01 * th1 + h11 * span * om1
        out_omega[j] = h00 * om0 + h10 * span * acc0 + h01 * om1 + h11 * span * acc1
        j += 1
    return j


@nb.njit(cache=True)
def _event_in_step(theta, omega, th1, om1, tau, sigma, forcing, side, p2, alpha, g, fall, peak):
    """The first event inside the Runge-Kutta step of length ``sigma`` from ``(theta, omega)`` at ``tau``
    to ``(th1, om1)``: ``(event, length to it, peak)``, ``event`` -1 and the whole length if none.

    An extremum inside the step is found first: a maximum past ``fall`` means the block overturned before it
    (one short of it raises the peak), a minimum past zero that it impacted before it; otherwise the
    step's end is checked for either."""
    event, at, lo = -1, sigma, 0.0
    if side * omega >= 0.0 and side * om1 < 0.0:
        top = _locate(_MAXIMUM, 0.0, sigma, theta, omega, tau, forcing, side, p2, alpha, g, fall)
        th_top, _ = _rk4(theta, omega, tau, top, forcing, side, p2, alpha, g)
        if side * th_top >= fall:
            event, at = _OVERTURN, _locate(_OVERTURN, 0.0, top, theta, omega, tau, forcing, side, p2, alpha, g, fall)
        else:
            peak = max(peak, side * th_top)
            lo = top
    elif side * omega < 0.0 and side * om1 > 0.0:
        bottom = _locate(_MINIMUM, 0.0, sigma, theta, omega, tau, forcing, side, p2, alpha, g, fall)
        th_bottom, _ = _rk4(theta, omega, tau, bottom, forcing, side, p2, alpha, g)
        if side * th_bottom <= 0.0:
            event, at = _IMPACT, _locate(_IMPACT, 0.0, bottom, theta, omega, tau, forcing, side, p2, alpha, g, fall)
    if event < 0:
        if side * th1 >= fall:
            event, at = _OVERTURN, _locate(_OVERTURN, lo, sigma, theta, omega, tau, forcing, side, p2, alpha, g, fall)
        elif side * th1 <= 0.0:
            event, at = _IMPACT, _locate(_IMPACT, lo, sigma, theta, omega, tau, forcing, side, p2, alpha, g, fall)
    return event, at, peak


@nb.njit(cache=True)
def _write_piece(out_t, out_theta, out_omega, j, t_knot, tau, at, theta, omega, th_end, om_end, forcing, side, p2,
                 alpha, g):
    """Fill the outputs over the piece of length ``at`` from local time ``tau`` (:func:`_write`), with the
    angular accelerations at its two ends; returns the next output index."""
    acc0 = _angular_acceleration(theta, forcing[0] + forcing[1] * tau, forcing[2] + forcing[3] * tau,
                                 side, p2, alpha, g)
    t_end = tau + at
    acc1 = _angular_acceleration(th_end, forcing[0] + forcing[1] * t_end,
                                 forcing[2] + forcing[3] * t_end, side, p2, alpha, g)
    return _write(out_t, out_theta, out_omega, j, t_knot + tau, t_knot + t_end, theta, omega, acc0,
                  th_end, om_end, acc1)


@nb.njit(cache=True)
def _rest_until_uplift(out_t, out_theta, out_omega, j, t_knot, tau, tau_end, forcing, g, tan_alpha):
    """A block at rest from local time ``tau``: zero outputs until the ground lifts a corner or ``tau_end``.
    Returns ``(local time reached, corner lifted (0: none), next output index)``."""
    start, corner = _uplift(tau, tau_end, forcing, g, tan_alpha)
    while j < out_t.shape[0] and out_t[j] <= t_knot + start:
        out_theta[j], out_omega[j] = 0.0, 0.0
        j += 1
    return start, corner, j


@nb.njit(cache=True)
def _integrate(knot_t, knot_ah, knot_av, max_step, p2, alpha, g, fall, restitution, rest_speed, theta0, omega0,
               out_t, max_steps):
    """The rocking history on ``out_t``; see the module docstring.

    knot_t, knot_ah, knot_av : (n,) knot times (s, non-decreasing, from 0) and ground accelerations (m/s^2).
    max_step : s, the longest Runge-Kutta step.
    out_t : (m,) sorted output times within the knots' span, s.
    Returns ``(theta (m,), omega (m,), impacts (k,), uplift time, overturn time, peak, status, time reached,
    loop passes)``; NaN outputs after an overturn or after running out of budget.
    """
    out_theta = np.full(out_t.shape[0], np.nan)
    out_omega = np.full(out_t.shape[0], np.nan)
    impacts = np.empty(64)
    n_impacts = 0
    forcing = np.empty(4)
    theta, omega = theta0, omega0
    side = 1.0 if theta > 0.0 or (theta == 0.0 and omega > 0.0) else -1.0
    resting = theta == 0.0 and omega == 0.0
    uplift = np.nan if resting else knot_t[0]
    peak = abs(theta)
    tan_alpha = math.tan(alpha)
    passes, j = 0, 0
    while j < out_t.shape[0] and out_t[j] <= knot_t[0]:
        out_theta[j], out_omega[j] = theta, omega
        j += 1
    for i in range(knot_t.shape[0] - 1):
        t_knot, length = knot_t[i], knot_t[i + 1] - knot_t[i]
        if length <= 0.0:
            continue  # a jump: the two knots at one time
        forcing[0], forcing[1] = knot_ah[i], (knot_ah[i + 1] - knot_ah[i]) / length
        forcing[2], forcing[3] = knot_av[i], (knot_av[i + 1] - knot_av[i]) / length
        n_steps = max(1, int(math.ceil(length / max_step - 1e-9)))
        tau = 0.0
        for k in range(1, n_steps + 1):
            tau_end = length if k == n_steps else length * k / n_steps
            while tau < tau_end:
                passes += 1
                if passes > max_steps:
                    return (out_theta, out_omega, impacts[:n_impacts], uplift, np.nan, peak, _OUT_OF_BUDGET,
                            t_knot + tau, passes)
                if resting:
                    tau, corner, j = _rest_until_uplift(out_t, out_theta, out_omega, j, t_knot, tau, tau_end, forcing,
                                                        g, tan_alpha)
                    if corner != 0:
                        resting, side, theta, omega = False, float(corner), 0.0, 0.0
                        if np.isnan(uplift):
                            uplift = t_knot + tau
                    continue
                sigma = tau_end - tau
                th1, om1 = _rk4(theta, omega, tau, sigma, forcing, side, p2, alpha, g)
                event, at, peak = _event_in_step(theta, omega, th1, om1, tau, sigma, forcing, side, p2, alpha, g,
                                                 fall, peak)
                if event < 0:
                    th_end, om_end = th1, om1
                else:
                    th_end, om_end = _rk4(theta, omega, tau, at, forcing, side, p2, alpha, g)
                    th_end = 0.0 if event == _IMPACT else side * fall
                j = _write_piece(out_t, out_theta, out_omega, j, t_knot, tau, at, theta, omega, th_end, om_end,
                                 forcing, side, p2, alpha, g)
                tau = tau + at
                if event < 0:
                    peak = max(peak, side * th1)
                    theta, omega = th1, om1
                elif event == _OVERTURN:
                    return (out_theta, out_omega, impacts[:n_impacts], uplift, t_knot + tau, fall, _OVERTURNED,
                            t_knot + tau, passes)
                else:
                    if n_impacts == impacts.shape[0]:
                        impacts = np.concatenate((impacts, np.empty(impacts.shape[0])))
                    impacts[n_impacts] = t_knot + tau
                    n_impacts += 1
                    theta, omega, side = 0.0, restitution * om_end, -side
                    if abs(omega) <= rest_speed:
                        resting, omega = True, 0.0
    return out_theta, out_omega, impacts[:n_impacts], uplift, np.nan, peak, _RUNNING, knot_t[-1], passes


def rocking_response(block: RockingBlock, ground, duration: float | None = None, *, dt: float | None = None,
                     vertical=None, theta0: float = 0.0, omega0: float = 0.0, restitution: float | None = None,
                     substeps: int | None = None, sample_dt: float = ANALYTIC_SAMPLE_DT, output_dt: float | None = None,
                     max_steps: int | None = None, overturn_angle: float | None = None) -> RockingHistory:
    """Rocking of a rigid block on a rigid base without sliding under a ground motion (docs/method.md 4.3).

    block : the rectangular block (``p``, ``alpha``, ``g``).
    ground : a :class:`dem_core.inputs.excitation.GroundMotion` (sampled records are taken on their
        own samples; analytic components are sampled every ``sample_dt`` s), or an (n,) array of
        horizontal ground accelerations (m/s^2) every ``dt`` s from t = 0.
    duration : s; default the motion's end.  After the last sample the ground is still.
    dt : s, the sampling interval of an array ``ground``.
    vertical : (n,) vertical ground accelerations (m/s^2) on the same samples as an array ``ground``.
    theta0, omega0 : rad, rad/s, the initial state (default: at rest).
    restitution : ``omega`` ratio across an impact (default Housner's ``1 - 1.5 sin^2(alpha)``).
    substeps : Runge-Kutta steps per sample interval (default: the fewest with ``p h <= STEP_TIMES_P``).
    sample_dt : s, the knot spacing of analytic components.
    output_dt : s between outputs (default: the Runge-Kutta step).
    max_steps : step budget (default ``STEP_BUDGET_PER_STEP`` per regular step).
    overturn_angle : rad, the rotation at which the block counts as overturned and the run stops: alpha by
        default; up to pi/2, where the block lands on its side and the equation ends.
    Returns a :class:`comparisons.references.analytical.RockingHistory` whose ``peak`` is the largest
    ``|theta|`` between samples too; ``theta`` and ``omega`` are NaN after an overturn.
    Raises :class:`StepBudgetExceeded` when the budget runs out.
    """
    knot_t, knot_ah, knot_av, spacing, duration = _knots(ground, duration, dt, vertical, sample_dt)
    fall = block.alpha if overturn_angle is None else float(overturn_angle)
    if not block.alpha <= fall <= 0.5 * math.pi:
        raise ValueError(f"overturn_angle must lie between the block's critical angle {block.alpha:.6g} rad and "
                         f"pi/2, got {overturn_angle}")
    substeps = default_substeps(block, spacing) if substeps is None else substeps
    if int(substeps) != substeps or substeps < 1:
        raise ValueError(f"substeps must be a positive integer, got {substeps}")
    step = spacing / substeps
    output_dt = step if output_dt is None else float(output_dt)
    if not output_dt > 0:
        raise ValueError(f"output_dt must be positive, got {output_dt}")
    out_t = np.minimum(np.arange(int(np.floor(duration / output_dt + 1e-9)) + 1) * output_dt, duration)
    regular_steps = int(np.ceil(duration / step - 1e-9)) + 1
    max_steps = STEP_BUDGET_PER_STEP * regular_steps if max_steps is None else int(max_steps)
    e = block.restitution if restitution is None else float(restitution)
    theta, omega, impacts, uplift, overturn, peak, status, reached, passes = _integrate(
        knot_t, knot_ah, knot_av, step, block.p**2, block.alpha, block.g, fall, e,
        REST_SPEED_FRACTION * block.p * block.alpha, float(theta0), float(omega0), out_t, max_steps)
    if status == _OUT_OF_BUDGET:
        raise StepBudgetExceeded(
            f"rocking reference: step budget of {max_steps} passes used up at t = {reached:.6g} s of "
            f"{duration:.6g} s after {len(impacts)} impacts (step {step:.3g} s); raise max_steps if the "
            f"block really impacts this often")
    return RockingHistory(out_t, theta, omega, impacts.copy(), float(uplift), status == _OVERTURNED,
                          float(overturn), float(peak))


def default_substeps(block: RockingBlock, sample_interval: float) -> int:
    """Runge-Kutta steps per sample interval (s) by default: the fewest with ``p h <= STEP_TIMES_P``."""
    return max(1, int(np.ceil(block.p * sample_interval / STEP_TIMES_P - 1e-9)))


def _knots(ground, duration, dt, vertical, sample_dt):
    """Knot times (n,) s, horizontal and vertical accelerations (n,) m/s^2 spanning ``[0, duration]``,
    the regular knot spacing (s) and the duration."""
    if isinstance(ground, GroundMotion):
        if dt is not None or vertical is not None:
            raise ValueError("dt and vertical are for array ground motions; a GroundMotion carries its own")
        duration = ground.end_time if duration is None else float(duration)
        if not (np.isfinite(duration) and duration > 0):
            raise ValueError(f"give a positive duration: {ground.name!r} has no natural end")
        sampled = _common_samples(ground)
        if sampled is None:
            return (*_sample_analytic(ground, duration, sample_dt), duration)
        ah, av, spacing = sampled
    else:
        if dt is None or not dt > 0:
            raise ValueError("an array ground motion needs its sampling interval dt > 0 (s)")
        ah = np.asarray(ground, dtype=float)
        av = np.zeros_like(ah) if vertical is None else np.asarray(vertical, dtype=float)
        if ah.ndim != 1 or len(ah) < 2 or av.shape != ah.shape:
            raise ValueError(f"ground and vertical must be (n,) arrays of the same length, n >= 2; got "
                             f"{ah.shape} and {av.shape}")
        spacing = float(dt)
        duration = (len(ah) - 1) * spacing if duration is None else float(duration)
    if not np.all(np.isfinite(ah)) or not np.all(np.isfinite(av)):
        raise ValueError("ground accelerations must be finite")
    t = np.arange(len(ah)) * spacing
    if duration < t[-1]:
        keep = t < duration
        t, ah, av = (np.append(x[keep], np.interp(duration, t, x)) for x in (t, ah, av))
    elif duration > t[-1]:  # the ground stops with the record: a jump to zero, then stillness
        t = np.append(t, [t[-1], duration])
        ah = np.append(ah, [0.0, 0.0])
        av = np.append(av, [0.0, 0.0])
    return t, ah, av, spacing, duration


def _common_samples(motion):
    """``(horizontal, vertical, dt)`` of a motion whose moving components are records on one grid, else None."""
    moving = [c for c in (motion.horizontal, motion.vertical) if not isinstance(c, Still)]
    if not moving or not all(isinstance(c, Sampled) for c in moving):
        return None
    spacing = moving[0].dt
    if any(abs(c.dt - spacing) > 1e-9 * spacing for c in moving):
        return None
    n = max(len(c.samples) for c in moving)

    def samples(component):
        if isinstance(component, Still):
            return np.zeros(n)
        return np.pad(np.asarray(component.samples, dtype=float), (0, n - len(component.samples)))

    return samples(motion.horizontal), samples(motion.vertical), spacing


def _sample_analytic(motion, duration, sample_dt):
    """Knots every ``sample_dt`` (or slightly less, to end on ``duration``) and a double knot at
    each component's end inside the run: the value just before it and the value at it."""
    n = max(1, int(np.ceil(duration / sample_dt - 1e-9)))
    spacing = duration / n
    grid = np.arange(n + 1) * spacing
    grid[-1] = duration
    ends = sorted({float(c.end_time) for c in (motion.horizontal, motion.vertical)
                   if 0.0 < c.end_time < duration})
    regular = grid[np.all([np.abs(grid - end) > 1e-9 * spacing for end in ends], axis=0)] if ends else grid
    t = np.concatenate([regular, *([end, end] for end in ends)])
    at = np.concatenate([regular, *([np.nextafter(end, -np.inf), end] for end in ends)])
    order = np.argsort(t, kind="stable")
    t, at = t[order], at[order]
    ah = np.asarray(motion.horizontal.acceleration(at), dtype=float)
    av = np.asarray(motion.vertical.acceleration(at), dtype=float)
    return t, ah, av, spacing
