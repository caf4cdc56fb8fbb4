"""The contact law: damping from a target restitution, parameter validation, the stiffness factor."""

import dataclasses

import numpy as np
import pytest

import dem_core
from dem_core import scenes, stability
from dem_core.engine.contact import damping_ratio_for_restitution, normal_damping, restitution_for_damping_ratio
from dem_core.engine.geometry import rectangle, transform
from dem_core.engine.model import compile_model


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
def test_a_corner_impact_rebounds_with_the_target_restitution(e):
    """Corner law: a square dropped onto a corner right below its centre of mass meets the base at one point
    whose effective mass is the block's: that point's spring-dashpot must give the restitution asked for."""
    zeta = damping_ratio_for_restitution(e)
    lift = np.sqrt(0.5) + 0.1  # the corner starts 0.1 m above the base: gravity's impulse over the contact is small
    diamond = dem_core.Block("block", transform(rectangle(1.0, 1.0, -0.5, -0.5), np.pi / 4, (0.0, lift)),
                             angle=np.pi / 4)
    scene = scenes.block(1.0, 1.0).replace(blocks=(diamond,), contact=dem_core.ContactParameters(restitution=e),
                                           allow_free_blocks=True)
    assert scene.contact.normal_damping_ratio == pytest.approx(zeta)
    dt = stability.stability_limit(compile_model(scene)) / 40.0  # resolve the ~1 ms contact finely
    result = dem_core.simulate(scene, duration=0.16, dt=dt, output_dt=dt, stop_at_overturn=False)
    gap = result.y[:, 0] - np.sqrt(0.5)
    velocity = np.diff(result.y[:, 0]) / dt
    enter = np.argmax(gap < 0.0)
    leave = enter + np.argmax(gap[enter:] > 0.0)
    assert np.ptp(result.theta) == 0.0  # symmetric: it bounces without turning
    assert velocity[leave] / -velocity[enter - 1] == pytest.approx(e, abs=0.01)  # measured 0.296, 0.598, 0.799


def test_contact_parameters_are_validated():
    with pytest.raises(ValueError, match="kn must be positive"):
        dem_core.ContactParameters(kn=0.0)
    with pytest.raises(ValueError, match="damping_ratio must be >= 0"):
        dem_core.ContactParameters(damping_ratio=-1.0)
    with pytest.raises(ValueError, match="exactly one"):
        normal_damping(1.0, 1.0)
    with pytest.raises(ValueError, match="contact law must be one of corner, overlap_area"):
        dem_core.ContactParameters(law="hertz")
    with pytest.raises(ValueError, match="not both"):
        dem_core.ContactParameters(damping_ratio=0.5, restitution=0.5)
    with pytest.raises(ValueError, match="no rocking couple"):
        dem_core.ContactParameters(rocking_damping_ratio=0.5)
    assert dem_core.ContactParameters().normal_damping_ratio == 1.0  # critical by default
    assert dem_core.ContactParameters(law="overlap_area").normal_damping_ratio == 0.3


def test_stiffer_scales_k_n_and_keeps_every_other_setting():
    contact = dem_core.ContactParameters(law="overlap_area", damping_ratio=0.4, tangential_stiffness_ratio=0.3, ct=5.0)
    stiff = dem_core.contact.stiffer(contact, 10.0)
    assert stiff.kn == contact.kn * 10.0
    assert dataclasses.replace(stiff, kn=contact.kn) == contact
    with pytest.raises(ValueError, match="stiffness factor"):
        dem_core.contact.stiffer(contact, 0.0)


def test_the_laws_names_are_their_kernel_codes():
    """A compiled model's law code indexes ``contact.LAWS``: one list of names for the API and the kernel."""
    for law in dem_core.contact.LAWS:
        scene = scenes.block(1.0, 2.0, contact=dem_core.ContactParameters(law=law))
        assert dem_core.contact.LAWS[compile_model(scene).law.law] == law
