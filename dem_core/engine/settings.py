"""A run's settings as the compiled driver reads them, the integrators' defaults, and the codes a run ends with.

Defined once, here: :class:`Settings` is two arrays, one of reals and one of integers, whose columns are named by
this module's constants (``settings.real[DT]``); :func:`make_settings` fills them by name from the run's set-up
(:mod:`dem_core.simulation`), and a batch stacks its members' rows (:mod:`dem_core.batch_gpu`).  In Python a
setting is also an attribute, by its lower-case name (``settings.dt``, ``settings.max_sweeps``).
"""

from typing import NamedTuple

import numpy as np

#: the time-stepping schemes, by name at the position of their codes: central differences on the contact springs
#: (docs/method.md 1.6) and Moreau-Jean at the velocity level (1.8)
INTEGRATORS = ("explicit", "moreau")
EXPLICIT, MOREAU = range(2)
#: per integrator, how far (in steps) the cell of a step's ground load, and the ground velocity a moving base is placed
#: with, start before the step: central differences' velocity update spans [t - dt/2, t + dt/2], and its velocities
#: are those of the half step before; Moreau-Jean's spans [t, t + dt], its velocities those of the step
#: (docs/method.md section 2)
LOAD_CELL_LEAD = (0.5, 0.0)

#: the real settings, in their columns' order: the step (s); a block's speed (m/s) relative to the ground that no
#: stable run reaches; the energy balance's tolerance (a fraction) and scale (J); gravity (m/s^2); the base's top
#: relative to its centre (m); half the broad phase's skin (m); the motion's scale and the base's starting centre
#: (m); for Moreau-Jean theta, the index set's look-ahead gap and the position projection's slop (m), the solver's
#: tolerance (m/s), the change (a fraction of g times the step) past which a solve has failed, the shortest part
#: a step is split into (s) and Newton's restitution
REAL_NAMES = ("dt", "speed_limit", "energy_tolerance", "energy_scale", "gravity", "floor", "half_skin", "scale",
              "start_x", "start_y", "theta", "active_gap", "slop", "solver_tolerance", "solver_failure",
              "shortest_substep", "restitution")
(DT, SPEED_LIMIT, ENERGY_TOLERANCE, ENERGY_SCALE, GRAVITY, FLOOR, HALF_SKIN, SCALE, START_X, START_Y, THETA,
 ACTIVE_GAP, SLOP, SOLVER_TOLERANCE, SOLVER_FAILURE, SHORTEST_SUBSTEP, RESTITUTION) = range(len(REAL_NAMES))
#: the integer settings: the integrator and the contact law (their codes), the output stride (steps), the steps
#: between the samples of the joints' offsets, the last step, whether an overturn ends the run, 1 for the inertial
#: frame (0: a moving base), the substeps of a central difference step while a block is overturned, and
#: Moreau-Jean's Gauss-Seidel sweeps, rescue sweeps, position sweeps, direct passes by statuses and the most parts
#: a step is split into
INTEGER_NAMES = ("integrator", "contact_law", "stride", "interface_stride", "last_step", "stop_at_overturn",
                 "inertial", "substeps", "max_sweeps", "rescue_sweeps", "projection_sweeps", "status_passes",
                 "max_substeps")
(INTEGRATOR, CONTACT_LAW, STRIDE, INTERFACE_STRIDE, LAST_STEP, STOP_AT_OVERTURN, INERTIAL, SUBSTEPS, MAX_SWEEPS,
 RESCUE_SWEEPS, PROJECTION_SWEEPS, STATUS_PASSES, MAX_SUBSTEPS) = range(len(INTEGER_NAMES))
#: s between the samples of the joints' offsets, whose travel is the slip (engine/_interfaces.py): every engine's
#: joints are measured on their motion every millisecond, or every step where its steps are longer
INTERFACE_INTERVAL = 1e-3


def interface_stride(dt: float) -> int:
    """Steps of ``dt`` s between the samples of the joints' offsets: INTERFACE_INTERVAL, or one step."""
    return max(1, round(INTERFACE_INTERVAL / dt))

#: how a run's driver ends a chunk: it can go on (OK), or why it stopped.  FULL: a fixed-capacity store (the
#: code's first body field names which, :data:`STORES`) would overflow; the chunk is taken again with it larger
(STATUS_OK, STATUS_NONFINITE, STATUS_DEEP_OVERLAP, STATUS_RUNAWAY, STATUS_ENERGY, STATUS_OVERTURNED, STATUS_FELL_OFF,
 STATUS_UNCONVERGED, STATUS_FULL) = range(9)
#: the stores a run holds at a fixed capacity: its listed pairs and the slips of pairs that left the list
#: (Moreau-Jean's contact points, two a pair at most, have rows for two a pair: they cannot fill)
STORES = ("pairs", "retired")
PAIR_STORE, RETIRED_STORE = range(len(STORES))
#: steps between energy balance checks
ENERGY_CHECK_INTERVAL = 16

#: Moreau-Jean's weight of the new velocity in the positions' update.  The smooth forces (gravity, the ground's
#: load) are constant over a step, so theta only shapes the position update: 0.5 is the trapezoidal rule, second
#: order and free of numerical damping between impacts (the rocking equation conserves energy there); above 0.5
#: it damps like implicit Euler and is first order.  Siconos' rocking block uses 0.50001 with an LCP solver.
MOREAU_THETA = 0.5
#: Moreau-Jean's step when none is given (s): the accuracy of the impacts, not stability, sets it
MOREAU_DT = 1e-3
#: and no more than this fraction of the shortest time of the motion (a pulse's duration, a harmonic's period) or
#: of the scene (1/p of its most agile block, p = sqrt(3 g / (4 R)) the rocking frequency)
MOREAU_TIME_FRACTION = 0.02
#: Moreau-Jean's index set takes the points whose gap at the step's end (at the start's velocity) is below this
#: fraction of g h^2, the distance gravity closes from rest in a step of h; points are pushed out at the position
#: level beyond MOREAU_SLOP g h^2.  Scaled with the step, both vanish as it shrinks, and so does what they add to the
#: error (a corner held that far early, or left that deep)
MOREAU_ACTIVE_GAP = 1.0
MOREAU_SLOP = 0.1
#: Gauss-Seidel stops when no point's velocity changed by more than this fraction of g h in a sweep, or after
#: MOREAU_MAX_SWEEPS sweeps.  A step whose last sweep still changed a velocity by more than MOREAU_SOLVER_FAILURE
#: of g h is far from a solution of the contact problem (a stack's first step, an impact running through a
#: column): it sweeps on, up to MOREAU_RESCUE_SWEEPS more; if that does not bring the change below it, the part
#: of the step is taken again (MOREAU_RETRIES, below), and the run stops if those fail too.  The position
#: projection takes MOREAU_PROJECTION_SWEEPS
MOREAU_SOLVER_TOLERANCE = 1e-6
MOREAU_MAX_SWEEPS = 50
MOREAU_SOLVER_FAILURE = 0.1
MOREAU_RESCUE_SWEEPS = 2000
MOREAU_PROJECTION_SWEEPS = 4
#: passes of the direct solve by statuses before Gauss-Seidel (engine/_active_set.py; 0: Gauss-Seidel alone)
MOREAU_STATUS_PASSES = 8
#: a step is split where a point meets its face inside it, at most into this many parts, none shorter than
#: MOREAU_SHORTEST_SUBSTEP of the step
MOREAU_MAX_SUBSTEPS = 4
MOREAU_SHORTEST_SUBSTEP = 0.02
#: a part whose contact solve failed (statuses that do not settle in their passes and Gauss-Seidel still far from
#: a solution after its rescue sweeps, as where a high-friction column lands on a corner or an impact runs through
#: a colonnade) is taken again from its start, cold, at half its length, with MOREAU_RETRY_PASSES times the passes
#: by statuses and each point's Gauss-Seidel update taken MOREAU_RELAXATION of the way (under-relaxed: the cycle
#: the full update can fall into is damped), up to MOREAU_RETRIES times; a step is taken in MOREAU_MAX_PARTS parts
#: at most, the last of them taking what is left
MOREAU_RETRIES = 4
MOREAU_RETRY_PASSES = 4
MOREAU_RELAXATION = 0.5
MOREAU_MAX_PARTS = 32


class Settings(NamedTuple):
    """real : (len(REAL_NAMES),) float64 and integer : (len(INTEGER_NAMES),) int64, columns by this module's
    constants.  ``settings.<name>`` reads a column by its lower-case name (an integer setting as an int)."""

    real: np.ndarray
    integer: np.ndarray

    def __getattr__(self, name: str):
        if name in REAL_NAMES:
            return float(self.real[REAL_NAMES.index(name)])
        if name in INTEGER_NAMES:
            return int(self.integer[INTEGER_NAMES.index(name)])
        raise AttributeError(f"Settings has no {name!r}; settings are {', '.join(REAL_NAMES + INTEGER_NAMES)}")

    def replace(self, **changes) -> "Settings":
        """A copy with the settings named in ``changes`` changed."""
        return make_settings(**{**{name: getattr(self, name) for name in REAL_NAMES + INTEGER_NAMES}, **changes})


def make_settings(**values) -> Settings:
    """:class:`Settings` from every setting by name; ``TypeError`` naming a missing or unknown one."""
    missing = [name for name in REAL_NAMES + INTEGER_NAMES if name not in values]
    unknown = [name for name in values if name not in REAL_NAMES + INTEGER_NAMES]
    if missing or unknown:
        raise TypeError(f"settings missing {missing}, unknown {unknown}")
    return Settings(np.array([float(values[name]) for name in REAL_NAMES]),
                    np.array([int(values[name]) for name in INTEGER_NAMES], np.int64))
