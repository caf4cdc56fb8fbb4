"""Stacks of blocks (columns) and the overturn of a stack as a whole.

docs/method.md section 3: a column overturns when a block *or the column*
passes its critical angle.  For a stack of drums the column's critical tilt is
reached when the centre of mass of the stack passes over an end of the bottom
drum's base (for one rigid block that is exactly |theta| = atan(b/h)); a
drum's own critical angle (0.46 rad for a 1 x 2 m drum) comes much later in
the collapse.

A stack is a chain of blocks from one standing on the base alone, each next
block resting on the previous one alone and being its only block above (so a
column's drums and capital, not an epistyle shared by several columns).
"""

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from . import geometry
from ._checks import first_overturns as _first_overturns

#: a contact counts as "resting on" when its normal is within ~25 degrees of the base top's normal
VERTICAL_NORMAL = 0.9


@dataclass(frozen=True)
class Stack:
    """blocks: indices into ``scene.blocks``, bottom first (two or more).
    foot_local: (2, 2) the ends of the bottom block's base, in that block's own frame (about its
    centroid, its starting angle undone), m."""

    blocks: tuple
    foot_local: np.ndarray


def find_stacks(scene) -> tuple:
    """The stacks of two or more blocks standing on the base of ``scene``; which block rests on which is
    judged along the normal of the base's top (:func:`top_face`), vertical on a level base."""
    below = {b: [] for b in range(len(scene.bodies))}
    above = {b: [] for b in range(len(scene.bodies))}
    on_base = set()
    bodies = scene.bodies
    up = top_face(scene.base)[1]
    for i, j, contact in scene.touching_pairs():
        if abs(contact.normal @ up) < VERTICAL_NORMAL:
            continue
        low, high = (i, j) if bodies[i].centroid @ up < bodies[j].centroid @ up else (j, i)
        below[high].append(low)
        above[low].append(high)
        if low == 0:
            on_base.add(high)
    stacks = []
    for bottom in sorted(on_base):
        if below[bottom] != [0]:
            continue
        chain = [bottom]
        while len(above[chain[-1]]) == 1 and below[above[chain[-1]][0]] == [chain[-1]]:
            chain.append(above[chain[-1]][0])
        if len(chain) < 2:
            continue
        stacks.append(Stack(tuple(b - 1 for b in chain), base_ends(bodies[bottom])))
    return tuple(stacks)


class Column(NamedTuple):
    """A stack as results report it: ``blocks`` the names bottom first; ``critical_angle`` (rad) the
    tilt of the whole stack, rotated as one body about a corner of its base, at which its centre of
    mass passes over that corner (for a single rectangle atan(b/h))."""

    blocks: tuple
    critical_angle: float


def columns(scene, stacks=None) -> tuple:
    """The :class:`Column` of each stack of ``scene`` (``stacks`` from :func:`find_stacks` if not given)."""
    stacks = find_stacks(scene) if stacks is None else stacks
    found = []
    for st in stacks:
        members = [scene.blocks[b] for b in st.blocks]
        mass = np.array([b.mass for b in members])
        com = np.array([b.centroid for b in members]).T @ mass / mass.sum()
        bottom = members[0]
        # the base's ends in the world at the start, and the stack's centre of mass relative to them
        ends = geometry.transform(st.foot_local, bottom.angle, bottom.centroid)
        angle0 = bottom.angle
        arms = [geometry.transform((com - end)[None, :], -angle0)[0] for end in ends]
        found.append(Column(tuple(b.name for b in members),
                            float(min(np.arctan2(abs(a[0]), a[1]) for a in arms))))
    return tuple(found)


def top_face(base) -> tuple:
    """The face of ``base`` (a :class:`~dem_core.Block`) that blocks stand on: ``(ends, normal)``, its ends (2, 2) m
    and its outward unit normal (2,), the edge whose normal points most upwards ((0, 1) on a level base)."""
    v = base.vertices
    following = np.roll(v, -1, axis=0)
    edges = following - v
    normals = np.column_stack([edges[:, 1], -edges[:, 0]]) / np.hypot(edges[:, 0], edges[:, 1])[:, None]
    k = int(np.argmax(normals[:, 1]))
    return np.array([v[k], following[k]]), normals[k]


def base_ends(block) -> np.ndarray:
    """(2, 2) the two ends of a block's base (its lowest face with its starting angle undone), in
    its own frame about its centroid, m: the corners it rocks on."""
    v = geometry.transform(block.vertices - block.centroid, -block.angle)
    size = np.ptp(v, axis=0).max()
    low = v[v[:, 1] <= v[:, 1].min() + 1e-9 * size]
    return np.array([low[np.argmin(low[:, 0])], low[np.argmax(low[:, 0])]])


def first_overturns(model, x, y, theta) -> tuple:
    """Index of the first output at which each block overturned and each stack tipped, by the rule the
    kernel applies every step (:func:`dem_core.engine._checks.mark_overturns`): ``(blocks
    (n_blocks,), stacks (n_stacks,))`` int64, -1 if never.  ``model`` : the compiled scene
    (:class:`~dem_core.engine.model.Model`).  ``x``, ``y``, ``theta`` (n, n_blocks) relative to the
    base, as a :class:`~dem_core.engine.result.Result` holds them less the ground, so the base stays where it
    started."""
    states = np.empty((len(x), len(model.bodies.mass), 3))
    states[:, 0] = [*model.bodies.centroid0[0], model.bodies.angle0[0]]
    states[:, 1:, 0], states[:, 1:, 1], states[:, 1:, 2] = x, y, theta
    blocks, stacks = _first_overturns(states, model.bodies, model.stacks)
    return blocks[1:], stacks
