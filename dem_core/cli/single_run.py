"""A scene file run once, as ``run`` and ``animate`` take it: the engine's set-up announced, a progress bar, and two
lines on what was simulated; and the animation both can write."""

import sys
from pathlib import Path

from .. import simulate
from ..output_files import replacing
from ..simulation import SimulationUnstable, run_duration
from .progress import CompileNotice, interactive, progress_callback


def simulated(spec, settings: dict):
    """``(result, setup seconds)`` of the scene file ``spec`` run by :func:`~dem_core.simulate` with ``settings``:
    its set-up (compiling the engine) announced when that takes long, the run with a progress bar on a terminal,
    then what was simulated (:func:`print_run`).  A run that loses stability raises :class:`SimulationUnstable`,
    with ``setup_s`` set, after printing what it reached."""
    bar = progress_callback()
    with CompileNotice() as notice:
        def progress(done, total):
            notice.finish()  # the first call comes before the first step: the set-up is done
            bar(done, total)

        try:
            result = simulate(spec.scene, spec.excitation, progress=progress, **settings)
        except SimulationUnstable as exc:
            exc.setup_s = notice.seconds
            if exc.partial is not None and len(exc.partial.t):
                print_run(exc.partial, run_duration(spec.excitation, settings.get("duration")), notice.seconds)
            raise
    print_run(result, run_duration(spec.excitation, settings.get("duration")), notice.seconds)
    return result, notice.seconds


def print_run(result, duration: float, setup: float) -> None:
    """Two lines: the contact law and time step of the run; the time simulated (and of how much, its ``duration``
    in s, when the run ended early), the wall time it took and ``setup``, the seconds the engine took to set up
    and compile."""
    info = result.info
    end = float(result.t[-1])
    early = f" of {duration:.4g} s" if end < duration - 1.5 * result.dt else ""
    if info.get("integrator") == "moreau":
        print(f"Moreau-Jean integrator (theta {info.get('theta')}) on the {info.get('contact_law', '?')} law's "
              f"points, rigid contacts; dt = {result.dt:.3g} s, {info.get('steps')} steps; contact solve "
              f"(docs/method.md 1.8): {info.get('status_passes_per_step', float('nan')):.3g} direct passes and "
              f"{info.get('sweeps_per_step', float('nan')):.2g} iterative sweeps a step; impacts: restitution "
              f"{info.get('restitution', float('nan')):.3g}")
    else:
        e = info.get("restitution")
        impacts = "dashpots as given" if e is None else f"restitution {e:.3g} at the points' dashpots"
        print(f"{info.get('contact_law', '?')} contact law, K_n = {info.get('kn', float('nan')):.3g} N/m^2, "
              f"{impacts}; dt = {result.dt:.3g} s (stability limit {info.get('stability_limit_s', float('nan')):.3g} "
              f"s), {info.get('steps')} steps")
    print(f"simulated {end:.4g} s{early} in {info['run_time_s']:.2f} s (setting up and compiling the engine: "
          f"{setup:.2f} s)")


def write_animation(spec, result, movie, strip, title, fps=25, speed=1.0, exaggerate=1.0):
    """The animation of ``result`` into ``movie`` and its snapshots into ``strip``, each whole or not at all."""
    from ..pictures.animation import animate, default_snapshot_times, frame_indices, snapshot_strip

    animate(spec.scene, result, movie, excitation=spec.excitation, fps=fps, speed=speed, title=title,
            exaggerate=exaggerate, progress=interactive())
    figure = snapshot_strip(spec.scene, result, default_snapshot_times(result), title=title, exaggerate=exaggerate)
    with replacing(strip) as tmp:
        figure.savefig(tmp, dpi=110, format="png")
    frames = len(frame_indices(result, fps, speed))
    shown = (f", rotations and displacements x {exaggerate:g}, each block's on what it rests on"
             if exaggerate != 1 else "")
    print(f"animation written to {movie} ({frames} frames, {frames / fps:.1f} s at {fps} frames/s{shown}), "
          f"snapshots to {strip}")
    if exaggerate != 1 and result.overturned:
        print(f"note: the collapse at {result.time_of_overturn:.2f} s is exaggerated too: its drawing is not to scale")


def movie_name_ok(name: str, option: str) -> bool:
    """Whether an animation file name has a format we write; says why not before any run starts."""
    from ..pictures.animation import can_write_mp4

    suffix = Path(name).suffix.lower()
    if suffix == ".gif" or (suffix == ".mp4" and can_write_mp4()):
        return True
    if suffix == ".mp4":
        print(f"error: {option} {name}: writing MP4 needs ffmpeg: install it, or pip install imageio-ffmpeg "
              "(pip install -e .[video]), or write a .gif", file=sys.stderr)
    else:
        print(f"error: {option} {name}: an animation file must end in .gif or .mp4", file=sys.stderr)
    return False
