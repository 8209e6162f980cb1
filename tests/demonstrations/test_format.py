"""The demo file: round trips, metadata, damaged files, the physics fingerprint."""

from __future__ import annotations

import json

import mujoco
import numpy as np
import pytest
import safetensors
import safetensors.numpy
from demokit import same_observations

import bigym
from bigym.action_modes import JointPositionActionMode
from bigym.demonstrations import Demo, DemoCorruptError, ReplayedDemo, model_fingerprint, record_episode, replay
from bigym.demonstrations.metadata import CHECKPOINT_SPEC, Metadata
from bigym.envs.reach_target import ReachTargetMultiModal, ReachTargetSingle
from bigym.observations import CameraConfig, ObservationConfig
from bigym.policies import RandomPolicy

METADATA_KEYS = {
    "format", "format_version", "task", "action_mode", "frequency", "observation_config", "task_kwargs", "robot",
    "seed", "source", "success", "uuid", "date", "num_steps", "checkpoint_interval", "checkpoint_spec",
    "initial_state_spec", "bigym_version", "mujoco_version", "model_fingerprint", "action_names", "extra",
    "packing",
}  # fmt: skip


@pytest.mark.parametrize(
    ("absolute", "frequency", "cameras"),
    [(True, 500, False), (False, 50, False), (True, 100, True)],
    ids=["absolute-500hz", "delta-50hz", "absolute-100hz-cameras"],
)
def test_random_episode_round_trip_is_bit_identical(tmp_path, absolute, frequency, cameras):
    config = ObservationConfig(
        cameras=(CameraConfig("head", depth=True, resolution=(24, 32)),) if cameras else (),
        privileged_information=True,
    )
    env = ReachTargetMultiModal(
        action_mode=JointPositionActionMode(absolute=absolute), control_frequency=frequency, observation_config=config
    )
    recorded: list[dict] = []
    demo = record_episode(env, RandomPolicy(env, seed=7), seed=11, source="random", max_steps=120,
                          steps_after_success=10**6, observations=recorded)  # fmt: skip
    env.close()
    assert len(demo) == 120 and len(recorded) == 121
    path = demo.save(tmp_path)
    assert path.name == f"{demo.uuid}.safetensors"
    loaded = Demo.load(path)

    np.testing.assert_array_equal(loaded.actions, demo.actions)
    assert loaded.actions.dtype == np.float64
    np.testing.assert_array_equal(loaded.initial_state, demo.initial_state)
    np.testing.assert_array_equal(loaded.checkpoint_states, demo.checkpoint_states)
    assert loaded.metadata == demo.metadata

    replayed = replay(loaded, config)
    assert replayed.report.exact
    assert replayed.report.checkpoints_checked == len(demo.checkpoint_steps) > 1
    # The episode ends at its first terminal step; the recording went on past it (the
    # recorder was told to), and the replay checked those steps but returns the episode only.
    episode = len(replayed)
    assert replayed.report.replayed_steps == 120 and replayed.report.episode_steps == episode
    ends = np.flatnonzero(replayed.terminated | replayed.truncated)
    assert episode == 120 and ends.size == 0 or ends.tolist() == [episode - 1]
    expected = {key: np.stack([obs[key] for obs in recorded[: episode + 1]]) for key in recorded[0]}
    assert same_observations(replayed.observations, expected)
    np.testing.assert_array_equal(replayed.actions, demo.actions[:episode])

    # The replayed demo survives its own file format too.
    again = ReplayedDemo.load(replayed.save(tmp_path / "replayed.safetensors"))
    assert same_observations(again.observations, replayed.observations)
    assert again.report == replayed.report


def test_file_holds_the_documented_tensors_and_metadata(tmp_path, expert_demos):
    demo = expert_demos["single_delta"]
    path = demo.save(tmp_path / "demo.safetensors")
    with safetensors.safe_open(str(path), "np") as handle:
        header = handle.metadata()
        keys = set(handle.keys())
        shapes = {key: handle.get_tensor(key).shape for key in keys}
        dtypes = {key: handle.get_tensor(key).dtype for key in keys}
    assert keys == {"actions_packed", "initial_state", "checkpoint_steps", "checkpoint_states_packed"}
    assert dtypes["actions_packed"] == np.uint8 and dtypes["checkpoint_states_packed"] == np.uint8
    assert dtypes["checkpoint_steps"] == np.int64
    assert set(header) == METADATA_KEYS
    values = {key: json.loads(value) for key, value in header.items() if key != "format"}
    assert header["format"] == "bigym-demo" and values["format_version"] == 2
    # This scripted policy's delta actions lie on no grid: packed as floats, with the shape they unpack to
    # (the human-like experts' actions pack as integers: tests/experts/test_dataset.py).
    assert values["packing"]["actions"] == {"codec": "shuffle-bz2", "shape": [len(demo), 16]}
    assert values["packing"]["checkpoint_states"]["shape"] == list(demo.checkpoint_states.shape)
    assert values["task"] == "ReachTargetSingle"
    assert values["action_mode"] == {"name": "JointPositionActionMode", "floating_base": True,
                                     "floating_dofs": ["x", "y", "z", "rz"], "absolute": False}  # fmt: skip
    assert values["robot"] == {"floating_base": True, "floating_dofs": ["x", "y", "z", "rz"], "torque_control": False}
    assert values["frequency"] == 500.0 and values["seed"] == 1
    assert values["source"] == "expert" and values["success"] is True
    assert values["bigym_version"] == bigym.__version__ and values["mujoco_version"] == mujoco.__version__
    assert len(values["model_fingerprint"]) == 64
    assert values["checkpoint_spec"] == CHECKPOINT_SPEC
    assert values["initial_state_spec"] == int(mujoco.mjtState.mjSTATE_INTEGRATION)
    assert values["date"].endswith("Z") and len(values["uuid"]) == 32
    assert values["action_names"][0] == "base_dx" and values["action_names"][-1] == "right_gripper"
    # The initial state is the full integration state, checkpoints every 0.1 s plus the last step.
    env = ReachTargetSingle(control_frequency=500)
    assert shapes["initial_state"] == (mujoco.mj_stateSize(env.model, mujoco.mjtState.mjSTATE_INTEGRATION),)
    steps = demo.checkpoint_steps
    assert steps[-1] == len(demo) and all(s % 50 == 0 for s in steps[:-1]) and steps[0] == 50
    env.close()


def test_damaged_files_fail_clearly(tmp_path, expert_demos):
    data = expert_demos["single_absolute"].to_bytes()
    truncated = tmp_path / "truncated.safetensors"
    truncated.write_bytes(data[: len(data) // 2])
    with pytest.raises(DemoCorruptError, match="truncated"):
        Demo.load(truncated)
    tiny = tmp_path / "tiny.safetensors"
    tiny.write_bytes(data[:5])
    with pytest.raises(DemoCorruptError, match="truncated or empty"):
        Demo.load(tiny)
    garbage = tmp_path / "garbage.safetensors"
    garbage.write_bytes(b"\x10\x00\x00\x00\x00\x00\x00\x00{not json at all}" + data[24:])
    with pytest.raises(DemoCorruptError):
        Demo.load(garbage)
    foreign = tmp_path / "foreign.safetensors"
    foreign.write_bytes(safetensors.numpy.save({"weights": np.zeros(3)}, metadata={"model": "x"}))
    with pytest.raises(DemoCorruptError, match="not a bigym demo"):
        Demo.load(foreign)
    newer = Metadata.from_header({**expert_demos["single_absolute"].metadata.to_header()})
    header = newer.to_header()
    header["format_version"] = "99"
    future = tmp_path / "future.safetensors"
    future.write_bytes(safetensors.numpy.save({"actions": np.zeros((1, 16))}, metadata=header))
    with pytest.raises(DemoCorruptError, match="upgrade bigym"):
        Demo.load(future)


def test_model_fingerprint_tracks_physics_not_rendering():
    cameras = ObservationConfig.robot_cameras(resolution=(16, 16))
    first = ReachTargetSingle(observation_config=cameras)
    second = ReachTargetSingle()
    fingerprint = model_fingerprint(first.model)
    assert fingerprint == model_fingerprint(second.model)
    first.reset(seed=0)
    for _ in range(3):  # rendering poses the visual legs (model.body_quat) and grows the offscreen buffer
        first.step(np.zeros(first.action_space.shape, np.float32))
    assert model_fingerprint(first.model) == fingerprint
    three_dofs = ReachTargetSingle(action_mode=JointPositionActionMode(floating_dofs=["x", "y", "rz"]))
    assert model_fingerprint(three_dofs.model) != fingerprint
    other_task = ReachTargetMultiModal()
    assert model_fingerprint(other_task.model) != fingerprint
    second.model.geom_friction[second.model.geom_contype != 0] *= 1.5
    assert model_fingerprint(second.model) != fingerprint
    for env in (first, second, three_dofs, other_task):
        env.close()
