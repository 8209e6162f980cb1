"""Shipped datasets: versions of demos that a store can complete on demand, byte for byte.

A shipped dataset version is a manifest (every file's path, size and sha256, in the
installed package) and a *recipe* that rebuilds any of its files deterministically. A
store that lacks a task's demos completes that task's slice from the recipe (or from a
hosted copy) instead of failing: see :mod:`bigym.demonstrations.provision`.

Recipes are found through the ``bigym.datasets`` entry-point group: the entry's name is
the dataset version, its value a callable that returns a :class:`DatasetRecipe`. bigym's
own (``v2``) is its experts' recipe; another package can ship a dataset the same way. The
demonstration system knows only this protocol, not who produces the demos.
"""

from __future__ import annotations

import functools
from collections.abc import Iterator
from importlib.metadata import entry_points
from typing import Protocol, runtime_checkable

from bigym.demonstrations.store import Manifest, ManifestEntry

ENTRY_POINT_GROUP = "bigym.datasets"


@runtime_checkable
class DatasetRecipe(Protocol):
    """How to rebuild the files of one dataset version."""

    version: str

    def manifest(self) -> Manifest:
        """Every file of the version: path, size, sha256 and metadata."""
        ...

    def estimate_seconds(self, task: str, entries: list[ManifestEntry], workers: int) -> float | None:
        """About how long building ``entries`` (of ``task``) takes with ``workers`` processes."""
        ...

    def build(self, task: str, entries: list[ManifestEntry], workers: int) -> Iterator[tuple[ManifestEntry, bytes]]:
        """Rebuild ``entries`` (all of ``task``), yielding each file's bytes as it is made,
        in any order. The caller checks every file against its entry."""
        ...


@functools.cache
def find_recipe(version: str) -> DatasetRecipe | None:
    """The recipe installed for dataset ``version``, or None."""
    for entry in entry_points(group=ENTRY_POINT_GROUP):
        if entry.name == version:
            recipe = entry.load()()
            if not isinstance(recipe, DatasetRecipe) or recipe.version != version:
                raise TypeError(f"the {ENTRY_POINT_GROUP} entry point {entry.value!r} is not a recipe of {version}")
            return recipe
    return None


__all__ = ["ENTRY_POINT_GROUP", "DatasetRecipe", "find_recipe"]
