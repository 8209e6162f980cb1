"""Environment variables for the worker processes a pool is about to spawn."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator


@contextlib.contextmanager
def child_environment(settings: dict[str, str]) -> Iterator[dict[str, str]]:
    """Set ``settings`` in ``os.environ`` while worker processes are started (spawned
    children inherit it), and restore the previous values afterwards."""
    previous = {name: os.environ.get(name) for name in settings}
    os.environ.update(settings)
    try:
        yield settings
    finally:
        for name, value in previous.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
