"""``python -m comparisons report [--quick] [--out reports]``: run the harness and write the report."""

import argparse
import sys
import time
from pathlib import Path

from comparisons.harness import run_harness
from comparisons.report import write_report
from comparisons.stress import run_stress


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m comparisons", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    report = sub.add_parser("report", help="run every case in every engine and write reports/index.html")
    report.add_argument("--quick", action="store_true", help="the reduced set (a few minutes; what CI runs)")
    report.add_argument("--out", default="reports", help="output folder (default: reports)")
    report.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    table = run_harness(quick=args.quick, progress=not args.no_progress)
    stress = run_stress(quick=args.quick, progress=not args.no_progress)
    index = write_report(table, stress, Path(args.out), quick=args.quick, run_time_s=time.perf_counter() - start)
    print(f"report written to {index} ({time.perf_counter() - start:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
