"""The strong-motion window of a bundled record: the part of it the ensembles and the colonnade run.

The window starts where the record's Arias intensity ``I(t) = pi / (2 g) int_0^t a^2 dt`` passes
:data:`START_SHARE` of its total and ends :data:`TAIL` s after it passes :data:`END_SHARE` (the
significant duration of Trifunac and Brady (1975), BSSA 65(3): 581-626, with a tail in which the
blocks' rocking and sliding die down).  Cutting the quiet start and end keeps the peak response and
makes the runs shorter: the four bundled records run 117 s in all instead of 329 s.  The engines and
the references are given the same samples, so the comparison is exact about what was run.
"""

from functools import cache

import numpy as np

from dem_core import excitation

START_SHARE = 0.005
END_SHARE = 0.95
TAIL = 5.0  # s


@cache
def window(record: str) -> tuple[float, float]:
    """``(start, end)`` of the strong-motion window of a bundled record, s from the record's start."""
    motion = excitation.record(record)
    a = np.asarray(motion.horizontal.samples)
    dt = motion.horizontal.dt
    arias = np.cumsum(a**2)
    arias /= arias[-1]
    t = np.arange(len(a)) * dt
    start = t[np.searchsorted(arias, START_SHARE)]
    end = min(t[np.searchsorted(arias, END_SHARE)] + TAIL, t[-1])
    return float(start), float(end)


def strong_motion(record: str, pga: float):
    """The bundled record's strong-motion window as a ground motion from t = 0, scaled to ``pga`` (m/s^2).

    The samples are those of :func:`dem_core.excitation.record` (baseline-corrected over the whole
    record), cut to the window; the window holds the record's peak, so the scaling is the whole
    record's.  Its ``end_time`` is the window's length.
    """
    cut, dt = _unit_window(record)
    start, end = window(record)
    motion = excitation.record(pga * cut, dt=dt, baseline=False)
    return excitation.GroundMotion(motion.horizontal, name=f"{record} {start:.1f}-{end:.1f} s at {pga:.3g} m/s^2")


@cache
def _unit_window(record: str) -> tuple[np.ndarray, float]:
    """The window's samples of the record scaled to a PGA of 1 m/s^2, and their interval (s)."""
    whole = excitation.record(record, pga=1.0)
    samples = np.asarray(whole.horizontal.samples)
    dt = whole.horizontal.dt
    start, end = window(record)
    cut = samples[round(start / dt):round(end / dt) + 1]
    if np.max(np.abs(cut)) < np.max(np.abs(samples)):
        raise ValueError(f"{record}: its strong-motion window {start:.2f}-{end:.2f} s misses the record's peak")
    cut.flags.writeable = False
    return cut, dt
