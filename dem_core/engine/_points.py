"""The rows of Moreau-Jean's problem, contact points and connectors: their layout and their kinematics.

Private module shared by the stages of :mod:`._moreau`, :mod:`._active_set` and :mod:`._connectors`.  Each point of
the index set is a row of floats (``rows``, N_COLUMNS) and a row of integers (``ints``, N_INTS); the incident body
is the one whose corner the point is, the reference body the one whose face it meets, and the normal is the
reference face's, into the incident body.  Impulses act positively on the incident body and negatively on the
reference.  A connector (:mod:`._connectors`) is a row of the same kind: its incident body the second of its joint,
its reference the first, its normal the joint's; its two unknowns, the tension and the shear impulse, are each
either compliant (``u + C P = target``) or fixed (``P = fixed``).
"""

import numba as nb

from ._angles import sine

#: columns of the per-point rows: the normal (reference face's, into the incident body), the lever arms from the
#: incident and reference bodies' centres of mass, the point's own Delassus block (1/kg; filled only where
#: Gauss-Seidel or the position sweeps need it), mu, the gap (m), the normal target velocity (m/s), the normal
#: velocity at the step's start (m/s), the impulses (N s), the tangential travel of the point over the step (m) and
#: the position projection's normal impulse (kg m); then a connector's: the tangential velocity at the step's start
#: (m/s), its opening and slip then (m), where the step takes them at that velocity alone (m, :func:`~._connectors.
#: connector_coefficients`), each unknown's compliance (s/kg; FIXED where its impulse is fixed), the tangential
#: target (m/s), the fixed impulses (N s; 0 for a point), the part's length and that times theta (s)
(NX, NY, RIX, RIY, RRX, RRY, WNN, WNT, WTT, FRICTION, GAP, TARGET, U0, PN, PT, TRAVEL, POSITION_IMPULSE, U0_T,
 OPENING0, SLIP0, REACH_N, REACH_T, COMPLIANCE_N, COMPLIANCE_T, TARGET_T, FIXED_N, FIXED_T, PART,
 PART_THETA) = range(29)
N_COLUMNS = 29
#: a connector unknown's compliance where its impulse is fixed
FIXED = -1.0
#: columns of the per-point integers: incident body, reference body, pair, slot (0 or 1) within the pair,
#: feature key, whether the point slid (its status in the direct solve, or the last sweep), the connector (-1: a
#: contact point) and its branches (:func:`~._connectors.branches`)
INC, REF, PAIR, SLOT, KEY, SLID, CONNECTOR, BRANCH = range(8)
N_INTS = 8


@nb.njit(cache=True, inline="always")
def delassus(ax, ay, bx, by, rix, riy, im_i, ii_i, rrx, rry, im_r, ii_r):
    """``a . W b`` (1/kg) for the incident and reference bodies: the velocity change along a at the point per unit
    impulse along b (applied positively on the incident body and negatively on the reference)."""
    ca_i = rix * ay - riy * ax
    cb_i = rix * by - riy * bx
    ca_r = rrx * ay - rry * ax
    cb_r = rrx * by - rry * bx
    dot = ax * bx + ay * by
    return (im_i + im_r) * dot + ii_i * ca_i * cb_i + ii_r * ca_r * cb_r


@nb.njit(cache=True, inline="always")
def relative_velocity(vel, i, r, rix, riy, rrx, rry, nx, ny):
    """``(u_n, u_t)`` m/s: the incident body's material point relative to the reference body's, along the normal
    and along ``t = (-n_y, n_x)``."""
    vx = (vel[i, 0] - vel[i, 2] * riy) - (vel[r, 0] - vel[r, 2] * rry)
    vy = (vel[i, 1] + vel[i, 2] * rix) - (vel[r, 1] + vel[r, 2] * rrx)
    return vx * nx + vy * ny, -vx * ny + vy * nx


@nb.njit(cache=True, inline="always")
def apply_impulse(vel, inv_mass, inv_inertia, i, r, rix, riy, rrx, rry, px, py):
    """Velocity changes of an impulse (px, py) N s on the incident body ``i`` and its opposite on ``r``."""
    vel[i, 0] += inv_mass[i] * px
    vel[i, 1] += inv_mass[i] * py
    vel[i, 2] += inv_inertia[i] * (rix * py - riy * px)
    vel[r, 0] -= inv_mass[r] * px
    vel[r, 1] -= inv_mass[r] * py
    vel[r, 2] -= inv_inertia[r] * (rrx * py - rry * px)


@nb.njit(cache=True, inline="always")
def block_turns(mid, h, turn):
    """``turn`` (nb, 2): each body's turn over a step of ``h`` s at the angular velocities of ``mid`` (nb, 3),
    ``phi = h omega``, as ``(cos phi - 1, sin phi)``, the first without cancellation (``-2 sin^2(phi / 2)``)."""
    for b in range(mid.shape[0]):
        phi = h * mid[b, 2]
        turn[b, 0] = -2.0 * sine(0.5 * phi) ** 2
        turn[b, 1] = sine(phi)


@nb.njit(cache=True, inline="always")
def point_travel(mid, h, turn, i, r, rix, riy, rrx, rry, nx, ny):
    """``(d_n, d_t)`` m: how far the incident body's material point moved over a step of ``h`` s at the velocities
    ``mid`` (each body translated by ``h`` times its velocity and turned exactly by its ``turn``,
    :func:`block_turns`), relative to the reference body and in its turned frame, along the normal and along
    ``t = (-n_y, n_x)`` at the step's start."""
    ci = turn[i, 0]
    si = turn[i, 1]
    ex = h * (mid[i, 0] - mid[r, 0]) + ci * rix - si * riy
    ey = h * (mid[i, 1] - mid[r, 1]) + si * rix + ci * riy
    cr = turn[r, 0]
    sr = turn[r, 1]
    dx = (1.0 + cr) * ex + sr * ey + cr * rrx + sr * rry
    dy = -sr * ex + (1.0 + cr) * ey - sr * rrx + cr * rry
    return dx * nx + dy * ny, -dx * ny + dy * nx
