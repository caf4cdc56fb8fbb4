"""Compiled: the slip of a pair that met during the run, the one rule both integrators tally it by.

Private module.  A recorded interface (touching at the start) has its slip measured on the bodies' motion
(:mod:`._interfaces`); any other pair (blocks that met later: a fallen drum, a column leaning on another) keeps
the slip of its contact points, handed to the retired slips if it leaves the list.
"""

import numba as nb

from .state import PAIR_INTERFACE


@nb.njit(cache=True, inline="always")
def tally_slip(p, ids, pair_slip, amount):
    """``amount`` (m, the largest slip of pair ``p``'s points over a step) into its own tally, unless it is a
    recorded interface."""
    if amount > 0.0 and ids[p, PAIR_INTERFACE] < 0:
        pair_slip[p] += amount
