"""Pool workers that end with the process that started them.

A process killed without closing its pool (``kill``, ``timeout``'s SIGTERM, an out-of-memory
kill) leaves its spawn workers behind: they finish their current job for nobody and then
wait forever for the next, each holding an env and its memory. Every bigym process pool
starts its workers with :func:`exit_with_parent`.
"""

from __future__ import annotations

import multiprocessing
import os
import threading


def exit_with_parent() -> None:
    """In a multiprocessing child: end this process as soon as its parent has ended."""
    parent = multiprocessing.parent_process()  # None outside multiprocessing (a Ray actor)
    if parent is None:
        return

    def watch() -> None:
        parent.join()  # returns when the parent's end of the pipe closes: it has exited
        os._exit(1)

    threading.Thread(target=watch, name="bigym-exit-with-parent", daemon=True).start()
