"""The slip of a joint, measured on the blocks' motion the same way for every engine (docs/method.md section 3):
kinematics with known answers, the kernel's tally against the same measure of its histories, and a peer's
result measured alike."""

import numpy as np
import pytest

import adapters
import dem_core
from dem_core import excitation, scenes
from dem_core.engine import geometry
from dem_core.engine.model import compile_model, interface_history, result_states
from dem_core.engine.settings import INTERFACE_INTERVAL

#: the two drums of these tests: 1 m wide, 0.5 m high
WIDTH, HEIGHT = 1.0, 0.5


def two_drums(tilt=0.0):
    return scenes.stack(((WIDTH, HEIGHT), (WIDTH, HEIGHT)), tilt=tilt)


def start(model) -> np.ndarray:
    """(nb, 3) the bodies' starting x, y, theta."""
    return np.column_stack([model.bodies.centroid0, model.bodies.angle0])


def rocked(state, body, corner, angle) -> np.ndarray:
    """``state`` with ``body`` turned by ``angle`` (rad) about the world point ``corner``."""
    moved = state.copy()
    moved[body, :2] = geometry.transform((state[body, :2] - corner)[None, :], angle, corner)[0]
    moved[body, 2] += angle
    return moved


def test_rocking_about_either_end_is_no_slip_and_a_shift_is():
    """The upper drum rocks about the joint's left end, back, about its right end, and then moves 2 mm along the
    joint and back: the joint's slip is 4 mm, the rocking none of it; the lower joint never slips."""
    model = compile_model(two_drums())
    rest = start(model)
    top = rest[1, 1] + HEIGHT / 2.0
    left, right = np.array([rest[1, 0] - WIDTH / 2, top]), np.array([rest[1, 0] + WIDTH / 2, top])
    shifted = rest.copy()
    shifted[2, 0] += 2e-3
    states = np.array([rest, rocked(rest, 2, left, 0.05), rest, rocked(rest, 2, right, -0.08), rest, shifted, rest])
    travel = interface_history(model, states)[1]
    np.testing.assert_allclose(travel[:, 0], 0.0, atol=1e-15)  # base/block1
    np.testing.assert_allclose(travel[:, 1], [0, 0, 0, 0, 0, 2e-3, 4e-3], atol=1e-12)


def test_a_flight_counts_what_it_moves_along_the_joint():
    """The upper drum lifted 1 mm, turned about its own centre and set down 0.5 mm further along: its slip is the
    0.5 mm its face's centre moved along the joint, whatever the turn in the air."""
    model = compile_model(two_drums())
    rest = start(model)
    flying = rest.copy()
    flying[2, 1] += 1e-3
    turned = flying.copy()
    turned[2, 2] = 0.01
    landed = rest.copy()
    landed[2, 0] += 5e-4
    travel = interface_history(model, np.array([rest, flying, landed]))[1]
    assert travel[-1, 1] == pytest.approx(5e-4, rel=1e-9)
    airborne = interface_history(model, np.array([rest, flying, turned, flying, landed]))[1]
    # turning 0.01 rad about the drum's centre, 0.25 m above its face, moves the face's centre 2.5 mm along the
    # joint, and the measure counts what rocking about an end would not have
    turn = HEIGHT / 2 * np.sin(0.01) + WIDTH / 2 * (1 - np.cos(0.01))
    assert airborne[2, 1] - airborne[1, 1] == pytest.approx(turn, rel=1e-9)


def test_a_block_tilted_onto_a_corner_rocks_without_slip():
    """A stack released tilted on the bottom drum's corner: rocking it back to flat about that corner, and on
    about the other corner, is no slip at either joint."""
    tilt = 0.05
    model = compile_model(two_drums(tilt))
    tilted = start(model)
    corner = geometry.transform(np.array([[-WIDTH / 2, -HEIGHT / 2]]), tilt, tilted[1, :2])[0]  # it stands on
    flat = rocked(rocked(tilted, 1, corner, -tilt), 2, corner, -tilt)
    other = corner + np.array([WIDTH, 0.0])
    beyond = rocked(rocked(flat, 1, other, -0.03), 2, other, -0.03)
    offset, travel = interface_history(model, np.array([tilted, flat, beyond, flat]))
    np.testing.assert_allclose(travel, 0.0, atol=1e-12)
    np.testing.assert_allclose(offset, 0.0, atol=1e-12)


@pytest.mark.parametrize("integrator", ["explicit", "moreau"])
def test_the_driver_measures_what_the_histories_measure(integrator):
    """Outputs every millisecond, when the driver samples the joints: its slip is the histories' measure (the
    same compiled function), for a block that slides."""
    scene = scenes.block(1.0, 0.5, friction=0.3, base_width=40.0)
    result = dem_core.simulate(scene, excitation.rectangular_pulse(6.0, 0.3), 0.6, output_dt=INTERFACE_INTERVAL,
                               integrator=integrator)
    model = compile_model(scene)
    offset, travel = interface_history(model, result_states(model, result))
    np.testing.assert_allclose(result.slip_history, travel, rtol=1e-12, atol=1e-15)
    # a sliding block's slip is its travel over the base: under one pulse it slides one way, and its offset is its
    # displacement relative to the base (the centroid's, to the 5e-9 m the explicit contacts' give turns it by)
    slid = abs(result.relative_x[-1, 0] - result.relative_x[0, 0])
    assert result.interface_slip[("base", "block")] == pytest.approx(slid, rel=1e-6)
    np.testing.assert_allclose(offset[:, 0], result.relative_x[:, 0] - result.relative_x[0, 0], atol=2e-8)


def test_a_peer_engine_is_measured_alike():
    """pymunk's result carries the slip of every interface touching at the start, measured on its states."""
    scene = scenes.block(1.0, 0.5, friction=0.3, base_width=40.0)
    result = adapters.simulate(scene, excitation.rectangular_pulse(6.0, 0.3), 0.6, engine="pymunk", dt=1e-3,
                               output_dt=1e-3)
    assert result.interfaces == (("base", "block"),)
    assert result.slip_history.shape == (len(result.t), 1)
    slid = abs(result.relative_x[-1, 0] - result.relative_x[0, 0])
    assert result.interface_slip[("base", "block")] == pytest.approx(slid, rel=1e-3)
