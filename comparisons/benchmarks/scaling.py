"""Cost of the native core as scenes grow: per block-step, the time-step set-up, memory, threads.

For 8, 64, 512 and 2,048 blocks (as near as the scene's layout allows) of three families (columns
of 8 drums standing apart, one long colonnade of 8-drum columns under a single epistyle, and a
two-tier colonnade), under a 2 Hz harmonic ground motion: the set-up time (scene checks, model,
stability limit), the wall time per block-step of a fixed number of steps (one thread, and all
threads), and the peak resident memory of the process.

    python -m comparisons scaling [--steps 2000] [--sizes 8 64 512 2048] [--families columns colonnade two_tier]
"""

import argparse
import resource
import time

import numba

import dem_core
from dem_core import excitation, scenes

SPACING = 2.5  # m between column centres


def columns(n_blocks):
    """Standalone 8-drum columns, far enough apart not to touch (a row of columns without epistyles)."""
    count = max(1, round(n_blocks / 8))
    blocks = []
    for c in range(count):
        column = scenes.column(8)
        blocks += [dem_core.Block(f"c{c + 1}_{b.name}", b.vertices + [c * SPACING, 0.0], density=b.density)
                   for b in column.blocks]
    span = (count - 1) * SPACING
    base = scenes.block(1.0, 1.0, base_width=span + 30.0).base
    base = dem_core.Block("base", base.vertices + [span / 2, 0.0], density=1.0)
    return dem_core.Scene(tuple(blocks), base)


def colonnade(n_blocks):
    """One colonnade of 8-drum columns under a single epistyle (type a)."""
    return scenes.colonnade(n_columns=max(2, round((n_blocks - 1) / 8)), n_drums=8, spacing=SPACING, epistyle="a")


def two_tier(n_blocks):
    """A two-tier colonnade: 3 lower and 2 upper drums per column and two epistyles (type a)."""
    return scenes.two_tier_colonnade(n_columns=max(2, round((n_blocks - 2) / 5)), spacing=SPACING)


FAMILIES = {"columns": columns, "colonnade": colonnade, "two_tier": two_tier}


def measure(scene, steps, parallel):
    """(set-up s, s per block-step) of ``steps`` steps with the serial or the threaded kernel."""
    started = time.perf_counter()
    run = dem_core.Simulation(scene, excitation.harmonic(pga=1.0, frequency=2.0), duration=10.0, parallel=parallel,
                              integrator="explicit")
    setup = time.perf_counter() - started
    run.advance(50)  # the first pair lists and caches
    started = time.perf_counter()
    run.advance(steps)
    return setup, (time.perf_counter() - started) / steps / len(scene.blocks)


def arguments(parser: argparse.ArgumentParser) -> None:
    """The options of its subcommand of ``python -m comparisons``."""
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--sizes", type=int, nargs="+", default=[8, 64, 512, 2048])
    parser.add_argument("--families", nargs="+", default=list(FAMILIES), choices=list(FAMILIES))


def run(args: argparse.Namespace) -> None:
    """Run with the options of :func:`arguments` and print the results."""
    threads = numba.config.NUMBA_NUM_THREADS
    print(f"{'family':10s} {'blocks':>6s} {'set-up (s)':>10s} {'1 thread':>12s} {f'{threads} threads':>12s} "
          f"{'speed-up':>8s} {'peak RSS (MB)':>13s}")
    for family in args.families:
        for size in args.sizes:
            scene = FAMILIES[family](size)
            setup, one = measure(scene, args.steps, False)
            _, many = measure(scene, args.steps, True)
            rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
            print(f"{family:10s} {len(scene.blocks):6d} {setup:10.3f} {one * 1e9:9.0f} ns {many * 1e9:9.0f} ns "
                  f"{one / many:8.2f} {rss:13.0f}", flush=True)

