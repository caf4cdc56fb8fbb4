"""The harness' progress bars: on a terminal only (:func:`dem_core.cli.progress.interactive`), silent in a log."""

import sys

from tqdm import tqdm

from dem_core.cli.progress import interactive


def terminal_bar(iterable=None, *, progress: bool, **options) -> tqdm:
    """A tqdm bar over ``iterable`` (or with ``total=`` in ``options``) on stderr, disabled unless ``progress`` is
    asked and stderr is a terminal."""
    return tqdm(iterable, disable=not (progress and interactive()), file=sys.stderr, **options)
