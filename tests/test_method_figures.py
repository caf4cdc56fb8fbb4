"""The figures docs/method.md quotes, each read from its source: a figure that drifts from its source fails here,
naming both.  Timings are left out (they are the machine's, not the code's); docs/studies.md quotes no result, only
its studies' inputs and the computing times their READMEs state.

From the comparison report (``reports/``): the explicit core's rocking ensemble (``scoreboard.csv``), the cases'
errors (``results.csv``: the Housner block at 1e-3 s, Moreau-Jean's free rocking as its step shrinks, the
overlap-area law's onset, the sliding block's travel, ``impact_slip``), the native core's overturns in the rocking
ensemble (``ensembles.csv``) and Moreau-Jean's step on the column ensemble (``column_ensemble.csv``).  From the code:
the band of the converged free rocking (comparisons/cases/catalogue.py) and the coverage tests/test_nested_fragility.py
asks of the bootstrap.  From the README, which tests/test_quoted_figures.py reads from the run: PyBullet's joint
slips.  The rest from runs made here, a few seconds each at most: the rocking reference's overturns and Moreau-Jean's
blocks run on past alpha (section 3), the squat block against Housner's period (4.1), the impacts of
tests/test_restitution.py and the heavier dashpots (1.3, 1.8), the explicit core's steps per impact (1.7), and the
bundled default's joints, pair lists and solves and the colonnades' solves (1.8)."""

import argparse
import re
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from test_quoted_figures import _usual, _words, case_error, percent
from test_restitution import lifted, rebounds, run_fine

import dem_core
from comparisons.cases import catalogue as cases
from comparisons.cases.measures import peaks_between_crossings
from comparisons.cases.strong_motion import strong_motion
from comparisons.harness.column_ensemble import summarise_pairs
from comparisons.report.scoreboard import usual_steps
from dem_core import excitation, scenes
from dem_core.engine.contact import EXPLICIT_LEAST_RESTITUTION, damping_ratio_for_restitution
from dem_core.engine.geometry import rectangle, transform

REPOSITORY = Path(__file__).resolve().parents[1]
REPORTS = REPOSITORY / "reports"
#: the explicit core's steps from 0.95 to 1.05 times the automatic one, over which section 1.7 gives the error
STEP_FACTORS = np.linspace(0.95, 1.05, 11)
#: the free-rocking cases whose convergence under Moreau-Jean section 1.8 quotes
FREE_ROCKING = ("free_rocking", "free_rocking_slender", "free_rocking_large", "free_rocking_slender_large",
                "free_rocking_squat")


@pytest.fixture(scope="module")
def method() -> str:
    return _words((REPOSITORY / "docs" / "method.md").read_text(encoding="utf-8"))


def _said(method: str, claims: list) -> None:
    """Each ``(what, text)`` of ``claims`` in method.md, or a failure naming every one that is not."""
    missing = [f"{what}: docs/method.md should say {text!r}" for what, text in claims if _words(text) not in method]
    assert missing == [], "\n".join(missing)


def _kept(share: float) -> str:
    """A share as a percentage of two significant figures, a trailing zero kept (0.20%)."""
    return f"{100 * share:#.2g}%"


def _exponent(x: float) -> str:
    """``x`` to two significant figures in the docs' exponent form (3.2e-4)."""
    mantissa, power = f"{x:.1e}".split("e")
    return f"{mantissa}e{int(power)}"


def _usual_error(results, case: str, engine: str, metric: str) -> float:
    return case_error(results, case, engine, usual_steps([engine])[engine], metric)


def test_the_figures_method_md_quotes_from_the_report_are_the_reports(method, results):
    board = pd.read_csv(REPORTS / "scoreboard.csv").set_index("engine")
    housner = [abs(_usual_error(results, "free_rocking", "dem-moreau", m)) for m in ("quarter_period", "peak_decay")]
    onset = _usual_error(results, "onset_ramp", "dem-overlap", "onset_acceleration")
    travel = {e: abs(_usual_error(results, "record_sliding", e, "slip_travel")) for e in cases.ENGINES}
    peers = max(travel[e] for e in ("dem", "dem-moreau", "pymunk", "pybullet"))
    converged = max(bands["dem-moreau"] for bands in cases.MOREAU_CONVERGED_BANDS.values())
    integrators = max(travel["dem"], travel["dem-moreau"])
    explicit = percent(board.loc["dem", "rocking_median"])
    _said(method, [
        ("the explicit core's rocking ensemble (scoreboard.csv)",
         f"in the comparison report's ensemble of the bundled records it is {explicit}"),
        ("the overlap-area law's onset (results.csv)", f"rocking onset {percent(onset, 1)} at the default K_n"),
        ("the Housner block under Moreau-Jean at 1e-3 s (results.csv)",
         (f"At 1e-3 s the Housner block's free-rocking quarter period is within {percent(housner[0])} of the rocking "
          f"equation and its peaks after five impacts within {percent(housner[1])} (reports/results.csv)")),
        ("Moreau-Jean's converged free rocking (catalogue.MOREAU_CONVERGED_BANDS)",
         (f"every free-rocking case's error falls at each refinement and is within {percent(converged)} of the "
          "rocking equation at 1e-4 s")),
        ("the sliding block's travel (results.csv)",
         (f"within {percent(peers)} of the rigid-plastic block's travel in every engine but the overlap-area law "
          f"({percent(travel['dem-overlap'])}) and MuJoCo ({percent(travel['mujoco'])};")),
        ("the two integrators on the sliding block's travel (results.csv)",
         f"the rigid-plastic block's travel under El Centro within {percent(integrators)}"),
    ])


def test_moreau_jeans_free_rocking_converges_as_the_report_measures_it(results):
    """Section 1.8's 'every free-rocking case's error falls at each refinement and is within the band at 1e-4 s',
    on results.csv's ladder of Moreau-Jean's steps."""
    moreau = results[(results.engine == "dem-moreau") & (results.settings == "{}")]
    for name in FREE_ROCKING:
        for metric, bands in cases.MOREAU_CONVERGED_BANDS.items():
            rows = moreau[(moreau.case == name) & (moreau.metric == metric)].sort_values("dt", ascending=False)
            sizes = np.abs(rows.error.to_numpy())
            assert np.all(np.diff(sizes) < 0), f"results.csv: {name}, {metric} does not fall with the step: {sizes}"
            assert rows.dt.iloc[-1] == pytest.approx(1e-4) and sizes[-1] <= bands["dem-moreau"], (name, metric, sizes)


def test_moreau_jeans_step_on_the_column_ensemble_is_the_reports(method):
    table = pd.read_csv(REPORTS / "column_ensemble.csv")
    pairs = summarise_pairs(table).set_index(["run", "against"])
    coarse, middle = (pairs.loc[(f"dem-moreau {step} s", "dem-moreau 2.5e-4 s")] for step in ("1e-3", "5e-4"))
    members = table.groupby("run").size()
    assert members.nunique() == 1, f"column_ensemble.csv: the configurations ran different members: {members}"
    assert coarse.overturn_agreement == middle.overturn_agreement == 1.0, "method.md: 'every run agrees on overturning'"
    _said(method, [("the column ensemble (column_ensemble.csv)", (
        f"{members.iloc[0]} runs, {int(coarse.compared)} of them standing and rocking in both) the typical change of "
        f"the top drum's peak from 1e-3 to 2.5e-4 s is {_kept(coarse.typical_difference)} (bootstrap 90% interval over "
        f"the runs {_kept(coarse.interval_low)} to {_kept(coarse.interval_high)}; the runs are chaotic), from 5e-4 to "
        f"2.5e-4 s {_kept(middle.typical_difference)}, and every run agrees on overturning"))])


def test_the_bootstrap_coverage_method_md_quotes_is_the_tests(method):
    """Section 3's coverage of the bootstrap by record: the suites and the least count of them that
    tests/test_nested_fragility.py asserts."""
    from test_nested_fragility import COVERAGE_SUITES as suites, COVERED_AT_LEAST as least

    _said(method, [("the bootstrap's coverage (tests/test_nested_fragility.py)",
                    f"on {suites} suites of 10 records from a known lognormal, the band drawn by record covers its "
                    f"median in at least {least}, the band drawn by run in fewer")])


def test_the_squat_blocks_period_against_housners_formula(method):
    """Section 4.1: the squat block's quarter period by the rocking equation (the case's reference) against
    Housner's linearised formula."""
    from comparisons.references import analytical

    case = cases.case("free_rocking_squat")
    block = analytical.RockingBlock.from_size(0.4, 1.0)
    longer = case.reference()["quarter"] / (0.25 * analytical.housner_period(block, 0.3 * block.alpha)) - 1.0
    _said(method, [("the squat block's quarter period", (f"for the squat 0.4 x 1.0 m block its quarter period is "
                                                         f"{percent(longer, 1)} longer than the formula's"))])


@pytest.mark.slow
def test_the_rocking_references_overturns_are_the_ones_method_md_counts(method):
    """Section 3: the rocking reference at alpha and at pi/2 on the report's rocking ensemble and on
    ``python -m comparisons overturn-rule``'s wider one, with that command's defaults."""
    from comparisons.benchmarks import overturn_rule
    from comparisons.harness.ensembles import Ensemble, ensemble

    options = argparse.ArgumentParser()
    overturn_rule.arguments(options)
    args = options.parse_args([])
    wide = Ensemble(name="overturn_rule_wide", title="", kind="rocking", blocks=overturn_rule.WIDE_BLOCKS,
                    scales=tuple(np.round(np.linspace(1.2, args.highest, args.scales), 3)))
    (members, passed, back), (wide_members, wide_passed, wide_back) = (
        overturn_rule.reference_counts(e) for e in (ensemble("rocking_records"), wide))
    blocks = ", ".join(f"{w:g} x {h:g}" for w, h in overturn_rule.WIDE_BLOCKS[:-1])
    last = "{:g} x {:g}".format(*overturn_rule.WIDE_BLOCKS[-1])
    _said(method, [("the rocking reference's overturns (overturn_rule.reference_counts)", (
        f"passes alpha in {passed} of the {members} members and comes back in {back or 'none'}; on {wide_members} "
        f"members (the {blocks} and {last} m blocks, the four records at {args.scales} amplitudes from 1.2 to "
        f"{args.highest:g} g tan(alpha)) it passes alpha in {wide_passed} and comes back in {wide_back} "
        f"({percent(wide_back / wide_passed)})"))])


def test_moreau_jeans_blocks_that_pass_alpha_do_not_come_back(method, ensembles):
    """Section 3: the native core's overturns in the report's rocking ensemble (ensembles.csv, each integrator at
    its usual step), and Moreau-Jean's run on to the end of their records: none ends upright.  (The explicit core's
    take half a minute; ``python -m comparisons overturn-rule`` runs them.)"""
    from comparisons.harness.ensembles import ensemble

    report = ensemble("rocking_records")
    rows = {engine: _usual(ensembles[ensembles.ensemble == report.name], engine) for engine in ("dem", "dem-moreau")}
    over = {engine: mine[mine.overturned.astype(bool)] for engine, mine in rows.items()}
    toppled = {(row.block, row.record, round(row.scale, 6)) for row in over["dem-moreau"].itertuples()}
    run_on = [m for m in report.members() if (m.block_label, m.record, round(m.scale, 6)) in toppled]
    assert len(run_on) == len(toppled), "ensembles.csv's members are not the rocking ensemble's"
    upright = []
    for m in run_on:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = dem_core.simulate(report.scene(m.block), strong_motion(m.record, m.pga), m.duration,
                                       stop_at_overturn=False, integrator="moreau")
        assert result.overturned, (m, "Moreau-Jean's run on does not overturn where ensembles.csv's does")
        if abs(result.theta[-1, 0]) < result.critical_angle[0]:
            upright.append(m)
    assert upright == [], f"Moreau-Jean's blocks past alpha that end upright: {upright}"
    _said(method, [("the native core's overturns (ensembles.csv)", (
        f"none of the native core's blocks that pass alpha in the report's ensemble ({len(over['dem'])} explicit, "
        f"{len(over['dem-moreau'])} Moreau-Jean) ends upright"))])


def _rocking_ratio(integrator: str, e: float) -> float:
    """``omega+ / omega-`` of the 1 x 6 m block's first impact after a release from 0.1 rad, measured as
    tests/test_restitution.py measures it (straight lines over 5 ms before and 3 ms after the impact)."""
    result = run_fine(scenes.block(1.0, 6.0, tilt=0.1, contact=dem_core.ContactParameters(restitution=e)),
                      integrator, 1.2)
    t, theta = result.t, result.theta[:, 0]
    impact = t[np.argmax(theta <= 0.0)]
    omega = np.gradient(theta, t)
    before = (t > impact - 0.006) & (t < impact - 0.001)
    after = (t > impact + 0.002) & (t < impact + 0.005)
    return (np.polyval(np.polyfit(t[after], omega[after], 1), impact)
            / np.polyval(np.polyfit(t[before], omega[before], 1), impact))


def _explicit_contact(e: float) -> dem_core.ContactParameters:
    """A restitution below the explicit core's least is given by its damping ratio."""
    if e < EXPLICIT_LEAST_RESTITUTION:
        return dem_core.ContactParameters(damping_ratio=damping_ratio_for_restitution(e))
    return dem_core.ContactParameters(restitution=e)


@pytest.mark.slow
def test_the_impacts_method_md_quotes_are_the_rigid_answers_measured(method):
    """Section 1.8's impacts, run as tests/test_restitution.py runs them: a corner impact, a rocking impact against
    ``1 - 1.5 (1 + e) sin^2(alpha)`` and two drums dropped flat in the explicit core."""
    corner = dem_core.Block("block", transform(rectangle(1.0, 1.0, -0.5, -0.5), np.pi / 4, (0.0, np.sqrt(0.5))),
                            angle=np.pi / 4)
    worst = 0.0
    for integrator in ("moreau", "explicit"):
        for e in (0.0, 0.1, 0.5):
            scene = scenes.block(1.0, 1.0).replace(blocks=(corner,), contact=dem_core.ContactParameters(restitution=e),
                                                   allow_free_blocks=True)
            result = run_fine(lifted(scene, 0.01), integrator, 0.1)
            given = e if integrator == "moreau" else max(e, EXPLICIT_LEAST_RESTITUTION)
            worst = max(worst, abs(rebounds(result.y, result.t)[0] - given))
    sin2 = 1.0 / 37.0  # the 1 x 6 m block's sin^2(alpha)

    def rule(e):
        return 1.0 - 1.5 * (1.0 + e) * sin2

    moreau = max(abs(_rocking_ratio("moreau", e) - rule(e)) for e in (0.0, 0.2, 0.5))
    least = abs(_rocking_ratio("explicit", 0.0) - rule(EXPLICIT_LEAST_RESTITUTION))
    above = {e: _rocking_ratio("explicit", e) for e in (0.1, 0.2, 0.5)}
    misses = [abs(ratio / rule(e) - 1.0) for e, ratio in above.items()]
    drops = []
    for e in (0.2, 0.05, 0.01):
        drums = scenes.stack(((1.0, 0.75), (1.0, 0.75)), contact=_explicit_contact(e))
        result = run_fine(lifted(drums, 0.005), "explicit", 0.05)
        lower, upper = rebounds(result.y, result.t) / e
        drops.append(f"{upper:.1f} `e` and {lower:.1f} `e` at {e:g}")
    _said(method, [
        ("a corner impact", (f"rebounds at `e` in both, within {worst:.2g} for `e` = 0 (the explicit core's "
                             f"{EXPLICIT_LEAST_RESTITUTION:g}), 0.1 and 0.5")),
        ("a rocking impact", (
            f"Moreau-Jean gives it within {_exponent(moreau)} at `e` = 0, 0.2 and 0.5, the explicit core within "
            f"{_exponent(least)} at its least restitution ({EXPLICIT_LEAST_RESTITUTION:g}). Above it the explicit core "
            f"misses it by {percent(min(misses), 1)} to {percent(max(misses), 1)} (the 1 x 6 m block: "
            + ", ".join(f"{r:.3f}" for r in above.values()) + " at `e` = 0.1, 0.2, 0.5 against "
            + ", ".join(f"{rule(e):.3f}" for e in above) + ")")),
        ("two drums dropped flat", "(" + ", ".join(drops) + " given by a damping ratio)"),
    ])


def test_heavier_dashpots_are_no_closer_to_the_rigid_answers(method):
    """Section 1.3: the explicit core at a restitution of 0.01 (by its damping ratio) against its least, and
    Moreau-Jean: the Housner block's slip on its base under the sine pulse, and the squat block's fifth peak."""
    heavy = _explicit_contact(0.01)
    runs = {"heavy": (heavy, "explicit"), "least": (dem_core.ContactParameters(), "explicit"),
            "moreau": (dem_core.ContactParameters(), "moreau")}
    slips = {}
    for label, (contact, integrator) in runs.items():
        result = dem_core.simulate(scenes.block(0.25, 1.0, contact=contact), excitation.sine_pulse(6.0, 0.25), 2.5,
                                   integrator=integrator)
        slips[label] = f"{1e3 * result.interface_slip[('base', 'block')]:#.2g}"
    squat = cases.case("free_rocking_squat")
    reference = squat.reference()["peaks"]
    fifth = {}
    for label, contact in (("heavy", heavy), ("least", dem_core.ContactParameters())):
        result = dem_core.simulate(squat.scene().replace(contact=contact), squat.motion(), squat.duration,
                                   output_dt=squat.output_dt, integrator="explicit")
        fifth[label] = abs(peaks_between_crossings(result.theta[:, 0], 6)[-1] / reference[-1] - 1.0)
    _said(method, [("the heavier dashpots", (
        f"at 0.01 (`zeta = {heavy.damping_ratio:.2g}`, a quarter of critical damping's step) a 0.25 x 1 m block under "
        f"a 6 m/s^2 sine pulse slips {slips['heavy']} mm on its base (section 3) against {slips['least']} mm at "
        f"{EXPLICIT_LEAST_RESTITUTION:g} and {slips['moreau']} mm in Moreau-Jean (rigid theory: none), and the squat "
        f"free-rocking block's fifth peak is {percent(fifth['heavy'])} off against {percent(fifth['least'], 1)}"))])


def test_the_explicit_cores_steps_per_impact_method_md_quotes(method):
    """Section 1.7: the Housner block's fifth peak of free rocking at 15 and 20 steps per shortest impact, each over
    :data:`STEP_FACTORS` times that step (where the impact sets the step, not the stability limit), and 10 steps per
    impact beyond the stability limit."""
    from dem_core.simulation import DEFAULT_STEPS_PER_IMPACT, set_up_scene

    case = cases.case("free_rocking")
    reference = case.reference()["peaks"]
    set_up = set_up_scene(case.scene(), integrator="explicit")
    assert DEFAULT_STEPS_PER_IMPACT == 15 and set_up.impact / 10 > set_up.limit
    ranges = []
    for steps in (15, 20):
        errors = []
        for factor in STEP_FACTORS:
            result = dem_core.simulate(case.scene(), case.motion(), case.duration, output_dt=case.output_dt,
                                       integrator="explicit", steps_per_impact=steps / factor)
            assert result.dt == pytest.approx(factor * set_up.impact / steps, rel=1e-12), "the limit set the step"
            errors.append(abs(peaks_between_crossings(result.theta[:, 0], 6)[-1] / reference[-1] - 1.0))
        ranges.append(f"{100 * min(errors):.2g}-{percent(max(errors))}")
    _said(method, [("the steps per impact", (
        f"the 0.25 x 1 m block's fifth peak after free rocking is {ranges[0]} off at 15 steps per impact and "
        f"{ranges[1]} at 20, over eleven steps from {STEP_FACTORS[0]:g} to {STEP_FACTORS[-1]:g} times the automatic "
        "one; 10 steps per impact would pass its stability limit"))])


def test_the_explicit_cores_joint_slip_in_impact_slip(method, results):
    """Section 1.12: case ``impact_slip``'s joint slip in the explicit core, the report's (results.csv) and at ten
    times K_n, run here."""
    case = cases.case("impact_slip")
    scene = case.scene()
    stiff = dem_core.simulate(scene.replace(contact=dem_core.contact.stiffer(scene.contact, 10.0)), case.motion(),
                              case.duration, output_dt=case.output_dt, integrator="explicit")
    report = _usual_error(results, "impact_slip", "dem", "joint_slip_m")
    said = (f"case `impact_slip`'s two-drum column: {1e3 * report:.2g} mm in the report, "
            f"{1e3 * case.errors(stiff, None)['joint_slip_m']:.2g} mm at ten times K_n")
    _said(method, [("the explicit core's joint slip (results.csv, and a run)", said)])


def _unconverged_before(scene, motion, duration: float, step: int, window: int) -> int:
    """How many of the ``window`` steps before step ``step`` of a Moreau-Jean run ended unconverged."""
    from dem_core.engine.state import UNCONVERGED

    run = dem_core.Simulation(scene, motion, duration, integrator="moreau")
    run.advance(step - window)
    before = int(run.state.counters[UNCONVERGED])
    run.advance(window)
    return int(run.state.counters[UNCONVERGED]) - before


@pytest.mark.slow
def test_the_bundled_defaults_joints_that_method_md_quotes(method):
    """Section 1.8: the 8-drum column under 20 s of El Centro in Moreau-Jean: its largest joint's slip per
    restitution; at e = 0, where its joints' slip comes from (each joint's largest step, and the steps before that
    ended unconverged) and how deep its bottom drum's pivot goes into the base; its slips at finer steps.  PyBullet's
    largest slip as the README quotes it (tests/test_quoted_figures.py runs it)."""
    from comparisons.benchmarks.restitution import joint_slips

    largest = [1e3 * max(joint_slips(dem_core.ContactParameters(restitution=e), "moreau", 20.0)[1])
               for e in (0.0, 0.1, 0.2)]
    scene, motion = scenes.column(8), excitation.record("el_centro_1940")
    result = dem_core.simulate(scene, motion, 20.0, output_dt=1e-3, integrator="moreau")
    history = 1e3 * result.slip_history
    slipped = np.flatnonzero(history[-1] > 0.5 * history[-1].max())
    steps = np.diff(history, axis=0)
    jumps = np.argmax(steps[:, slipped], axis=0) + 1  # the output (a step) whose interface stage saw the jump
    assert np.all(steps[jumps - 1, slipped] > 0.9 * history[-1, slipped]), "a joint slipped over more than one step"
    assert np.all(np.diff(np.sort(jumps)) == 1), f"the joints' jumps are not in successive steps: {result.t[jumps]}"
    first = int(np.min(jumps))
    unconverged = _unconverged_before(scene, motion, 20.0, first - 1, 5)  # the motion of step first - 1 is the jump
    words = {1: "one", 2: "two", 3: "three", 4: "four"}
    drum = scene.blocks[0]
    corners = drum.vertices - drum.centroid
    lowest = min(np.min(np.sin(th) * corners[:, 0] + np.cos(th) * corners[:, 1]) + y
                 for y, th in zip(result.y[:, 0] - result.base_y, result.theta[:, 0]))
    depth = scene.base.vertices[:, 1].max() - lowest
    finer = max(1e3 * max(dem_core.simulate(scene, motion, 20.0, dt=dt, integrator="moreau").interface_slip.values())
                for dt in (5e-4, 2.5e-4, 1e-4))
    readme = _words((REPOSITORY / "README.md").read_text(encoding="utf-8"))
    pybullet, = re.findall(r"PyBullet's, also rigid, at most ([0-9.]+) mm", readme)
    _said(method, [
        ("Moreau-Jean's largest joint per restitution", (
            f"At 1e-3 s Moreau-Jean's largest joint slips {largest[0]:.3f}, {largest[1]:.3f} and {largest[2]:.3f} mm "
            "where a restitution of 0, 0.1 and 0.2 is asked")),
        ("where its slips come from, and at finer steps", (
            f"its {history[-1, slipped].min():.2f} to {history[-1, slipped].max():.2f} mm come from "
            f"{words[len(jumps)]} successive steps of 1e-3 s at t = {result.t[first]:.2f} s, just after "
            f"{words[unconverged]} steps whose solve ended unconverged, and at 5e-4, 2.5e-4 and 1e-4 s no joint slips "
            f"more than {finer:.2g} mm over the 20 s; PyBullet's, also rigid, slip at most {pybullet} mm")),
        ("the pivot's depth in the base",
         f"under 20 s of El Centro the direct solve leaves it within {1e6 * depth:.1g} um"),
    ])


def test_the_bundled_defaults_pair_lists_and_solves_that_method_md_quotes(method):
    """Section 1.8: the bundled default run (the 8-drum column under El Centro as recorded) and the column at rest
    for 20 s: the pair lists made and the direct passes a step; Gauss-Seidel alone on the column's first second at
    rest, with sweeps enough to meet its tolerance."""
    from dem_core.cli import default_scene_path
    from dem_core.cli.single_run import simulated
    from dem_core.inputs.scene_file import load

    spec = load(default_scene_path())
    record, _ = simulated(spec, dict(spec.simulation))
    rest = dem_core.simulate(scenes.column(8), None, 20.0, integrator="moreau").info
    alone = dem_core.Simulation(scenes.column(8), None, 1.0, integrator="moreau")
    alone.settings = alone.settings.replace(status_passes=0, max_sweeps=20000)
    alone.advance()
    swept = alone.result().info
    assert record.dt == 1e-3 and rest["sweeps_per_step"] == 0.0 and swept["unconverged_steps"] == 0
    info = record.info
    _said(method, [
        ("the bundled default's pair lists", (
            f"on the bundled default (the 8-drum column under El Centro as recorded, {record.t[-1]:.1f} s at 1e-3 s) "
            f"Moreau-Jean made the list {info['pair_lists']} times in {info['steps']:,} steps, and at rest "
            f"{'once' if rest['pair_lists'] == 1 else str(rest['pair_lists']) + ' times'} in 20 s")),
        ("its direct passes", (f"({rest['status_passes_per_step']:.1f} passes a step at rest, "
                               f"{info['status_passes_per_step']:.3f} under the record, "
                               "no Gauss-Seidel sweep at rest)")),
        ("Gauss-Seidel alone at rest", (f"on the 8-drum column, over its first second at rest, it takes "
                                        f"{swept['sweeps_per_step']:.0f} sweeps a step to meet the tolerance")),
    ])


@pytest.mark.slow
def test_the_colonnades_solves_that_method_md_quotes(method):
    """Section 1.8: a five-column and a two-tier colonnade under 10 s of a 1 Hz harmonic of 1.5 m/s^2, by the
    direct solve (the steps it leaves to Gauss-Seidel) and by Gauss-Seidel alone (the steps left unconverged)."""
    from dem_core.engine._active_set import HALF_BAND

    motion = excitation.harmonic(pga=1.5, frequency=1.0)
    direct, alone = [], []
    for scene in (scenes.colonnade(5), scenes.two_tier_colonnade()):
        direct.append(dem_core.simulate(scene, motion, 10.0, integrator="moreau", stop_at_overturn=False).info)
        run = dem_core.Simulation(scene, motion, 10.0, integrator="moreau", stop_at_overturn=False)
        run.settings = run.settings.replace(status_passes=0)
        run.advance()
        alone.append(run.result().info)
    assert {info["steps"] for info in direct + alone} == {10_000}
    _said(method, [("the colonnades' solves", (
        f"A half-band above {HALF_BAND} (an epistyle on more than sixteen columns), or a vanishing pivot block, leaves "
        "the step to Gauss-Seidel alone, and 50 sweeps a step leave a wide colonnade's steps almost all unconverged: "
        f"under 10 s of a 1 Hz harmonic of 1.5 m/s^2, Gauss-Seidel alone leaves {alone[0]['unconverged_steps']:,} of "
        f"the 10,000 steps of a five-column colonnade unconverged and {alone[1]['unconverged_steps']:,} of a two-tier "
        f"colonnade's, where the direct solve leaves {direct[0]['status_fallbacks']} and "
        f"{direct[1]['status_fallbacks']} of them to Gauss-Seidel"))])
