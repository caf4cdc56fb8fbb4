"""``dem-core animate [SCENE]``: run a scene file and write an animation (GIF or MP4) and its snapshots."""

import sys

from ..output_files import output_file
from ..simulation import SimulationUnstable, run_duration
from .arguments import DEFAULT_SCENE, FPS, POSITIVE, SECONDS, add_integrator, scene_and_settings
from .console import motion_text, stopped_text
from .interrupts import INTERRUPTS
from .single_run import movie_name_ok, simulated, write_animation


def add(sub):
    anim = sub.add_parser("animate", help="run a scene file and write an animation and snapshots",
                          description="Run the scene and draw it: an animation of the blocks on the moving ground "
                          "(GIF or MP4, at most 5000 frames, --fps frames per second of --speed times real time) and "
                          "a strip of snapshots beside it; --exaggerate K draws each block's motion on what it "
                          "rests on K times larger, so that a small rocking shows.")
    anim.add_argument("scene", nargs="?", help=f"scene file; default the bundled {DEFAULT_SCENE}")
    anim.add_argument("--out", default="animation.gif", help="file to write (.gif or .mp4); snapshots go to "
                      "<name>_snapshots.png beside it.  Both are written whole or not at all")
    anim.add_argument("--duration", type=SECONDS, help="simulated time in s (default: from the file or the record)")
    add_integrator(anim)
    anim.add_argument("--fps", type=FPS, default=25, help="frames per second, 1 to 100 (default: 25)")
    anim.add_argument("--speed", type=POSITIVE, default=1.0, help="simulated seconds per second of playback, "
                      f"positive (default: 1); the animation may have at most {MOST_FRAMES} frames")
    anim.add_argument("--exaggerate", type=POSITIVE, default=1.0, metavar="K",
                      help="draw each block's rotation and displacement since the start, on what it rests on (the "
                      "base or the block below), K times larger, K > 0 (default: 1); a block rocking on a corner "
                      "still stands on it")


#: most frames an animation may have (at 25 frames/s, 200 s of playback): each is held in memory for a GIF
MOST_FRAMES = 5000


def run(args) -> int:
    loaded = scene_and_settings(args)
    if loaded is None:
        return 2
    path, spec, settings = loaded
    if not movie_name_ok(args.out, "--out"):
        return 2
    movie = output_file(args.out, "--out")
    try:
        duration = run_duration(spec.excitation, settings.get("duration"))
    except (TypeError, ValueError) as exc:
        print(f"error: {path}: {exc}", file=sys.stderr)
        return 2
    frames = duration * args.fps / args.speed + 1
    if frames > MOST_FRAMES:
        print(f"error: --speed {args.speed:g} at --fps {args.fps}: the animation of {duration:.4g} s would have "
              f"{frames:.3g} frames, more than {MOST_FRAMES}: raise --speed, lower --fps or shorten --duration",
              file=sys.stderr)
        return 2
    settings["output_dt"] = min(settings.get("output_dt", 0.01), args.speed / args.fps)
    print(f"scene {path} ({len(spec.scene.blocks)} blocks), ground motion: {motion_text(spec.excitation)}")
    args.on_interrupt = lambda: f"nothing was written ({movie} is written whole or not at all)"
    status = 0
    try:
        result, _ = simulated(spec, settings)
    except SimulationUnstable as exc:
        INTERRUPTS.check()
        result, status = exc.partial, 3
        if result is None or len(result.t) == 0:
            print(f"error: {stopped_text(exc)}; nothing was written", file=sys.stderr)
            return 3
        print(f"error: {stopped_text(exc)}; animating up to t = {result.t[-1]:.4g} s", file=sys.stderr)
    except (TypeError, ValueError) as exc:
        print(f"error: {path}: {exc}", file=sys.stderr)
        return 2
    INTERRUPTS.check()
    write_animation(spec, result, movie, movie.with_name(movie.stem + "_snapshots.png"), path.stem, args.fps,
                     args.speed, args.exaggerate)
    return status
