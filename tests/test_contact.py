"""The contact law: damping from a target restitution, parameter validation, the stiffness factor."""

import dataclasses

import numpy as np
import pytest

import dem_core
from dem_core import scenes
from dem_core.engine.contact import (EXPLICIT_LEAST_RESTITUTION, damping_ratio_for_restitution, normal_damping,
                                     restitution_for_damping_ratio)
from dem_core.engine.model import compile_model


@pytest.mark.parametrize("e", [0.002, 0.01, 0.05, 0.1353, 0.15, 0.37, 0.8, 1.0])
def test_restitution_mapping_round_trips(e):
    zeta = damping_ratio_for_restitution(e)
    assert restitution_for_damping_ratio(zeta) == pytest.approx(e, rel=1e-10)
    assert normal_damping(4.0, 9.0, restitution=e) == pytest.approx(2 * zeta * 6.0)


def test_the_restitution_is_continuous_through_critical_damping_and_falls_as_one_over_four_zeta_squared():
    """The under- and over-damped closed forms meet ``exp(-2)`` at ``zeta = 1``; a large dashpot leaves
    ``e ~ 1 / (4 zeta^2)``."""
    critical = np.exp(-2.0)
    for side in (1.0 - 1e-7, 1.0, 1.0 + 1e-7):
        assert restitution_for_damping_ratio(side) == pytest.approx(critical, rel=1e-6)
    assert restitution_for_damping_ratio(100.0) * 4e4 == pytest.approx(1.0, rel=0.01)
    zetas = np.linspace(0.0, 20.0, 401)
    assert np.all(np.diff([restitution_for_damping_ratio(z) for z in zetas]) < 0)


def test_no_tension_restitution_is_above_the_linear_oscillator_value():
    """Parting when the force (not the overlap) vanishes loses less energy than a full half cycle."""
    for zeta in (0.1, 0.3, 0.6):
        linear = np.exp(-zeta * np.pi / np.sqrt(1 - zeta**2))
        assert restitution_for_damping_ratio(zeta) > linear


def test_a_plastic_impact_is_asked_by_default_and_the_explicit_core_gives_its_least():
    """Newton's coefficient is 0 unless given; the explicit core's dashpots give EXPLICIT_LEAST_RESTITUTION for it,
    the restitution asked above it, and nothing of their own where a damping ratio is given."""
    plastic = dem_core.ContactParameters()
    assert plastic.impact_restitution == 0.0 and plastic.explicit_restitution == EXPLICIT_LEAST_RESTITUTION
    assert plastic.normal_damping_ratio == damping_ratio_for_restitution(EXPLICIT_LEAST_RESTITUTION)
    assert dem_core.ContactParameters(restitution=0.3).explicit_restitution == 0.3
    assert dem_core.ContactParameters(damping_ratio=0.5).explicit_restitution is None
    overlap = dem_core.ContactParameters(law="overlap_area")
    assert overlap.explicit_restitution is None and overlap.normal_damping_ratio == 0.3
    model = compile_model(scenes.block(1.0, 2.0, contact=dem_core.ContactParameters(restitution=0.2)))
    assert model.law.restitution == 0.2


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
    for bad in (-0.1, 1.5):
        with pytest.raises(ValueError, match="restitution must be from 0 to 1"):
            dem_core.ContactParameters(restitution=bad)
    with pytest.raises(ValueError, match=r"restitution must be in \(0, 1\]"):
        damping_ratio_for_restitution(0.0)


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
