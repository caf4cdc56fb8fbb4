"""``python -m comparisons report [--quick] [--out reports]``: run the harness, the ensembles, the overturning
spectra and the stress tests, write the report, and print how long it all took."""

import argparse
import sys
import time
from pathlib import Path

from comparisons.ensembles import run_ensembles
from comparisons.harness import run_harness
from comparisons.overturning_spectra import run_spectra
from comparisons.provenance import provenance
from comparisons.report import write_report
from comparisons.stress import run_stress


def make_report(quick: bool, out: Path, progress: bool = True) -> tuple[Path, dict]:
    """Run every part and write the report into ``out``: ``(index.html, {part: tidy table})``; prints the
    time each part took."""
    start = time.perf_counter()
    made = provenance()  # the code the numbers come from: the checkout may move while the report runs
    parts = {}
    for name, run in (("cases", run_harness), ("ensembles", run_ensembles), ("spectra", run_spectra),
                      ("stress tests", run_stress)):
        began = time.perf_counter()
        parts[name] = run(quick=quick, progress=progress)
        print(f"{name}: {time.perf_counter() - began:.0f} s", flush=True)
    index = write_report(parts["cases"], parts["stress tests"], Path(out), quick=quick,
                         run_time_s=time.perf_counter() - start, ensemble_table=parts["ensembles"],
                         spectra_table=parts["spectra"], made=made)
    return index, parts


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m comparisons", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    report = sub.add_parser("report", help="run every case in every engine and write reports/index.html")
    report.add_argument("--quick", action="store_true", help="the reduced set (under 3 minutes; what CI runs)")
    report.add_argument("--out", default="reports", help="output folder (default: reports)")
    report.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    index, _ = make_report(args.quick, Path(args.out), progress=not args.no_progress)
    print(f"report written to {index} ({time.perf_counter() - start:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
