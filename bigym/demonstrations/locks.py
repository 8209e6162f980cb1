"""Locks for stores that several processes write: one writer at a time, or a clear refusal.

* :func:`file_lock`: an advisory lock on a local file (``fcntl.flock``). Waiters block
  until the holder is done; the kernel drops the lock of a process that dies, so a killed
  writer never leaves a store locked.
* :func:`remote_lease`: object stores (s3, gcs, hf, ...) have no such lock, and fsspec
  offers no write-if-absent. A writer there takes a *lease*: a small file naming it and
  when it started. A second writer that finds a fresh lease is refused with a
  :class:`~bigym.demonstrations.errors.DemoStoreBusyError` saying who holds it, instead
  of silently overwriting the first writer's manifest. A lease older than ``stale_after``
  seconds (its writer died) is taken over.
"""

from __future__ import annotations

import contextlib
import json
import os
import secrets
import socket
import time
from collections.abc import Callable, Iterator
from pathlib import Path

from bigym.demonstrations.errors import DemoStoreBusyError

#: seconds after which a remote lease whose writer never released it counts as abandoned
LEASE_STALE_AFTER = 600.0


@contextlib.contextmanager
def file_lock(path: Path | str, on_wait: Callable[[], None] | None = None) -> Iterator[None]:
    """Hold an exclusive advisory lock on ``path`` (created if absent).

    ``on_wait`` is called once if another process holds the lock, before blocking on it
    (to say why nothing seems to happen). Without ``fcntl`` (Windows) a single writer is
    assumed.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        import fcntl
    except ImportError:
        yield
        return
    with open(path, "a") as handle:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            if on_wait is not None:
                on_wait()
            fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def writer_name() -> str:
    """Who is writing: host and process, for error messages."""
    return f"{socket.gethostname()} pid {os.getpid()}"


@contextlib.contextmanager
def remote_lease(fs, path: str, url: str, stale_after: float = LEASE_STALE_AFTER) -> Iterator[None]:
    """Hold the write lease ``path`` on the fsspec file system ``fs`` (the store ``url``).

    Refuses with :class:`DemoStoreBusyError` while another writer's lease is fresh. The
    lease is written, then read back: of two writers that wrote it at the same moment,
    only the one whose token survived goes on.
    """
    token = secrets.token_hex(8)
    holder = _read_lease(fs, path)
    if holder is not None:
        age = time.time() - float(holder.get("since", 0.0))
        if age < stale_after:
            raise DemoStoreBusyError(_busy_message(url, path, holder, age, stale_after), holder=holder)
    lease = {"token": token, "writer": writer_name(), "since": time.time()}
    fs.pipe_file(path, json.dumps(lease).encode())
    holder = _read_lease(fs, path)
    if holder is None or holder.get("token") != token:
        raise DemoStoreBusyError(_busy_message(url, path, holder or {}, 0.0, stale_after), holder=holder)
    try:
        yield
    finally:
        if (_read_lease(fs, path) or {}).get("token") == token:
            with contextlib.suppress(FileNotFoundError):
                fs.rm_file(path)


def _read_lease(fs, path: str) -> dict | None:
    try:
        return json.loads(fs.cat_file(path))
    except FileNotFoundError:
        return None
    except (ValueError, UnicodeDecodeError):
        return {"writer": "unknown (unreadable lease)", "since": 0.0}


def _busy_message(url: str, path: str, holder: dict, age: float, stale_after: float) -> str:
    return (
        f"{url} is being written by {holder.get('writer', 'another writer')} (for {age:.0f} s); bigym refuses "
        "concurrent writes to a remote store, which could lose each other's manifest entries. Try again when it "
        f"is done; a lease older than {stale_after:.0f} s is taken over, or delete {path} if that writer is gone"
    )


__all__ = ["LEASE_STALE_AFTER", "file_lock", "remote_lease", "writer_name"]
