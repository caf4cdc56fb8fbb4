"""Measurements taken from time histories the same way for every engine and reference."""

from itertools import pairwise

import numpy as np


def first_zero_crossing(t, theta) -> float:
    """Time (s) of the first sign change of ``theta``, linearly interpolated; NaN if none."""
    t = np.asarray(t)
    theta = np.asarray(theta)
    sign = np.sign(theta)
    change = np.nonzero(sign[1:] * sign[:-1] < 0)[0]
    if not change.size:
        return float("nan")
    k = change[0]
    return float(t[k] + (t[k + 1] - t[k]) * theta[k] / (theta[k] - theta[k + 1]))


def peaks_between_crossings(theta, count: int) -> np.ndarray:
    """Largest |theta| in each stretch between sign changes: the peak before the first
    impact, then the peak after each impact.  At most ``count`` values."""
    theta = np.asarray(theta)
    crossings = np.nonzero(np.diff(np.sign(theta)) != 0)[0] + 1
    bounds = np.concatenate([[0], crossings, [len(theta)]])
    peaks = [np.max(np.abs(theta[a:b])) for a, b in pairwise(bounds) if b > a]
    return np.array(peaks[:count])


def first_exceedance(t, values, threshold: float) -> float:
    """First time (s) |values| exceeds ``threshold``, linearly interpolated; NaN if never.

    NaN entries (an overturned reference) count as exceeding.
    """
    a = np.nan_to_num(np.abs(np.asarray(values, dtype=float)), nan=np.inf)
    above = np.nonzero(a > threshold)[0]
    if not above.size:
        return float("nan")
    k = above[0]
    if k == 0 or not np.isfinite(a[k]):
        return float(t[k])
    return float(t[k - 1] + (t[k] - t[k - 1]) * (threshold - a[k - 1]) / (a[k] - a[k - 1]))


def pivot_slip(result, half_width: float, half_height: float) -> np.ndarray:
    """(n,) horizontal slip (m) over the ground of the bottom corner a single rectangular block
    (``result`` of a one-block scene) tips onto first: the left one if its first clear rotation is positive."""
    theta = result.theta[:, 0]
    moving = np.nonzero(np.abs(theta) > 1e-6)[0]
    side = -1.0 if not moving.size or theta[moving[0]] > 0 else 1.0
    corner = result.x[:, 0] + side * half_width * np.cos(theta) + half_height * np.sin(theta) - result.base_x
    return corner - corner[0]


def observed_mode(result, half_width: float, half_height: float, *, rotation: float, slip: float = 1e-5) -> str:
    """``"rest"``, ``"rocking"``, ``"sliding"`` or ``"slide-rock"``: whether the block's rotation passes
    ``rotation`` (rad) and the slip of its pivot corner passes ``slip`` (m) during the run."""
    rocks = bool(np.max(np.abs(result.theta[:, 0])) > rotation)
    slides = bool(np.max(np.abs(pivot_slip(result, half_width, half_height))) > slip)
    return {(False, False): "rest", (True, False): "rocking", (False, True): "sliding",
            (True, True): "slide-rock"}[(rocks, slides)]
