"""The benchmark cases of FORMULATION section 4, defined once for tests, scripts and the harness.

A :class:`Case` is a scene, a ground motion, a duration and a way of judging a
run: ``errors(result, reference)`` returns named errors (relative, or in the
unit the name gives), where ``reference`` is what :meth:`Case.reference`
computed once (an analytical solution, or the converged native core for the
scenes without a closed form).
"""

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

import dem_core
from comparisons import analytical
from comparisons.measures import first_exceedance, first_zero_crossing, peaks_between_crossings
from comparisons.stacked_rocking import TwoBlockStack, stack_response
from dem_core import excitation, scenes, thresholds

#: FORMULATION 4.1-4.2: the 0.25 x 1.0 m granite block released from 0.05236 rad (3 degrees)
HOUSNER_WIDTH = 0.25
HOUSNER_HEIGHT = 1.0
HOUSNER_THETA0 = 0.05236

#: FORMULATION 4.6: the 1 x 6 m column, rocking onset at g b / h = 1.635 m/s^2
ONSET_WIDTH = 1.0
ONSET_HEIGHT = 6.0
ONSET_RAMP_RATE = 0.5  # m/s^2 per s

#: FORMULATION 4.7: Psycharis' stack, lower block 2.5 x 2.5 m, upper 2.0 x 5.0 m, released from 0.1 rad
STACK_SIZES = ((2.5, 2.5), (2.0, 5.0))
STACK_THETA0 = 0.1

#: FORMULATION 4.6 (Zhang-Makris): the 0.25 x 1.0 m block with mu = 0.3 > tan(alpha) = 0.25
SLIDE_ROCK_MU = 0.3
SLIDE_ROCK_PULSE = 0.1  # s, rectangular pulse
SLIDE_ROCK_SLIP = 1e-5  # m of slip that counts as sliding during the pulse


def housner_scene(**kwargs):
    """The free-rocking block, tilted onto its left corner."""
    return scenes.block(HOUSNER_WIDTH, HOUSNER_HEIGHT, tilt=HOUSNER_THETA0, **kwargs)


@dataclass(frozen=True)
class Case:
    """One benchmark: what to run and how to judge it.

    name : identifier used in tables and file names.
    title : one line for the report.
    scene, motion : builders (called when the case runs).
    duration : s.
    reference : computes what the errors are measured against (called once).
    errors : ``(result, reference) -> {metric: error}``.
    output_dt : s between recorded states.
    quick : part of the reduced set run by ``--quick`` and CI.
    primary : the metric the report ranks engines by (default: the first one).
    """

    name: str
    title: str
    scene: Callable
    motion: Callable
    duration: float
    reference: Callable
    errors: Callable
    output_dt: float = 1e-3
    quick: bool = True
    primary: str | None = None


def _relative(value, reference):
    return float(value / reference - 1.0) if reference else float("nan")


# --- free rocking (4.1, 4.2) -------------------------------------------------------------------

def _free_rocking(width, height, theta0):
    block = analytical.RockingBlock.from_size(width, height)

    def reference():
        return {"quarter": analytical.housner_period(block, theta0) / 4.0,
                "peaks": analytical.housner_peaks(block, theta0, 5)[1:]}

    def errors(result, ref):
        peaks = peaks_between_crossings(result.theta[:, 0], 6)[1:]
        decay = (float(np.max(np.abs(peaks / ref["peaks"] - 1.0))) if len(peaks) == 5 else float("inf"))
        return {"quarter_period": _relative(first_zero_crossing(result.t, result.theta[:, 0]), ref["quarter"]),
                "peak_decay": decay}

    return reference, errors


# --- rocking under a ground motion (4.3) --------------------------------------------------------

def _forced_rocking(width, height, make_motion, duration):
    block = analytical.RockingBlock.from_size(width, height)

    def reference():
        motion = make_motion()
        step = getattr(motion.horizontal, "dt", 1e-3)
        return analytical.rocking_response(block, lambda t: float(motion.horizontal.acceleration(t)), duration,
                                           max_step=min(step, 2e-3))

    def errors(result, ref):
        theta = np.interp(ref.t, result.t, result.theta[:, 0])
        valid = np.isfinite(ref.theta)
        return {"peak_rotation": _relative(np.max(np.abs(result.theta[:, 0])), ref.peak),
                "rms_rotation": float(np.sqrt(np.mean((theta[valid] - ref.theta[valid]) ** 2)) / ref.peak),
                "overturn_mismatch": float(bool(result.overturned) != bool(ref.overturned))}

    return reference, errors


# --- sliding (4.4, 4.5) ---------------------------------------------------------------------------

def _newmark(ratio, mu, t_p):
    a_p = ratio * mu * analytical.G

    def reference():
        return analytical.newmark_max_slip(a_p, t_p, mu)

    def errors(result, ref):
        slip = result.relative_x[:, 0] - result.relative_x[0, 0]
        return {"max_slip": _relative(np.max(np.abs(slip)), ref)}

    return a_p, reference, errors


def _record_sliding(mu, make_motion, duration):
    def reference():
        motion = make_motion()
        return analytical.rigid_plastic_sliding(motion.horizontal.samples, motion.horizontal.dt, mu, t_end=duration)

    def errors(result, ref):
        slip = result.relative_x[:, 0] - result.relative_x[0, 0]
        on_grid = np.interp(ref.t, result.t, slip)
        return {"max_slip": _relative(np.max(np.abs(slip)), ref.max_slip),
                "residual_slip": float((slip[-1] - ref.residual) / ref.max_slip),
                "rms_slip": float(np.sqrt(np.mean((on_grid - ref.u) ** 2)) / ref.max_slip)}

    return reference, errors


# --- onset (4.6) ------------------------------------------------------------------------------------

def _ramp_onset():
    block = analytical.RockingBlock.from_size(ONSET_WIDTH, ONSET_HEIGHT)
    threshold = block.alpha / 30.0

    def reference():
        ode = analytical.rocking_response(block, lambda t: ONSET_RAMP_RATE * t, 6.0, max_step=1e-3)
        return ONSET_RAMP_RATE * first_exceedance(ode.t, ode.theta, threshold)

    def errors(result, ref):
        return {"onset_acceleration": _relative(ONSET_RAMP_RATE * first_exceedance(result.t, result.theta[:, 0],
                                                                                   threshold), ref)}

    return reference, errors


def _sliding_onset(mu, rate, duration, slip_threshold=1e-4):
    """Ground acceleration (m/s^2) at which the slip passes ``slip_threshold`` under a ramp."""
    def reference():
        dt = 1e-3
        t = np.arange(0.0, duration + dt, dt)
        slip = analytical.rigid_plastic_sliding(rate * t, dt, mu)
        return rate * first_exceedance(slip.t, slip.u, slip_threshold)

    def errors(result, ref):
        slip = result.relative_x[:, 0] - result.relative_x[0, 0]
        return {"onset_acceleration": _relative(rate * first_exceedance(result.t, slip, slip_threshold), ref)}

    return reference, errors


def _slide_rock(factor):
    """A rectangular pulse at ``factor`` times the Zhang-Makris slide-rock threshold."""
    block = analytical.RockingBlock.from_size(HOUSNER_WIDTH, HOUSNER_HEIGHT)
    amplitude = factor * analytical.slide_rock_acceleration(block, SLIDE_ROCK_MU)

    def reference():
        return analytical.initial_mode_under_pulse(block, SLIDE_ROCK_MU, amplitude)

    def errors(result, ref):
        mode = thresholds.motion_mode(scenes.block(HOUSNER_WIDTH, HOUSNER_HEIGHT), result, SLIDE_ROCK_SLIP)
        return {"mode_mismatch": float(mode != ref)}

    return amplitude, reference, errors


# --- two stacked blocks (4.7) ------------------------------------------------------------------

def _stacked_blocks():
    (w1, h1), (w2, h2) = STACK_SIZES
    stack = TwoBlockStack(w1 / 2.0, h1 / 2.0, w2 / 2.0, h2 / 2.0)

    def reference():
        return stack_response(stack, STACK_THETA0, 5.0)

    def errors(result, ref):
        before = result.t <= ref.impact_time
        t = result.t[before]
        rms = [float(np.sqrt(np.mean((result.theta[before, k] - np.interp(t, ref.t, th)) ** 2)) / STACK_THETA0)
               for k, th in enumerate((ref.theta1, ref.theta2))]
        return {"impact_time": _relative(first_zero_crossing(result.t, result.theta[:, 0]), ref.impact_time),
                "rms_lower": rms[0], "rms_upper": rms[1]}

    return reference, errors


# --- statics (4.8) ------------------------------------------------------------------------------------

def _statics_errors(result, _ref):
    """Drift of a resting stack: absolute, in m and rad."""
    settled = result.t >= 1.0
    return {"drift_m": float(np.max(np.abs(result.x - result.x[0]))),
            "settled_drift_m": float(np.max(np.abs(result.y[settled] - result.y[settled][0]))),
            "rotation_rad": float(np.max(np.abs(result.theta)))}


# --- scenes without a closed form: judged against the native core at 1/16 of its step (finer than any run) ---

def _against_converged(make_scene, make_motion, duration, refine=16):
    def reference():
        scene, motion = make_scene(), make_motion()
        dt = dem_core.automatic_time_step(scene) / refine
        return dem_core.simulate(scene, motion, duration=duration, dt=dt, output_dt=0.005, stop_at_overturn=False)

    def errors(result, ref):
        top = np.interp(ref.t, result.t, result.theta[:, -1])
        peak = np.max(np.abs(ref.theta[:, -1]))
        return {"peak_rotation": _relative(np.max(np.abs(result.theta[:, -1])), peak),
                "rms_rotation": float(np.sqrt(np.mean((top - ref.theta[:, -1]) ** 2)) / peak),
                "overturn_mismatch": float(result.overturned != ref.overturned)}

    return reference, errors


def _el_centro(pga=None):
    return lambda: excitation.record("el_centro_1940", pga=pga)


def all_cases() -> list:
    """Every benchmark case, quick ones first."""
    rocking_ref, rocking_err = _free_rocking(HOUSNER_WIDTH, HOUSNER_HEIGHT, HOUSNER_THETA0)
    slender_theta0 = 0.2 * np.arctan(1.0 / 6.0)
    slender_ref, slender_err = _free_rocking(1.0, 6.0, slender_theta0)
    a_p, newmark_ref, newmark_err = _newmark(2.0, 0.3, 0.3)
    sine = lambda: excitation.sine_pulse(6.0, 0.25)
    cosine = lambda: excitation.cosine_pulse(2.5, 1.0)
    sine_ref, sine_err = _forced_rocking(HOUSNER_WIDTH, HOUSNER_HEIGHT, sine, 2.5)
    cosine_ref, cosine_err = _forced_rocking(1.0, 6.0, cosine, 6.0)
    record_rock_ref, record_rock_err = _forced_rocking(1.0, 6.0, _el_centro(2.75), 15.0)
    slide_ref, slide_err = _record_sliding(0.1, _el_centro(), 35.0)
    onset_ref, onset_err = _ramp_onset()
    slide_onset_ref, slide_onset_err = _sliding_onset(0.3, 0.5, 8.0)
    large_ref, large_err = _free_rocking(HOUSNER_WIDTH, HOUSNER_HEIGHT, 0.5 * np.arctan(HOUSNER_WIDTH / HOUSNER_HEIGHT))
    slender_large_ref, slender_large_err = _free_rocking(1.0, 6.0, 2.5 * slender_theta0)
    squat_theta0 = 0.3 * np.arctan(0.4)
    squat_ref, squat_err = _free_rocking(0.4, 1.0, squat_theta0)
    newmark_low, newmark_low_ref, newmark_low_err = _newmark(1.25, 0.3, 0.3)
    newmark_high, newmark_high_ref, newmark_high_err = _newmark(4.0, 0.3, 0.3)
    northridge = lambda: excitation.record("northridge_1994")
    kalamata = lambda: excitation.record("kalamata_1986")
    northridge_ref, northridge_err = _record_sliding(0.2, northridge, 30.0)
    kalamata_ref, kalamata_err = _record_sliding(0.1, kalamata, 30.0)
    sine_slender = lambda: excitation.sine_pulse(4.0, 0.6)
    sine_slender_ref, sine_slender_err = _forced_rocking(1.0, 6.0, sine_slender, 6.0)
    column_ref, column_err = _against_converged(lambda: scenes.column(8), _el_centro(), 20.0)
    colonnade = lambda: scenes.colonnade(3, 3, spacing=2.5, epistyle="b", epistyle_density=8000.0)
    mexico = lambda: excitation.record("mexico_city_1985", pga=2.5)
    colonnade_ref, colonnade_err = _against_converged(colonnade, mexico, 40.0)
    stack_ref, stack_err = _stacked_blocks()
    northridge_rocking = lambda: excitation.record("northridge_1994", pga=4.0)
    northridge_rock_ref, northridge_rock_err = _forced_rocking(1.0, 6.0, northridge_rocking, 15.0)
    below, below_ref, below_err = _slide_rock(0.85)
    above, above_ref, above_err = _slide_rock(1.25)
    housner_block = lambda: scenes.block(HOUSNER_WIDTH, HOUSNER_HEIGHT, friction=SLIDE_ROCK_MU)
    return [
        Case("free_rocking", "Free rocking of the 0.25 x 1.0 m block from 0.05236 rad (Housner 4.1, 4.2)",
             housner_scene, excitation.still, 4.0, rocking_ref, rocking_err, primary="peak_decay"),
        Case("newmark", "Sliding block under a rectangular pulse, a_p/(mu g) = 2 (Newmark 4.4)",
             lambda: scenes.block(1.0, 0.5, friction=0.3, base_width=40.0),
             lambda: excitation.rectangular_pulse(a_p, 0.3), 1.2, newmark_ref, newmark_err),
        Case("sine_pulse", "0.25 x 1.0 m block under a one-sine pulse, 6 m/s^2 for 0.25 s (rocking equation 4.3)",
             lambda: scenes.block(HOUSNER_WIDTH, HOUSNER_HEIGHT), sine, 2.5, sine_ref, sine_err),
        Case("record_sliding", "Block sliding under El Centro 1940, mu = 0.1 (rigid-plastic 4.5)",
             lambda: scenes.block(1.0, 0.5, friction=0.1, base_width=40.0), _el_centro(), 35.0, slide_ref,
             slide_err, output_dt=0.005),
        Case("statics", "8-drum column at rest for 10 s (statics 4.8)", lambda: scenes.column(8), excitation.still,
             10.0, lambda: None, _statics_errors, output_dt=0.01, primary="drift_m"),
        Case("free_rocking_slender", "Free rocking of a 1 x 6 m monolith from 0.2 alpha (Housner 4.1, 4.2)",
             lambda: scenes.block(1.0, 6.0, tilt=slender_theta0), excitation.still, 12.0, slender_ref, slender_err,
             quick=False, primary="peak_decay"),
        Case("cosine_pulse", "1 x 6 m monolith under a one-cosine pulse, 2.5 m/s^2 for 1 s (rocking equation 4.3)",
             lambda: scenes.block(1.0, 6.0), cosine, 6.0, cosine_ref, cosine_err, quick=False),
        Case("record_rocking", "1 x 6 m monolith under El Centro 1940 at 2.75 m/s^2 (rocking equation 4.3)",
             lambda: scenes.block(1.0, 6.0), _el_centro(2.75), 15.0, record_rock_ref, record_rock_err,
             output_dt=0.005, quick=False),
        Case("record_rocking_northridge", "1 x 6 m monolith under Northridge 1994 (Sylmar) at 4 m/s^2, peak "
             "0.29 alpha (rocking equation 4.3)", lambda: scenes.block(1.0, 6.0), northridge_rocking, 15.0,
             northridge_rock_ref, northridge_rock_err, output_dt=0.005, quick=False),
        Case("onset_ramp", "Rocking onset of the 1 x 6 m monolith under a 0.5 m/s^2/s ramp (4.6; criterion theta_cr/30)",
             lambda: scenes.block(ONSET_WIDTH, ONSET_HEIGHT), lambda: excitation.ramp(ONSET_RAMP_RATE), 4.5,
             onset_ref, onset_err, quick=False),
        Case("free_rocking_large", "Free rocking of the 0.25 x 1.0 m block from 0.5 alpha (Housner 4.1, 4.2)",
             lambda: scenes.block(HOUSNER_WIDTH, HOUSNER_HEIGHT, tilt=0.5 * np.arctan(HOUSNER_WIDTH / HOUSNER_HEIGHT)),
             excitation.still, 6.0, large_ref, large_err, quick=False, primary="peak_decay"),
        Case("free_rocking_slender_large", "Free rocking of the 1 x 6 m monolith from 0.5 alpha (Housner 4.1, 4.2)",
             lambda: scenes.block(1.0, 6.0, tilt=2.5 * slender_theta0), excitation.still, 14.0, slender_large_ref,
             slender_large_err, quick=False, primary="peak_decay"),
        Case("free_rocking_squat", "Free rocking of a 0.4 x 1.0 m block (alpha 0.38) from 0.3 alpha (Housner 4.1, 4.2)",
             lambda: scenes.block(0.4, 1.0, tilt=squat_theta0), excitation.still, 4.0, squat_ref, squat_err,
             quick=False, primary="peak_decay"),
        Case("newmark_low", "Sliding block under a rectangular pulse, a_p/(mu g) = 1.25 (Newmark 4.4)",
             lambda: scenes.block(1.0, 0.5, friction=0.3, base_width=40.0),
             lambda: excitation.rectangular_pulse(newmark_low, 0.3), 0.8, newmark_low_ref, newmark_low_err,
             quick=False),
        Case("newmark_high", "Sliding block under a rectangular pulse, a_p/(mu g) = 4 (Newmark 4.4)",
             lambda: scenes.block(1.0, 0.5, friction=0.3, base_width=40.0),
             lambda: excitation.rectangular_pulse(newmark_high, 0.3), 1.6, newmark_high_ref, newmark_high_err,
             quick=False),
        Case("sine_pulse_slender", "1 x 6 m monolith under a one-sine pulse, 4 m/s^2 for 0.6 s (rocking equation 4.3)",
             lambda: scenes.block(1.0, 6.0), sine_slender, 6.0, sine_slender_ref, sine_slender_err, quick=False),
        Case("sliding_northridge", "Block sliding under Northridge 1994 (Sylmar), mu = 0.2 (rigid-plastic 4.5)",
             lambda: scenes.block(1.0, 0.5, friction=0.2, base_width=40.0), northridge, 30.0, northridge_ref,
             northridge_err, output_dt=0.005, quick=False),
        Case("sliding_kalamata", "Block sliding under Kalamata 1986, mu = 0.1 (rigid-plastic 4.5)",
             lambda: scenes.block(1.0, 0.5, friction=0.1, base_width=40.0), kalamata, 30.0, kalamata_ref,
             kalamata_err, output_dt=0.005, quick=False),
        Case("sliding_onset", "Onset of sliding of a squat block, mu = 0.3, under a 0.5 m/s^2/s ramp (4.6; slip 0.1 mm)",
             lambda: scenes.block(1.0, 0.5, friction=0.3, base_width=40.0), lambda: excitation.ramp(0.5), 8.0,
             slide_onset_ref, slide_onset_err, quick=False),
        Case("slide_rock_below", f"0.25 x 1.0 m block, mu = 0.3, rectangular pulse {below:.2f} m/s^2: rocking only "
             "(0.85 x the Zhang-Makris slide-rock threshold, 4.6)", housner_block,
             lambda: excitation.rectangular_pulse(below, SLIDE_ROCK_PULSE), SLIDE_ROCK_PULSE, below_ref, below_err,
             quick=False),
        Case("slide_rock_above", f"0.25 x 1.0 m block, mu = 0.3, rectangular pulse {above:.2f} m/s^2: rocking and "
             "sliding (1.25 x the Zhang-Makris slide-rock threshold, 4.6)", housner_block,
             lambda: excitation.rectangular_pulse(above, SLIDE_ROCK_PULSE), SLIDE_ROCK_PULSE, above_ref, above_err,
             quick=False),
        Case("stacked_blocks", "Two stacked blocks (2.5 x 2.5 m under 2.0 x 5.0 m) released from 0.1 rad, up to "
             "the first impact (Psycharis 4.7)", lambda: scenes.stack(STACK_SIZES, tilt=STACK_THETA0),
             excitation.still, 0.8, stack_ref, stack_err, quick=False, primary="impact_time"),
        Case("column_record", "8-drum column under 20 s of El Centro 1940 (against the converged native core)",
             lambda: scenes.column(8), _el_centro(), 20.0, column_ref, column_err, output_dt=0.005, quick=False),
        Case("colonnade_mexico", "3-column colonnade, epistyles (b) of 8000 kg/m^3, under Mexico City 1985 at "
             "2.5 m/s^2 (against the converged native core)", colonnade, mexico, 40.0, colonnade_ref,
             colonnade_err, output_dt=0.005, quick=False),
    ]
