"""What a restoration changes: the 8-drum column (the bundled default scene) as built, with oak poles at every
joint, and with titanium bars at every joint or at the top joint only (docs/method.md 1.12; the presets of
dem_core/inputs/connectors.py), under the bundled demonstration suite and under sequences of two of its motions.

1. Fragility (:func:`dem_core.analyses.fragility_study.fragility_study`): each variant under the suite's 40 motions
   scaled to LEVELS PGA stripes up to 2 g, each followed by 10 s of ground at rest; peak |theta|/alpha states and
   overturning, the residual dislocation of a drum over the one below and the residual tilt, each measure's states
   fitted together, bands drawn by record; and per stripe the share of runs in which a connector ruptured.
2. Sequences: each variant under PAIRS pairs of the suite's motions, one after the other with SEQUENCE_REST s of
   rest between (records of coarser sampling put on the finer one's), each pair scaled so that its PGA is
   SEQUENCE_PGA: the residual dislocation and tilt after the first event and after the second (:func:`dem_core.inputs.excitation.sequence`, :attr:`dem_core.Result.events`).
3. The bars' stiffness: the titanium bars and the oak poles at ten times their stiffness, under El Centro 1940 at
   20 amplitudes from 1.2 to 3 times the column's uplift acceleration, against the same runs with every amplitude
   times 1.001, a change nobody would call physical: whether the stiffness moves the peaks more than the
   response's own sensitivity does.
"""

import dataclasses
import math
import time

import numpy as np
import pandas as pd
from _study import CACHE, markdown_table, out_dir, plt, save_figure, write_readme

from dem_core import excitation, scenes, simulate, simulate_batch
from dem_core.analyses.fragility_study import fragility_study, state_label, stripes
from dem_core.analyses.run_identity import machine
from dem_core.inputs.connectors import OAK_POLOS, Placement, titanium_bar
from dem_core.inputs.records import G_STANDARD
from dem_core.inputs.suites import DEFAULT_SUITE, load_suite

NAME = "restoration"
LEVELS, TOP = 16, 2.0 * G_STANDARD
STATES = (0.1, 0.3, 0.5, 1.0)
RESIDUAL = {"dislocation": (1.0, 5.0), "tilt": (0.002,)}
OPTIONS = {"integrator": "moreau"}
VARIANTS = {
    "as built": [],
    "oak poles at every joint": [Placement(OAK_POLOS, "all")],
    "titanium bars at every joint": [Placement(titanium_bar(), "all")],
    "a titanium bar at the top joint": [Placement(titanium_bar(), "capital")],
}
COLOURS = dict(zip(VARIANTS, ("#222222", "#b8860b", "#1f77b4", "#17becf")))
PAIRS, SEQUENCE_PGA, SEQUENCE_REST = 20, 0.6 * G_STANDARD, 10.0
STIFFNESS_FACTOR, AMPLITUDES, PERTURBATION = 10.0, 20, 1e-3
RESAMPLES = 2000


def column(variant: str):
    """The 8-drum column of ``variant``."""
    return scenes.column(connectors=VARIANTS[variant])


def bootstrap_band(values, statistic=np.median) -> tuple:
    """The 90% band of ``statistic`` of ``values`` (one per record or pair), the values drawn again."""
    rng = np.random.default_rng(1)
    values = np.asarray(values, float)
    draws = [statistic(rng.choice(values, len(values))) for _ in range(RESAMPLES)]
    return tuple(np.percentile(draws, [5, 95], method="nearest"))


def millimetres(value: float) -> str:
    return f"{value:.3g}" if np.isfinite(value) else "overturned"


def slug(variant: str) -> str:
    return variant.replace(" ", "_")


def fragilities(records: dict) -> dict:
    """{variant: FragilityStudy} under the suite, each logged run by run in ``.study_cache/restoration/``, from
    which a study started again resumes."""
    levels = stripes(LEVELS, TOP)
    (CACHE / NAME).mkdir(parents=True, exist_ok=True)
    return {variant: fragility_study(column(variant), records, levels, STATES, residual=RESIDUAL,
                                     log=CACHE / NAME / f"{slug(variant)}.jsonl", **OPTIONS)
            for variant in VARIANTS}


def fragility_cost(studies: dict, seconds: float) -> str:
    """How many fragility runs this invocation ran and in how long, and how many it read from the study's log
    instead (their time is not in it)."""
    read = sum(study.resumed for study in studies.values())
    ran = sum(len(study.runs) for study in studies.values()) - read
    logged = f"read from `.study_cache/{NAME}/`, where an earlier invocation logged them"
    if not ran:
        return f"{read} fragility runs {logged}"
    return f"{ran} fragility runs in {seconds:.0f} s" + (f" ({read} {logged})" if read else "")


def sequences(records: dict) -> pd.DataFrame:
    """One row per variant, pair and event: the residual dislocation (mm, the largest over the joints) and tilt (rad)
    after it, infinite where the column overturned by then."""
    names = list(records)
    rows = []
    for variant in VARIANTS:
        scene = column(variant)
        for k in range(PAIRS):
            first, second = names[2 * k], names[2 * k + 1]
            pair = excitation.sequence([records[first], records[second]], rest=SEQUENCE_REST, resample=True)
            motion = excitation.scaled(pair, SEQUENCE_PGA / excitation.peak_acceleration(pair))
            result = simulate(scene, motion, **OPTIONS)
            reached = {event["event"]: event for event in result.events.to_dict("records")}
            fell = bool(np.isfinite(result.overturn_time).any())
            for number in (1, 2):
                event = reached.get(number)
                standing = event is not None and not (fell and number == max(reached))
                rows.append({"variant": variant, "pair": f"{first} + {second}", "event": number,
                             "dislocation_mm": 1e3 * max(abs(v) for key, v in event.items()
                                                         if key.startswith("residual_dislocation_m[")) if standing
                             else np.inf,
                             "tilt_rad": max(abs(v) for key, v in event.items() if key.startswith("residual_tilt_rad["))
                             if standing else np.inf,
                             "overturned": not standing,
                             "ruptured": 0 if result.connectors is None else int(result.connectors.ruptured.sum())})
    return pd.DataFrame(rows)


def stiffness_check() -> pd.DataFrame:
    """Per connector kind the median |log| of the member-by-member ratio of the peak |theta| at STIFFNESS_FACTOR
    times its stiffness, and at every amplitude times 1 + PERTURBATION, to the peak at its own stiffness."""
    record = excitation.record("el_centro_1940")
    base = column("as built")
    uplift = G_STANDARD * math.tan(base.rocking_slenderness)
    amplitudes = np.linspace(1.2, 3.0, AMPLITUDES) * uplift
    pga = excitation.peak_acceleration(record)
    rows = []
    for kind in (titanium_bar(), OAK_POLOS):
        stiff = dataclasses.replace(kind, name=f"{kind.name} x{STIFFNESS_FACTOR:g}",
                                    shear_stiffness=STIFFNESS_FACTOR * kind.shear_stiffness,
                                    axial_stiffness=STIFFNESS_FACTOR * kind.axial_stiffness)
        peaks, fell = {}, {}
        for label, bar, factor in (("own", kind, 1.0), ("stiff", stiff, 1.0), ("nudged", kind, 1.0 + PERTURBATION)):
            batch = simulate_batch(scenes.column(connectors=[Placement(bar, "all")]),
                                   [excitation.scaled(record, a * factor / pga) for a in amplitudes], **OPTIONS)
            peaks[label] = batch.table["max_peak_abs_theta_rad"].to_numpy()
            fell[label] = batch.table["overturned"].to_numpy(bool)
        standing = ~(fell["own"] | fell["stiff"] | fell["nudged"])
        change = np.median(np.abs(np.log(peaks["stiff"][standing] / peaks["own"][standing])))
        floor = np.median(np.abs(np.log(peaks["nudged"][standing] / peaks["own"][standing])))
        rows.append({"kind": kind.name, "members": AMPLITUDES, "standing": int(standing.sum()),
                     "stiffness_change": change, "perturbation_floor": floor,
                     "overturns_agree": int((fell["own"] == fell["stiff"]).sum())})
    return pd.DataFrame(rows)


def figure_fragility(studies: dict) -> None:
    """Overturning and the 5 mm dislocation, a panel each: each variant's lognormal and its observed fractions."""
    levels = np.linspace(0.01, TOP, 300)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    for ax, state, title in ((axes[0], 1.0, "overturning"), (axes[1], ("dislocation", 5.0),
                                                                "residual dislocation of 5 mm")):
        for variant, study in studies.items():
            fit = study.fits[state]
            ax.plot(levels / G_STANDARD, fit.probability(levels), color=COLOURS[variant], label=variant)
            ax.plot(fit.levels / G_STANDARD, fit.exceed / np.maximum(fit.runs, 1), "o", ms=3, color=COLOURS[variant])
        ax.set(xlabel="PGA, g", ylabel="probability of exceedance", title=title, ylim=(-0.02, 1.02))
    for variant, study in studies.items():
        runs = study.runs[study.runs.status == "ok"]
        if "connectors_ruptured" in runs:
            share = (runs.connectors_ruptured > 0).groupby(runs.level).mean()
            axes[2].plot(share.index / G_STANDARD, share.to_numpy(), "o-", ms=3, color=COLOURS[variant],
                         label=variant)
    axes[2].set(xlabel="PGA, g", ylabel="share of runs", title="a connector ruptured", ylim=(-0.02, 1.02))
    axes[0].legend(loc="lower right", fontsize=8)
    save_figure(fig, NAME, "fragility.png", "")


def figure_residuals(studies: dict, pairs: pd.DataFrame) -> None:
    """The median residual dislocation against PGA (the records' middle half shaded), and after each event of the
    sequences."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    for variant, study in studies.items():
        runs = study.runs[(study.runs.status == "ok") & ~study.runs.overturned.astype(bool)]
        by_level = runs.groupby("level")["residual_dislocation_mm"]
        middle = by_level.median()
        axes[0].plot(middle.index / G_STANDARD, middle.to_numpy(), color=COLOURS[variant], label=variant)
        axes[0].fill_between(middle.index / G_STANDARD, by_level.quantile(0.25).to_numpy(),
                             by_level.quantile(0.75).to_numpy(), color=COLOURS[variant], alpha=0.12)
    axes[0].set(xlabel="PGA, g", ylabel="residual dislocation, mm\n(median of the standing runs)",
                title="what the suite's motions leave", yscale="symlog")
    axes[0].yaxis.set_major_formatter(plt.matplotlib.ticker.ScalarFormatter())
    width = 0.18
    fell = int(pairs[(pairs.variant == "as built") & (pairs.event == 2)].overturned.sum())
    for k, variant in enumerate(VARIANTS):
        own = pairs[pairs.variant == variant]
        for event in (1, 2):
            values = own[own.event == event].dislocation_mm.to_numpy()
            x = event + (k - 1.5) * width
            standing = values[np.isfinite(values)]
            axes[1].plot(np.full(len(standing), x), standing, ".", color=COLOURS[variant], alpha=0.5)
            axes[1].plot([x - 0.07, x + 0.07], [np.median(values)] * 2, color=COLOURS[variant], lw=2.5,
                         label=variant if event == 1 else None)
    axes[1].set(xticks=[1, 2], xticklabels=["after the first event", "after the second"],
                ylabel="residual dislocation, mm",
                title=f"{PAIRS} pairs of motions at {SEQUENCE_PGA / G_STANDARD:g} g: the bar the median\n"
                      f"(the overturned, {fell} as built, counted above it)")
    axes[1].legend(fontsize=8, loc="upper left")
    save_figure(fig, NAME, "residuals.png", "")


def median_row(variant, study, bare) -> list:
    """A row of the fits' table: each state's median PGA (g) and its 90% band, and against the column as built."""
    cells = [variant]
    for state in (1.0, ("dislocation", 5.0), ("dislocation", 1.0), ("tilt", 0.002)):
        fit, plain = study.fits[state], bare.fits[state]
        if not math.isfinite(fit.median):
            cells.append(f"none ({fit.note})")
            continue
        low, high = fit.median_band
        ratio = fit.median / plain.median if math.isfinite(plain.median) else math.nan
        cells.append(f"{fit.median / G_STANDARD:.3g} g ({low / G_STANDARD:.3g} to {high / G_STANDARD:.3g}), "
                     f"x{ratio:.2f}")
    return cells


def main():
    started = time.perf_counter()
    records = load_suite(DEFAULT_SUITE).motions()
    studies = fragilities(records)
    fragility_time = sum(s.wall_time_s for s in studies.values())
    pairs = sequences(records)
    sequence_time = time.perf_counter() - started - fragility_time
    stiffness = stiffness_check()
    out = out_dir(NAME)
    for variant, study in studies.items():
        study.runs.assign(variant=variant).to_parquet(out / f"runs_{slug(variant)}.parquet", index=False)
    pairs.to_csv(out / "sequences.csv", index=False)
    stiffness.to_csv(out / "stiffness.csv", index=False)
    figure_fragility(studies)
    figure_residuals(studies, pairs)

    bare = studies["as built"]
    states = ["overturning", state_label(("dislocation", 5.0)), state_label(("dislocation", 1.0)),
              state_label(("tilt", 0.002))]
    table = markdown_table(["variant", *(f"median PGA: {s}".replace("|", "\\|") for s in states)],
                           [median_row(v, s, bare) for v, s in studies.items()])
    sequence_rows = []
    for variant in VARIANTS:
        own = pairs[pairs.variant == variant]
        cells = [variant]
        for event in (1, 2):
            values = own[own.event == event].dislocation_mm
            low, high = bootstrap_band(values)
            cells.append(f"{millimetres(np.median(values))} mm ({millimetres(low)} to {millimetres(high)})")
        cells.append(f"{int(own[own.event == 2].overturned.sum())} of {PAIRS}")
        sequence_rows.append(cells)
    sequence_table = markdown_table(["variant", "residual dislocation after the first event: median (90% band)",
                                     "after the second", "overturned"], sequence_rows)
    stiffness_table = markdown_table(
        ["connector at every joint", "members standing", f"median |log| change of the peak at x{STIFFNESS_FACTOR:g} "
         "stiffness", f"the same under amplitudes x{1 + PERTURBATION:g}", "overturns that agree"],
        [[r.kind, f"{r.standing} of {r.members}", f"{r.stiffness_change:.3g}", f"{r.perturbation_floor:.3g}",
          f"{r.overturns_agree} of {r.members}"] for r in stiffness.itertuples()])

    def standing(variant):
        runs = studies[variant].runs
        return runs[(runs.status == "ok") & ~runs.overturned.astype(bool)]

    def effect(variant, statistic):
        """The ratio of ``statistic`` of the standing runs' residual dislocation to the column's as built, and its
        90% band, the records drawn again (each with all its stripes, in both variants)."""
        own, plain = standing(variant), standing("as built")
        names = np.array(list(records))
        rng = np.random.default_rng(2)
        draws = []
        for _ in range(RESAMPLES):
            drawn = rng.choice(names, len(names))
            pick = pd.Series(drawn).value_counts()
            weights_own, weights_plain = own.record.map(pick).fillna(0), plain.record.map(pick).fillna(0)
            draws.append(statistic(np.repeat(own.residual_dislocation_mm, weights_own.astype(int)))
                         / statistic(np.repeat(plain.residual_dislocation_mm, weights_plain.astype(int))))
        ratio = statistic(own.residual_dislocation_mm) / statistic(plain.residual_dislocation_mm)
        low, high = np.percentile(draws, [5, 95])
        return f"{ratio:.2f} ({low:.2f} to {high:.2f})"

    effects = [f"{variant}: median {effect(variant, np.median)}, mean {effect(variant, np.mean)}"
               for variant in list(VARIANTS)[1:]]
    connected = {v: s.runs for v, s in studies.items() if VARIANTS[v]}
    ruptured = {v: (int((runs.connectors_ruptured > 0).sum()), int(runs.connectors_ruptured.sum()),
                    int(runs.connectors_pulled_out.sum())) for v, runs in connected.items()}
    findings = [
        f"Every figure rests on the {len(records)} motions of the {DEFAULT_SUITE} suite; bands are 90% and drawn by "
        f"record (or by pair), the level where the variability lives. Moreau-Jean at its automatic step "
        f"(docs/method.md 1.12 says why connectors are run with it).",
        "The literature's direction of effect (Papadopoulos and Vintzileou: poles at every interface limit the "
        "residual deformation, one at the capital little): the residual dislocation of the standing runs over every "
        "stripe, its median and its mean against the column as built's (90% band, records drawn again): "
        + "; ".join(effects) + ". Under the sequences (second table) the titanium bars at every joint leave the "
        "smallest dislocation after each event.",
        "Runs in which a connector ruptured: " + "; ".join(
            f"{v} {runs} of {len(studies[v].runs)} ({broken} connectors: {pulled} pulled out in tension as the joints "
            f"opened, {broken - pulled} broke in shear)" for v, (runs, broken, pulled) in ruptured.items()) + ".",
        f"The bars' stiffness: at {STIFFNESS_FACTOR:g} times their stiffness the connectors move the column's peaks "
        f"by less than amplitudes {1 + PERTURBATION:g} times larger do (the third table; El Centro 1940 at "
        f"{AMPLITUDES} amplitudes): the results are not an artefact of the bars' stiffness."
        if (stiffness.stiffness_change < stiffness.perturbation_floor).all() else
        "The bars' stiffness moves the peaks more than a perturbation of the amplitudes does (third table): read "
        "the connectors' results with their stiffness in mind.",
        f"{fragility_cost(studies, fragility_time)}, {len(pairs) // 2} sequence runs in {sequence_time:.0f} s "
        f"({machine()}).",
    ]
    write_readme(NAME, "What a restoration changes: connectors in the 8-drum column", findings,
                 [("fragility.png", "Probability of exceedance against PGA, overturning and a residual dislocation of "
                   "5 mm, each variant's lognormal and its observed fractions; and the share of runs in which a "
                   "connector ruptured"),
                  ("residuals.png", "The residual dislocation (largest over the joints) of the standing runs against "
                   "PGA, median with the records' middle half; and after each event of the sequences")],
                 started, "restoration.py", resumes=False,
                 tables=[*table, "", *sequence_table, "", *stiffness_table, ""])


if __name__ == "__main__":
    main()
