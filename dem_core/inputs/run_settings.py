"""The settings a run is given (the keywords of :func:`dem_core.simulate`), their defaults and their checks that
need no scene: a scene file's ``[simulation]`` is checked by them on reading, a run by them before anything else."""

import math

from ..engine.settings import INTEGRATORS, MOREAU_THETA
from .number_types import is_real

#: largest fraction of the stability limit used when dt is not given (the scheme is stable up to the
#: limit: mirror-image runs stay mirror images to round-off there)
DEFAULT_SAFETY = 0.8
#: time steps per shortest impact when dt is not given: resolving impacts matters for the energy they take.
#: The lagged dashpots make the loss first order in dt, and where an impact falls within a step scatters it
#: (docs/method.md 1.7 gives the rocking peaks' error at 10, 15 and 20 steps)
DEFAULT_STEPS_PER_IMPACT = 15
#: how the ground moves the scene: as inertial forces on the blocks in the ground's frame, or as the base moving
GROUND_MOTION_MODES = ("inertial", "moving_base")


def seconds(name: str, value) -> float:
    """``value`` as a positive, finite number of seconds; ``TypeError``/``ValueError`` naming ``name``."""
    if not is_real(value):
        raise TypeError(f"{name} must be a number of seconds, got {type(value).__name__} {value!r}")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be positive and finite, got {value}")
    return float(value)


def integrator_code(integrator: str) -> int:
    """The code of ``integrator`` (its position in ``INTEGRATORS``); ``ValueError`` naming the choices."""
    if integrator not in INTEGRATORS:
        raise ValueError(f"integrator must be one of {INTEGRATORS}, got {integrator!r}")
    return INTEGRATORS.index(integrator)


def check_step_fraction(step_fraction) -> None:
    if not 0.0 < step_fraction <= 1.0:
        raise ValueError(f"step_fraction multiplies the automatic step; it must be in (0, 1], got {step_fraction}")


def check_step_options(safety, steps_per_impact, step_fraction) -> None:
    """The options that choose the automatic step; ``ValueError`` naming the first out of its range."""
    if not 0.0 < safety <= 1.0:
        raise ValueError(f"safety is the fraction of the stability limit used as dt; it must be in (0, 1], "
                         f"got {safety}")
    if not steps_per_impact > 0:
        raise ValueError(f"steps_per_impact must be positive, got {steps_per_impact}")
    check_step_fraction(step_fraction)


def check_settings(*, duration=None, dt=None, output_dt=None, ground_motion: str = "inertial",
                   safety: float = DEFAULT_SAFETY, steps_per_impact: float = DEFAULT_STEPS_PER_IMPACT,
                   step_fraction: float = 1.0, integrator: str | None = None, theta: float = MOREAU_THETA,
                   stop_at_overturn: bool = True) -> None:
    """The settings of a run (:func:`dem_core.simulate`'s keywords) checked without its scene:
    ``TypeError``/``ValueError`` naming the first that is out of its range."""
    for name, value in (("duration", duration), ("dt", dt), ("output_dt", output_dt)):
        if value is not None:
            seconds(name, value)
    if ground_motion not in GROUND_MOTION_MODES:
        raise ValueError(f"ground_motion must be one of {GROUND_MOTION_MODES}, got {ground_motion!r}")
    check_step_options(safety, steps_per_impact, step_fraction)
    if integrator is not None:
        integrator_code(integrator)
    if not 0.5 <= theta <= 1.0:
        raise ValueError(f"theta weighs the new velocity in Moreau-Jean's position update; it must be in "
                         f"[0.5, 1], got {theta}")
