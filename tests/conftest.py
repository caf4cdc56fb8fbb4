"""Shared fixtures: the Housner block as a reference and as a scene."""

import pytest

from comparisons import analytical, cases


@pytest.fixture(scope="session")
def housner_block():
    return analytical.RockingBlock.from_size(cases.HOUSNER_WIDTH, cases.HOUSNER_HEIGHT)


@pytest.fixture(scope="session")
def housner_scene():
    return cases.housner_scene()
