"""The connector cases of docs/method.md 4.9: a block held to the base by one bar, against closed forms.

A 1.0 x 0.5 m block on the base, held by one bar at the middle of its joint.  Under a slow ramp of ground
acceleration it creeps as the bar takes the load; a perfectly plastic bar yields when the inertial load reaches
``mu g + F_y / m`` (:func:`yield_onset`), and an elastic bar's force against the slip is zero within its clearance
and then rises at its stiffness (:func:`load_slip`).  On a frictionless base under a harmonic motion a
perfectly plastic bar yields back and forth; the energy the run loses, the ground's work less the mechanical and
the bar's elastic energy at the end, is the bar's hysteresis, ``F_y`` times the plastic slip it took
(:func:`hysteresis`).  Only the native core models connectors: these cases run its engines alone.

Below a joint's sliding a bar's shear follows the joint's micro-slip, which the integrators model differently
(docs/method.md 1.12): :func:`impact_slip` is the case that decides, a two-drum column rocking freely, whose joint
rigid theory keeps shut and still through its impacts.
"""

import numpy as np

from comparisons.cases.case import CLOSED_FORM, Case
from dem_core import excitation, scenes
from dem_core.engine._checks import mechanical_energy
from dem_core.engine.model import compile_model
from dem_core.inputs.connectors import Connector, ConnectorKind

#: the engines that model connectors
NATIVE = ("dem", "dem-overlap", "dem-moreau")
BLOCK = (1.0, 0.5)  # m, width and height: squat, it slides and does not rock
MU = 0.3
STIFFNESS = 2e7  # N/m
YIELD_FRACTION = 0.2  # F_y / (m g)
CLEARANCE = 5e-4  # m
RAMP_RATE = 0.5  # m/s^2 per s
#: the harmonic motion of the hysteresis case: its peak acceleration (m/s^2), frequency (Hz) and duration (s)
HARMONIC = (5.0, 2.0, 3.0)


def held_block(mu: float, kind: ConnectorKind):
    """The block on the base, friction ``mu``, held by one connector of ``kind`` at the middle of its joint."""
    scene = scenes.block(*BLOCK, friction=mu)
    return scene.replace(connectors=(Connector(("base", "block"), kind),))


def _weight() -> float:
    block = scenes.block(*BLOCK).blocks[0]
    return block.mass * 9.81


def _relative(value, reference):
    return float(value / reference - 1.0) if np.isfinite(value) else np.nan


def plastic_bar() -> ConnectorKind:
    return ConnectorKind("perfectly plastic bar", shear_stiffness=STIFFNESS, yield_force=YIELD_FRACTION * _weight())


def loose_bar() -> ConnectorKind:
    return ConnectorKind("elastic bar with clearance", shear_stiffness=STIFFNESS, clearance=CLEARANCE)


def yield_onset():
    """The ground acceleration (m/s^2) at which the bar first yields, against ``mu g + F_y / m``."""
    def reference():
        return MU * 9.81 + YIELD_FRACTION * 9.81

    def errors(result, ref):
        return {"yield_acceleration": _relative(RAMP_RATE * result.connectors.yield_time_s[0], ref)}

    return {"reference": reference, "errors": errors, "reference_kind": "closed form",
            "reference_uncertainty": CLOSED_FORM}


def load_slip():
    """The bar's force against its slip while it bears: a line of the bar's stiffness that meets zero force at its
    clearance, fitted over the outputs where it bears."""
    def errors(result, _reference):
        force, slip = np.abs(result.connector_history[:, 0, 0]), np.abs(result.connector_history[:, 0, 2])
        bearing = force > 0.0
        stiffness, intercept = np.polyfit(slip[bearing], force[bearing], 1)
        return {"shear_stiffness": _relative(stiffness, STIFFNESS), "clearance_m": -intercept / stiffness - CLEARANCE}

    return {"reference": lambda: None, "errors": errors, "reference_kind": "closed form",
            "reference_uncertainty": CLOSED_FORM}


def hysteresis():
    """The energy the run lost (J), against the bar's hysteresis ``F_y`` times its plastic slip."""
    def errors(result, _reference):
        model = compile_model(held_block(0.0, plastic_bar()))
        state = result.final_state
        bodies = model.bodies
        end = mechanical_energy(state.pos, state.vel, bodies.mass, bodies.inv_inertia, model.gravity)
        stored = result.connector_history[-1, 0, 0] ** 2 / (2.0 * STIFFNESS)
        lost = state.ledger[0] + state.ledger[1] - end - stored
        return {"dissipated_energy": _relative(lost, plastic_bar().yield_force * result.connectors.plastic_slip_m[0])}

    return {"reference": lambda: None, "errors": errors, "reference_kind": "closed form",
            "reference_uncertainty": CLOSED_FORM}


#: the two-drum column of the impact slip case: 1 x 6 m, released from this fraction of its critical angle, for
#: this long (s): several impacts
IMPACT_COLUMN = (2, 1.0, 6.0)
IMPACT_RELEASE = 0.5
IMPACT_DURATION = 3.0


def joint_impulse_ratio(n_drums: int, width: float, height: float) -> float:
    """|tangential / normal| of the impulse the upper drums of a column rocking as one rigid body take through the
    top joint of its bottom drum at an impact (Housner's: about the new corner, the angular velocity times
    ``1 - 1.5 sin^2 alpha``): where it is below the joint's friction, rigid theory keeps the joint from slipping."""
    b, drum = 0.5 * width, height / n_drums
    alpha = np.arctan(b / (0.5 * height))
    ratio = 1.0 - 1.5 * np.sin(alpha) ** 2
    above = np.array([0.0, drum + 0.5 * (height - drum)])  # the centre of mass of the drums above the joint
    before = above - np.array([-b, 0.0])
    after = above - np.array([b, 0.0])
    change = ratio * np.array([-after[1], after[0]]) - np.array([-before[1], before[0]])
    return float(abs(change[0] / change[1]))


def impact_slip():
    """The slip at the joint of a two-drum column rocking freely through its impacts: rigid theory's is 0 (its
    joint impulse stays within the friction cone, :func:`joint_impulse_ratio`)."""
    def errors(result, _reference):
        return {"joint_slip_m": float(result.interface_slip.get(("drum1", "drum2"), 0.0))}

    return {"reference": lambda: 0.0, "errors": errors, "reference_kind": "closed form",
            "reference_uncertainty": 0.0}


def connector_cases() -> list:
    """The three cases, each for the native core's engines."""
    pga, frequency, duration = HARMONIC
    onset = (MU + YIELD_FRACTION) * 9.81 / RAMP_RATE
    return [
        Case(name="connector_yield", title=f"Block held by a perfectly plastic bar (F_y = {YIELD_FRACTION:g} m g), "
             f"mu = {MU:g}, under a {RAMP_RATE:g} m/s^2/s ramp: the bar yields at mu g + F_y/m (4.9)",
             scene=lambda: held_block(MU, plastic_bar()), motion=lambda: excitation.ramp(RAMP_RATE),
             duration=onset + 0.5, engines=NATIVE, quick=True,
             # measured: dem -5.9e-4, dem-overlap -6.3e-4 (the creep's dynamic lag); dem-moreau 0 (the onset falls
             # on a step: it is within RAMP_RATE dt of the closed form, 1e-4 of it)
             bands={"yield_acceleration": {"dem": 2e-3, "dem-overlap": 2e-3, "dem-moreau": 2e-4}}, **yield_onset()),
        Case(name="connector_load_slip", title=f"Block held by an elastic bar with {CLEARANCE * 1e3:g} mm clearance, "
             f"mu = {MU:g}, pushed by a {RAMP_RATE:g} m/s^2/s ramp: the load-slip line (4.9)",
             scene=lambda: held_block(MU, loose_bar()), motion=lambda: excitation.ramp(RAMP_RATE),
             duration=MU * 9.81 / RAMP_RATE + 2.0, engines=NATIVE, quick=True,
             # measured: every engine to round-off (below 1e-13 and 1e-17 m)
             bands={"shear_stiffness": {"dem": 1e-6, "dem-overlap": 1e-6, "dem-moreau": 1e-6},
                    "clearance_m": {"dem": 1e-9, "dem-overlap": 1e-9, "dem-moreau": 1e-9}}, **load_slip()),
        Case(name="connector_hysteresis", title=f"Block on a frictionless base held by a perfectly plastic bar under "
             f"{duration:g} s of a {frequency:g} Hz harmonic motion, {pga:g} m/s^2: the energy lost is the bar's "
             f"hysteresis (4.9)", scene=lambda: held_block(0.0, plastic_bar()),
             motion=lambda: excitation.harmonic(pga=pga, frequency=frequency), duration=duration, engines=NATIVE,
             quick=True,
             # measured: dem -1.6e-4, dem-overlap -5.7e-4, dem-moreau 5.6e-4
             bands={"dissipated_energy": {"dem": 2e-3, "dem-overlap": 2e-3, "dem-moreau": 2e-3}}, **hysteresis()),
        Case(name="impact_slip", title=f"Two-drum 1 x 6 m column rocking freely from {IMPACT_RELEASE:g} alpha for "
             f"{IMPACT_DURATION:g} s: no slip at its joint (rigid impacts keep it inside the friction cone, 4.9)",
             scene=lambda: scenes.column(IMPACT_COLUMN[0], IMPACT_COLUMN[1], IMPACT_COLUMN[2],
                                         tilt=IMPACT_RELEASE * np.arctan(0.5 * IMPACT_COLUMN[1]
                                                                         / (0.5 * IMPACT_COLUMN[2]))),
             motion=excitation.still, duration=IMPACT_DURATION, accuracy=1e-6,
             # measured: dem-moreau 4.9e-8 m (2.3e-9 at a quarter of its step); dem 7.5e-5 m, 7.4e-5 at ten times
             # its contact stiffness, dem-overlap 4.3e-5: the compliant impacts slip, which rigid theory does not;
             # pymunk 7.8e-5, mujoco 2.8e-5, pybullet 7.8e-6
             bands={"joint_slip_m": {"dem-moreau": 1e-6, "dem": 2e-4, "dem-overlap": 1e-4, "pymunk": 2e-4,
                                     "mujoco": 1e-4, "pybullet": 3e-5}}, **impact_slip()),
    ]
