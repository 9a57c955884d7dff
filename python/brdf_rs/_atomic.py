"""Atomic file writes: every file the package writes goes through :func:`atomic_write`.

The new content is written to a temporary file of its own in the target's folder (a
fresh name per write, so writers in several processes or threads never share one),
flushed to disk, and renamed onto the target with ``os.replace``, which is atomic on one
file system. The target therefore holds either its old content or the whole new one:
never a half-written file, also after a crash, a full disk, Ctrl-C, or when several
processes write it at once (the last rename wins). On any failure the temporary file is
removed and the target left as it was, and an ``OSError`` names the target the caller
gave, not the temporary file.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["atomic_write", "save_npz"]


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yields the path of a new, empty temporary file for the caller to write ``path``'s
    content into; when the block ends without an exception the file replaces ``path``.

    The temporary file sits in ``path``'s folder (a rename across file systems would not
    be atomic), is hidden (a leading dot) and ends in ``path``'s suffix, so writers that
    choose a format by the suffix see the right one. An existing ``path`` keeps its
    permission bits; a new one gets the usual ones (``0o666`` less the umask).
    """
    path = Path(path)
    tmp = _create_temporary(path)
    try:
        yield tmp
        _flush_to_disk(tmp)
        _copy_mode(path, tmp)
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        if isinstance(exc, OSError):
            raise _naming(exc, path, tmp) from None
        raise


def save_npz(path: str | os.PathLike[str], **arrays: Any) -> None:
    """Writes ``arrays`` as a compressed ``.npz`` at ``path`` (exactly that name: NumPy
    appends ``.npz`` only to names, never to open files), atomically."""
    with atomic_write(path) as tmp, open(tmp, "wb") as f:
        np.savez_compressed(f, **arrays)


def _create_temporary(path: Path) -> Path:
    """Creates a new empty file with a name no other writer uses, next to ``path``."""
    stem = path.stem[:64]  # room for the random part within a file system's name limit
    for _ in range(100):
        tmp = path.with_name(f".{stem}.{secrets.token_hex(8)}.tmp{path.suffix}")
        try:
            flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
            fd = os.open(tmp, flags, 0o666)  # less the umask, as open() would give
        except FileExistsError:
            continue
        except OSError as exc:
            raise _naming(exc, path, tmp) from None
        os.close(fd)
        return tmp
    raise FileExistsError(f"{path}: could not create a temporary file next to it")


def _flush_to_disk(tmp: Path) -> None:
    """Asks the OS to put the file's content on disk before it is renamed into place (a
    rename that reaches the disk before the data would leave an empty file after a power
    cut)."""
    fd = os.open(tmp, os.O_RDWR | getattr(os, "O_BINARY", 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _copy_mode(path: Path, tmp: Path) -> None:
    """Gives ``tmp`` the permission bits of an existing regular file at ``path``."""
    try:
        st = os.stat(path)
    except OSError:
        return
    if stat.S_ISREG(st.st_mode):
        os.chmod(tmp, stat.S_IMODE(st.st_mode))


def _naming(exc: OSError, path: Path, tmp: Path) -> OSError:
    """``exc`` saying ``path`` where it said the temporary file (or no file at all)."""
    if exc.errno is None or exc.filename not in (None, str(tmp), tmp):
        return exc
    renamed = OSError(exc.errno, exc.strerror, os.fspath(path))  # the errno's subclass
    return renamed.with_traceback(exc.__traceback__)
