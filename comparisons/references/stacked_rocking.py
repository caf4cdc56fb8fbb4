"""Two rigid blocks stacked on rigid ground, rocking without sliding (docs/method.md 4.7).

The exact reference up to the first impact: after it, the rigid model needs an
impact rule, and Psycharis' (1990) rule is one assumption among several, so
the reference stops there.  Until then the motion is a sequence of modes, each
a Lagrangian system with the pivot corners fixed:

  ``locked``  the stack rocks as one body on a bottom corner of the lower block;
  ``both``    the lower block rocks on the ground, the upper one on a top corner of the lower one;
  ``upper``   the lower block stays down, the upper one rocks on it.

A mode ends at an impact (a rotation returning to zero) or, for ``locked``,
when the contact resultant under the upper block leaves its base and it starts
to rock on that edge.  Angles as in :mod:`comparisons.references.analytical`: counter-
clockwise positive, ``theta1`` the lower block's angle, ``theta2`` the upper
one's (absolute).  Which corners the blocks pivot on is part of the state, not
read off the signs of the angles: ``pivot1 = +1`` is the lower block's left
bottom corner (it rocks with ``theta1 > 0``), ``-1`` its right one;
``pivot2`` likewise for the upper block on the lower one (with
``theta2 - theta1``).  A pivot is chosen when the motion on it starts and kept
until the impact that ends it, so the state at an impact, where an angle is
zero give or take round-off, still belongs to the corner it rocked on.

Reference:
  Psycharis, I. N. (1990) Dynamic behaviour of rocking two-block assemblies.
      Earthquake Engineering and Structural Dynamics 19(4): 555-575.
"""

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from comparisons.references.analytical import G

_E = np.array([[0.0, -1.0], [1.0, 0.0]])  # rotation by +90 degrees


def _rot(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


@dataclass(frozen=True)
class TwoBlockStack:
    """Lower block 2 b1 x 2 h1, upper block 2 b2 x 2 h2 (m), centred, same density; per unit mass m1 = 1."""

    b1: float
    h1: float
    b2: float
    h2: float
    g: float = G

    @property
    def m1(self) -> float:
        return 1.0

    @property
    def m2(self) -> float:
        """Upper mass relative to the lower one (same density)."""
        return self.b2 * self.h2 / (self.b1 * self.h1)

    @property
    def i1(self) -> float:
        """Centroidal moment of inertia of the lower block, m1 (b1^2 + h1^2) / 3."""
        return self.m1 * (self.b1 ** 2 + self.h1 ** 2) / 3.0

    @property
    def i2(self) -> float:
        return self.m2 * (self.b2 ** 2 + self.h2 ** 2) / 3.0

    def _arms(self, pivot1, pivot2):
        """Lower pivot (corner1), its arm to block 1's centroid (a1), lower pivot to upper pivot (e), upper
        pivot to upper centroid (d2), all in the blocks' own frames; ``pivot1``, ``pivot2`` are +1 or -1."""
        if pivot1 not in (1, -1) or pivot2 not in (1, -1):
            raise ValueError(f"pivots are +1 (left corner) or -1 (right corner), got {pivot1}, {pivot2}")
        corner1 = np.array([-pivot1 * self.b1, 0.0])
        a1 = np.array([0.0, self.h1]) - corner1
        e = np.array([-pivot2 * self.b2, 2.0 * self.h1]) - corner1
        d2 = np.array([pivot2 * self.b2, self.h2])
        return corner1, a1, e, d2

    def centroids(self, theta1, theta2, pivot1, pivot2):
        """World centroids (2, 2) of the lower and upper block for the given angles (rad) and pivots."""
        corner1, a1, e, d2 = self._arms(pivot1, pivot2)
        c1 = corner1 + _rot(theta1) @ a1
        c2 = corner1 + _rot(theta1) @ e + _rot(theta2) @ d2
        return np.array([c1, c2])

    def energy(self, theta1, theta2, omega1, omega2, pivot1, pivot2) -> float:
        """Kinetic plus potential energy per unit lower mass (J/kg), potential zero at y = 0."""
        _, a1, e, d2 = self._arms(pivot1, pivot2)
        v_lower = omega1 * (_E @ _rot(theta1) @ a1)
        v_upper = omega1 * (_E @ _rot(theta1) @ e) + omega2 * (_E @ _rot(theta2) @ d2)
        c = self.centroids(theta1, theta2, pivot1, pivot2)
        return float(0.5 * self.m1 * v_lower @ v_lower + 0.5 * self.m2 * v_upper @ v_upper
                     + 0.5 * self.i1 * omega1 ** 2 + 0.5 * self.i2 * omega2 ** 2
                     + self.g * (self.m1 * c[0, 1] + self.m2 * c[1, 1]))

    def accelerations(self, mode, theta1, theta2, omega1, omega2, pivot1, pivot2):
        """Angular accelerations (rad/s^2) of both blocks in ``mode`` (Lagrange's equations)."""
        _, a1, e, d2 = self._arms(pivot1, pivot2)
        r1, r2 = _rot(theta1), _rot(theta2)
        u1, v1, v2 = _E @ r1 @ a1, _E @ r1 @ e, _E @ r2 @ d2
        m1, m2, g = self.m1, self.m2, self.g
        mass = np.array([[m1 * u1 @ u1 + self.i1 + m2 * v1 @ v1, m2 * v1 @ v2],
                         [m2 * v1 @ v2, m2 * v2 @ v2 + self.i2]])
        # generalised gravity forces and the velocity-product terms (the others vanish: E R a is normal to R a)
        force = np.array([-g * (m1 * u1[1] + m2 * v1[1]) + m2 * omega2 ** 2 * v1 @ (r2 @ d2),
                          -g * m2 * v2[1] + m2 * omega1 ** 2 * v2 @ (r1 @ e)])
        if mode == "both":
            return np.linalg.solve(mass, force)
        if mode == "locked":
            alpha = force.sum() / mass.sum()
            return np.array([alpha, alpha])
        if mode == "upper":
            return np.array([0.0, force[1] / mass[1, 1]])
        raise ValueError(f"unknown mode {mode!r}")

    def upper_resultant(self, theta, omega, pivot):
        """In ``locked`` mode, the stack rocking as one body on corner ``pivot`` of the lower block: where
        the contact force under the upper block acts, along its base from its centre line (m, in its own
        frame).  Beyond +-b2 the upper block tips onto that edge."""
        # locked, the upper block's pivot does not matter: e + d2 runs from corner to centroid either way
        alpha = self.accelerations("locked", theta, theta, omega, omega, pivot, 1)[0]
        _, _, e, d2 = self._arms(pivot, 1)
        arm = _rot(theta) @ (e + d2)  # lower pivot to upper centroid
        accel = alpha * (_E @ arm) - omega ** 2 * arm
        force = self.m2 * (accel + np.array([0.0, self.g]))  # from the lower block on the upper one
        tangential, normal = _rot(theta).T @ force
        return (self.i2 * alpha - self.h2 * tangential) / normal


@dataclass(frozen=True)
class StackHistory:
    """theta1, theta2 (rad) and omega1, omega2 (rad/s) at times t (s), up to the first impact.

    pivot1, pivot2 : (n,) the corners the blocks pivot on at each sample (+1 left, -1 right, see the
    module docstring).  modes : ((start time, mode), ...).  impact_time : s, when a rotation first returns to zero
    (NaN if none within the time asked for).  impact : which interface closed, "ground" or "upper".
    """

    t: np.ndarray
    theta1: np.ndarray
    theta2: np.ndarray
    omega1: np.ndarray
    omega2: np.ndarray
    pivot1: np.ndarray
    pivot2: np.ndarray
    modes: tuple
    impact_time: float
    impact: str | None


def stack_response(stack: TwoBlockStack, theta0: float, t_end: float, *, max_step: float = 1e-3,
                   rtol: float = 1e-10) -> StackHistory:
    """Motion of the stack released at rest tilted as one body by ``theta0`` (rad), to its first impact.

    The release starts in ``locked`` mode, or in ``both`` if the upper block's contact resultant is
    already outside its base.
    """
    if theta0 == 0.0:
        raise ValueError("theta0 must be non-zero: an upright stack at rest stays at rest")
    pivot1 = 1 if theta0 > 0 else -1
    pivot2 = pivot1  # locked, the upper pivot is immaterial (see upper_resultant)
    mode = "locked"
    resultant = stack.upper_resultant(theta0, 0.0, pivot1)
    if abs(resultant) > stack.b2:
        mode, pivot2 = "both", (-1 if resultant > 0 else 1)
    y = np.array([theta0, theta0, 0.0, 0.0])
    t0 = 0.0
    pieces, modes = [], []
    impact_time, impact = float("nan"), None
    while t0 < t_end:
        modes.append((t0, mode))

        def rhs(_t, state, mode=mode, pivots=(pivot1, pivot2)):
            return [state[2], state[3], *stack.accelerations(mode, *state, *pivots)]

        def ground(_t, state):
            return state[0] * pivot1
        ground.terminal, ground.direction = True, -1

        def upper(_t, state):
            return state[1] - state[0]
        upper.terminal = True

        def tip(_t, state):
            return stack.b2 - abs(stack.upper_resultant(state[0], state[2], pivot1))
        tip.terminal, tip.direction = True, -1

        events = {"locked": [ground, tip], "both": [ground, upper], "upper": [upper]}[mode]
        upper.direction = -pivot2  # the relative angle returning to zero
        sol = solve_ivp(rhs, (t0, t_end), y, method="DOP853", events=events, max_step=max_step, rtol=rtol,
                        atol=1e-12, dense_output=False)
        pieces.append((sol.t, sol.y, pivot1, pivot2))
        hit = [k for k, te in enumerate(sol.t_events) if len(te)]
        if not hit:
            break
        which = events[hit[0]]
        t0, y = float(sol.t_events[hit[0]][0]), sol.y_events[hit[0]][0].copy()
        if which is tip:
            mode = "both"
            # the resultant left the upper block's base at its edge: it tips onto that corner
            pivot2 = -1 if stack.upper_resultant(y[0], y[2], pivot1) > 0 else 1
            continue
        impact_time, impact = t0, ("ground" if which is ground else "upper")
        break
    t = np.concatenate([p[0] for p in pieces])
    states = np.concatenate([p[1] for p in pieces], axis=1)
    pivot1s = np.concatenate([np.full(len(p[0]), p[2]) for p in pieces])
    pivot2s = np.concatenate([np.full(len(p[0]), p[3]) for p in pieces])
    return StackHistory(t, states[0], states[1], states[2], states[3], pivot1s, pivot2s, tuple(modes),
                        impact_time, impact)
