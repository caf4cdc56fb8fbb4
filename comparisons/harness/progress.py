"""The harness' progress bars: shown on a terminal, silent in a log or a CI pipe."""

import sys

from tqdm import tqdm


def bar(iterable=None, *, progress: bool, **options) -> tqdm:
    """A tqdm bar over ``iterable`` (or with ``total=`` in ``options``) on stderr, disabled unless ``progress`` is
    asked and stderr is a terminal."""
    return tqdm(iterable, disable=not (progress and sys.stderr.isatty()), file=sys.stderr, **options)
