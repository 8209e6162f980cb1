"""Lossless packing of a lightweight demo's arrays, so that a demo-second costs a few KB.

A demo's bulk is its actions: 500 float64 rows per second. The experts' actions lie on a
power-of-two grid (``k * 2**-17``) and are smooth, so the integers ``k`` have small second
differences; stored column by column and compressed, they take ~2 KB per demo-second
instead of ~64 KB (rounding leaves some ``-0.0``: a bit mask keeps their sign). State checkpoints are arbitrary float64: their bytes are shuffled (all
first bytes, then all second bytes, ...) so that the slowly changing sign and exponent
bytes sit together, then compressed.

Every packing is checked by unpacking it: the unpacked array equals the original bit for
bit (including ``-0.0``), or the array is stored as plain shuffled float64 instead. bz2 is
the compressor because its output is the same for the same input on every platform and
Python build (libbzip2 1.0.x has not changed its format or its choices in decades; zlib
builds such as zlib-ng do not give zlib's bytes), and a rebuilt dataset must match its
manifest byte for byte.
"""

from __future__ import annotations

import bz2

import numpy as np

from bigym.demonstrations.errors import DemoCorruptError

#: finest grid tried for actions: 2**-MAX_GRID_BITS
MAX_GRID_BITS = 30
_INT32 = np.iinfo(np.int32)


def _compress(raw: bytes) -> np.ndarray:
    return np.frombuffer(bz2.compress(raw, 9), dtype=np.uint8)


def _decompress(blob: np.ndarray, expected: int, name: str) -> bytes:
    try:
        raw = bz2.decompress(np.ascontiguousarray(blob, dtype=np.uint8).tobytes())
    except (OSError, ValueError, EOFError) as error:
        raise DemoCorruptError(f"packed {name} are corrupt: {error}") from error
    if len(raw) != expected:
        raise DemoCorruptError(f"packed {name} hold {len(raw)} bytes, expected {expected}")
    return raw


# ---------------------------------------------------------------------- float arrays
def pack_floats(array: np.ndarray) -> tuple[np.ndarray, dict]:
    """Any float64 array as compressed shuffled bytes (exact)."""
    array = np.ascontiguousarray(array, dtype="<f8")
    rows, columns = _rows_columns(array.shape)
    shuffled = array.reshape(rows, columns).view(np.uint8).reshape(rows, columns, 8).transpose(2, 1, 0)
    return _compress(shuffled.tobytes()), {"codec": "shuffle-bz2", "shape": list(array.shape)}


def _rows_columns(shape: tuple[int, ...]) -> tuple[int, int]:
    rows = int(shape[0]) if shape else 1
    return rows, int(np.prod(shape[1:], dtype=np.int64))


def _unpack_floats(blob: np.ndarray, info: dict, name: str) -> np.ndarray:
    shape = tuple(int(n) for n in info["shape"])
    rows, columns = _rows_columns(shape)
    raw = _decompress(blob, rows * columns * 8, name)
    shuffled = np.frombuffer(raw, dtype=np.uint8).reshape(8, columns, rows)
    return np.ascontiguousarray(shuffled.transpose(2, 1, 0)).view("<f8").reshape(shape).astype(np.float64)


# ---------------------------------------------------------------------- actions on a grid
def grid_bits(actions: np.ndarray) -> int | None:
    """The smallest ``b`` such that every action is an integer multiple of ``2**-b``."""
    for bits in range(MAX_GRID_BITS + 1):
        scaled = np.ldexp(actions, bits)
        if np.array_equal(scaled, np.round(scaled)):
            return bits
    return None


def pack_actions(actions: np.ndarray) -> tuple[np.ndarray, dict]:
    """(T, A) float64 actions packed as second differences of their grid integers, column
    by column (and, where any entry is -0.0, a bit mask of those entries: rounding gives
    them, and an integer cannot keep the sign of a zero); actions off every grid (or out
    of int32 range) are packed as floats."""
    actions = np.ascontiguousarray(actions, dtype=np.float64)
    bits = grid_bits(actions) if actions.size and np.isfinite(actions).all() else None
    if bits is not None:
        k = np.round(np.ldexp(actions, bits)).astype(np.int64)
        second = np.diff(k, n=2, axis=0, prepend=np.zeros((2, k.shape[1]), np.int64))
        if second.size and _INT32.min <= second.min() and second.max() <= _INT32.max:
            raw = np.ascontiguousarray(second.T, dtype="<i4").tobytes()
            negative_zero = np.logical_and(actions == 0.0, np.signbit(actions))
            info = {"codec": "grid-delta2-bz2", "grid_bits": bits, "shape": list(actions.shape)}
            if negative_zero.any():
                raw += np.packbits(negative_zero.T.ravel()).tobytes()
                info["negative_zeros"] = True
            blob = _compress(raw)
            if np.array_equal(unpack_actions(blob, info).view(np.uint64), actions.view(np.uint64)):
                return blob, info
    return pack_floats(actions)


def unpack_actions(blob: np.ndarray, info: dict) -> np.ndarray:
    if info.get("codec") == "shuffle-bz2":
        return _unpack_floats(blob, info, "actions")
    if info.get("codec") != "grid-delta2-bz2":
        raise DemoCorruptError(f"unknown action packing {info.get('codec')!r}: upgrade bigym")
    steps, size = (int(n) for n in info["shape"])
    count = steps * size
    mask_bytes = (count + 7) // 8 if info.get("negative_zeros") else 0
    raw = _decompress(blob, count * 4 + mask_bytes, "actions")
    second = np.frombuffer(raw, dtype="<i4", count=count).reshape(size, steps).T.astype(np.int64)
    k = np.cumsum(np.cumsum(second, axis=0), axis=0)
    actions = np.ldexp(k.astype(np.float64), -int(info["grid_bits"]))
    if mask_bytes:
        bits = np.unpackbits(np.frombuffer(raw, dtype=np.uint8, offset=count * 4), count=count)
        actions[bits.reshape(size, steps).T.astype(bool)] = -0.0
    return actions


def unpack_floats(blob: np.ndarray, info: dict, name: str = "arrays") -> np.ndarray:
    if info.get("codec") != "shuffle-bz2":
        raise DemoCorruptError(f"unknown packing {info.get('codec')!r} of {name}: upgrade bigym")
    return _unpack_floats(blob, info, name)


__all__ = ["grid_bits", "pack_actions", "pack_floats", "unpack_actions", "unpack_floats"]
