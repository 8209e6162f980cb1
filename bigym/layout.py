"""Named layouts of flat vectors (actions, proprioception): which entry means what."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class LayoutEntry:
    """One named element of a vector, with its bounds and unit for the docs."""

    name: str
    index: int
    low: float
    high: float
    unit: str = ""
    group: str = ""


class Layout:
    """An ordered table of entries; ``layout["left_elbow"]`` is an index, ``layout.group("base")`` a slice."""

    def __init__(self, entries: list[LayoutEntry]) -> None:
        self.entries = tuple(entries)
        self._index = {e.name: e.index for e in entries}
        self._groups: dict[str, slice] = {}
        for entry in entries:
            if entry.group:
                current = self._groups.get(entry.group)
                start = entry.index if current is None else current.start
                self._groups[entry.group] = slice(start, entry.index + 1)

    def __len__(self) -> int:
        return len(self.entries)

    def __getitem__(self, name: str) -> int:
        try:
            return self._index[name]
        except KeyError:
            raise KeyError(f"no entry {name!r}; entries: {', '.join(self.names)}") from None

    def __contains__(self, name: str) -> bool:
        return name in self._index

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(e.name for e in self.entries)

    @property
    def groups(self) -> dict[str, slice]:
        return dict(self._groups)

    def group(self, name: str) -> slice:
        """The contiguous slice of a group such as ``"base"``, ``"left_arm"`` or ``"grippers"``."""
        try:
            return self._groups[name]
        except KeyError:
            raise KeyError(f"no group {name!r}; groups: {', '.join(self._groups)}") from None

    def table(self) -> str:
        """A Markdown table of the layout, for docs and ``bigym`` CLI output."""
        lines = ["| index | name | group | low | high | unit |", "|---|---|---|---|---|---|"]
        for e in self.entries:
            lines.append(f"| {e.index} | {e.name} | {e.group} | {e.low:g} | {e.high:g} | {e.unit} |")
        return "\n".join(lines)
