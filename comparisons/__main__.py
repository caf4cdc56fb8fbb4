"""``python -m comparisons report [--quick] [--out reports]``: run the harness, the ensembles, the column
ensemble, the overturning spectra and the stress tests, write the report, take a 1280-pixel screenshot of its first screen
(``first_screen.png``, with headless Chromium where it is installed) and print how long it all took.  The other
subcommands are the timings and calibrations of comparisons/benchmarks/ (``python -m comparisons SUBCOMMAND
--help``)."""

import argparse
import importlib
import shutil
import subprocess
import sys
import time
from pathlib import Path

#: subcommand: the module of :mod:`comparisons.benchmarks` that declares its options and runs it, imported when its
#: subcommand is named or listed (``gpu-check`` runs where the other engines are not installed)
BENCHMARKS = {
    "against-pymunk": "against_pymunk",
    "batch-throughput": "batch_throughput",
    "column-ensemble": "column_ensemble",
    "scaling": "scaling",
    "sweep-throughput": "sweep_throughput",
    "stability-probe": "stability_probe",
    "calibrate-damping": "calibrate_damping",
    "stiffness-ensembles": "stiffness_ensembles",
    "overturn-rule": "overturn_rule",
    "moreau-stages": "moreau_stages",
    "restitution": "restitution",
    "gpu-check": "gpu_check",
    "gpu-reference": "gpu_reference",
    "kernel-accesses": "kernel_accesses",
    "step-instructions": "step_instructions",
    "fragility-suite": "fragility_suite",
    "connector-cost": "connector_cost",
}


#: the browsers tried, in turn, for the screenshot of the first screen
CHROMIUM = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
#: the window the first screen is taken in (pixels)
SCREEN = (1280, 900)


def screenshot(index: Path, png: Path | None = None, size=SCREEN, timeout_s: float = 60.0) -> Path | None:
    """A screenshot of the first screen of ``index`` (an HTML file) at ``size`` pixels, written to ``png``
    (default: ``first_screen.png`` beside it) with headless Chromium; returns its path, or None, having printed
    why, where no Chromium is installed or it fails (the report never fails for want of a screenshot)."""
    index = Path(index).resolve()
    png = (index.parent / "first_screen.png") if png is None else Path(png).resolve()
    browser = next((found for name in CHROMIUM if (found := shutil.which(name))), None)
    if browser is None:
        print("screenshot skipped: no Chromium found (apt-get install chromium)", flush=True)
        return None
    command = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
               f"--window-size={size[0]},{size[1]}", f"--screenshot={png}", index.as_uri()]
    try:
        subprocess.run(command, capture_output=True, timeout=timeout_s, check=False)
    except (OSError, subprocess.SubprocessError) as error:
        print(f"screenshot skipped: {browser} failed ({error})", flush=True)
        return None
    if not png.is_file():
        print(f"screenshot skipped: {browser} wrote no {png.name}", flush=True)
        return None
    return png


def make_report(quick: bool, out: Path, progress: bool = True, shot: bool = True) -> tuple[Path, dict]:
    """Run every part and write the report into ``out``: ``(index.html, {part: tidy table})``, with a screenshot
    of its first screen (unless ``shot`` is False); prints the time each part took."""
    from comparisons.harness.case_runs import run_harness
    from comparisons.harness.column_ensemble import run_column_ensemble
    from comparisons.harness.ensembles import run_ensembles
    from comparisons.harness.overturning_spectra import run_spectra
    from comparisons.harness.stress import run_stress
    from comparisons.report.page import write_report
    from comparisons.report.provenance import provenance

    start = time.perf_counter()
    made = provenance()  # the code the numbers come from: the checkout may move while the report runs
    parts = {}
    for name, run in (("cases", run_harness), ("ensembles", run_ensembles), ("column ensemble", run_column_ensemble),
                      ("spectra", run_spectra), ("stress tests", run_stress)):
        began = time.perf_counter()
        parts[name] = run(quick=quick, progress=progress)
        print(f"{name}: {time.perf_counter() - began:.0f} s", flush=True)
    index = write_report(parts["cases"], parts["stress tests"], Path(out), quick=quick,
                         run_time_s=time.perf_counter() - start, ensemble_table=parts["ensembles"],
                         spectra_table=parts["spectra"], column_table=parts["column ensemble"], made=made)
    if shot:
        screenshot(index)
    return index, parts


def _report(args) -> None:
    start = time.perf_counter()
    index, _ = make_report(args.quick, Path(args.out), progress=not args.no_progress, shot=not args.no_screenshot)
    print(f"report written to {index} ({time.perf_counter() - start:.0f} s)")


def parser(command: str | None = None) -> argparse.ArgumentParser:
    """The command line: ``report`` and one subcommand per benchmark (only ``command``'s module imported where it
    names one)."""
    top = argparse.ArgumentParser(prog="python -m comparisons", description=__doc__)
    sub = top.add_subparsers(dest="command", required=True)
    report = sub.add_parser("report", help="run every case in every engine and write reports/index.html",
                            description="Run every case, ensemble, overturning spectrum and stress test in every "
                                        "engine; write the tables, the figures and index.html into OUT.")
    report.add_argument("--quick", action="store_true", help="the reduced set (under 3 minutes; what CI runs)")
    report.add_argument("--out", default="reports", help="output folder (default: reports)")
    report.add_argument("--no-progress", action="store_true")
    report.add_argument("--no-screenshot", action="store_true",
                        help="skip first_screen.png (a 1280 x 900 screenshot taken with headless Chromium)")
    report.set_defaults(run=_report)
    for name, module_name in BENCHMARKS.items():
        if command in BENCHMARKS and name != command:
            continue
        module = importlib.import_module(f"comparisons.benchmarks.{module_name}")
        benchmark = sub.add_parser(name, help=module.__doc__.splitlines()[0], description=module.__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
        module.arguments(benchmark)
        benchmark.set_defaults(run=module.run)
    return top


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    args = parser(argv[0] if argv else None).parse_args(argv)
    args.run(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
