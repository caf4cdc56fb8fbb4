"""The command line's arguments: the parser, the types that check every number given, and the SCENE argument.

:class:`Parser` is argparse with an error as one line naming the option, returned by ``main`` as exit status 2,
and with every option's default shown in ``--help``; the ``type`` callables here refuse NaN, infinities and
values out of range before any run starts.
"""

import argparse
import math
import sys
from importlib import resources
from pathlib import Path

from ..engine.settings import INTEGRATORS
from ..inputs.scene_file import SceneFileError, load
from ..inputs.text_files import did_you_mean

DEFAULT_SCENE = "column_el_centro.toml"


def default_scene_path() -> Path:
    return Path(str(resources.files("dem_core") / "data" / "scenes" / DEFAULT_SCENE))


class ArgumentError(Exception):
    """A command line argparse refuses; ``main`` prints it as one line and returns 2.  ``reason``: argparse's
    message, without the pointer to the help."""

    def __init__(self, reason: str, prog: str):
        super().__init__(f"{reason} (see {prog} --help)")
        self.reason = reason


class HelpFormatter(argparse.HelpFormatter):
    """argparse's help with every option's default shown: "(default: X)" is added to the help of an option
    that has a default and whose help does not already say it (an option without one says in its help
    what it falls back to: the scene file, the record)."""

    def _get_help_string(self, action):
        text = action.help or ""
        default = action.default
        if ("default" in text or default is None or default is False or default is argparse.SUPPRESS
                or action.nargs == 0 or not (action.option_strings or action.nargs in ("?", "*"))):
            return text
        shown = " ".join(f"{v:g}" if isinstance(v, float) else str(v) for v in default) \
            if isinstance(default, (list, tuple)) else (f"{default:g}" if isinstance(default, float) else default)
        return f"{text} (default: {shown})".lstrip()


class Parser(argparse.ArgumentParser):
    """argparse, with an error as one line naming the option (no usage block) returned by ``main`` as 2
    rather than a ``SystemExit`` (``--help`` still exits), and every default shown in ``--help``."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message):
        raise ArgumentError(message, self.prog)

    def parse_args(self, args=None, namespace=None):
        """As argparse's, except that arguments a command does not know are refused by that command's parser,
        whose ``--help`` lists the options it does know, and the nearest of those options is suggested for a
        mistyped one."""
        given = sys.argv[1:] if args is None else list(args)
        at = _single_dash_words(given)
        words = [given[i] for i in at]
        refused = ""
        try:
            parsed, unknown = self.parse_known_args([a for i, a in enumerate(given) if i not in at], namespace)
        except ArgumentError as error:
            if not words:
                raise
            parsed, unknown, refused = None, [], f"; {error.reason}"  # perhaps for want of a word (-out o)
        unknown = words + unknown
        if unknown:
            commands = [a for a in self._actions if isinstance(a, argparse._SubParsersAction)]
            name = next((a for a in given if commands and a in commands[0].choices), None)
            after_name = name is not None and not set(unknown) & set(given[:given.index(name)])
            parser = commands[0].choices[name] if after_name else self
            options = [option for action in parser._actions for option in action.option_strings]
            typed = [u.split("=", 1)[0] for u in unknown if u[:1] == "-" and u.lstrip("-")[:1].isalpha()]
            near = did_you_mean(typed, options, prefix="-")
            parser.error(f"unrecognized arguments: {' '.join(unknown)}{near}{refused}")
        return parsed


def _single_dash_words(given: list) -> list:
    """The positions in ``given`` of the arguments before any ``--`` that are a single dash and a word (-heigth,
    -out), which argparse would read as -h with the argument "eigth", or take for a value: not numbers (-inf), nor
    values with a space."""
    at = []
    for i, argument in enumerate(given):
        if argument == "--":
            break
        head = argument.split("=", 1)[0]
        if head[:1] == "-" and head[1:2].isalpha() and len(head) > 2 and " " not in argument:
            try:
                float(argument)
            except ValueError:
                at.append(i)
    return at


def _number(parse, test, requirement: str):
    """An argparse ``type`` that parses with ``parse`` and refuses values failing ``test``: NaN, infinities and
    values out of range never reach a run.  The message names the option: ``argument --rate: must be a positive,
    finite number (m/s^2 per s), got 0``."""
    def check(text):
        try:
            value = parse(text)
        except (TypeError, ValueError):
            raise argparse.ArgumentTypeError(f"expected {requirement}, got {text!r}") from None
        if not test(value):
            raise argparse.ArgumentTypeError(f"must be {requirement}, got {text}")
        return value

    return check


def _finite_positive(value) -> bool:
    return math.isfinite(value) and value > 0


SECONDS = _number(float, _finite_positive, "a positive, finite number of seconds")
POSITIVE = _number(float, _finite_positive, "a positive, finite number")
RATE = _number(float, _finite_positive, "a positive, finite number (m/s^2 per s)")
WORKERS = _number(int, lambda v: v >= 1, "a whole number of at least 1")
#: frames per second of an animation: GIF players honour at most 100
FPS = _number(int, lambda v: 1 <= v <= 100, "a whole number from 1 to 100")
SCALES = _number(int, lambda v: 2 <= v <= 1000, "a whole number from 2 to 1000")
LEVELS = _number(int, lambda v: 2 <= v <= 100_000, "a whole number from 2 to 100000")
STATE = _number(float, lambda v: 0 < v <= 1, "a number above 0 and at most 1")
FRACTION = _number(float, lambda v: 0 < v < 1, "a number between 0 and 1 (both excluded)")
REST = _number(float, lambda v: math.isfinite(v) and v >= 0, "a finite number of seconds, at least 0")
DAMPING = _number(float, lambda v: 0 <= v < 1, "a damping ratio from 0 up to (not including) 1")


def add_integrator(command) -> None:
    """The ``--integrator`` option of a command that runs scenes: the same choices, default and words everywhere."""
    command.add_argument("--integrator", choices=INTEGRATORS, help="moreau, Moreau-Jean's velocity-level steps on "
                         "rigid contacts, or explicit, central differences on the contact springs (docs/method.md "
                         "1.8; default: the scene file's [simulation] integrator, else moreau, or explicit for the "
                         "overlap-area law)")


def add_no_progress(command) -> None:
    """The ``--no-progress`` option of a command with a bar over its runs."""
    command.add_argument("--no-progress", action="store_true", help="no progress shown: neither the bar on a "
                         "terminal nor the progress lines in a log or a pipe")


def with_integrator(settings: dict, args) -> dict:
    """``settings`` (a scene file's [simulation]) with the command's ``--integrator`` where it has one and it is
    given."""
    chosen = getattr(args, "integrator", None)
    return {**settings, "integrator": chosen} if chosen is not None else dict(settings)


def load_or_fail(path):
    """The scene file at ``path``, or None after printing why it cannot be read."""
    try:
        return load(path)
    except SceneFileError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return None


def scene_and_settings(args):
    """(path, scene file, simulate settings with --duration and --integrator applied) of a command's SCENE argument
    (the bundled default if none), or None after printing why it cannot be read."""
    path = Path(args.scene) if args.scene else default_scene_path()
    spec = load_or_fail(path)
    if spec is None:
        return None
    settings = with_integrator(spec.simulation, args)
    if args.duration is not None:
        settings["duration"] = args.duration
    return path, spec, settings
