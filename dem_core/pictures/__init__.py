"""Figures and animations of runs (these modules import matplotlib; this one does not)."""

#: sliding is given in mm while it stays under this (m), else in m
SLIP_IN_MM_BELOW = 0.1


def slip_scale(largest: float) -> tuple[float, str]:
    """``(scale, unit)`` in which to give sliding of at most ``largest`` m: (1e3, "mm") under
    :data:`SLIP_IN_MM_BELOW`, else (1.0, "m")."""
    return (1e3, "mm") if largest < SLIP_IN_MM_BELOW else (1.0, "m")
