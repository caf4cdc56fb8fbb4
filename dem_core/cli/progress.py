"""Progress: bars over runs and over a run's steps, and the announcement of the engine's compiling.

Bars show where stderr is a terminal; elsewhere (a log, CI) a command's bar over its runs writes a line every
:data:`LOG_EVERY_S` s instead.  The callback every run gets also raises, between a run's chunks, a Ctrl-C that
came while the compiled driver ran (:mod:`.interrupts`).
"""

import sys
import threading
import time
import warnings

from .. import simulate
from .interrupts import INTERRUPTS


def interactive() -> bool:
    """Whether progress bars are wanted: stderr is a terminal, not a log file or a CI pipe."""
    return sys.stderr.isatty()


#: s between the progress lines written where stderr is not a terminal (a log, a CI pipe)
LOG_EVERY_S = 10.0


def progress_bar(**options):
    """A tqdm bar on a terminal; elsewhere (a log, a CI pipe) a :class:`ProgressLines` with the same options."""
    if not interactive():
        return ProgressLines(**options)
    from tqdm import tqdm

    return tqdm(**options)


class ProgressLines:
    """The part of a tqdm bar the commands use (``n``, ``total``, :meth:`update`, :meth:`set_postfix_str`,
    :meth:`close`, a context) as a line on stderr every :data:`LOG_EVERY_S` s and one at the end: what is done of
    the total, the time so far and, from the rate so far, the time left ("runs: 120 of 1600 (7.5%), 45 s,
    about 9.2 min left"; a bar whose ``bar_format`` shows no count gives its share alone: "runs: 29.4%, ...")."""

    def __init__(self, total=None, desc: str = "", unit: str = "it", initial: int = 0, disable: bool = False,
                 bar_format: str | None = None, clock=time.perf_counter, **_):
        self.total, self.desc, self.unit, self.n, self.postfix, self.clock = total, desc, unit, initial, "", clock
        # a bar whose format shows no count (its steps are weights: stiffness) writes its share alone, as tqdm does
        self.counts = bar_format is None or "{n" in bar_format or "{total" in bar_format
        self.disable = disable
        self.started = self.said = clock()
        self.initial = self.n_said = initial

    def __enter__(self):
        return self

    def __exit__(self, *_) -> None:
        self.close()

    def update(self, n=1) -> None:
        self.n += n
        if self.clock() - self.said >= LOG_EVERY_S:
            self._say()

    def set_postfix_str(self, text: str) -> None:
        self.postfix = text

    def close(self) -> None:
        if self.n != self.n_said:
            self._say(ended=True)

    def _say(self, ended: bool = False) -> None:
        self.said, self.n_said = self.clock(), self.n
        if self.disable:
            return
        took = self.said - self.started
        if not self.total:
            done = f"{self.n:g}"
        elif self.counts:
            done = f"{self.n:g} of {self.total:g} ({100 * self.n / self.total:.1f}%)"
        else:
            done = f"{100 * self.n / self.total:.1f}%"
        left = ""
        if not ended and self.total and self.initial < self.n < self.total:
            left = f", about {_duration(took * (self.total - self.n) / (self.n - self.initial))} left"
        extra = f"; {self.postfix}" if self.postfix else ""
        print(f"{self.desc or self.unit}: {done}, {_duration(took)}{left}{extra}", file=sys.stderr, flush=True)


def _duration(seconds: float) -> str:
    return f"{seconds:.0f} s" if seconds < 120 else f"{seconds / 60:.1f} min"


def simulate_options(settings: dict, *, progress: bool = True) -> dict:
    """The keyword arguments of every ``simulate`` call the command line makes, directly or through
    an analysis: the one place where run-wide options are added.  ``progress``: a bar with the time
    left for each long run, shown only on a terminal (commands that run many short runs have their
    own bar over the runs and pass False).  The progress callback is always given: between a run's
    chunks it raises a Ctrl-C that came while the compiled driver ran (:class:`~.interrupts.Interrupts`)."""
    return {**settings, "progress": progress_callback(progress)}


def progress_callback(progress: bool = True):
    """``simulate``'s ``progress``: a bar on a terminal (when ``progress``), and the check for a held-back Ctrl-C."""
    bar = StepProgress() if progress and sys.stderr.isatty() else None

    def report(done: int, total: int):
        INTERRUPTS.check()
        if bar is not None:
            bar(done, total)

    return report


class StepProgress:
    """``simulate``'s progress callback as a tqdm bar over simulated seconds; a new bar for each run."""

    def __init__(self):
        self.bar = None

    def __call__(self, done: int, total: int):
        from tqdm import tqdm

        if self.bar is None or done < self.bar.n or total != self.bar.total:
            if self.bar is not None:
                self.bar.close()
            self.bar = tqdm(total=total, desc="simulating", unit="step", unit_scale=True, leave=False)
        self.bar.update(done - self.bar.n)
        if done >= total and self.bar is not None:
            self.bar.close()


#: s: setting a run up (compiling the engine, or loading it from numba's cache) that takes longer than this is
#: announced while it goes on, and its time printed when it ends (a first run compiles for a few minutes, silently:
#: numba says nothing while it compiles, so the notice says how long to expect)
COMPILE_NOTICE_S = 2.0
COMPILING = "compiling the engine (once, a few minutes; cached for later runs) ..."


class CompileNotice:
    """A context for a run's set-up: it prints :data:`COMPILING` on stderr once the set-up has taken
    :data:`COMPILE_NOTICE_S`, and, when the set-up ends (:meth:`finish`, at the latest the context's end), how long
    it took; ``seconds`` is that time, whether announced or not."""

    def __init__(self):
        self.seconds = None
        self.shown = False

    def __enter__(self):
        self.started = time.perf_counter()
        self.timer = threading.Timer(COMPILE_NOTICE_S, self._show)
        self.timer.daemon = True
        self.timer.start()
        return self

    def _show(self):
        self.shown = True
        print(COMPILING, file=sys.stderr, flush=True)

    def finish(self, announce: bool = True) -> None:
        """The set-up ended (once: later calls do nothing); its time said where it was announced."""
        if self.seconds is not None:
            return
        self.timer.cancel()
        self.timer.join()
        self.seconds = time.perf_counter() - self.started
        if self.shown and announce:
            print(f"done in {self.seconds:.0f} s", file=sys.stderr, flush=True)

    def __exit__(self, *exc):
        self.finish(announce=exc[0] is None)
        return False


def compile_first(scene, excitation, settings: dict) -> None:
    """Compile the engine (or load it from numba's cache) before a command's runs, announced when that takes
    long: a run of ``scene`` one step long.  Whatever it meets (a bad setting, a warning, an unstable step) is
    left for the runs themselves to report."""
    options = {k: v for k, v in settings.items() if k not in ("duration", "output_dt", "progress")}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with CompileNotice():
                simulate(scene, excitation, duration=1e-9, **options)
    except Exception:  # noqa: BLE001 - the runs report it
        pass
