"""Contact queries for success and failure checks: read the contacts once per step, answer many.

Why: a task's checks ask several "does anything of A touch anything of B?" questions per
step. Reading ``data.contact`` and testing geom membership for each question cost 5-6 us
apiece, more than the physics step itself on some tasks. Here every geom set a task uses
gets one bit; each geom carries the bits of the sets it belongs to. Once per step the
contacts are reduced to the few distinct (bits of geom 1, bits of geom 2) pairs among
registered geoms, and each question is then a scan of those pairs in plain Python.

Sets are registered once, when a task binds (at most 31 per env: two labels fold into one int64);
a set made later, or beyond that number, still works through the slower mask test.
"""

from __future__ import annotations

from collections.abc import Iterable

import mujoco
import numpy as np

from bigym.hotloop import label_pairs_function

MAX_BITS = 31  # two labels fold into one int64
_LOW_BITS = (1 << MAX_BITS) - 1


class GeomSet:
    """A set of geom ids, as a boolean mask over the model's geoms and, when registered, a bit."""

    __slots__ = ("_contacts", "bit", "mask")

    def __init__(self, contacts: ContactState, mask: np.ndarray, bit: int) -> None:
        self._contacts = contacts
        self.mask = mask
        self.bit = bit

    @property
    def ids(self) -> np.ndarray:
        return np.flatnonzero(self.mask)

    def __or__(self, other: GeomSet) -> GeomSet:
        if not isinstance(other, GeomSet):
            return NotImplemented
        return self._contacts.geom_set(np.flatnonzero(self.mask | other.mask))

    def __len__(self) -> int:
        return int(self.mask.sum())

    def __repr__(self) -> str:
        return f"GeomSet({self.ids.tolist()}, bit={self.bit})"


class ContactState:
    """The active contacts of one MjData, as seen by registered geom sets.

    Outside :meth:`hold` every query reads ``data.contact`` afresh, so code that edits the
    state and calls ``mj_forward`` between queries always sees the current contacts.
    Between :meth:`hold` and :meth:`release` (the env's success and failure checks) the
    contacts are read once and shared by all queries.
    """

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        self._model = model
        self._data = data
        self._labels = np.zeros(model.ngeom, np.int64)
        self._next_bit = 0
        # Contacts are generated up to a geom's margin; only those at distance <= 0 touch.
        # With no margins anywhere every generated contact touches: skip the distance test.
        self._check_distance = bool(np.any(model.geom_margin > 0))
        self._held = False
        self._pairs: tuple[tuple[int, int], ...] | None = None
        self._geoms: np.ndarray | None = None
        self._compiled_pairs = label_pairs_function()  # the same reduction in C (bigym.hotloop), or None
        self._labels_address = int(self._labels.ctypes.data)  # geom_set updates the labels in place

    def geom_set(self, geom_ids: Iterable[int]) -> GeomSet:
        """Register a geom set (do it once, at bind time) and return it."""
        mask = np.zeros(self._model.ngeom, dtype=bool)
        ids = np.asarray(list(geom_ids), dtype=np.int64)
        if ids.size and (ids.min() < 0 or ids.max() >= self._model.ngeom):
            raise ValueError(f"geom ids out of range [0, {self._model.ngeom}): {ids.tolist()}")
        mask[ids] = True
        bit = 0
        if self._next_bit < MAX_BITS:
            bit = 1 << self._next_bit
            self._next_bit += 1
            self._labels[mask] |= bit
            self._pairs = None
        return GeomSet(self, mask, bit)

    # ------------------------------------------------------------------ per-step sharing
    def hold(self) -> None:
        """Share one reading of the contacts among the queries until :meth:`release`."""
        self._held = True
        self._pairs = self._geoms = None

    def release(self) -> None:
        self._held = False
        self._pairs = self._geoms = None

    # ------------------------------------------------------------------ reading
    def _active_geoms(self) -> np.ndarray:
        """(n, 2) geom ids of the touching contacts."""
        if self._held and self._geoms is not None:
            return self._geoms
        data = self._data
        n = data.ncon
        contact = data.contact
        geoms = contact.geom[:n]
        if self._check_distance and n:
            geoms = geoms[contact.dist[:n] <= 0.0]
        if self._held:
            self._geoms = geoms
        return geoms

    def _label_pairs(self) -> tuple[tuple[int, int], ...]:
        if self._held and self._pairs is not None:
            return self._pairs
        pairs = self._compiled_label_pairs() if self._compiled_pairs is not None else None
        if pairs is None:
            pairs = self._python_label_pairs()
        if self._held:
            self._pairs = pairs
        return pairs

    def _compiled_label_pairs(self) -> tuple[tuple[int, int], ...] | None:
        """The distinct label pairs from C, or ``None`` when there are too many for it."""
        contact = self._data.contact  # the ncon active contacts
        return self._compiled_pairs(self._labels_address, contact.geom, contact.dist if self._check_distance else None)

    def _python_label_pairs(self) -> tuple[tuple[int, int], ...]:
        labels = self._labels.take(self._active_geoms())
        first, second = labels[:, 0], labels[:, 1]
        # Most contacts involve an unregistered geom (robot links, walls) and the rest repeat a
        # few label pairs (a mug's rim on a rack: dozens of contacts): drop the former in
        # numpy and fold each pair into one int, so Python sees only the distinct pairs.
        codes = np.bitwise_or(np.left_shift(first, MAX_BITS), second)[np.logical_and(first, second)]
        if codes.size > 4:  # the contacts of one geom pair come one after another: keep the first
            keep = np.empty(codes.size, dtype=bool)
            keep[0] = True
            np.not_equal(codes[1:], codes[:-1], out=keep[1:])
            codes = codes[keep]
        return tuple((code >> MAX_BITS, code & _LOW_BITS) for code in set(codes.tolist()))

    def touching(self, a: GeomSet | np.ndarray, b: GeomSet | np.ndarray) -> bool:
        """Some touching contact joins a geom of ``a`` and a geom of ``b``."""
        bit_a = a.bit if type(a) is GeomSet else 0
        bit_b = b.bit if type(b) is GeomSet else 0
        if bit_a and bit_b:
            for first, second in self._label_pairs():
                if (first & bit_a and second & bit_b) or (first & bit_b and second & bit_a):
                    return True
            return False
        mask_a = a.mask if type(a) is GeomSet else np.asarray(a, dtype=bool)
        mask_b = b.mask if type(b) is GeomSet else np.asarray(b, dtype=bool)
        geoms = self._active_geoms()
        first, second = geoms[:, 0], geoms[:, 1]
        return bool(np.any((mask_a[first] & mask_b[second]) | (mask_b[first] & mask_a[second])))
