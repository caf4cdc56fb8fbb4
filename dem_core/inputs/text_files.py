"""How the readers of text files (scene, sweep and record files) word a file they cannot read."""

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
