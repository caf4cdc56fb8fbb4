"""Rigid rocking references of the studies' systems, as inputs of the compiled rocking equation.

:func:`comparisons.references.rocking_equation.rocking_response` integrates the rocking equation of a
rectangular block (``p``, ``alpha``, Housner's restitution unless given).  Two other systems of the
studies obey the same equation with other constants:

* a rigid body symmetric about its vertical axis standing on the corners ``(+-b, 0)`` of its base
  (a monolithic column carrying a load held fixed to it): ``alpha = atan(b / h_G)``,
  ``p^2 = m g R / I_O`` with ``R = sqrt(b^2 + h_G^2)`` and ``I_O`` the inertia about a corner, and the
  angular velocity ratio at impact ``e = 1 - 2 m b^2 / I_O`` (angular momentum about the new corner
  kept; Housner 1963 for a rectangle, where it gives ``1 - 1.5 sin^2 alpha``);
* the rocking frame of ``N`` equal monolithic columns capped by a rigid beam of mass ``M``
  (Makris and Vassiliou 2013, Earthquake Engng Struct. Dyn. 42: 431-449): the columns' ``alpha``,
  ``p^2 (1 + 2 gamma) / (1 + 3 gamma)`` and ``e = (1 - 1.5 sin^2 alpha + 3 gamma cos 2 alpha) /
  (1 + 3 gamma)`` with ``gamma = M / (N m)``; it uplifts at ``g tan(alpha)`` like one column.

Each is returned as the :class:`~comparisons.references.analytical.RockingBlock` with that ``alpha`` and ``p``
(a rectangle of another size) and the restitution to pass with it.
"""

import numpy as np
from _checkout import ROOT  # noqa: F401 - this checkout's packages below

from comparisons.references.analytical import G, RockingBlock
from comparisons.references.rocking_equation import StepBudgetExceeded, rocking_response
from dem_core.analyses.thresholds import scan_and_refine


def equivalent_block(alpha: float, p: float, g: float = G) -> RockingBlock:
    """The rectangle with slenderness ``alpha`` (rad) and frequency parameter ``p`` (rad/s)."""
    size = 3.0 * g / (4.0 * p * p)  # R of the rectangle with this p
    return RockingBlock(size * np.sin(alpha), size * np.cos(alpha), g)


def rigid_body(scene, g: float = G) -> tuple[RockingBlock, float]:
    """All blocks of ``scene`` as one rigid body rocking on the bottom corners of its lowest block:
    ``(equivalent block, restitution)``."""
    blocks = scene.blocks
    masses = np.array([b.mass for b in blocks])
    centroids = np.array([b.centroid for b in blocks])
    mass = masses.sum()
    centre = masses @ centroids / mass
    bottom = min(blocks, key=lambda b: b.vertices[:, 1].min())
    half_width = 0.5 * np.ptp(bottom.vertices[:, 0])
    corner = np.array([centre[0] + half_width, bottom.vertices[:, 1].min()])
    inertia = sum(b.inertia + m * np.sum((c - corner) ** 2) for b, m, c in zip(blocks, masses, centroids))
    height = centre[1] - corner[1]
    lever = np.hypot(half_width, height)
    p = np.sqrt(mass * g * lever / inertia)
    return equivalent_block(np.arctan2(half_width, height), p, g), 1.0 - 2.0 * mass * half_width ** 2 / inertia


def rocking_frame(column: RockingBlock, n_columns: int, column_mass: float,
                  beam_mass: float) -> tuple[RockingBlock, float]:
    """Makris and Vassiliou's frame of ``n_columns`` columns like ``column`` under a beam:
    ``(equivalent block, restitution)``."""
    gamma = beam_mass / (n_columns * column_mass)
    alpha = column.alpha
    p = column.p * np.sqrt((1.0 + 2.0 * gamma) / (1.0 + 3.0 * gamma))
    restitution = (1.0 - 1.5 * np.sin(alpha) ** 2 + 3.0 * gamma * np.cos(2.0 * alpha)) / (1.0 + 3.0 * gamma)
    return equivalent_block(alpha, p, column.g), restitution


def overturning(block: RockingBlock, restitution: float, motion_at, low: float, high: float,
                duration: float | None = None, **search):
    """The overturning scales of the rigid reference under ``motion_at(scale)`` for ``duration`` s (default: the
    motion's end), by the same search as the native core's (:func:`dem_core.analyses.thresholds.scan_and_refine`)."""
    def overturns(scale):
        return rocking_response(block, motion_at(scale), duration, restitution=restitution).overturned

    return scan_and_refine(overturns, low, high, criterion="overturning", failures=(StepBudgetExceeded,), **search)
