"""Compiled: a connector's law, a bar across a joint in shear and in tension (docs/method.md 1.12).

Private module, read by both integrators' connector stages (:mod:`._connectors`).  A connector joins an anchor
point in each of its two blocks; ``delta`` is the anchor of the second block relative to the first's, along the
joint (shear) or across it (opening, positive apart).  Each law gives the force ``F`` that resists it (N,
positive against a positive ``delta``).

Shear: a gap of ``clearance`` each way (the hole wider than the pin) in series with an elastic-plastic spring of
stiffness ``k``, yield force ``F_y`` and linear kinematic hardening ``H`` up to the ultimate force ``F_u`` (the
monotonic envelope's slope after yield is ``k_h = k H / (k + H)`` until it reaches ``F_u``, flat after: the back
force is held within ``F_u - F_y``).  Its state is the spring's plastic slip ``x_p``, where the gap's middle has
moved to, the back force ``beta`` and the plastic slip accumulated over every excursion.  With
``r = delta - x_p``, no force acts while ``|r| <= clearance``; past it the trial force is ``k (r - clearance s)``
(``s`` the sign of ``r``), and where it is more than ``F_y`` from ``beta`` the spring yields (the return mapping
of 1D plasticity; Simo and Hughes 1998, "Computational Inelasticity", section 1.4).  Each piece of the law is an
affine function of ``delta``, its branch (:func:`shear_branch`, :func:`shear_affine`), which is how Moreau-Jean
solves it implicitly.

Tension: a spring of stiffness ``k_a`` on the opening, none in compression (the stone carries that).

The connector ruptures, and carries nothing after, when its accumulated plastic slip reaches its capacity or its
tension its strength (:func:`ruptures`).
"""

import numba as nb

#: columns of a connector's row of ModelArrays.connector_law: its anchor in the first body's frame and in the
#: second's (m), the joint's normal in the first body's frame (from the first body into the second), the shear
#: stiffness (N/m), yield force (N), hardening (N/m), the back force's bound F_u - F_y (N), clearance (m) and
#: plastic slip capacity (m), the tensile stiffness (N/m) and strength (N)
(ANCHOR_AX, ANCHOR_AY, ANCHOR_BX, ANCHOR_BY, AXIS_X, AXIS_Y, SHEAR_K, YIELD_FORCE, HARDENING, BACK_LIMIT, CLEARANCE,
 SLIP_CAPACITY, AXIAL_K, AXIAL_STRENGTH) = range(14)
N_LAW = 14
#: columns of a connector's row of State.connectors: the shear spring's plastic slip, back force (N) and
#: accumulated plastic slip (m); the last shear force and tension (N), slip and opening (m); the peak shear force
#: and tension (N); the step at which it first yielded and ruptured (-1: not yet); the last step's impulses
#: (N s, Moreau-Jean's warm start)
(PLASTIC_SLIP, BACK_FORCE, ACCUMULATED, SHEAR_FORCE, TENSION, SLIP, OPENING, PEAK_SHEAR, PEAK_TENSION,
 YIELD_STEP, RUPTURE_STEP, IMPULSE_N, IMPULSE_T) = range(13)
N_STATE = 13
#: the shear branches: apart (within the clearance); elastic; yielding towards +delta or -delta, each plus the
#: side of the gap the pin bears on (the low bit: 1 for +)
FREE, ELASTIC, YIELD_UP, YIELD_DOWN = 0, 2, 4, 6


@nb.njit(cache=True, inline="always")
def shear_branch(delta, law, state):
    """The branch of the shear law (FREE, or ELASTIC, YIELD_UP, YIELD_DOWN with the low bit set where the pin bears
    on the gap's + side) at slip ``delta`` (m) from the state ``state`` (a connector's row of State.connectors) of
    the step's start; ``law`` the connector's row of ModelArrays.connector_law."""
    r = delta - state[PLASTIC_SLIP]
    gap = law[CLEARANCE]
    if abs(r) <= gap:
        return FREE
    up = 1 if r > 0.0 else 0
    trial = law[SHEAR_K] * (r - gap if up == 1 else r + gap)
    over = trial - state[BACK_FORCE]
    if abs(over) <= law[YIELD_FORCE]:
        return ELASTIC | up
    return (YIELD_UP if over > 0.0 else YIELD_DOWN) | up


@nb.njit(cache=True, inline="always")
def shear_affine(branch, law, state):
    """``(k, f0)``: the shear force of ``branch`` as ``F = k delta + f0`` (N/m, N) from the state of the step's
    start."""
    if branch == FREE:
        return 0.0, 0.0
    k = law[SHEAR_K]
    shift = state[PLASTIC_SLIP] + (law[CLEARANCE] if branch & 1 else -law[CLEARANCE])
    kind = branch & ~1
    if kind == ELASTIC:
        return k, -k * shift
    toward = 1.0 if kind == YIELD_UP else -1.0
    h = hardening(toward, law, state)
    tangent = k * h / (k + h)
    return tangent, -tangent * shift + k / (k + h) * (state[BACK_FORCE] + toward * law[YIELD_FORCE])


@nb.njit(cache=True, inline="always")
def hardening(toward, law, state):
    """The hardening (N/m) of plastic flow ``toward`` +1 or -1: ``H``, or 0 where the back force is at its bound
    that way (the force at ``F_u``)."""
    return 0.0 if toward * state[BACK_FORCE] >= law[BACK_LIMIT] else law[HARDENING]


@nb.njit(cache=True, inline="always")
def tension_affine(opening, law):
    """``(k, f0)``: the tension (N) at ``opening`` (m) as ``k opening + f0``: the bar's spring while the joint is
    open, nothing while it is closed."""
    return (law[AXIAL_K], 0.0) if opening > 0.0 else (0.0, 0.0)


@nb.njit(cache=True, inline="always")
def commit(delta, opening, law, state, step):
    """The connector's state taken to slip ``delta`` and ``opening`` (m) at the end of step ``step``: the shear
    spring's plastic slip, back force and accumulated slip returned to the yield surface, the forces, their peaks,
    the steps of first yield and of rupture.  Returns whether it ruptured at this step."""
    branch = shear_branch(delta, law, state)
    elastic = FREE if branch == FREE else ELASTIC | (branch & 1)
    if branch >= YIELD_UP:
        toward = 1.0 if (branch & ~1) == YIELD_UP else -1.0
        k, f0 = shear_affine(elastic, law, state)
        trial = k * delta + f0
        h = hardening(toward, law, state)
        flow = toward * (abs(trial - state[BACK_FORCE]) - law[YIELD_FORCE]) / (k + h)
        back = state[BACK_FORCE] + h * flow
        if toward * back > law[BACK_LIMIT]:  # the back force meets its bound within the step: flat from there
            back = toward * law[BACK_LIMIT]
            flow = (trial - back - toward * law[YIELD_FORCE]) / k
        state[PLASTIC_SLIP] += flow
        state[BACK_FORCE] = back
        state[ACCUMULATED] += abs(flow)
        if state[YIELD_STEP] < 0.0:
            state[YIELD_STEP] = step
    k, f0 = shear_affine(elastic, law, state)
    force = k * delta + f0
    ka, fa = tension_affine(opening, law)
    tension = ka * opening + fa
    state[SHEAR_FORCE] = force
    state[TENSION] = tension
    state[SLIP] = delta
    state[OPENING] = opening
    state[PEAK_SHEAR] = max(state[PEAK_SHEAR], abs(force))
    state[PEAK_TENSION] = max(state[PEAK_TENSION], tension)
    if ruptures(law, state):
        state[RUPTURE_STEP] = step
        state[SHEAR_FORCE] = 0.0
        state[TENSION] = 0.0
        state[IMPULSE_N] = 0.0
        state[IMPULSE_T] = 0.0
        return True
    return False


@nb.njit(cache=True, inline="always")
def ruptures(law, state):
    """Whether a connector in ``state`` has used up its plastic slip capacity or pulled past its strength."""
    return state[ACCUMULATED] >= law[SLIP_CAPACITY] or state[TENSION] >= law[AXIAL_STRENGTH]


@nb.njit(cache=True, inline="always")
def intact(state):
    """Whether the connector has not ruptured."""
    return state[RUPTURE_STEP] < 0.0
