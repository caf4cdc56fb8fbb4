"""``dem-core select [SUITE] --ec8 B --ag 2.4 --out DIR``: the records of a suite whose spectra best match a target
spectrum over a range of periods, each scaled to it, written as a suite (:mod:`dem_core.analyses.target_spectra`)."""

import sys

import numpy as np

from ..analyses.target_spectra import EC8_FLOOR, EC8_GROUND, MODELS, ec8_spectrum, model_spectrum, select_and_scale
from ..inputs.excitation import GroundMotion, Sampled
from ..inputs.records import G_STANDARD
from ..inputs.suites import DEFAULT_SUITE, METADATA, SuiteError, SuiteRecord, load_suite, write_suite
from ..inputs.synthetic import MECHANISMS, Scenario
from ..output_files import output_folder, replacing
from .arguments import POSITIVE, WORKERS

#: periods at which the spectra are compared, evenly spaced in log between --periods
PERIODS = 30


def add(sub):
    select = sub.add_parser(
        "select", help="the records of a suite that best match a target spectrum, scaled to it and written as a suite",
        description="Scale every record of the suite by the factor that brings its 5%%-damped spectrum nearest the "
        "target over --periods (least squares of the logarithms), keep the --count records whose spectra then "
        "match it best in shape, and write them, scaled, as a suite folder (records.csv and a text file each) "
        "with selection.csv (every record's factor and misfit) and spectra.png.  The target is Eurocode 8's "
        f"elastic spectrum (--ec8 and --ag; the selected records' mean is then lifted to at least {EC8_FLOOR:g} of "
        "it everywhere, EN 1998-1 3.2.3.1.2) or a ground-motion model's median for a scenario (--scenario).")
    select.add_argument("suite", nargs="?", default=DEFAULT_SUITE, help=f"a suite folder or a bundled suite's name "
                        f"(default: {DEFAULT_SUITE})")
    target = select.add_mutually_exclusive_group(required=True)
    target.add_argument("--ec8", choices=tuple(EC8_GROUND[1]), metavar="GROUND",
                        help="Eurocode 8's elastic spectrum on ground type A to E (default: none; or --scenario)")
    target.add_argument("--scenario", nargs=4, metavar=("M", "R_KM", "VS30", "MECHANISM"),
                        help=f"a ground-motion model's median spectrum for magnitude M at R_KM km on a site of "
                        f"VS30 m/s, mechanism one of {', '.join(MECHANISMS)} (default: none; or --ec8)")
    select.add_argument("--ag", type=POSITIVE, help="m/s^2, Eurocode 8's design ground acceleration on ground A "
                        "(default: none; required with --ec8)")
    select.add_argument("--spectrum-type", type=int, choices=(1, 2), default=1, help="Eurocode 8's spectrum type")
    select.add_argument("--model", choices=tuple(MODELS), default="ASB14", help="the ground-motion model of "
                        "--scenario: Akkar, Sandikkaya and Bommer 2014 (Europe) or Boore, Stewart, Seyhan and "
                        "Atkinson 2014")
    select.add_argument("--periods", type=POSITIVE, nargs=2, default=(0.2, 2.0), metavar=("LOW", "HIGH"),
                        help="s, the range of periods matched")
    select.add_argument("--count", type=WORKERS, default=10, help="records kept")
    select.add_argument("--largest-factor", type=POSITIVE, default=5.0, help="records needing a scale factor above "
                        "this or below its inverse are left out")
    select.add_argument("--units", choices=("m/s^2", "g", "cm/s^2"), default="m/s^2", help=f"units of text records "
                        f"{METADATA} gives none for (AT2 files state theirs)")
    select.add_argument("--out", required=True, help="the folder of the selected suite, created if need be")


def run(args) -> int:
    low, high = args.periods
    periods = np.geomspace(low, high, PERIODS)
    try:
        target, name = _target(args, periods)
        suite = load_suite(args.suite, args.units)
        motions = suite.motions()
        selection = select_and_scale(motions, periods, target, args.count, largest_factor=args.largest_factor,
                                     floor=EC8_FLOOR if args.ec8 else None)
    except (SuiteError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    out = output_folder(args.out, "--out")
    entries = []
    known = {entry.name: entry for entry in suite.records}
    for record, factor in selection.factors.items():
        horizontal = motions[record].horizontal
        scaled_motion = GroundMotion(Sampled(horizontal.samples * factor, horizontal.dt, name=record), name=record)
        entry = known[record]
        entries.append(SuiteRecord(record, scaled_motion, f"{record}.txt",
                                   f"{entry.source}; scaled by {factor:.4g} to {name}".lstrip("; "),
                                   magnitude=entry.magnitude, distance_km=entry.distance_km, vs30=entry.vs30,
                                   pulse_period=entry.pulse_period))
    write_suite(entries, out)
    with replacing(out / "selection.csv") as tmp:
        selection.table.to_csv(tmp, index=False)
    _figure(selection, name, out / "spectra.png", EC8_FLOOR if args.ec8 else None)
    chosen = selection.table[selection.table["selected"]]
    print(f"{len(chosen)} of {len(suite)} records of {suite.name} matched to {name} from {low:g} to {high:g} s"
          + (f", then all scaled by {selection.common:.3g} so that their mean is at least {EC8_FLOOR:g} of it"
             if selection.common > 1.0 else ""))
    for _, row in chosen.iterrows():
        print(f"  {row['record']:18s} factor {row['factor'] * selection.common:.3g}, misfit {row['misfit']:.3f}")
    ratio = selection.mean / selection.target
    print(f"the selected records' mean spectrum is {ratio.min():.2f} to {ratio.max():.2f} of the target; wrote "
          f"{METADATA}, {len(chosen)} records, selection.csv and spectra.png in {out}")
    return 0


def _target(args, periods) -> tuple:
    """``(target m/s^2 at periods, its name in words)`` of the command's options, or ValueError."""
    if args.ec8:
        if args.ag is None:
            raise ValueError("--ec8: give the design ground acceleration --ag (m/s^2)")
        return (ec8_spectrum(periods, args.ag, args.ec8, args.spectrum_type),
                f"Eurocode 8's type {args.spectrum_type} spectrum on ground {args.ec8}, a_g {args.ag:g} m/s^2 "
                f"({args.ag / G_STANDARD:.3g} g)")
    if args.ag is not None:
        raise ValueError("--ag is Eurocode 8's (--ec8); a --scenario's spectrum comes from its model")
    magnitude, distance, vs30, mechanism = args.scenario
    try:
        scenario = Scenario(float(magnitude), float(distance), float(vs30), mechanism)
    except ValueError as exc:
        raise ValueError(f"--scenario: {exc}") from None
    median, _ = model_spectrum(periods, scenario, args.model)
    return median, f"the {args.model} median for {scenario.label}"


def _figure(selection, name: str, path, floor: float | None) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, ax = plt.subplots(figsize=(7.5, 4.8))
    ax.loglog(selection.periods, selection.target / G_STANDARD, "k-", linewidth=2, label=f"target: {name}")
    if floor:
        ax.loglog(selection.periods, floor * selection.target / G_STANDARD, "k:", linewidth=1,
                  label=f"{floor:g} of the target: the records' mean stays above it")
    ax.loglog(selection.periods, selection.mean / G_STANDARD, "C3--", linewidth=2,
              label="the selected records' mean, scaled")
    ax.set(xlabel="period (s)", ylabel="5%-damped spectral acceleration (g)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    figure.tight_layout()
    try:
        with replacing(path) as tmp:
            figure.savefig(tmp, dpi=130, format="png")
    finally:
        plt.close(figure)
