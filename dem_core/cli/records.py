"""``dem-core records [SUITE]``: a record suite's motions (the bundled demonstration suite by default), with their
intensities, where each one's sampling interval comes from, and what is known of its earthquake."""

import math
import sys

from ..analyses.fragility_study import intensity
from ..inputs.suites import BUNDLED_SUITES, DEFAULT_SUITE, METADATA, SuiteError, load_suite
from .console import acceleration_text


def add(sub):
    listing = sub.add_parser(
        "records", help="list a record suite's motions: PGA, PGV, length, sampling interval, strong motion, "
        "earthquake and source",
        description=f"List the motions of a record suite: a folder of record files (AT2 or text) with an optional "
        f"{METADATA} (columns file, name, dt, units, component, magnitude, distance_km, vs30, pulse_period, source), "
        f"or a bundled suite ({', '.join(BUNDLED_SUITES)}).  Every record is read, so a suite this lists is one "
        f"fragility can run.")
    listing.add_argument("suite", nargs="?", default=DEFAULT_SUITE, help=f"a suite folder or a bundled suite's "
                         f"name (default: {DEFAULT_SUITE})")
    listing.add_argument("--units", choices=("m/s^2", "g", "cm/s^2"), default="m/s^2", help="units of text records "
                         f"{METADATA} gives none for (AT2 files state theirs)")
    listing.add_argument("--csv", metavar="FILE", help="also write the listing as a CSV table to FILE (default: none)")


def run(args) -> int:
    try:
        suite = load_suite(args.suite, args.units)
    except SuiteError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    table = suite.table()
    table.insert(3, "pgv_m_s", [intensity(entry.motion, "pgv") for entry in suite.records])
    print(f"suite {suite.name}: {len(suite)} records")
    for entry, (_, row) in zip(suite.records, table.iterrows()):
        known = ", ".join(text for text, value in (("M{:g}", row["magnitude"]), ("{:.3g} km", row["distance_km"]),
                                                   ("Vs30 {:.3g} m/s", row["vs30"]),
                                                   ("pulse {:.3g} s", row["pulse_period_s"]))
                          if math.isfinite(value) for text in [text.format(value)])
        print(f"{entry.name:18s} PGA {acceleration_text(row['pga_m_s2'])}, PGV {row['pgv_m_s']:.3g} m/s, "
              f"{row['length_s']:.4g} s every {row['dt_s']:.3g} s ({entry.sampling}), strong motion "
              f"{row['strong_start_s']:.3g} to {row['strong_end_s']:.3g} s" + (f"; {known}" if known else "")
              + (f": {entry.source}" if entry.source else ""))
    if suite.ignored:
        print(f"not in {METADATA}, so left out of the suite: {', '.join(suite.ignored)}")
    if args.csv:
        try:
            table.to_csv(args.csv, index=False)
        except OSError as exc:
            print(f"error: --csv {args.csv}: {exc.strerror or exc}", file=sys.stderr)
            return 2
        print(f"wrote {args.csv}")
    return 0
