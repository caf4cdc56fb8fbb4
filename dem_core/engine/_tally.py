"""Compiled: where the slip of a pair goes, the one rule both integrators tally by.

Private module.  A pair that is a recorded interface adds its slip to the interface's tally, which the outputs
follow over time; any other pair keeps its own, handed to the retired slips if it leaves the list.
"""

import numba as nb

from .state import PAIR_INTERFACE


@nb.njit(cache=True, inline="always")
def tally_slip(p, ids, pair_slip, interface_slip, amount):
    """``amount`` (m, the largest slip of pair ``p``'s points over a step) into its interface's or its own tally."""
    if amount > 0.0:
        k = ids[p, PAIR_INTERFACE]
        if k >= 0:
            interface_slip[k] += amount
        else:
            pair_slip[p] += amount
