"""Compiled: the ground's input to each step, from samples of the ground motion's velocity and displacement.

Private module, the driver's ground stage.  A chunk of steps ``first .. first + steps`` of ``dt`` (s) reads the
motion through :func:`ground_samples` once, and each step's input follows from those samples by :func:`ground_at`
(on a GPU, each member of a scaled record scales the record's shared samples), into a window of the step and the
next, from which :func:`place_base` places the base at a step, and :func:`ground_before_end` gives the input within
it: the base's place at a part's start (:func:`place_base_within`) and its velocity at a Moreau-Jean part's end.

The load of step k is the ground's mean acceleration over the step's cell, the difference of its exact
velocity over dt: ``[t_k - dt/2, t_k + dt/2]``, which the velocity update of central differences spans, or
``[t_k, t_k+1]``, Moreau-Jean's; so the impulse the blocks receive is exact whatever the motion (a pulse that
ends between steps, a record's piecewise-linear samples).  A moving base is placed at the ground's displacement
of each step, with the ground's velocity at the start of the step's cell (``lead`` steps before it), and the step's
velocity update takes it to the ground's velocity at the cell's end.
"""

import numba as nb
import numpy as np


def ground_samples(excitation, dt: float, inertial: bool, lead: float, first: int, steps: int) -> np.ndarray:
    """(4, steps + 2) samples of ``excitation`` (a :class:`~dem_core.inputs.excitation.GroundMotion`) for steps
    ``first`` .. ``first + steps`` of ``dt`` (s).

    inertial : the blocks move relative to the ground under its inertial load: rows 0, 1 are the ground's
    velocity x, y (m/s) at the ``steps + 2`` cell edges ``(first + i - lead) dt`` (lead 0.5 for central
    differences, 0 for Moreau-Jean); rows 2, 3 are zero.  Otherwise (a moving base) rows 0, 1 are the velocity
    ``lead`` steps before each step and rows 2, 3 the displacement x, y (m) at each step, the last column
    unused."""
    samples = np.zeros((4, steps + 2))
    if inertial:
        samples[0:2] = np.array(excitation.velocity((first + np.arange(steps + 2) - lead) * dt))
    else:
        t = (first + np.arange(steps + 1)) * dt
        samples[0:2, :-1] = np.array(excitation.velocity(t - lead * dt))
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


@nb.njit(cache=True, inline="always")
def place_base(pos, vel, window, column):
    """The base (body 0) where the ground motion puts it at the step of ``window[:, column]`` (:func:`ground_at`)."""
    pos[0, 0] = window[2, column]
    pos[0, 1] = window[3, column]
    vel[0, 0] = window[4, column]
    vel[0, 1] = window[5, column]


@nb.njit(cache=True, inline="always")
def ground_before_end(window, row, left, dt):
    """Row ``row`` of the ground's input (:func:`ground_at`) ``left`` (s) before the end of the step of ``dt`` (s)
    from ``window[:, 0]`` to ``window[:, 1]``, on the line between the two: the base's place where a part starts
    with ``left`` of the step to go (rows 2, 3), or its velocity where a Moreau-Jean part ends leaving ``left``
    (rows 4, 5)."""
    return window[row, 1] - left / dt * (window[row, 1] - window[row, 0])


@nb.njit(cache=True, inline="always")
def place_base_within(pos, window, left, dt):
    """The base where the ground has it ``left`` (s) before the end of the step of ``dt`` (s) from ``window[:, 0]``
    to ``window[:, 1]``: where a part of a step after its first starts.  Its velocity is the integrator's to set
    (the part's velocity update)."""
    pos[0, 0] = ground_before_end(window, 2, left, dt)
    pos[0, 1] = ground_before_end(window, 3, left, dt)
