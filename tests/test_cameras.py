"""Camera observations, metric depth, and the render modes."""

from __future__ import annotations

import gymnasium as gym
import mujoco
import numpy as np
import pytest

from bigym.envs.reach_target import ReachTargetSingle
from bigym.observations import CameraConfig, ObservationConfig
from bigym.rendering import CameraRenderer

from testkit import zero_action

CONFIG = ObservationConfig(
    cameras=[
        CameraConfig("head", rgb=True, depth=True, resolution=(24, 40)),
        CameraConfig("left_wrist", rgb=True, depth=False, resolution=(16, 16)),
        CameraConfig("right_wrist", rgb=False, depth=True, resolution=(20, 12)),
    ]
)


@pytest.fixture(scope="module")
def env():
    env = ReachTargetSingle(observation_config=CONFIG, render_mode="rgb_array", render_resolution=(36, 48))
    yield env
    env.close()


def test_observation_keys_shapes_dtypes(env):
    obs, _ = env.reset(seed=0)
    expected_images = {
        "rgb_head": ((3, 24, 40), np.uint8),
        "depth_head": ((24, 40), np.float32),
        "rgb_left_wrist": ((3, 16, 16), np.uint8),
        "depth_right_wrist": ((20, 12), np.float32),
    }
    image_keys = {k for k in obs if k.startswith(("rgb_", "depth_"))}
    assert image_keys == set(expected_images)
    assert set(obs) == set(env.observation_space.spaces)
    for key, (shape, dtype) in expected_images.items():
        assert obs[key].shape == shape, key
        assert obs[key].dtype == dtype, key
        assert env.observation_space[key].shape == shape
        assert env.observation_space[key].dtype == dtype
    assert env.observation_space.contains(obs)
    obs, *_ = env.step(zero_action(env))
    assert set(obs) == set(env.observation_space.spaces)
    assert env.observation_space.contains(obs)
    # Real images, not blank buffers.
    assert obs["rgb_head"].std() > 5
    assert obs["rgb_left_wrist"].std() > 1
    # Fresh arrays every step: the env must not hand out buffers it later overwrites.
    before = obs["rgb_head"].copy()
    action = zero_action(env)
    action[env.action_layout["base_dyaw"]] = 0.3
    obs2, *_ = env.step(action)
    np.testing.assert_array_equal(obs["rgb_head"], before)
    assert not np.array_equal(obs2["rgb_head"], before)


@pytest.mark.parametrize(
    "config",
    [
        ObservationConfig(),
        ObservationConfig.robot_cameras(resolution=(8, 10)),
        ObservationConfig(cameras=[CameraConfig("external", rgb=True, depth=False, resolution=(8, 8))], proprioception=False),
    ],
    ids=["none", "robot_cameras", "external_only"],
)
def test_obs_keys_match_space(config):
    env = ReachTargetSingle(observation_config=config)
    try:
        obs, _ = env.reset(seed=0)
        assert set(obs) == set(env.observation_space.spaces)
        obs, *_ = env.step(zero_action(env))
        assert set(obs) == set(env.observation_space.spaces)
        assert env.observation_space.contains(obs)
        n_cameras = len(config.cameras)
        assert sum(k.startswith("rgb_") for k in obs) == sum(c.rgb for c in config.cameras) == n_cameras
        assert sum(k.startswith("depth_") for k in obs) == sum(c.depth for c in config.cameras)
        assert ("proprioception" in obs) == config.proprioception
    finally:
        env.close()


def _ray_depth(model, data, camera_name: str, shape: tuple[int, int], row: int, col: int) -> float:
    """Depth (distance along the view axis) of pixel (row, col) by ray casting visible geoms."""
    camera = model.camera(camera_name)
    h, w = shape
    focal = 0.5 * h / np.tan(np.deg2rad(model.cam_fovy[camera.id]) / 2)
    local = np.array([(col + 0.5 - 0.5 * w) / focal, (0.5 * h - row - 0.5) / focal, -1.0])
    direction = data.cam_xmat[camera.id].reshape(3, 3) @ (local / np.linalg.norm(local))
    geom = np.zeros(1, np.int32)
    groups = np.array([1, 1, 1, 0, 0, 0], np.uint8)  # the geom groups the cameras show
    # Skip the head's own mesh, which surrounds the camera (culled back faces in the render).
    distance = mujoco.mj_ray(model, data, data.cam_xpos[camera.id], direction, groups, 1, camera.bodyid[0], geom)
    return distance / np.linalg.norm(local)


def test_depth_is_metric(env):
    obs, _ = env.reset(seed=0)
    depth = obs["depth_head"]
    assert np.all(np.isfinite(depth))
    assert depth.min() > 0.05 and depth.max() < 20.0, (depth.min(), depth.max())
    # The head camera looks down at the floor: compare pixels across the image with rays
    # cast through their centres.
    h, w = depth.shape
    checked = 0
    for row in (h // 4, h // 2, 3 * h // 4):
        for col in (w // 4, w // 2, 3 * w // 4):
            expected = _ray_depth(env.model, env.data, "head", (h, w), row, col)
            assert 0.3 < expected < 10.0, "premise: the ray hits the scene"
            assert depth[row, col] == pytest.approx(expected, rel=0.03), (row, col)
            checked += 1
    assert checked == 9
    # The centre pixels: distance to the floor along the optical axis.
    camera = env.model.camera("head")
    axis = -env.data.cam_xmat[camera.id].reshape(3, 3)[:, 2]
    floor_distance = env.data.cam_xpos[camera.id][2] / -axis[2]
    centre = depth[h // 2 - 1 : h // 2 + 1, w // 2 - 1 : w // 2 + 1].mean()
    assert centre == pytest.approx(floor_distance, rel=0.03)
    # The floor is further away at the top of the image than at the bottom.
    assert depth[0].mean() > depth[-1].mean()
    # Wrist depth (right wrist camera) is metric too.
    assert 0.05 < obs["depth_right_wrist"].min() and np.all(np.isfinite(obs["depth_right_wrist"]))


def test_depth_sees_the_arm():
    """Raise the left forearm in front of the head camera: the depth there drops to it."""
    env = ReachTargetSingle(observation_config=CONFIG)
    try:
        obs0, _ = env.reset(seed=0)
        action = zero_action(env)
        layout = env.action_layout
        action[layout["left_shoulder_pitch_delta"]] = -0.5  # arm forward and up
        action[layout["left_shoulder_roll_delta"]] = -0.1
        for _ in range(6):
            obs, *_ = env.step(action)
        action[:] = 0.0
        for _ in range(20):
            obs, *_ = env.step(action)
        h, w = obs["depth_head"].shape
        closer = obs["depth_head"] < obs0["depth_head"] - 0.2
        assert closer.any(), "the raised arm does not show in the head depth image"
        # The pixels that changed agree with rays cast at the new state (allowing a few
        # misses on the arm's silhouette, where a pixel's centre ray can slip past).
        rows, cols = np.nonzero(closer)
        samples = list(zip(rows, cols))[:: max(1, len(rows) // 10)]
        agree = [
            abs(obs["depth_head"][r, c] - _ray_depth(env.model, env.data, "head", (h, w), r, c))
            <= 0.02 + 0.05 * obs["depth_head"][r, c]
            for r, c in samples
        ]
        assert np.mean(agree) >= 0.8, f"{sum(agree)} of {len(agree)} arm pixels match a ray cast"
    finally:
        env.close()


def test_camera_images_match_returned_state(env):
    """Images must show the state the step returns (like the proprioception does).

    Re-render the returned state from scratch (full state copied, ``mj_forward``) with a
    second renderer and compare.
    """
    obs, _ = env.reset(seed=0)
    configs = [c for c in CONFIG.cameras if c.depth]
    reference = CameraRenderer(env.model, configs)
    scratch = mujoco.MjData(env.model)
    spec = mujoco.mjtState.mjSTATE_INTEGRATION
    state = np.empty(mujoco.mj_stateSize(env.model, spec))

    def rerender():
        mujoco.mj_getState(env.model, env.data, state, spec)
        mujoco.mj_setState(env.model, scratch, state, spec)
        mujoco.mj_forward(env.model, scratch)
        out = {}
        reference.render(scratch, out)
        return out

    try:
        # The comparison itself is exact on a freshly reset state.
        out = rerender()
        for config in configs:
            np.testing.assert_array_equal(out[f"depth_{config.name}"], obs[f"depth_{config.name}"])
        action = zero_action(env)
        action[env.action_layout["base_dx"]] = 0.1  # the head camera rides on the moving torso
        for step in range(3):
            obs, *_ = env.step(action)
            out = rerender()
            for config in configs:
                key = f"depth_{config.name}"
                difference = np.abs(out[key] - obs[key]).max()
                assert difference < 1e-4, (
                    f"step {step + 1}: {key} differs from a render of the returned state by up to "
                    f"{difference:.4f} m: the image shows an older state than the observation"
                )
    finally:
        reference.close()


def test_rgb_array_render(env):
    env.reset(seed=0)
    frame = env.render()
    assert isinstance(frame, np.ndarray)
    assert frame.shape == (36, 48, 3)
    assert frame.dtype == np.uint8
    assert frame.std() > 5
    # The default external view is 480 x 640 (H x W).
    default = gym.make("bigym/ReachTargetSingle-v0", render_mode="rgb_array").unwrapped
    try:
        default.reset(seed=0)
        assert default.render().shape == (480, 640, 3)
    finally:
        default.close()


def test_no_render_mode_renders_nothing():
    env = ReachTargetSingle()
    try:
        env.reset(seed=0)
        assert env.render() is None
    finally:
        env.close()


def test_human_render_without_display(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    env = ReachTargetSingle(render_mode="human")
    try:
        env.reset(seed=0)
        with pytest.raises(RuntimeError, match="(?i)display"):
            env.render()
    finally:
        env.close()


def test_bad_render_mode():
    with pytest.raises(ValueError, match="render_mode"):
        ReachTargetSingle(render_mode="rgb")


@pytest.mark.parametrize(
    "make",
    [
        lambda: CameraConfig("ceiling"),
        lambda: CameraConfig("head", resolution=(0, 10)),
        lambda: CameraConfig("head", resolution=(10.5, 10)),
        lambda: CameraConfig("head", rgb=False, depth=False),
        lambda: ObservationConfig(cameras=[CameraConfig("head"), CameraConfig("head", depth=True)]),
    ],
    ids=["unknown", "zero", "float", "nothing", "duplicate"],
)
def test_bad_camera_config(make):
    with pytest.raises(ValueError):
        make()


# --------------------------------------------------------------------------- camera poses
def test_external_camera_world_pose():
    """A free camera 4 m above the floor looking straight down sees the floor at 4 m."""
    config = ObservationConfig(
        cameras=[CameraConfig("external", rgb=False, depth=True, resolution=(16, 16), pos=(3.0, 2.0, 4.0), quat=(2, 0, 0, 0))]
    )
    env = ReachTargetSingle(observation_config=config)
    try:
        obs, _ = env.reset(seed=0)
        camera = env.model.camera("external").id
        np.testing.assert_allclose(env.data.cam_xpos[camera], (3.0, 2.0, 4.0))
        np.testing.assert_allclose(env.data.cam_xmat[camera], np.eye(3).ravel(), atol=1e-12)
        assert obs["depth_external"][6:10, 6:10] == pytest.approx(4.0, rel=1e-3)
    finally:
        env.close()


def test_mounted_camera_local_pose():
    """A robot camera's pose is relative to the link that carries it, and moves with it."""
    offset = (0.3, 0.1, 0.5)
    config = ObservationConfig(cameras=[CameraConfig("head", resolution=(8, 8), pos=offset, quat=(0, 0, 1, 0))])
    env = ReachTargetSingle(observation_config=config)
    default = ReachTargetSingle(observation_config=ObservationConfig(cameras=[CameraConfig("head", resolution=(8, 8))]))
    try:
        obs, _ = env.reset(seed=0)
        default_obs, _ = default.reset(seed=0)
        camera = env.model.camera("head")
        body = camera.bodyid[0]
        rotation = env.data.xmat[body].reshape(3, 3)
        np.testing.assert_allclose(env.data.cam_xpos[camera.id], env.data.xpos[body] + rotation @ offset, atol=1e-12)
        # quat (0, 0, 1, 0): half a turn about the link's y axis.
        expected = rotation @ np.diag([-1.0, 1.0, -1.0])
        np.testing.assert_allclose(env.data.cam_xmat[camera.id].reshape(3, 3), expected, atol=1e-12)
        assert not np.array_equal(obs["rgb_head"], default_obs["rgb_head"])
        # Only the camera moved: the physics is the same.
        np.testing.assert_array_equal(obs["proprioception"], default_obs["proprioception"])
    finally:
        env.close()
        default.close()


def test_camera_pose_round_trips_and_normalises():
    camera = CameraConfig("head", pos=[0.1, 0.2, 0.3], quat=(0.0, 0.0, 0.0, 2.0))
    assert camera.pos == (0.1, 0.2, 0.3) and camera.quat == (0.0, 0.0, 0.0, 1.0)
    config = ObservationConfig(cameras=[camera, CameraConfig("left_wrist")])
    assert ObservationConfig.from_dict(config.to_dict()) == config
    # The built-in pose is not written out: the content keys of existing replays stay valid.
    assert set(config.to_dict()["cameras"][1]) == {"name", "rgb", "depth", "resolution"}


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"pos": (0.0, 1.0)}, "pos must be 3"),
        ({"pos": (0.0, float("nan"), 1.0)}, "pos must be 3 finite"),
        ({"pos": "abc"}, "pos must be 3"),
        ({"quat": (1.0, 0.0, 0.0)}, "quat must be 4"),
        ({"quat": (0.0, 0.0, 0.0, 0.0)}, "quat must not be zero"),
        ({"quat": (1.0, float("inf"), 0.0, 0.0)}, "quat must be 4 finite"),
    ],
    ids=["pos_short", "pos_nan", "pos_text", "quat_short", "quat_zero", "quat_inf"],
)
def test_bad_camera_pose(kwargs, message):
    with pytest.raises(ValueError, match=message):
        CameraConfig("head", **kwargs)
