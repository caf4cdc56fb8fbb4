"""How the readers of text files (scene, sweep and record files) word a file they cannot read and a name they
do not know."""

import difflib
from contextlib import contextmanager
from typing import Callable


@contextmanager
def file_errors(path, error: type[Exception], what: str, hint: Callable[[], str] | None = None):
    """Turn the errors of opening and decoding ``path`` inside the ``with`` block into ``error`` naming the
    file and saying why: no such ``what`` (followed by ``hint()`` if given), a folder, or not UTF-8 text."""
    try:
        yield
    except FileNotFoundError:
        raise error(f"{path}: no such {what}{hint() if hint else ''}") from None
    except IsADirectoryError:
        raise error(f"{path}: is a folder, not a {what}") from None
    except UnicodeDecodeError as exc:
        raise error(f"{path}: not a text file ({exc.reason} at byte {exc.start})") from None


def did_you_mean(names, allowed, prefix: str = "") -> str:
    """How an error suggests the nearest of ``allowed`` for each of ``names`` that it does not hold (close
    matches by :func:`difflib.get_close_matches`, ignoring case and leading ``prefix`` characters, such as an
    option's dashes, so that ``-integrater`` finds ``--integrator``; a name of 3 letters or fewer may differ by one):
    ``" (did you mean 'mode'?)"``, ``" (did you mean 'n_drums' for 'n_drum' and 'width' for 'widht'?)"``, or
    ``""`` when none is close."""
    names = [names] if isinstance(names, str) else sorted(names, key=str)
    by_lower = {str(a).lower().lstrip(prefix): str(a) for a in sorted(allowed, key=str)}

    def nearest(name):
        name = str(name).lower().lstrip(prefix)
        close = difflib.get_close_matches(name, by_lower, n=1, cutoff=0.5 if len(name) <= 3 else 0.6)
        return by_lower[close[0]] if close else None

    pairs = [(name, match) for name in names if (match := nearest(name)) is not None]
    if not pairs:
        return ""
    if len(names) == 1:
        return f" (did you mean {pairs[0][1]!r}?)"
    return f" (did you mean {' and '.join(f'{match!r} for {name!r}' for name, match in pairs)}?)"


def shown(value, width: int = 60) -> str:
    """``repr(value)`` as an error message shows it: cut to ``width`` characters, ending "..." where cut."""
    text = repr(value)
    return text if len(text) <= width else text[:width - 3] + "..."
