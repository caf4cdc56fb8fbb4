"""The contact points of Moreau-Jean's index set: their row layout and their kinematics.

Private module shared by the stages of :mod:`._moreau` and :mod:`._active_set`.  Each point of the index set is a
row of floats (``rows``, N_COLUMNS) and a row of integers (``ints``, 6); the incident body is the one whose corner
the point is, the reference body the one whose face it meets, and the normal is the reference face's, into the
incident body.  Impulses act positively on the incident body and negatively on the reference.
"""

import numba as nb

#: columns of the per-point rows: the normal (reference face's, into the incident body), the lever arms from the
#: incident and reference bodies' centres of mass, the point's own Delassus block (1/kg; filled only where
#: Gauss-Seidel or the position sweeps need it), mu, the gap (m), the normal target velocity (m/s), the normal
#: velocity at the step's start (m/s), the impulses (N s) and the position projection's impulse (kg m)
NX, NY, RIX, RIY, RRX, RRY, WNN, WNT, WTT, FRICTION, GAP, TARGET, U0, PN, PT, POSITION_IMPULSE = range(16)
N_COLUMNS = 16
#: columns of the per-point integers: incident body, reference body, pair, slot (0 or 1) within the pair,
#: feature key, whether the point slid (its status in the direct solve, or the last sweep)
INC, REF, PAIR, SLOT, KEY, SLID = range(6)


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
