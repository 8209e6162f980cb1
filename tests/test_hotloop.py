"""The compiled step path (bigym/_hotloop.c) gives the bits of the Python code it stands for.

Each case runs two envs side by side from the same reset, one on the compiled path and one
with it switched off (the Python reference), and compares everything a step hands out and
the whole simulator state after every step.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from bigym import hotloop
from bigym.action_modes import JointPositionActionMode, TorqueActionMode
from bigym.cli import task_class
from bigym.contacts import ContactState


def python_only(env) -> None:
    """Switch one env to the Python reference code."""
    env._compiled_step = None
    env._proprioception._compiled = None
    env.contacts._compiled_pairs = None


def outcome(env, action):
    """What ``env.step(action)`` hands out, as comparable bytes, or the error it raises."""
    try:
        obs, reward, terminated, truncated, info = env.step(action)
    except ValueError as error:
        return ("ValueError", str(error))
    return ({key: value.tobytes() for key, value in obs.items()}, reward, terminated, truncated, info)


def test_the_extension_is_built_and_used():
    """CI installs bigym with a C compiler: the compiled path must be there and in use."""
    assert hotloop.AVAILABLE
    env = task_class("ReachTargetSingle")()
    env.reset(seed=0)
    assert env._compiled_step is not None
    assert env._proprioception._compiled is not None
    assert env.contacts._compiled_pairs is not None
    env.close()


@pytest.mark.parametrize(
    ("task", "frequency", "mode"),
    [
        ("MoveTwoPlates", 500, JointPositionActionMode()),
        ("MoveTwoPlates", 50, JointPositionActionMode(absolute=True)),
        ("DishwasherLoadCups", 20, JointPositionActionMode()),
        ("StackBlocks", 25, TorqueActionMode(floating_base=True)),
        ("StackBlocks", 500, JointPositionActionMode(floating_base=False)),
        ("ReachTargetMultiModal", 100, JointPositionActionMode(floating_dofs=["x", "y", "rz"])),  # z constant
    ],
)
def test_compiled_steps_equal_the_python_steps_bit_for_bit(task, frequency, mode):
    compiled, reference = (task_class(task)(control_frequency=frequency, action_mode=mode) for _ in range(2))
    python_only(reference)
    for env in (compiled, reference):
        env.reset(seed=3)
    rng = np.random.default_rng(0)
    low, high = compiled.action_space.low, compiled.action_space.high
    for i in range(40):
        action = rng.uniform(low, high).astype(np.float32) * (0.3 if i % 2 else 1.0)
        if i % 4 == 1:
            action = action.astype(np.float64)  # the float64 comparison
        elif i % 4 == 2:
            action = action.tolist()  # converted in Python, then compiled
        elif i % 4 == 3:
            action = action[::-1].copy()[::-1]  # not contiguous: the Python path
        got, expected = outcome(compiled, action), outcome(reference, action)
        assert got == expected, f"step {i}"
        assert compiled.state_digest() == reference.state_digest(), f"step {i}"
    # refused actions: the same error, nothing applied
    for bad in (np.full(low.shape, 100.0, np.float32), np.where(np.arange(low.size) == 1, np.nan, low), low[None]):
        got, expected = outcome(compiled, bad), outcome(reference, bad)
        assert got == expected and got[0] == "ValueError"
        assert compiled.state_digest() == reference.state_digest()
    for env in (compiled, reference):
        env.close()


def test_signed_zeros_and_bounds_clip_as_in_python():
    """-0.0 and the exact float32 bounds: the clip and the widening must round alike."""
    compiled, reference = (
        task_class("ReachTargetSingle")(action_mode=JointPositionActionMode(absolute=True)) for _ in range(2)
    )
    python_only(reference)
    for env in (compiled, reference):
        env.reset(seed=0)
    low, high = compiled.action_space.low, compiled.action_space.high
    for action in (np.full(low.shape, -0.0, np.float32), low.copy(), high.copy(), low.astype(np.float64)):
        assert outcome(compiled, action) == outcome(reference, action)
        assert np.array_equal(np.signbit(compiled.data.ctrl), np.signbit(reference.data.ctrl))
        assert compiled.state_digest() == reference.state_digest()


def test_label_pairs_match_the_python_reduction():
    env = task_class("DishwasherLoadCups")()
    env.reset(seed=0)
    contacts = env.contacts
    assert env.data.ncon > 20  # mugs on the rack: many contacts, few label pairs
    assert set(contacts._compiled_label_pairs()) == set(contacts._python_label_pairs())
    env.close()


def test_label_pairs_keep_only_touching_labelled_contacts_and_give_up_past_capacity():
    label_pairs = hotloop.label_pairs_function()
    labels = np.array([0, 1, 2, 4, 8], np.int64)
    geoms = np.array([[1, 2], [2, 1], [1, 2], [0, 3], [3, 4], [4, 4]], np.int32)
    dists = np.array([-0.001, 0.0, -0.002, -0.001, 0.002, np.nan])
    assert set(label_pairs(labels.ctypes.data, geoms, None)) == {(1, 2), (2, 1), (4, 8), (8, 8)}
    assert set(label_pairs(labels.ctypes.data, geoms, dists)) == {(1, 2), (2, 1)}
    many = np.arange(1, 101, dtype=np.int64)
    pairs = np.array([[i, i + 1] for i in range(70)], np.int32)
    assert label_pairs(many.ctypes.data, pairs, None) is None  # ContactState then counts in Python


def test_contact_queries_fall_back_to_python_past_the_c_capacity(monkeypatch):
    env = task_class("DishwasherLoadCups")()
    env.reset(seed=0)
    contacts: ContactState = env.contacts
    expected = set(contacts._python_label_pairs())
    monkeypatch.setattr(contacts, "_compiled_pairs", lambda *args: None)
    contacts.hold()
    try:
        assert set(contacts._label_pairs()) == expected
    finally:
        contacts.release()
    env.close()


def test_bigym_pure_python_turns_the_compiled_path_off():
    code = "import bigym.hotloop as h; from bigym.cli import task_class; e = task_class('ReachTargetSingle')(); e.reset(seed=0); "
    code += "print(h.AVAILABLE, e._compiled_step is None, e._proprioception._compiled is None)"
    result = subprocess.run(
        [sys.executable, "-c", code],
        check=False,
        env={**os.environ, "BIGYM_PURE_PYTHON": "1"},
        capture_output=True,
        text=True,
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["False", "True", "True"]
