"""Atomic file writes: a reader sees the old file or the complete new one, never a part.

Data goes to a hidden temporary file in the destination folder, is flushed and fsynced,
then :func:`os.replace` renames it over the destination (atomic on POSIX and Windows
within one file system). A writer killed before the rename leaves only its temporary
file, which no loader treats as an entry and :func:`sweep_partial_files` removes once
its writer process is gone.
"""

from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import BinaryIO

_PARTIAL_PREFIX = ".partial-"
_PARTIAL_SUFFIX = ".tmp"


def partial_path(path: Path) -> Path:
    """A fresh temporary name beside ``path``; it records the writer's pid."""
    return path.with_name(f"{_PARTIAL_PREFIX}{os.getpid()}-{secrets.token_hex(4)}-{path.name}{_PARTIAL_SUFFIX}")


def is_partial(path: Path | str) -> bool:
    """True for the temporary file of an unfinished (or killed) atomic write."""
    name = Path(path).name
    return name.startswith(_PARTIAL_PREFIX) and name.endswith(_PARTIAL_SUFFIX)


@contextlib.contextmanager
def atomic_open(path: Path | str) -> Iterator[BinaryIO]:
    """Open ``path`` for binary writing so that it appears complete or not at all."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = partial_path(path)
    try:
        with open(tmp, "wb") as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
        raise
    _fsync_folder(path.parent)


def atomic_write(path: Path | str, data: bytes | Callable[[BinaryIO], None]) -> Path:
    """Write ``data`` (bytes, or a function writing to a binary file) to ``path`` atomically."""
    path = Path(path)
    with atomic_open(path) as handle:
        if callable(data):
            data(handle)
        else:
            handle.write(data)
    return path


def _fsync_folder(folder: Path) -> None:
    """Make the rename itself durable (best effort: not every platform opens folders)."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _writer_alive(path: Path) -> bool:
    try:
        pid = int(path.name[len(_PARTIAL_PREFIX) :].split("-", 1)[0])
    except ValueError:
        return False
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def sweep_partial_files(folder: Path | str) -> list[Path]:
    """Delete the temporary files of writers that died mid-write under ``folder``; return them."""
    folder = Path(folder)
    removed: list[Path] = []
    if not folder.is_dir():
        return removed
    for path in folder.rglob(f"{_PARTIAL_PREFIX}*{_PARTIAL_SUFFIX}"):
        if not _writer_alive(path):
            with contextlib.suppress(FileNotFoundError):
                path.unlink()
                removed.append(path)
    return removed
