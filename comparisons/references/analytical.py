"""Analytical and exact references of docs/method.md section 4.

Conventions as in the native core: SI units, angles counter-clockwise
positive.  A rectangular block of width ``2b`` and height ``2h`` rocks about
its left bottom corner when ``theta > 0`` and about its right one when
``theta < 0``; a positive ground acceleration (ground pushed towards +x)
throws it onto its left corner.  ``g`` defaults to 9.81 m/s^2, the value
docs/method.md 4.6 uses.

References:
  Housner, G. W. (1963) The behavior of inverted pendulum structures during
      earthquakes.  BSSA 53(2): 403-417.            (sections 4.1 to 4.3)
  Newmark, N. M. (1965) Effects of earthquakes on dams and embankments.
      Geotechnique 15(2): 139-160.                  (section 4.4)
  Zhang, J. and Makris, N. (2001) Rocking response of free-standing blocks
      under cycloidal pulses.  J. Eng. Mech. 127(5): 473-483.
      Shenton, H. W. (1996) Criteria for initiation of slide, rock, and
      slide-rock rigid-body modes.  J. Eng. Mech. 122(7): 690-693.  (section 4.6)
"""

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

G = 9.81


@dataclass(frozen=True)
class RockingBlock:
    """Geometry of a rectangular block of width 2b and height 2h (m)."""

    b: float
    h: float
    g: float = G

    @classmethod
    def from_size(cls, width: float, height: float, g: float = G) -> "RockingBlock":
        return cls(width / 2.0, height / 2.0, g)

    @property
    def alpha(self) -> float:
        """Slenderness angle atan(b/h), rad."""
        return float(np.arctan2(self.b, self.h))

    @property
    def R(self) -> float:
        """Half diagonal, m."""
        return float(np.hypot(self.b, self.h))

    @property
    def p(self) -> float:
        """Frequency parameter sqrt(3 g / (4 R)), rad/s (I_O = 4/3 m R^2)."""
        return float(np.sqrt(3.0 * self.g / (4.0 * self.R)))

    @property
    def restitution(self) -> float:
        """Housner's angular velocity ratio across an impact, 1 - 1.5 sin^2(alpha)."""
        return 1.0 - 1.5 * np.sin(self.alpha) ** 2


def housner_period(block: RockingBlock, theta0: float) -> float:
    """Free-rocking period without energy loss from amplitude theta0 (s), docs/method.md 4.1.

    ``T = (4 / p) arccosh(1 / (1 - theta0 / alpha))``; the first impact comes at T / 4.
    """
    ratio = abs(theta0) / block.alpha
    if not 0.0 < ratio < 1.0:
        raise ValueError(f"theta0 must be between 0 and alpha = {block.alpha:.4f} rad, got {theta0}")
    return 4.0 / block.p * float(np.arccosh(1.0 / (1.0 - ratio)))


def housner_peaks(block: RockingBlock, theta0: float, n_impacts: int) -> np.ndarray:
    """Peak |theta| after 0..n_impacts impacts (rad), docs/method.md 4.2.

    ``theta_n = alpha (1 - sqrt(1 - r^n (1 - (1 - theta0/alpha)^2)))`` with ``r = e^2``.
    """
    a = block.alpha
    r = block.restitution**2
    n = np.arange(n_impacts + 1)
    return a * (1.0 - np.sqrt(1.0 - r**n * (1.0 - (1.0 - abs(theta0) / a) ** 2)))


@dataclass(frozen=True)
class RockingHistory:
    """Solution of the rocking equation.

    t, theta, omega : (n,) s, rad, rad/s.
    impacts : times of the impacts (theta = 0), s.
    uplift_time : first time the block left rest, s (NaN if it never did).
    overturned : whether |theta| reached alpha; overturn_time (s, NaN if not).
    peak : largest |theta| reached, rad: over the outputs (:func:`rocking_response`), or between
        them too (:func:`comparisons.references.rocking_equation.rocking_response`); alpha once overturned there.
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    impacts: np.ndarray
    uplift_time: float
    overturned: bool
    overturn_time: float
    peak: float


def rocking_response(block: RockingBlock, ground_acceleration, t_end: float, *, theta0: float = 0.0,
                     omega0: float = 0.0, restitution: float | None = None, vertical_acceleration=None,
                     t_eval=None, max_step: float | None = None, rtol: float = 1e-10,
                     atol: float = 1e-12) -> RockingHistory:
    """Rocking of a rigid block on a rigid base without sliding (docs/method.md 4.3).

    ``theta'' = -p^2 [ sgn(theta) (1 + a_v/g) sin(alpha - |theta|) - (a_g/g) cos(alpha - |theta|) ]``
    (the sign convention of this module), the block resting while
    ``|a_g| <= (g + a_v) tan(alpha)``, and at each impact (theta = 0)
    ``omega -> e omega`` with ``e`` = Housner's restitution unless given.
    Integrated with scipy's ``solve_ivp`` (DOP853) and event detection: slow (seconds per record,
    and no end in sight under a record just above the uplift threshold, where the block chatters);
    for records, pulses and ensembles use the compiled
    :func:`comparisons.references.rocking_equation.rocking_response`, checked against this one.

    ground_acceleration, vertical_acceleration : callables ``t -> m/s^2``.
    t_eval : output times (default: every ``max_step``).
    max_step : s, the largest solver step (default T_p / 200-ish: 1e-3 s);
        give the record's sampling interval for records.
    Returns a :class:`RockingHistory`; integration stops at overturning.
    """
    e = block.restitution if restitution is None else restitution
    p2, alpha, g = block.p**2, block.alpha, block.g
    av = vertical_acceleration or (lambda t: 0.0)
    max_step = 1e-3 if max_step is None else max_step
    t_eval = np.arange(0.0, t_end + 0.5 * max_step, max_step) if t_eval is None else np.asarray(t_eval)

    def rhs(t, y, side):
        # ``side`` is the corner rocked on (+1 left), fixed from uplift or impact to the next impact, so
        # that the solver's trial points just past theta = 0 do not switch corners: |theta| = side theta
        th, om = y
        gv = 1.0 + av(t) / g
        lever = alpha - side * th
        return [om, -p2 * (side * gv * np.sin(lever) - ground_acceleration(t) / g * np.cos(lever))]

    def uplift_margin(t):
        return abs(ground_acceleration(t)) - (g + av(t)) * np.tan(alpha)

    out_theta = np.zeros_like(t_eval, dtype=float)
    out_omega = np.zeros_like(t_eval, dtype=float)
    impacts = []
    t, th, om = 0.0, float(theta0), float(omega0)
    uplift_time = np.nan if th == 0.0 and om == 0.0 else 0.0
    overturn_time = np.nan
    rest_speed = 1e-6 * block.p * alpha
    while t < t_end:
        if th == 0.0 and abs(om) <= rest_speed:
            # at rest: wait for the ground to lift a corner
            t_start = _first_uplift(uplift_margin, t, t_end, max_step)
            if t_start is None:
                break
            t = t_start
            th = np.copysign(1e-12, ground_acceleration(t) + 0.0)
            om = 0.0
            if np.isnan(uplift_time):
                uplift_time = t
        side = 1.0 if th > 0 or (th == 0.0 and om > 0) else -1.0
        sol = _rock_on_corner(rhs, side, alpha, t, t_end, th, om, max_step=max_step, rtol=rtol, atol=atol)
        t_stop = sol.t[-1]
        mask = (t_eval >= t) & (t_eval <= t_stop)
        if np.any(mask):
            y = sol.sol(t_eval[mask])
            out_theta[mask], out_omega[mask] = y[0], y[1]
        if sol.t_events[1].size:
            overturn_time = float(sol.t_events[1][0])
            after = t_eval > overturn_time
            out_theta[after] = np.nan
            out_omega[after] = np.nan
            break
        if sol.t_events[0].size:
            t = float(sol.t_events[0][0])
            impacts.append(t)
            om = e * float(sol.y_events[0][0][1])
            th = 0.0
            if abs(om) > rest_speed:
                th = -side * 1e-14  # continue on the other corner
            continue
        break
    return RockingHistory(t_eval, out_theta, out_omega, np.array(impacts), float(uplift_time),
                          bool(np.isfinite(overturn_time)), overturn_time, float(np.nanmax(np.abs(out_theta))))


def _rock_on_corner(rhs, side, alpha, t, t_end, th, om, **tolerances):
    """``solve_ivp`` of ``rhs(t, y, side)`` from ``(th, om)`` at ``t`` up to the first impact (``theta``
    back to zero: event 0), overturning (``|theta| = alpha``: event 1) or ``t_end``, with dense output."""

    def crossing(t_, y):
        return y[0]

    crossing.terminal = True
    crossing.direction = -side

    def topple(t_, y):
        return abs(y[0]) - alpha

    topple.terminal = True
    topple.direction = 1.0
    return solve_ivp(lambda t_, y: rhs(t_, y, side), (t, t_end), [th, om], method="DOP853",
                     events=(crossing, topple), dense_output=True, **tolerances)


def _first_uplift(margin, t0, t_end, step):
    """First time after t0 where ``margin(t) > 0`` (scan at ``step``, refine by bisection)."""
    if margin(t0) > 0:
        return t0
    grid = np.arange(t0, t_end + step, step)
    values = np.array([margin(t) for t in grid])
    above = np.nonzero(values > 0)[0]
    if not above.size:
        return None
    k = above[0]
    return brentq(margin, grid[k - 1], grid[k], xtol=1e-12)


def newmark_max_slip(a_p: float, t_p: float, mu: float, g: float = G) -> float:
    """Largest slip (m) of a rigid block under a rectangular pulse a_p (m/s^2) of T_p (s).

    ``u_max = (a_p T_p^2 / 2) (a_p / (mu g) - 1)`` for a_p > mu g, else 0 (docs/method.md 4.4).
    """
    if a_p <= mu * g:
        return 0.0
    return a_p * t_p**2 / 2.0 * (a_p / (mu * g) - 1.0)


@dataclass(frozen=True)
class SlidingHistory:
    """Exact rigid-plastic sliding: t (n,) s, u (n,) slip of the block relative to the ground (m),
    v (n,) its rate (m/s), total_slip (m, accumulated |du|)."""

    t: np.ndarray
    u: np.ndarray
    v: np.ndarray
    total_slip: float

    @property
    def max_slip(self) -> float:
        return float(np.max(np.abs(self.u)))

    @property
    def residual(self) -> float:
        return float(self.u[-1])


def rigid_plastic_sliding(acceleration, dt: float, mu: float, *, vertical=None, g: float = G,
                          t_end: float | None = None) -> SlidingHistory:
    """Exact stick-slip response of a rigid block on a rigid base (docs/method.md 4.5).

    acceleration : (n,) ground accelerations every ``dt`` s, linear in between
        (the interpolation the native core uses); zero after the last sample.
    vertical : (n,) vertical ground accelerations on the same grid, or None.
    While sliding, ``u'' = -a_g - sgn(u') mu (g + a_v)``; the block sticks
    when ``u'`` reaches zero and ``|a_g| <= mu (g + a_v)``.  Within each
    linear piece the motion is a polynomial, so phase changes are found as
    roots of linear and quadratic equations: exact to round-off.
    t_end : s, end of the integration: before the record's end, or past it with the ground still.
    Returns the history at the record's sample times.
    """
    a = np.asarray(acceleration, dtype=float)
    av = np.zeros_like(a) if vertical is None else np.asarray(vertical, dtype=float)
    if t_end is not None:  # cut the record short, or let the ground stand still after it
        n = int(np.ceil(t_end / dt - 1e-9)) + 1
        a = np.concatenate([a, np.zeros(max(0, n - len(a)))])[:n]
        av = np.concatenate([av, np.zeros(max(0, n - len(av)))])[:n]
    n = len(a)
    u = np.zeros(n)
    v = np.zeros(n)
    total = 0.0
    uk, vk = 0.0, 0.0
    for k in range(n - 1):
        a0, sa = a[k], (a[k + 1] - a[k]) / dt
        f0, sf = mu * (g + av[k]), mu * (av[k + 1] - av[k]) / dt
        tau = 0.0
        while tau < dt:
            rem = dt - tau
            a_now = a0 + sa * tau
            f_now = f0 + sf * tau
            if vk == 0.0:
                # stuck: find when |a| first exceeds the friction capacity
                start = _first_exceedance(a_now, sa, f_now, sf, rem)
                if start is None:
                    break
                tau += start
                a_now = a0 + sa * tau
                sign = -1.0 if a_now > 0 else 1.0
                vk = sign * 1e-300  # leave rest in the direction the ground drags the block
                continue
            sign = 1.0 if vk > 0 else -1.0
            # v(s) = vk - c1 s - c2 s^2 / 2 with c1 = a + sign f, c2 = sa + sign sf
            c1 = a_now + sign * f_now
            c2 = sa + sign * sf
            s_stop = _first_root(vk, -c1, -c2 / 2.0, rem)
            s = rem if s_stop is None else s_stop
            du = vk * s - c1 * s**2 / 2.0 - c2 * s**3 / 6.0
            uk += du
            total += abs(du)
            if s_stop is None:
                vk = vk - c1 * s - c2 * s**2 / 2.0
                tau = dt
            else:
                vk = 0.0
                tau += s
        u[k + 1], v[k + 1] = uk, vk
    return SlidingHistory(np.arange(n) * dt, u, v, total)


def _first_exceedance(a0, sa, f0, sf, span):
    """First s in [0, span] where |a0 + sa s| > f0 + sf s, or None."""
    best = None
    for sign in (1.0, -1.0):
        c0 = sign * a0 - f0
        c1 = sign * sa - sf
        if c0 > 0:
            return 0.0
        if c1 > 0:
            s = -c0 / c1
            if s <= span and (best is None or s < best):
                best = s
    return best


def _first_root(c0, c1, c2, span):
    """Smallest s in (0, span] with c0 + c1 s + c2 s^2 = 0 where the sign of c0 is lost, or None."""
    roots = []
    if abs(c2) < 1e-300:
        if c1 != 0:
            roots = [-c0 / c1]
    else:
        disc = c1 * c1 - 4.0 * c2 * c0
        if disc >= 0:
            q = -0.5 * (c1 + np.copysign(np.sqrt(disc), c1))
            roots = [q / c2] + ([c0 / q] if q != 0 else [])
    valid = [s for s in roots if 0.0 < s <= span]
    return min(valid) if valid else None


def rocking_onset_acceleration(block: RockingBlock) -> float:
    """Ground acceleration that lifts a corner, g tan(alpha) = g b / h (m/s^2), docs/method.md 4.6."""
    return block.g * block.b / block.h


def sliding_onset_acceleration(mu: float, g: float = G) -> float:
    """Ground acceleration at which a block starts to slide, mu g (m/s^2)."""
    return mu * g


def initial_mode(block: RockingBlock, mu: float) -> str:
    """Which motion a slowly growing ground acceleration starts: ``"rocking"`` or ``"sliding"``.

    Rocking first when ``mu > tan(alpha)``, sliding first when ``mu < tan(alpha)`` (docs/method.md 4.6).
    """
    return "rocking" if mu > block.b / block.h else "sliding"


def slides_on_incline(slope: float, mu: float) -> bool:
    """Whether a block on an incline of ``slope`` rad slides: tan(slope) > mu (docs/method.md 4.8)."""
    return bool(np.tan(slope) > mu)


def slide_rock_acceleration(block: RockingBlock, mu: float) -> float:
    """Ground acceleration applied at once above which a block starts rocking *and* sliding (m/s^2).

    At the start of rocking about a corner (angular acceleration
    ``3 (a h - g b) / (4 R^2)``) the corner needs a friction force
    ``m (a - h theta'')`` against a normal force ``m (g + b theta'')``; it slips when
    the ratio exceeds ``mu``, that is when
    ``a / g > (mu (b^2 + 4 h^2) - 3 b h) / (4 b^2 + h^2 - 3 mu b h)``
    (Zhang and Makris 2001, Shenton 1996).  Infinite when the corner never slips;
    equal to ``g b / h`` at ``mu = b / h``.  Meaningful for ``mu > b / h``.
    """
    b, h = block.b, block.h
    denominator = 4.0 * b * b + h * h - 3.0 * mu * b * h
    if denominator <= 0:
        return float("inf")
    return block.g * (mu * (b * b + 4.0 * h * h) - 3.0 * b * h) / denominator


def initial_mode_under_pulse(block: RockingBlock, mu: float, acceleration: float) -> str:
    """Motion a ground acceleration applied at once (a pulse with finite initial value, m/s^2) starts:
    ``"rest"``, ``"rocking"``, ``"sliding"`` or ``"slide-rock"`` (docs/method.md 4.6).

    A sliding block never tips while ``mu < b / h`` (its contact resultant stays at ``mu h`` from
    the centre line, inside the base), so with ``mu < b / h`` the choice is rest or sliding.
    """
    a = abs(acceleration)
    if mu < block.b / block.h:
        return "sliding" if a > mu * block.g else "rest"
    if a <= rocking_onset_acceleration(block):
        return "rest"
    return "slide-rock" if a > slide_rock_acceleration(block, mu) else "rocking"
