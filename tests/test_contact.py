"""The contact law: damping from a target restitution, parameter validation."""

import numpy as np
import pytest

import dem_core
from dem_core import scenes, stability
from dem_core.engine.contact import damping_ratio_for_restitution, normal_damping, restitution_for_damping_ratio


@pytest.mark.parametrize("e", [0.15, 0.37, 0.8, 1.0])
def test_restitution_mapping_round_trips(e):
    zeta = damping_ratio_for_restitution(e)
    assert restitution_for_damping_ratio(zeta) == pytest.approx(e, rel=1e-10)
    assert normal_damping(4.0, 9.0, restitution=e) == pytest.approx(2 * zeta * 6.0)


def test_no_tension_restitution_is_above_the_linear_oscillator_value():
    """Parting when the force (not the overlap) vanishes loses less energy than a full half cycle."""
    for zeta in (0.1, 0.3, 0.6):
        linear = np.exp(-zeta * np.pi / np.sqrt(1 - zeta**2))
        assert restitution_for_damping_ratio(zeta) > linear


@pytest.mark.parametrize("e", [0.3, 0.6, 0.8])
def test_a_block_dropped_flat_rebounds_with_the_target_restitution(e):
    """A flat face contact is a linear spring-dashpot (F = K_n d L delta): the mapping must hold in the simulation."""
    zeta = damping_ratio_for_restitution(e)
    resting = scenes.block(1.0, 0.5)
    dropped = dem_core.Block("block", resting.blocks[0].vertices + [0.0, 0.002])
    scene = resting.replace(blocks=(dropped,), contact=dem_core.ContactParameters(damping_ratio=zeta))
    # the contact lasts pi / omega_0 ~ 0.8 ms: resolve it with a step well below the automatic one
    dt = stability.stability_limit(scene) / 40.0
    result = dem_core.simulate(scene, duration=0.03, dt=dt, output_dt=dt, stop_at_overturn=False)
    gap = result.y[:, 0] - 0.25
    velocity = np.diff(result.y[:, 0]) / dt
    enter = np.argmax(gap < 0.0)
    leave = enter + np.argmax(gap[enter:] > 0.0)
    # gravity keeps pulling during the ~1 ms contact: it takes about 0.01 m/s off a 0.2 m/s rebound
    assert velocity[leave] / -velocity[enter - 1] == pytest.approx(e, abs=0.03)  # measured 0.282, 0.593, 0.797


def test_contact_parameters_are_validated():
    with pytest.raises(ValueError, match="kn must be positive"):
        dem_core.ContactParameters(kn=0.0)
    with pytest.raises(ValueError, match="damping_ratio must be >= 0"):
        dem_core.ContactParameters(damping_ratio=-1.0)
    with pytest.raises(ValueError, match="exactly one"):
        normal_damping(1.0, 1.0)
