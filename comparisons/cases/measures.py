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




def peak_until_overturn(result, block: int | None = None) -> float:
    """Largest |theta| (rad) of ``block`` (None: of any block) up to the first overturn, inclusive.

    A block that overturned reached its critical angle: that angle is its peak.  After an overturn an
    engine that goes on runs the collapse, whose rotations say nothing about the rocking before it.
    """
    theta = np.abs(result.theta)
    if result.overturned:
        theta = theta[result.t <= result.time_of_overturn]
    peaks = np.max(theta, axis=0) if len(theta) else np.zeros(result.n_blocks)
    if block is None:
        return float(np.max(peaks))
    if np.isfinite(result.overturn_time[block]):
        return float(result.critical_angle[block])
    return float(min(peaks[block], result.critical_angle[block]))
