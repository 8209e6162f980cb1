"""Exports: LeRobot v3.0 layout and robomimic-style HDF5."""

from __future__ import annotations

import json

import h5py
import imageio.v2 as imageio
import numpy as np
import pyarrow.parquet as pq
import pytest

from bigym.demonstrations import DemoError, make_env, replay_many
from bigym.demonstrations.export import export_lerobot, export_minari, export_robomimic
from bigym.observations import CameraConfig, ObservationConfig

CONFIG = ObservationConfig(
    cameras=(CameraConfig("head", resolution=(24, 32)), CameraConfig("left_wrist", depth=True, resolution=(16, 16)))
)


@pytest.fixture(scope="module")
def replayed(expert_demos):
    # Two episodes of one task in one action mode: the delta demo is converted to absolute on the fly.
    demos = [expert_demos["single_absolute"], expert_demos["single_delta"]]
    converted = replay_many(demos[:1], CONFIG, 50, progress=False)
    converted += replay_many(demos[1:], CONFIG, 50, action_mode=demos[0].metadata.action_mode, progress=False)
    return converted


def test_lerobot_v3_layout(replayed, tmp_path):
    root = export_lerobot(replayed, tmp_path / "dataset")
    lengths = [len(r) for r in replayed]
    total = sum(lengths)
    info = json.loads((root / "meta" / "info.json").read_text())
    assert info["codebase_version"] == "v3.0" and info["fps"] == 50
    assert info["total_episodes"] == 2 and info["total_frames"] == total and info["total_tasks"] == 1
    assert info["data_path"] == "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
    assert info["video_path"] == "videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4"
    assert info["splits"] == {"train": "0:2"} and info["chunks_size"] == 1000
    features = info["features"]
    for name in ("timestamp", "frame_index", "episode_index", "index", "task_index"):
        assert features[name]["shape"] == [1]
    assert features["observation.state"]["shape"] == [60] and len(features["observation.state"]["names"]) == 60
    assert features["action"] == {"dtype": "float32", "shape": [16], "names": replayed[0].metadata.action_names}
    head = features["observation.images.head"]
    assert head["dtype"] == "video" and head["shape"] == [24, 32, 3]
    assert head["names"] == ["height", "width", "channels"] and head["info"]["video.fps"] == 50
    assert not any("/" in name for name in features)
    assert "observation.depth_left_wrist" not in features  # depth is not exported to LeRobot

    data = pq.read_table(root / "data" / "chunk-000" / "file-000.parquet")
    assert data.num_rows == total
    assert set(data.column_names) == {name for name, f in features.items() if f["dtype"] != "video"}
    assert data.column("index").to_pylist() == list(range(total))
    assert data.column("frame_index").to_pylist() == list(range(lengths[0])) + list(range(lengths[1]))
    np.testing.assert_allclose(
        np.array(data.column("action").to_pylist())[: lengths[0]], replayed[0].actions.astype(np.float32)
    )
    np.testing.assert_array_equal(
        np.array(data.column("observation.state").to_pylist())[lengths[0] :],
        replayed[1].observations["proprioception"][:-1],
    )
    assert data.column("timestamp").to_pylist()[1] == pytest.approx(0.02)

    episodes = pq.read_table(root / "meta" / "episodes" / "chunk-000" / "file-000.parquet").to_pylist()
    assert [e["episode_index"] for e in episodes] == [0, 1]
    spans = [(e["dataset_from_index"], e["dataset_to_index"]) for e in episodes]
    assert spans == [(0, lengths[0]), (lengths[0], total)]
    assert episodes[1]["videos/observation.images.head/from_timestamp"] == pytest.approx(lengths[0] / 50)
    assert episodes[0]["tasks"][0].startswith("Reach the target with one named wrist (hand")
    assert "stats/action/mean" in episodes[0] and episodes[0]["meta/episodes/file_index"] == 0

    tasks = pq.read_table(root / "meta" / "tasks.parquet")
    assert tasks.column("task_index").to_pylist() == [0]
    assert json.loads(tasks.schema.metadata[b"pandas"])["index_columns"] == ["task"]
    stats = json.loads((root / "meta" / "stats.json").read_text())
    assert stats["action"]["count"] == [total] and len(stats["action"]["mean"]) == 16
    assert np.array(stats["observation.images.head"]["mean"]).shape == (3, 1, 1)
    head_stats = stats["observation.images.head"]
    assert 0.0 <= np.min(head_stats["min"]) <= np.max(head_stats["max"]) <= 1.0

    for key, (h, w) in (("head", (24, 32)), ("left_wrist", (16, 16))):
        reader = imageio.get_reader(root / "videos" / f"observation.images.{key}" / "chunk-000" / "file-000.mp4")
        frames = [frame for frame in reader]
        reader.close()
        assert len(frames) == total and frames[0].shape == (h, w, 3)
        # Lossy, but close to the rendered frames.
        first = replayed[0].observations[f"rgb_{key}"][0].transpose(1, 2, 0).astype(float)
        assert np.abs(frames[0].astype(float) - first).mean() < 12


def test_lerobot_export_refuses_fractional_fps_and_existing_folders(replayed, tmp_path, expert_demos):
    odd = replay_many([expert_demos["single_absolute"]], None, 30, progress=False)
    with pytest.raises(DemoError, match="whole number of frames per second"):
        export_lerobot(odd, tmp_path / "odd")
    assert not (tmp_path / "odd").exists()
    (tmp_path / "taken").mkdir()
    with pytest.raises(DemoError, match="exists"):
        export_lerobot(replayed, tmp_path / "taken")
    with pytest.raises(DemoError, match="must share one control rate"):
        export_lerobot([replayed[0], odd[0]], tmp_path / "mixed")


def test_robomimic_hdf5(replayed, tmp_path):
    path = export_robomimic(replayed, tmp_path / "demos.hdf5")
    with h5py.File(path, "r") as f:
        data = f["data"]
        assert data.attrs["total"] == sum(len(r) for r in replayed)
        env_args = json.loads(data.attrs["env_args"])
        assert env_args["env_name"] == "bigym/ReachTargetSingle-v0" and env_args["type"] == 2
        assert env_args["env_kwargs"]["control_frequency"] == 50
        assert sorted(data) == ["demo_0", "demo_1"]
        for k, demo in enumerate(replayed):
            group = data[f"demo_{k}"]
            steps = len(demo)
            assert group.attrs["num_samples"] == steps and group.attrs["uuid"] == demo.uuid
            np.testing.assert_array_equal(group["actions"][:], demo.actions)
            assert group["rewards"].shape == (steps,) and group["dones"][-1] == 1 and group["dones"][:-1].sum() == 0
            np.testing.assert_array_equal(group["states"][:], demo.states[:-1])
            assert group["obs/rgb_head"].shape == (steps, 24, 32, 3)
            assert group["obs/depth_left_wrist"].shape == (steps, 16, 16, 1)
            np.testing.assert_array_equal(group["obs/rgb_head"][0], demo.observations["rgb_head"][0].transpose(1, 2, 0))
            np.testing.assert_array_equal(group["next_obs/proprioception"][:], demo.observations["proprioception"][1:])
        assert [name.decode() for name in f["mask/train"][:]] == ["demo_0", "demo_1"]


def test_exported_episodes_end_at_their_first_terminal_step(replayed, tmp_path):
    """The expert recordings run past their first success; no export holds those steps, and
    every exported episode is done on its last frame only, the one that succeeded."""
    for demo in replayed:
        assert demo.report.episode_steps < demo.report.replayed_steps, "premise: the recording has a tail"
    root = export_lerobot(replayed, tmp_path / "dataset")
    data = pq.read_table(root / "data" / "chunk-000" / "file-000.parquet")
    episode_index = np.array(data.column("episode_index").to_pylist())
    done = np.array(data.column("next.done").to_pylist()).ravel()
    success = np.array(data.column("next.success").to_pylist()).ravel()
    reward = np.array(data.column("next.reward").to_pylist()).ravel()
    for k, demo in enumerate(replayed):
        rows = episode_index == k
        assert rows.sum() == demo.report.episode_steps
        assert np.flatnonzero(done[rows]).tolist() == [demo.report.episode_steps - 1]
        assert success[rows][-1] and reward[rows][-1] == 1.0 and not success[rows][:-1].any()
    path = export_robomimic(replayed, tmp_path / "demos.hdf5")
    with h5py.File(path) as f:
        for k, demo in enumerate(replayed):
            group = f[f"data/demo_{k}"]
            dones = group["dones"][()]
            assert len(dones) == group.attrs["num_samples"] == demo.report.episode_steps
            assert np.flatnonzero(dones).tolist() == [len(dones) - 1]
            assert group["rewards"][-1] == 1.0 and group["rewards"][:-1].sum() == 0.0


def test_robomimic_depth_is_normalised_as_its_readers_expect(replayed, tmp_path):
    """robomimic clips depth images to [0, 1]: the file holds depth over a stated range."""
    near, far = 0.05, 0.3  # a short range, so that some pixels lie beyond it
    path = export_robomimic(replayed, tmp_path / "depth.hdf5", depth_range=(near, far))
    metric = replayed[0].observations["depth_left_wrist"][:-1]
    assert (metric > far).any() and (metric < far).any(), "premise: pixels on both sides of far"
    with h5py.File(path, "r") as f:
        stored = f["data/demo_0/obs/depth_left_wrist"]
        assert stored.dtype == np.float32 and stored.attrs["near"] == near and stored.attrs["far"] == far
        assert "metres" in stored.attrs["encoding"]
        values = stored[()][..., 0]
        env_args = json.loads(f["data"].attrs["env_args"])
    assert env_args["bigym"]["depth_range"] == [near, far]
    assert values.min() >= 0.0 and values.max() <= 1.0
    inside = metric < far
    np.testing.assert_allclose(near + values[inside] * (far - near), metric[inside], rtol=1e-6)
    assert np.all(values[~inside] == 1.0)
    with pytest.raises(ValueError, match="depth_range"):
        export_robomimic(replayed, tmp_path / "bad.hdf5", depth_range=(1.0, 0.5))


def test_env_from_robomimic_reproduces_the_exported_episodes(replayed, tmp_path):
    """The env_args rebuild the env (robomimic's own create_env_from_metadata cannot): reset
    with a demo's seed and its exported actions give its exported states, bit for bit."""
    import mujoco

    from bigym.demonstrations.export import env_from_robomimic

    path = export_robomimic(replayed, tmp_path / "demos.hdf5")
    env = env_from_robomimic(path)
    try:
        assert env.control_frequency == 50 and type(env).__name__ == "ReachTargetSingle"
        with h5py.File(path, "r") as f:
            for k in range(len(replayed)):
                group = f[f"data/demo_{k}"]
                spec = int(group.attrs["state_spec"])
                states, actions = group["states"][()], group["actions"][()]
                env.reset(seed=int(group.attrs["seed"]))
                state = np.empty(mujoco.mj_stateSize(env.model, spec))
                for t, action in enumerate(actions):
                    mujoco.mj_getState(env.model, env.data, state, spec)
                    np.testing.assert_array_equal(state, states[t], err_msg=f"demo_{k} step {t}")
                    _, reward, terminated, truncated, info = env.step(action)
                assert info["is_success"] and terminated and reward == 1.0
    finally:
        env.close()
    from bigym.demonstrations import DemoError

    with pytest.raises(DemoError, match="not written by bigym"):
        env_from_robomimic({"env_name": "Lift", "type": 1, "env_kwargs": {}})


@pytest.fixture(scope="module")
def state_replays(expert_demos):
    demo = expert_demos["single_absolute"]
    config = ObservationConfig(privileged_information=True)
    env = make_env(demo.metadata, config, 50)
    yield env, replay_many([demo], config, 50, progress=False)
    env.close()


def test_minari_dataset_holds_the_replayed_episodes(state_replays, tmp_path, monkeypatch):
    import minari

    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path / "minari"))
    env, replayed = state_replays
    dataset = export_minari(replayed, "bigym/reach_target_single/expert-v0", env)
    loaded = minari.load_dataset("bigym/reach_target_single/expert-v0")
    assert loaded.total_episodes == len(replayed) == dataset.total_episodes
    episode, demo = next(loaded.iterate_episodes()), replayed[0]
    assert set(episode.observations) == set(demo.observations)
    for key, values in demo.observations.items():
        np.testing.assert_array_equal(episode.observations[key], values)
    np.testing.assert_array_equal(episode.actions, demo.actions.astype(np.float32))
    np.testing.assert_array_equal(episode.rewards, demo.rewards)
    assert episode.terminations.tolist() == demo.terminated.tolist() and episode.terminations[-1]
    assert episode.truncations.tolist() == demo.truncated.tolist()
    about = json.loads(loaded.storage.metadata["description"])
    assert about["task"] == "ReachTargetSingle" and about["frequency"] == 50
    assert about["observations"] == list(demo.observations)


def test_minari_export_refuses_observations_the_env_lacks(state_replays, tmp_path, monkeypatch):
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path / "minari"))
    _, replayed = state_replays
    plain = make_env(replayed[0].metadata, ObservationConfig(), 50)
    try:
        with pytest.raises(DemoError, match="the env lacks"):
            export_minari(replayed, "bigym/reach_target_single/expert-v0", plain)
    finally:
        plain.close()
