"""Packed demo arrays: exact round trips whatever the values, old files readable, damage detected."""

from __future__ import annotations

import json

import numpy as np
import pytest

from bigym.demonstrations import Demo, DemoCorruptError
from bigym.demonstrations.demo import safetensors_bytes
from bigym.demonstrations.packing import grid_bits, pack_actions, pack_floats, unpack_actions, unpack_floats


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint64), b.view(np.uint64))


def smooth_grid_actions(steps: int = 2000, size: int = 16, bits: int = 17) -> np.ndarray:
    t = np.linspace(0.0, 4.0, steps)[:, None]
    signal = np.sin(t * np.arange(1, size + 1)) * 1.3
    return np.ldexp(np.round(np.ldexp(signal, bits)), -bits)


def test_grid_actions_pack_as_integers_and_come_back_bit_for_bit():
    actions = smooth_grid_actions()
    assert grid_bits(actions) == 17
    blob, info = pack_actions(actions)
    assert info["codec"] == "grid-delta2-bz2" and info["grid_bits"] == 17
    assert same_bits(unpack_actions(blob, info), actions)
    assert blob.nbytes * 8 < actions.nbytes  # smooth signals: far smaller than float64


@pytest.mark.parametrize(
    "case", ["off-grid", "negative-zero", "huge", "empty", "one-row", "coarse-grid", "subnormal"]
)
def test_any_float64_actions_come_back_bit_for_bit(case):
    rng = np.random.default_rng(0)
    actions = {
        "off-grid": rng.normal(size=(300, 16)),
        "negative-zero": np.where(rng.random((300, 16)) < 0.1, -0.0, smooth_grid_actions(300)),
        "huge": smooth_grid_actions(300) * 2.0**40,  # second differences leave int32
        "empty": np.zeros((0, 16)),
        "one-row": smooth_grid_actions(1),
        "coarse-grid": np.round(rng.normal(size=(300, 4)) * 4) / 4 + 0.0,  # + 0.0: no -0.0
        "subnormal": np.full((5, 3), 5e-324),
    }[case]
    blob, info = pack_actions(actions)
    unpacked = unpack_actions(blob, info)
    assert same_bits(unpacked, np.ascontiguousarray(actions, np.float64)), info
    if case == "coarse-grid":
        assert info["grid_bits"] == 2
    if case in ("off-grid", "huge", "subnormal"):
        assert info["codec"] == "shuffle-bz2"  # no exact integer form: stored as floats
    if case == "negative-zero":  # rounding gives -0.0: integers plus a mask of the zeros' signs
        assert info["codec"] == "grid-delta2-bz2" and info["negative_zeros"] is True


@pytest.mark.parametrize("shape", [(7, 97), (0, 97), (1, 1), (12,)])
def test_float_arrays_come_back_bit_for_bit(shape):
    values = np.random.default_rng(1).normal(size=shape) * 10.0 ** np.random.default_rng(2).integers(-300, 300, shape)
    blob, info = pack_floats(values)
    assert same_bits(unpack_floats(blob, info), values)


def test_damaged_packing_is_reported(expert_demos):
    data = bytearray(expert_demos["single_absolute"].to_bytes())
    header_size = int.from_bytes(data[:8], "little")
    start, end = json.loads(data[8 : 8 + header_size])["actions_packed"]["data_offsets"]
    data[8 + header_size + (start + end) // 2] ^= 0xFF  # inside the packed actions
    with pytest.raises(DemoCorruptError, match="corrupt|hold"):
        Demo.from_bytes(bytes(data), "flipped.safetensors")
    blob, info = pack_actions(smooth_grid_actions(50))
    with pytest.raises(DemoCorruptError, match="hold"):
        unpack_actions(blob, {**info, "shape": [51, 16]})
    with pytest.raises(DemoCorruptError, match="upgrade bigym"):
        unpack_actions(blob, {**info, "codec": "zstd"})


def test_format_1_files_stay_readable(expert_demos):
    demo = expert_demos["single_delta"]
    header = demo.metadata.to_header()
    header["format_version"] = "1"
    old = safetensors_bytes(
        {
            "actions": demo.actions,
            "initial_state": demo.initial_state,
            "checkpoint_steps": demo.checkpoint_steps,
            "checkpoint_states": demo.checkpoint_states,
        },
        header,
    )
    loaded = Demo.from_bytes(old, "v1.safetensors")
    for name in ("actions", "initial_state", "checkpoint_states"):
        assert same_bits(getattr(loaded, name), getattr(demo, name))
    assert loaded.metadata == demo.metadata
    # Written again, it is format 2 and smaller (off-grid actions of a short demo: the header weighs).
    new = loaded.to_bytes()
    assert len(new) * 2 < len(old)
    size = int.from_bytes(new[:8], "little")
    assert json.loads(json.loads(new[8 : 8 + size])["__metadata__"]["format_version"]) == 2
