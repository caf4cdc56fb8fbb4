"""Compiled: the sine and cosine of an angle, quick where it is small.

Private module shared by the driver's stages.  The poses of standing blocks and the turns of a step are angles
well under ``SMALL``, where a few terms of the Taylor series give the library's value to within a unit in its last
place at a fraction of its cost; larger angles go to the library.
"""

import math

import numba as nb

#: rad: the largest angle taken by its series, whose first term left out (``x^11 / 11!``) is then below 3e-18 of
#: ``x``, under the rounding of a double
SMALL = 0.1


@nb.njit(cache=True, inline="always")
def sine(x):
    """``sin x`` (x in rad)."""
    if not abs(x) < SMALL:
        return math.sin(x)
    x2 = x * x
    return x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0))))


@nb.njit(cache=True, inline="always")
def cosine(x):
    """``cos x`` (x in rad), as ``1 - 2 sin^2(x / 2)`` where the angle is small."""
    if not abs(x) < SMALL:
        return math.cos(x)
    half = sine(0.5 * x)
    return 1.0 - 2.0 * half * half
