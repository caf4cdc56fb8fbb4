"""Compiled: the ground's input to each step, from samples of the ground motion's velocity and displacement.

Private module.  A chunk of steps ``first .. first + steps`` of ``dt`` (s) reads the motion through
:func:`ground_samples` once, and each step's input follows from those samples by :func:`ground_at`, a stage
that the single run (through :func:`ground_input`) and the batched GPU kernel (one member of a scaled record
at a time, the record's samples shared) both call, so that the two read a motion by one rule.

The load of step k is the ground's mean acceleration over the step's cell, the difference of its exact
velocity over dt: ``[t_k - dt/2, t_k + dt/2]``, which the velocity update of central differences spans, or
``[t_k, t_k+1]``, Moreau-Jean's; so the impulse the blocks receive is exact whatever the motion (a pulse that
ends between steps, a record's piecewise-linear samples).  A moving base is placed at the ground's
displacement of the step and moves at its velocity of the half step before it.
"""

import numba as nb
import numpy as np


def ground_samples(excitation, dt: float, inertial: bool, lead: float, first: int, steps: int) -> np.ndarray:
    """(4, steps + 2) samples of ``excitation`` (a :class:`~dem_core.inputs.excitation.GroundMotion`) for steps
    ``first`` .. ``first + steps`` of ``dt`` (s).

    inertial : the blocks move relative to the ground under its inertial load: rows 0, 1 are the ground's
    velocity x, y (m/s) at the ``steps + 2`` cell edges ``(first + i - lead) dt`` (lead 0.5 for central
    differences, 0 for Moreau-Jean); rows 2, 3 are zero.  Otherwise (a moving base) rows 0, 1 are the velocity
    at the half step before each step and rows 2, 3 the displacement x, y (m) at each step, the last column
    unused."""
    samples = np.zeros((4, steps + 2))
    if inertial:
        samples[0:2] = np.array(excitation.velocity((first + np.arange(steps + 2) - lead) * dt))
    else:
        t = (first + np.arange(steps + 1)) * dt
        samples[0:2, :-1] = np.array(excitation.velocity(t - 0.5 * dt))
        samples[2:4, :-1] = np.array(excitation.displacement(t))
    return samples


@nb.njit(cache=True, inline="always")
def ground_at(samples, k, scale, start_x, start_y, dt, inertial, ground, column):
    """Step ``k`` of a chunk into ``ground[:, column]`` (6, ...): the inertial load x, y (m/s^2), the base's
    position x, y (m) and its velocity x, y (m/s), for ``scale`` times the motion whose :func:`ground_samples`
    are ``samples``, the base's centre starting at (start_x, start_y)."""
    if inertial:
        ground[0, column] = -(scale * samples[0, k + 1] - scale * samples[0, k]) / dt
        ground[1, column] = -(scale * samples[1, k + 1] - scale * samples[1, k]) / dt
        ground[2, column] = start_x
        ground[3, column] = start_y
        ground[4, column] = 0.0
        ground[5, column] = 0.0
    else:
        ground[0, column] = 0.0
        ground[1, column] = 0.0
        ground[2, column] = start_x + scale * samples[2, k]
        ground[3, column] = start_y + scale * samples[3, k]
        ground[4, column] = scale * samples[0, k]
        ground[5, column] = scale * samples[1, k]


@nb.njit(cache=True)
def _fill(samples, scale, start_x, start_y, dt, inertial, ground):
    for k in range(ground.shape[1]):
        ground_at(samples, k, scale, start_x, start_y, dt, inertial, ground, k)


def ground_input(excitation, dt: float, start, inertial: bool, lead: float, first: int, steps: int) -> np.ndarray:
    """(6, steps + 1): the input of each of steps ``first`` .. ``first + steps`` (:func:`ground_at`), the base's
    centre starting at ``start`` (2,) m; ``inertial`` and ``lead`` as :func:`ground_samples` takes them."""
    ground = np.empty((6, steps + 1))
    _fill(ground_samples(excitation, dt, inertial, lead, first, steps), 1.0, float(start[0]), float(start[1]),
          float(dt), bool(inertial), ground)
    return ground
