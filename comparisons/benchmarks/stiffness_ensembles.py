"""Do multi-block scenes' answers depend on the contact stiffness?  An ensemble at several K_n.

The 8-drum column and a three-column colonnade (three drums each, a single epistyle of 8000 kg/m^3)
under each bundled record's strong motion (:mod:`comparisons.cases.strong_motion`) at ``--scales`` amplitudes
(default 10) from 1.2 to 3 times the scene's uplift acceleration ``g tan(alpha)``, with the native core's
default contact law at multiples of its default stiffness.  Printed per stiffness: how many members
overturn, the median peak rotation (largest |theta| of any block) over the members that stand at every
stiffness with its change against the stiffest and a bootstrap 90% interval of that change (members
resampled), the median and geometric mean of the member-by-member ratios of the peaks, and the agreement
on overturning.  A member near a jump of the response can change by a factor under any change, and the
median of a few tens of peaks jumps when one member crosses it: read the interval before the change.
``--perturb EPS`` also reruns the first stiffness with every amplitude times ``1 + EPS`` and prints the
same measures against the unperturbed run, with the median |log| of the member-by-member ratios for
every comparison: how far members move under a change nobody would call physical, the floor below
which a stiffness dependence cannot be told from the response's own sensitivity.

    python -m comparisons stiffness-ensembles [--scene column|colonnade] [--factors 1 10 100] [--scales 10]
        [--perturb 0.001] [--members FILE.csv]
    python -m comparisons stiffness-ensembles --summarise FILE.csv
"""

import argparse
import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

import dem_core
from comparisons.cases.strong_motion import strong_motion
from comparisons.report import provenance
from dem_core import records, scenes

SCALE_RANGE = (1.2, 3.0)  # amplitudes, in multiples of the uplift acceleration g tan(alpha)
BOOTSTRAP = 2000  # resamplings of the members for the interval of the median's change
SCENES = {
    "column": lambda: scenes.column(8),
    "colonnade": lambda: scenes.colonnade(3, 3, spacing=2.5, epistyle="a", epistyle_density=8000.0),
}


def members(n_scales: int) -> list:
    """(record, amplitude in multiples of the uplift acceleration) of each member."""
    return [(name, float(scale)) for name in records.BUNDLED for scale in np.linspace(*SCALE_RANGE, n_scales)]


def peaks(scene, factor: float, ensemble: list, amplitude_factor: float = 1.0) -> tuple:
    """(peak |theta| (members,) rad, overturned (members,) bool) of ``ensemble`` at ``factor`` x K_n, every
    amplitude times ``amplitude_factor``, run as one batch on every core (:func:`dem_core.simulate_batch`); a run
    that lost stability counts as overturned, with a NaN peak."""
    scene = scene.replace(contact=dem_core.contact.stiffer(scene.contact, factor))
    uplift = scene.gravity * np.tan(scene.rocking_slenderness)
    motions = [strong_motion(name, scale * amplitude_factor * uplift) for name, scale in ensemble]
    table = dem_core.simulate_batch(scene, motions, integrator="explicit").table
    refused = table[table["status"] == "refused"]
    if len(refused):
        raise ValueError(f"member {refused['member'].iloc[0]} ({refused['motion'].iloc[0]}) could not be run: "
                         f"{refused['error'].iloc[0]}")
    unstable = (table["status"] == "unstable").to_numpy()
    peak = np.where(unstable, np.nan, table["max_peak_abs_theta_rad"].to_numpy(float))
    return peak, unstable | table["overturned"].to_numpy(bool)


def median_change_interval(peak, reference, level: float = 0.9, seed: int = 0) -> tuple:
    """Bootstrap interval (low, high) of median(peak) / median(reference) - 1 over members resampled together."""
    rng = np.random.default_rng(seed)
    picks = rng.integers(0, len(peak), size=(BOOTSTRAP, len(peak)))
    change = np.median(peak[picks], axis=1) / np.median(reference[picks], axis=1) - 1.0
    return tuple(np.quantile(change, [(1.0 - level) / 2.0, (1.0 + level) / 2.0]))


def measures(peak, over, reference_peak, reference_over, standing) -> dict:
    """How ``peak``/``over`` (members,) compare with the reference run over the members ``standing`` in every run:
    ``median`` (rad) and its ``change`` against the reference's median with the bootstrap 90% interval
    ``change_low``/``change_high``; member by member, ``median_ratio``, ``geometric_mean`` (of the ratios) with
    the ``standard_error`` of its log, and ``typical_change`` (the median |log ratio|); ``overturned`` (a count) and
    ``agreement`` on overturning (a share)."""
    median = np.median(peak[standing])
    low, high = median_change_interval(peak[standing], reference_peak[standing])
    log_ratio = np.log(peak[standing] / reference_peak[standing])
    error = log_ratio.std(ddof=1) / np.sqrt(len(log_ratio)) if len(log_ratio) > 1 else np.nan
    return {"median": median, "change": median / np.median(reference_peak[standing]) - 1.0, "change_low": low,
            "change_high": high, "median_ratio": np.exp(np.median(log_ratio)),
            "geometric_mean": np.exp(log_ratio.mean()), "standard_error": error,
            "typical_change": np.median(np.abs(log_ratio)), "overturned": int(over.sum()),
            "agreement": np.mean(over == reference_over)}


def compare(label: str, peak, over, reference_peak, reference_over, standing) -> str:
    """One line of :func:`measures`: ``peak``/``over`` (members,) against the reference run, the peaks over the
    members ``standing`` in every run."""
    m = measures(peak, over, reference_peak, reference_over, standing)
    return (f"  {label}: overturned {m['overturned']}, median peak {m['median']:.5f} rad "
            f"({m['change']:+.1%}, 90% interval {m['change_low']:+.1%} to {m['change_high']:+.1%}); "
            f"member by member: median ratio {m['median_ratio']:.4f}, geometric mean ratio "
            f"{m['geometric_mean']:.4f} (standard error {m['standard_error']:.1%}), median |log ratio| "
            f"{m['typical_change']:.3f}; agrees on overturning {m['agreement']:.0%}")


def run_ensemble(scene, factors: list, n_scales: int, perturb: float | None = None, name: str = "") -> pd.DataFrame:
    """One row per member (record, scale) with ``peak_<run>`` (rad) and ``overturned_<run>`` for each run:
    ``<factor>x`` per stiffness factor, and ``<first factor>x_perturbed`` (amplitudes x (1 + perturb))."""
    ensemble = members(n_scales)
    table = pd.DataFrame(ensemble, columns=["record", "scale"])
    plan = [(f"{f:g}x", f, 1.0) for f in factors]
    if perturb:
        plan.append((f"{factors[0]:g}x_perturbed", factors[0], 1.0 + perturb))
    for key, factor, amplitude in plan:
        started = time.perf_counter()
        table[f"peak_{key}"], table[f"overturned_{key}"] = peaks(scene, factor, ensemble, amplitude)
        print(f"{name}: {factor:g} x K_n" + (f", amplitudes x {amplitude:g}" if amplitude != 1.0 else "")
              + f" done in {time.perf_counter() - started:.0f} s", flush=True)
    return table


def _runs(table: pd.DataFrame) -> tuple[dict, np.ndarray, str]:
    """``({run key: (peak, overturned)}, standing in every run (members,), the stiffest run's key)`` of ``table``."""
    keys = [c[len("peak_"):] for c in table.columns if c.startswith("peak_")]
    run = {k: (table[f"peak_{k}"].to_numpy(float), table[f"overturned_{k}"].to_numpy(bool)) for k in keys}
    standing = np.all([~over for _, over in run.values()], axis=0)
    factors = {k: float(k[:-1]) for k in keys if not k.endswith("_perturbed")}
    return run, standing, max(factors, key=factors.get)


def _against(key: str, stiffest: str) -> str:
    """The run a run of :func:`run_ensemble` is compared with: a perturbed run with its run as given, a stiffness
    with the stiffest."""
    return key[:-len("_perturbed")] if key.endswith("_perturbed") else stiffest


def compared(table: pd.DataFrame) -> dict:
    """``{run key: measures}`` (:func:`measures`) of ``table`` (:func:`run_ensemble`): each stiffness against the
    stiffest, a perturbed run against its run as given, over the members standing in every run."""
    run, standing, stiffest = _runs(table)
    return {k: measures(*run[k], *run[_against(k, stiffest)], standing) for k in run}


def summarise(table: pd.DataFrame, name: str = "") -> list:
    """Lines comparing each stiffness of ``table`` (:func:`run_ensemble`) with the stiffest, and the perturbed
    run, if any, with its unperturbed one."""
    run, standing, stiffest = _runs(table)
    lines = [f"{name}, {len(table)} members, {standing.sum()} standing in every run; against {stiffest} K_n:"]
    for k in run:
        if k.endswith("_perturbed"):
            base = _against(k, stiffest)
            lines += [f"against {base} K_n with the amplitudes as given (the response's own sensitivity):",
                      compare(f"{base} K_n, amplitudes perturbed", *run[k], *run[base], standing)]
        else:
            lines.append(compare(f"{k} K_n = {float(k[:-1]) * dem_core.ContactParameters().kn:.0e}", *run[k],
                                 *run[stiffest], standing))
    return lines


def write_stamp(members: Path, args: argparse.Namespace) -> Path:
    """Write ``members``' stamp beside it (``.json``): the digest of the sources the peaks come from
    (:func:`comparisons.report.provenance.source_digest`), the commit, and the options that made it."""
    made = provenance.provenance()
    stamp = {"digest": made["digest"], "commit": made["commit"], "modified": made["modified"],
             "options": {k: v for k, v in vars(args).items() if k in ("scene", "factors", "scales", "perturb")}}
    path = members.with_suffix(".json")
    path.write_text(json.dumps(stamp, indent=1) + "\n", encoding="utf-8")
    return path


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--scene", choices=list(SCENES), default="column")
    parser.add_argument("--factors", type=float, nargs="+", default=[1.0, 10.0, 100.0])
    parser.add_argument("--scales", type=int, default=10, help="amplitudes per record, from 1.2 to 3 g tan(alpha)")
    parser.add_argument("--perturb", type=float, help="also rerun the first stiffness with amplitudes x (1 + PERTURB)")
    parser.add_argument("--members", help="write every member's peak and outcome in each run to this CSV, and "
                        "beside it (.json) the digest of the sources and the options it comes from")
    parser.add_argument("--summarise", metavar="CSV",
                        help="print the summary of a CSV written by --members; run nothing")


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the results."""
    if args.summarise:
        print("\n".join(summarise(pd.read_csv(args.summarise), args.summarise)))
        return
    if args.members:  # made before the runs, so that they are not lost to a missing folder after them
        Path(args.members).parent.mkdir(parents=True, exist_ok=True)
    table = run_ensemble(SCENES[args.scene](), args.factors, args.scales, args.perturb, args.scene)
    if args.members:
        table.to_csv(args.members, index=False)
        write_stamp(Path(args.members), args)
    print("\n".join(summarise(table, args.scene)))

