"""The benchmark cases of FORMULATION section 4, defined once for tests, scripts and the harness."""

from dem_core import scenes

#: FORMULATION 4.1-4.2: the 0.25 x 1.0 m granite block released from 0.05236 rad (3 degrees)
HOUSNER_WIDTH = 0.25
HOUSNER_HEIGHT = 1.0
HOUSNER_THETA0 = 0.05236

#: FORMULATION 4.6: the 1 x 6 m column, rocking onset at g b / h = 1.635 m/s^2
ONSET_WIDTH = 1.0
ONSET_HEIGHT = 6.0
ONSET_RAMP_RATE = 0.5  # m/s^2 per s


def housner_scene(**kwargs):
    """The free-rocking block, tilted onto its left corner."""
    return scenes.block(HOUSNER_WIDTH, HOUSNER_HEIGHT, tilt=HOUSNER_THETA0, **kwargs)
