"""Camera images stay exact whatever happens to other envs' OpenGL contexts.

Every lifecycle a user, a notebook or an evaluation script goes through (envs created in a
loop and dropped without ``close()``, several alive at once and used in turn, closed and
rebuilt, garbage-collected in the middle of another env's episode, inside vector envs of
both kinds) must give exactly the images, RGB and depth, that a fresh env in a fresh
process gives. The reference images come from a separate Python process, so nothing this
process did to its GL state can leak into them.
"""

from __future__ import annotations

import gc
import json
import subprocess
import sys
from functools import partial

import gymnasium as gym
import numpy as np
import pytest

from bigym.observations import CameraConfig, ObservationConfig

TASKS = ("ReachTargetMultiModal", "DrawerTopOpen")  # an empty room and a kitchen scene
SEEDS = (0, 1)
STEPS = 3  # zero-change steps after reset: images of a state the physics produced
CONFIG = ObservationConfig(
    cameras=[
        CameraConfig("head", rgb=True, depth=True, resolution=(48, 64)),
        CameraConfig("left_wrist", rgb=True, depth=True, resolution=(32, 32)),
    ]
)
KEYS = ("rgb_head", "depth_head", "rgb_left_wrist", "depth_left_wrist")

_REFERENCE_SCRIPT = """
import json, sys
import numpy as np
import gymnasium as gym
import bigym
from bigym.observations import ObservationConfig
config = ObservationConfig.from_dict(json.loads(sys.argv[1]))
out = {}
for task in json.loads(sys.argv[2]):
    for seed in json.loads(sys.argv[3]):
        env = gym.make(f"bigym/{task}-v0", observation_config=config)
        obs, _ = env.reset(seed=seed)
        for _ in range(int(sys.argv[4])):
            obs, *_ = env.step(np.zeros(env.action_space.shape, np.float32))
        for key in ("rgb_head", "depth_head", "rgb_left_wrist", "depth_left_wrist"):
            out[f"{task}/{seed}/{key}"] = obs[key]
        env.close()
np.savez(sys.argv[5], **out)
"""


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """Images from fresh envs in a fresh process: {(task, seed): {key: array}}."""
    path = tmp_path_factory.mktemp("reference") / "images.npz"
    args = [json.dumps(CONFIG.to_dict()), json.dumps(TASKS), json.dumps(SEEDS), str(STEPS), str(path)]
    subprocess.run([sys.executable, "-c", _REFERENCE_SCRIPT, *args], check=True)
    with np.load(path) as stored:
        images = {(task, seed): {k: stored[f"{task}/{seed}/{k}"] for k in KEYS} for task in TASKS for seed in SEEDS}
    # The reference itself must be real pictures, or equality below proves nothing.
    for (task, seed), obs in images.items():
        assert obs["rgb_head"].std() > 10, (task, seed)
        assert obs["rgb_left_wrist"].std() > 3, (task, seed)
        for key in ("depth_head", "depth_left_wrist"):
            depth = obs[key]
            assert np.all(np.isfinite(depth)) and depth.min() > 0.01 and depth.max() < 30.0, (task, seed, key)
            assert depth.std() > 0.01, (task, seed, key)
    assert not np.array_equal(images[(TASKS[0], 0)]["rgb_head"], images[(TASKS[1], 0)]["rgb_head"])
    return images


def _make(task: str):
    return gym.make(f"bigym/{task}-v0", observation_config=CONFIG)


def _episode(env, seed: int) -> dict[str, np.ndarray]:
    obs, _ = env.reset(seed=seed)
    for _ in range(STEPS):
        obs, *_ = env.step(np.zeros(env.action_space.shape, np.float32))
    return obs


def _assert_same(obs: dict[str, np.ndarray], expected: dict[str, np.ndarray], where: str) -> None:
    for key in KEYS:
        if not np.array_equal(obs[key], expected[key]):
            difference = np.abs(obs[key].astype(np.float64) - expected[key]).max()
            pytest.fail(f"{where}: {key} differs from a fresh env's (max |difference| {difference})")


@pytest.mark.parametrize("collect", [False, True], ids=["implicit_gc", "gc_collect"])
def test_envs_dropped_without_close_in_a_loop(reference, collect):
    for i in range(4):
        task, seed = TASKS[i % 2], SEEDS[(i // 2) % 2]
        env = _make(task)  # the previous env is dropped here, never closed
        if collect:
            gc.collect()
        _assert_same(_episode(env, seed), reference[(task, seed)], f"loop iteration {i}")
    del env


def test_a_reused_env_shows_nothing_of_its_earlier_frames(reference):
    """After an episode that carried the cameras elsewhere (the base walked back, crouched
    and turned), ``reset`` gives a fresh env's images: MuJoCo places the floor plane by the
    scene's camera, which held the previous frame's last camera until the renderer set it
    first (the floor's shading then differed by up to 6 levels)."""
    env = _make(TASKS[1])
    env.reset(seed=SEEDS[1])
    move = np.zeros(env.action_space.shape, np.float32)
    move[:4] = (-0.01, 0.005, -0.004, 0.02)  # per step at 50 Hz: back, left, down, turning
    for _ in range(40):
        env.step(move)
    first_frames = {seed: env.reset(seed=seed)[0] for seed in SEEDS}  # the frames right after reset
    for seed in SEEDS:
        fresh = _make(TASKS[1])
        _assert_same(first_frames[seed], fresh.reset(seed=seed)[0], f"reset to seed {seed} after a walk")
        fresh.close()
        _assert_same(_episode(env, seed), reference[(TASKS[1], seed)], f"seed {seed} after a walk")
    env.close()


def test_envs_closed_and_rebuilt(reference):
    for i in range(3):
        env = _make(TASKS[0])
        _assert_same(_episode(env, SEEDS[i % 2]), reference[(TASKS[0], SEEDS[i % 2])], f"rebuild {i}")
        env.close()
        env.close()  # closing twice is harmless


def test_many_envs_alive_used_in_turn(reference):
    envs = [(_make(task), task, seed) for task in TASKS for seed in SEEDS]
    try:
        # Interleave the episodes step by step: each env's images must be its own.
        observations = [env.reset(seed=seed)[0] for env, _, seed in envs]
        for _ in range(STEPS):
            observations = [env.step(np.zeros(env.action_space.shape, np.float32))[0] for env, _, _ in envs]
        for obs, (_, task, seed) in zip(observations, envs):
            _assert_same(obs, reference[(task, seed)], f"interleaved {task} seed {seed}")
    finally:
        for env, _, _ in envs:
            env.close()


@pytest.mark.parametrize("how", ["close", "drop"])
def test_other_env_released_mid_episode(reference, how):
    """An env closed or garbage-collected between another env's steps leaves that env intact."""
    survivor = _make(TASKS[1])
    victim = _make(TASKS[0])
    created_after = None
    try:
        survivor.reset(seed=SEEDS[0])
        victim.reset(seed=SEEDS[1])
        zero = np.zeros(survivor.action_space.shape, np.float32)
        survivor.step(zero)
        if how == "close":
            victim.close()
        else:
            del victim
            gc.collect()
        created_after = _make(TASKS[0])  # reuses GL names the released context had
        obs = None
        for _ in range(STEPS - 1):
            obs, *_ = survivor.step(zero)
        _assert_same(obs, reference[(TASKS[1], SEEDS[0])], f"survivor after the other env was {how}d")
        _assert_same(_episode(created_after, SEEDS[1]), reference[(TASKS[0], SEEDS[1])], "env created after")
    finally:
        survivor.close()
        if created_after is not None:
            created_after.close()


def test_rgb_array_viewer_dropped_beside_observation_cameras(reference):
    """The external ``render()`` camera is a second GL context in the same env."""
    for _ in range(2):
        env = gym.make(f"bigym/{TASKS[0]}-v0", observation_config=CONFIG, render_mode="rgb_array",
                       render_resolution=(24, 32))
        obs = _episode(env, SEEDS[0])
        frame = env.render()
        assert frame.shape == (24, 32, 3) and frame.std() > 5
        _assert_same(obs, reference[(TASKS[0], SEEDS[0])], "env with an rgb_array viewer")
    del env
    gc.collect()
    env = _make(TASKS[0])
    try:
        _assert_same(_episode(env, SEEDS[0]), reference[(TASKS[0], SEEDS[0])], "env after a dropped viewer")
    finally:
        env.close()


def test_closed_env_refuses_to_observe():
    env = _make(TASKS[0])
    env.reset(seed=0)
    env.close()
    with pytest.raises(RuntimeError, match="closed"):
        env.reset(seed=0)


@pytest.mark.parametrize("kind", ["sync", "async_fork", "async_spawn"])
def test_vector_envs(reference, kind):
    """Sub-envs render their own scenes, also when the parent process already holds GL contexts."""
    parent = _make(TASKS[0])  # a live context in the parent, inherited by forked workers
    parent.reset(seed=0)
    factories = [partial(_make, TASKS[0]), partial(_make, TASKS[0])]
    if kind == "sync":
        vector = gym.vector.SyncVectorEnv(factories)
    else:
        vector = gym.vector.AsyncVectorEnv(factories, context=kind.removeprefix("async_"))
    try:
        obs, _ = vector.reset(seed=list(SEEDS))
        zero = np.zeros(vector.action_space.shape, np.float32)
        for _ in range(STEPS):
            obs, *_ = vector.step(zero)
        for index, seed in enumerate(SEEDS):
            _assert_same({k: obs[k][index] for k in KEYS}, reference[(TASKS[0], seed)], f"{kind} sub-env {index}")
        _assert_same(_episode(parent, SEEDS[0]), reference[(TASKS[0], SEEDS[0])], f"parent beside {kind}")
    finally:
        vector.close()
        parent.close()


def test_fork_beside_a_foreign_gl_context_fails_clearly(tmp_path):
    """With a GL context bigym does not own alive (a user's mujoco.Renderer), the EGL display
    cannot be released before a fork: a forked child that renders must raise, not hang."""
    script = """
import multiprocessing, os, sys
import mujoco, numpy as np, gymnasium as gym
import bigym
from bigym.observations import CameraConfig, ObservationConfig
config = ObservationConfig(cameras=[CameraConfig("head", resolution=(16, 16))])
def child(queue):
    try:
        gym.make("bigym/ReachTargetSingle-v0", observation_config=config).reset(seed=0)
        queue.put("rendered")
    except RuntimeError as error:
        queue.put(str(error))
model = mujoco.MjModel.from_xml_string("<mujoco><worldbody><geom size='1'/></worldbody></mujoco>")
renderer = mujoco.Renderer(model, 8, 8)  # the user's own context, alive across the fork
context = multiprocessing.get_context("fork")
queue = context.Queue()
process = context.Process(target=child, args=(queue,))
process.start()
print(queue.get(timeout=120))
process.join()
renderer.close()
"""
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert "spawn" in result.stdout and "forked" in result.stdout, result.stdout
