"""Where bigym keeps files it can regenerate (mesh caches, demos)."""

from __future__ import annotations

import os
from pathlib import Path


def bigym_home() -> Path:
    """The cache root: ``$BIGYM_HOME`` if set, else ``~/.cache/bigym``."""
    root = os.environ.get("BIGYM_HOME")
    return Path(root).expanduser() if root else Path.home() / ".cache" / "bigym"
