"""The report's words: plain column headers, metric names, and the glossary at the foot of the page."""

from comparisons.cases.case import ACCURACY, EXACT_ABSOLUTE, EXACT_RELATIVE
from comparisons.harness.consensus import CONVERGED, NO_REFERENCE_SPREAD
from comparisons.harness.ensembles import ROCKING_FLOOR, SLIDING_FLOOR
from dem_core.engine.contact import EXPLICIT_LEAST_RESTITUTION

#: table columns as the page heads them
HEADERS = {
    "engine": "Engine",
    "metric": "Measure",
    "best_error": "Smallest |error|",
    "best_step": "at step",
    "best_wall_s": "its run time (s)",
    "fastest_within_10pct": "Run time to reach 10% (s)",
    "fastest_within_3pct": "Run time to reach 3% (s)",
    "fastest_within_1pct": "Run time to reach 1% (s)",
    "order": "Order of convergence in dt",
    "usual_error": "|Error| at the usual step",
    "band": "Band at the usual step",
    "within_band": "Within its band",
    "step": "Step",
    "dt": "dt (s)",
    "members": "Runs",
    "judged_on_peak": "Runs judged on the peak",
    "median_error": "Median |peak error|",
    "p90_error": "90th percentile |peak error|",
    "overturn_agreement": "Agrees on overturning",
    "reference_overturns": "Reference overturns in",
    "median_wall_time_s": "Median run time (s)",
    "stopped": "Runs stopped unstable",
    "points": "Points",
    "agreement": "Agrees with the reference",
    "columns": "Columns",
    "boundary_within_3pct": "Columns with the boundary within 3%",
    "boundary_within_10pct": "within 10%",
    "status": "Outcome",
    "message": "Engine's message",
    "test": "Stress test",
    "setting": "Setting",
    "value": "Value",
    "wall_time_s": "Run time (s)",
    "reference": "Consensus",
    "reference_uncertainty": "Its uncertainty (relative)",
    "reference_members": "Engines in it",
    "no_reference": "Why no reference",
    "finest": "Finest answer",
    "next": "Next-finest answer",
    "converged": "Converged",
    "run": "Engine and step",
    "against": "Against",
    "typical_difference": "Typical difference of the top drum's peak",
    "interval_low": "90% interval from",
    "interval_high": "to",
    "p90_difference": "90th percentile",
    "compared": "Runs compared",
    "overturned": "Overturned in",
    "ns_per_block_step": "ns per block-step",
    "time_vs_pymunk": "Time against pymunk's",
}

#: metrics as the page names them
METRICS = {
    "quarter_period": "time to the first impact (a quarter period)",
    "peak_decay": "worst peak after impacts 1 to 5",
    "max_slip": "largest slip",
    "residual_slip": "slip at the end (relative to the largest)",
    "rms_slip": "RMS slip history (relative to the largest)",
    "slip_travel": "the joint's slip as every engine's result measures it, its travel back and forth (relative to "
                   "the rigid-plastic block's)",
    "joint_slip_m": "the largest slip of any joint, measured on the blocks' motion (m)",
    "peak_rotation": "peak rotation",
    "rms_rotation": "RMS rotation history (relative to the peak)",
    "overturn_mismatch": "whether it overturns (1 where it and the reference disagree)",
    "mode_mismatch": "the motion that starts: rest, rocking, sliding or slide-rock (1 where it and the reference "
                     "disagree)",
    "onset_acceleration": "ground acceleration at the onset",
    "impact_time": "time of the first impact",
    "rms_lower": "RMS rotation of the lower block (relative to the release angle)",
    "rms_upper": "RMS rotation of the upper block (relative to the release angle)",
    "drift_m": "horizontal drift (m)",
    "settled_drift_m": "vertical drift after the first second (m)",
    "rotation_rad": "largest rotation (rad)",
    "horizontal_drift_m": "horizontal drift (m)",
    "potential_energy_change_J": "change of potential energy after the first second (J)",
    "overturn_time_s": "time of the first overturn (s)",
    "dt_s": "automatic time step (s)",
    "none": "(run stopped)",
}

#: metrics in the few words of an axis label or a figure's tile
AXIS_NAMES = {
    "quarter_period": "quarter period",
    "peak_decay": "peak after impacts",
    "max_slip": "largest slip",
    "residual_slip": "final slip",
    "rms_slip": "RMS slip",
    "slip_travel": "slip travel",
    "joint_slip_m": "joint slip (m)",
    "peak_rotation": "peak rotation",
    "rms_rotation": "RMS rotation",
    "onset_acceleration": "onset acceleration",
    "impact_time": "first impact time",
    "rms_lower": "RMS rotation, lower block",
    "rms_upper": "RMS rotation, upper block",
    "drift_m": "horizontal drift (m)",
    "settled_drift_m": "vertical drift (m)",
    "rotation_rad": "largest rotation (rad)",
    "horizontal_drift_m": "horizontal drift (m)",
    "potential_energy_change_J": "potential energy change (J)",
    "overturn_time_s": "overturn time (s)",
    "dt_s": "automatic dt (s)",
}


def glossary() -> list:
    """``(term, explanation)`` pairs, in the order the page lists them."""
    return [
        ("auto/N",
         "a step of the native core: the step dem_core.simulate picks when given none (for the explicit core the "
         "smaller of 0.8 of the stability limit of its contacts and a fifteenth of the shortest impact; for "
         "Moreau-Jean 1e-3 s or less) divided by N. auto/1 is what a user gets; auto/4 is four times finer."),
        ("auto/1, 100 x K_n",
         "the native core at its automatic step with a contact 100 times stiffer than its law's default "
         "K_n (2e11 N/m^2 for the corner law, 2e10 for the overlap-area law; the step shrinks as K_n^-1/2)."),
        ("0.001 (a step in s)", "a fixed step of pymunk, PyBullet or MuJoCo; 1e-3 s is their usual one."),
        ("dem, dem-overlap",
         "the native core's explicit integrator with its default corner contact law (its dashpots at their "
         f"least restitution, {EXPLICIT_LEAST_RESTITUTION:g}, for the plastic impacts the scenes ask), and with "
         "the thesis' overlap-area law (the same scene with the law's default contact parameters)."),
        ("dem-moreau",
         "the native core's default integrator, Moreau-Jean (docs/method.md 1.8): the corner law's contact points "
         "as rigid unilateral constraints with Coulomb friction, solved at the velocity level; its automatic step "
         "is 1e-3 s or less where the motion or the scene is faster, and auto/N divides it. It has no K_n: its "
         "finest run on the multi-block scenes is auto/4."),
        ("iterations",
         "solver settings of pymunk (30 instead of 10), PyBullet and MuJoCo (200 instead of 50 and 100), tried "
         "at 1e-3 s."),
        ("|error|", "relative to the reference and written in percent on this page and in its figures, unless the "
         "measure names a unit (m, rad, J); results.csv keeps fractions (0.01 is 1%)."),
        ("exact",
         f"a relative error below {EXACT_RELATIVE:g} or an absolute one below {EXACT_ABSOLUTE:g} m or rad: below "
         "the accuracy of the references and of round-off, so such errors are not ranked."),
        ("Run time to reach 3%",
         "the wall time of the fastest run of that engine whose |error| is 3% or less (any step or setting): how "
         "long it takes to be that accurate. Not a step; blank if no run got there."),
        ("Order of convergence in dt",
         "the slope of log |error| against log dt over an engine's default-settings runs: 1 for a first-order "
         "method, 2 for second order; near 0 where the error does not come from the step (a bias of the contact "
         "model)."),
        ("Band at the usual step",
         "the |error| the tests allow that engine at its usual step (comparisons/cases/catalogue.py, declared once for "
         "tests and report)."),
        ("Right",
         f"an engine whose run comes within the case's accuracy ({ACCURACY:.0%} on relative measures unless the "
         "case says otherwise) or within the reference's own uncertainty where that is larger, and agrees on every "
         "mismatch measure."),
        ("No reference",
         "a scene judged by consensus where the consensus cannot be formed for some engine that ran it (too few "
         "other engines converged, they disagree about overturning, or they spread too far): no engine is called "
         "right or fastest on it, and the scoreboard leaves it out."),
        ("Consensus",
         f"the reference of a scene without a closed form: the median of the finest answers of the engines whose "
         f"finest and next-finest runs agree within {CONVERGED:.0%}, leaving out the engine judged (and, for the "
         f"native core, all its variants). Its uncertainty is half the range of those engines' finest and "
         f"next-finest answers; no reference exists when it exceeds {NO_REFERENCE_SPREAD:.0%}, when fewer than "
         "two other engines converged, or when they disagree about overturning."),
        ("Ensemble",
         "every bundled record's strong motion at 10 amplitudes from 1.2 to 3 times the threshold (g tan alpha "
         "for rocking, mu g for sliding) on two blocks, against the rocking equation or the rigid-plastic "
         "integration, run by run."),
        ("Peak error",
         f"(engine's peak - reference's peak) / reference's peak, with the reference's peak taken as at least "
         f"alpha/{1 / ROCKING_FLOOR:.0f} for rocking (docs/method.md's rocking criterion) and "
         f"{SLIDING_FLOOR * 1e3:g} mm for sliding; an overturned engine's peak is alpha. Runs whose reference "
         "overturns count only in the agreement on overturning."),
        ("Overturning spectrum",
         "which pulses overturn the block, against the pulse's dimensionless length (p t_d, omega_p/p) and "
         "amplitude a_p/(g tan alpha); points 3% and 10% either side of each boundary of the rocking equation "
         "and inside each band between two."),
        ("Stopped",
         "the engine raised its own stability error (the native core's energy, speed and overlap checks, or a "
         "block leaving the scene)."),
        ("Silently wrong",
         "a stress-test run that finished without a warning but is 10% or more off its reference (only error "
         "measures are judged; a time step is a setting, not an error)."),
    ]
