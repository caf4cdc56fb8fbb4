"""Output files written whole or not at all, and output paths checked before the work that fills them.

:func:`replacing` has a file written under a temporary name beside it (``NAME.partial``) and renames it
over ``NAME`` (``os.replace``) only once it is complete: a full disk, a crash or Ctrl-C never leaves a
truncated file under the real name, and the file that was there before stays until the new one is whole.
Writers that choose their format by the file's suffix must be told the format (the temporary name ends in
``.partial``).

:func:`output_folder` and :func:`output_file` check an output path before a run starts (a folder that
exists or can be created, can be written in, and is not a file), so that a bad path is refused at once,
naming the option that gave it, and not after the whole simulation.
"""

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path

#: suffix of the temporary name a file is written under before it replaces the real one
PARTIAL = ".partial"


class OutputPathError(ValueError):
    """An output path that cannot be used (a file where a folder belongs, a folder that cannot be created or
    written in); the message names the option or argument that gave it, the path and why."""


class OutputWriteError(OSError):
    """Writing an output file failed (a full disk, a read-only file system); nothing partial is left under its
    name.  ``str()`` is one line naming the file: ``cannot write out/time_history.csv: No space left on device``."""

    def __init__(self, path, cause: OSError):
        super().__init__(cause.errno, reason(cause), str(path))
        self.path, self.cause = Path(path), cause

    def __str__(self):
        return f"cannot write {self.path}: {reason(self.cause)}"


def reason(exc: OSError) -> str:
    """What went wrong, in the system's words (``No space left on device``), without Python's decoration."""
    if exc.strerror:
        return exc.strerror
    if exc.errno:
        return os.strerror(exc.errno)
    return str(exc).splitlines()[0] if str(exc) else type(exc).__name__


def temporary_name(path) -> Path:
    """The name ``path`` is written under until it is complete: ``NAME.partial`` beside it."""
    path = Path(path)
    return path.with_name(path.name + PARTIAL)


@contextmanager
def replacing(path):
    """``with replacing(path) as tmp: write(tmp)``: ``path`` is replaced by what was written to ``tmp`` when
    the block ends without an error; on any error or interruption ``tmp`` is removed and ``path`` is left as
    it was.  An ``OSError`` (a full disk) is raised as :class:`OutputWriteError`, naming ``path``."""
    path = Path(path)
    tmp = temporary_name(path)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            tmp.unlink(missing_ok=True)
        except OSError:
            pass
        if isinstance(exc, OSError) and not isinstance(exc, OutputWriteError):
            raise OutputWriteError(path, exc) from exc
        raise


def output_folder(path, option: str = "output folder") -> Path:
    """``path`` as a folder that exists (created with its parents if need be) and can be written in.

    :class:`OutputPathError` (``"--out results/a: is a file, not a folder"``) when it is a file, lies under
    a file, or cannot be created or written in (a read-only file system, no permission); ``option``
    names what gave the path.
    """
    path = Path(path)
    _check_folder(path, f"{option} {path}")
    return path


def output_file(path, option: str = "output file") -> Path:
    """``path`` as a file that can be written: not a folder, its folder created and writable (as
    :func:`output_folder`); :class:`OutputPathError` naming ``option`` otherwise."""
    path = Path(path)
    where = f"{option} {path}"
    if path.is_dir():
        raise OutputPathError(f"{where}: is a folder: give a file name")
    _check_folder(path.parent, f"{where}: its folder {path.parent}" if str(path.parent) != "." else where)
    return path


def _check_folder(path: Path, where: str) -> None:
    if path.exists() and not path.is_dir():
        raise OutputPathError(f"{where}: is a file, not a folder")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):
        raise OutputPathError(f"{where}: {_file_above(path)} is a file, not a folder") from None
    except OSError as exc:
        raise OutputPathError(f"{where}: cannot create the folder: {reason(exc)}") from None
    try:
        handle, probe = tempfile.mkstemp(dir=path, prefix=".dem-core-write-test-")
    except OSError as exc:
        raise OutputPathError(f"{where}: cannot write in this folder: {reason(exc)}") from None
    os.close(handle)
    os.unlink(probe)


def _file_above(path: Path) -> Path:
    """The nearest of ``path`` and its parents that exists and is not a folder (``path`` if none is found)."""
    for candidate in (path, *path.parents):
        if candidate.exists() and not candidate.is_dir():
            return candidate
    return path
