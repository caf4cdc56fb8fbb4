"""Stacks of blocks (columns) and the overturn of a stack as a whole.

FORMULATION section 3: a column overturns when a block *or the column*
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

#: a contact counts as "resting on" when its normal is within ~25 degrees of vertical
VERTICAL_NORMAL = 0.9


@dataclass(frozen=True)
class Stack:
    """blocks: indices into ``scene.blocks``, bottom first (two or more).
    foot_local: (2, 2) the ends of the bottom block's base, in that block's own frame (about its
    centroid, its starting angle undone), m."""

    blocks: tuple
    foot_local: np.ndarray


def find_stacks(scene) -> tuple:
    """The stacks of two or more blocks standing on the base of ``scene``."""
    below = {b: [] for b in range(len(scene.bodies))}
    above = {b: [] for b in range(len(scene.bodies))}
    on_base = set()
    bodies = scene.bodies
    for i, j, contact in scene.touching_pairs():
        if abs(contact.normal[1]) < VERTICAL_NORMAL:
            continue
        low, high = (i, j) if bodies[i].centroid[1] < bodies[j].centroid[1] else (j, i)
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


def base_ends(block) -> np.ndarray:
    """(2, 2) the two ends of a block's base (its lowest face with its starting angle undone), in
    its own frame about its centroid, m: the corners it rocks on."""
    v = geometry.transform(block.vertices - block.centroid, -block.angle)
    size = np.ptp(v, axis=0).max()
    low = v[v[:, 1] <= v[:, 1].min() + 1e-9 * size]
    return np.array([low[np.argmin(low[:, 0])], low[np.argmax(low[:, 0])]])


def kernel_arrays(scene, stacks) -> dict:
    """The stacks as the kernel takes them (body indices count the base as 0)."""
    n_bodies = len(scene.bodies)
    stack_id = np.full(n_bodies, -1, np.int64)
    for k, st in enumerate(stacks):
        stack_id[np.array(st.blocks) + 1] = k
    masses = np.array([b.mass for b in scene.blocks])
    return {
        "stack_id": stack_id,
        "stack_bottom": np.array([st.blocks[0] + 1 for st in stacks], np.int64),
        "stack_mass": np.array([masses[list(st.blocks)].sum() for st in stacks]),
        "stack_foot": np.array([st.foot_local for st in stacks]).reshape(len(stacks), 2, 2),
    }


def tipped(stacks, scene, x, theta) -> np.ndarray:
    """(n, n_stacks) whether each stack's centre of mass is past an end of its bottom block's
    base at each output; ``x``, ``theta`` (n, n_blocks) as in :class:`~dem_core.engine.result.Result`."""
    masses = np.array([b.mass for b in scene.blocks])
    out = np.zeros((x.shape[0], len(stacks)), bool)
    for k, st in enumerate(stacks):
        members = list(st.blocks)
        com = x[:, members] @ masses[members] / masses[members].sum()
        b = st.blocks[0]
        th = theta[:, b]
        ends = x[:, b, None] + np.cos(th)[:, None] * st.foot_local[:, 0] - np.sin(th)[:, None] * st.foot_local[:, 1]
        out[:, k] = (com < ends.min(axis=1)) | (com > ends.max(axis=1))
    return out
