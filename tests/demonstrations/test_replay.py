"""Replay: down-sampling, checkpoint checks, action-mode errors, conversions, parallel replay."""

from __future__ import annotations

import pickle
import subprocess
import sys

import mujoco
import numpy as np
import pytest
from demokit import same_observations
from hypothesis import given, settings
from hypothesis import strategies as st

from bigym.action_modes import JointPositionActionMode
from bigym.demonstrations import (
    DemoActionModeError,
    DemoDivergenceError,
    DemoError,
    DemoReplayError,
    convert_demo,
    default_tolerance,
    record_episode,
    replay,
    replay_many,
)
from bigym.demonstrations.convert import ABSOLUTE, DELTA, ActionSpec, convert_actions, held_controls
from bigym.demonstrations.metadata import state_segments
from bigym.demonstrations.player import TOLERANCE_SPEED
from bigym.envs.reach_target import ReachTargetSingle
from bigym.observations import ObservationConfig


def _qpos(demo, state):
    env = ReachTargetSingle()
    part = state_segments(env.model, demo.metadata.checkpoint_spec)["qpos"]
    env.close()
    return state[part]


@pytest.mark.parametrize("name", ["single_absolute", "single_delta", "dual_absolute", "dual_delta"])
@pytest.mark.parametrize("frequency", [50, 20])
def test_downsampled_replay_still_succeeds(expert_demos, name, frequency):
    demo = expert_demos[name]
    result = replay(demo, frequency=frequency)
    report = result.report
    assert not report.exact and report.frequency == frequency
    assert report.first_success_step is not None, "the down-sampled replay never reached success"
    assert report.checkpoints_checked >= 1
    # The whole recording is replayed and checked; the episode returned ends at its first
    # terminal step (the recording goes on past the first success).
    assert report.replayed_steps == -(-len(demo) // (500 // frequency))
    assert len(result) == report.episode_steps < report.replayed_steps
    assert np.flatnonzero(result.terminated | result.truncated).tolist() == [len(result) - 1]
    assert result.success[-1] and report.final_success
    # Joint positions stay within the tolerance at every aligned checkpoint, and the end state
    # matches the recording's within the tolerance plus what the robot can move in the "hold"
    # steps that pad the last window (checked by the replay itself, and here).
    pad = report.replayed_steps * (500 // frequency) - len(demo)
    slack = default_tolerance(frequency) + TOLERANCE_SPEED * pad / 500
    assert report.max_divergence <= slack
    whole = replay(demo, frequency=frequency, episode_only=False)
    assert len(whole) == report.replayed_steps
    np.testing.assert_array_equal(whole.states[: len(result) + 1], result.states)
    aligned = [k for k in range(len(demo.checkpoint_steps)) if demo.checkpoint_steps[k] % (500 // frequency) == 0]
    for k in aligned:
        replayed = _qpos(demo, whole.states[demo.checkpoint_steps[k] // (500 // frequency)])
        np.testing.assert_allclose(replayed, _qpos(demo, demo.checkpoint_states[k]), atol=default_tolerance(frequency))
    final = _qpos(demo, demo.checkpoint_states[-1])
    np.testing.assert_allclose(_qpos(demo, whole.states[-1]), final, atol=slack)


def test_native_rate_replay_checks_every_checkpoint_bit_for_bit(expert_demos):
    demo = expert_demos["dual_absolute"]
    result = replay(demo)
    assert result.report.exact and result.report.tolerance == 0.0
    assert result.report.checkpoints_checked == len(demo.checkpoint_steps)
    assert result.report.max_divergence == 0.0
    whole = replay(demo, episode_only=False)
    np.testing.assert_array_equal(whole.states[demo.checkpoint_steps], demo.checkpoint_states)
    inside = demo.checkpoint_steps <= len(result)  # the checkpoints within the returned episode
    np.testing.assert_array_equal(result.states[demo.checkpoint_steps[inside]], demo.checkpoint_states[inside])


def test_divergence_reports_first_step_and_size(expert_demos):
    demo = expert_demos["single_delta"]
    tampered = demo.replace(checkpoint_states=demo.checkpoint_states.copy())
    env = ReachTargetSingle()
    qpos = state_segments(env.model, demo.metadata.checkpoint_spec)["qpos"]
    elbow = qpos.start + env.model.joint("left_elbow").qposadr[0]
    env.close()
    tampered.checkpoint_states[1, elbow] += 1e-9  # the second checkpoint is off by a nanoradian
    with pytest.raises(DemoDivergenceError) as caught:
        replay(tampered)
    error = caught.value
    assert error.step == demo.checkpoint_steps[1]
    assert error.size == pytest.approx(1e-9, rel=1e-3)
    assert "left_elbow" in error.where and f"diverged at step {error.step}" in str(error)
    # The same demo with a changed action diverges at the first checkpoint after that action.
    actions = demo.actions.copy()
    actions[60, 5] += 0.01
    with pytest.raises(DemoDivergenceError) as caught:
        replay(demo.replace(actions=actions))
    assert caught.value.step == 100 and caught.value.size > 0
    # verify=False returns the drifted replay, and says how far it drifted.
    drifted = replay(demo.replace(actions=actions), verify=False)
    assert drifted.report.max_divergence > 0 and drifted.report.max_divergence_step == 100


def test_downsampled_drift_beyond_tolerance_is_an_error(expert_demos):
    with pytest.raises(DemoDivergenceError, match="tolerance 0.001") as caught:
        replay(expert_demos["dual_delta"], frequency=20, tolerance=0.001)
    assert caught.value.size > 0.001 and caught.value.tolerance == 0.001


def test_wrong_seed_fails_at_the_initial_state(expert_demos):
    demo = expert_demos["single_absolute"]
    wrong = demo.replace(metadata=demo.metadata.replace(seed=demo.metadata.seed + 1))
    with pytest.raises(DemoDivergenceError, match="state after reset") as caught:
        replay(wrong)
    assert caught.value.step == 0 and "mocap_pos" in caught.value.where


def test_claimed_success_must_be_reproduced():
    env = ReachTargetSingle(control_frequency=50)
    still = np.zeros(env.action_space.shape, np.float32)  # delta mode: the robot holds its start pose
    for seed in range(20):  # a target the start pose does not already touch
        demo = record_episode(env, lambda _obs: still, seed=seed, max_steps=10)
        if not demo.metadata.success:
            break
    env.close()
    assert demo.metadata.success is False
    replay(demo)  # not claimed: fine
    claimed = demo.replace(metadata=demo.metadata.replace(success=True))
    with pytest.raises(DemoReplayError, match="never reaches success"):
        replay(claimed)


def test_env_with_another_action_mode_fails_clearly(expert_demos):
    demo = expert_demos["single_absolute"]
    delta_env = ReachTargetSingle(action_mode=JointPositionActionMode(absolute=False), control_frequency=500)
    with pytest.raises(DemoActionModeError, match="recorded with absolute actions") as caught:
        replay(demo, env=delta_env)
    assert "bigym demos convert --to delta" in str(caught.value)
    three_dofs = ReachTargetSingle(
        action_mode=JointPositionActionMode(absolute=True, floating_dofs=["x", "y", "rz"]), control_frequency=500
    )
    with pytest.raises(DemoActionModeError, match="no conversion exists"):
        replay(demo, env=three_dofs)
    # Asked for explicitly, the conversion runs (and is checked).
    converted = replay(demo, env=delta_env, convert=True)
    assert converted.report.first_success_step is not None
    for env in (delta_env, three_dofs):
        env.close()


def test_delta_to_absolute_is_exact_and_absolute_to_delta_close(expert_demos):
    delta = expert_demos["single_delta"]
    absolute = convert_demo(delta, to="absolute")
    assert absolute.metadata.action_mode["absolute"] is True
    assert absolute.metadata.extra["conversion_exact"] is True
    original = replay(delta)
    again = replay(absolute)
    assert again.report.exact
    assert same_observations(original.observations, again.observations)
    back = convert_demo(absolute, to="delta")
    assert back.metadata.action_mode["absolute"] is False
    assert back.metadata.extra["conversion_max_divergence"] < 1e-6
    assert replay(back).report.first_success_step is not None


def test_rate_conversion_records_a_new_exact_demo(expert_demos):
    demo = expert_demos["dual_absolute"]
    at_50 = convert_demo(demo, frequency=50)
    assert at_50.metadata.frequency == 50 and len(at_50) == -(-len(demo) // 10)
    assert at_50.metadata.extra["conversion"] == "500hz->50hz"
    result = replay(at_50)
    assert result.report.exact and result.report.first_success_step is not None
    at_25 = replay(at_50, frequency=25)  # and on down from the converted demo
    assert at_25.report.first_success_step is not None


def test_upsampling_small_actions_is_exact():
    env = ReachTargetSingle(control_frequency=50)
    rng = np.random.default_rng(3)
    low, high = env.action_space.low, env.action_space.high

    def gentle(_obs):  # deltas that also fit the 500 Hz bounds
        action = rng.uniform(low / 20, high / 20).astype(np.float32)
        action[-2:] = rng.integers(0, 2, 2)
        return action

    demo = record_episode(env, gentle, seed=5, max_steps=40)
    env.close()
    fine = convert_demo(demo, frequency=500)
    assert fine.metadata.extra["conversion_exact"] is True and len(fine) == 400
    result = replay(demo, frequency=500)
    assert result.report.exact
    np.testing.assert_array_equal(result.states[::10][1:], replay(demo).states[1:])


def _spec(kinds, substeps, low=None, high=None):
    n = len(kinds)
    kinds = np.array(kinds)
    low_bound = None if low is None else np.full(n, low, float)
    high_bound = None if high is None else np.full(n, high, float)
    return ActionSpec(kinds, np.full(n, -1.0), np.full(n, 1.0), substeps, low_bound, high_bound)


@settings(max_examples=40, deadline=None)
@given(
    st.integers(1, 60),
    st.sampled_from([2, 5, 10, 25]),
    st.integers(0, 2**31 - 1),
)
def test_downsampling_keeps_targets_at_window_ends(steps, factor, seed):
    rng = np.random.default_rng(seed)
    kinds = [DELTA, DELTA, ABSOLUTE]
    source = _spec(kinds, 1)
    target = _spec(kinds, factor, -0.1 * factor, 0.1 * factor)
    actions = np.column_stack([rng.uniform(-0.1, 0.1, steps), rng.uniform(-0.1, 0.1, steps), rng.uniform(-1, 1, steps)])
    ctrl0 = np.array([0.9, -0.2, 0.0])  # the first target starts near its upper clamp
    out, exact = convert_actions(actions, source, target, ctrl0)
    assert not exact and len(out) == -(-steps // factor)
    assert (np.abs(out[:, :2]) <= 0.1 * factor + 1e-12).all()
    wanted = held_controls(actions, source, ctrl0)
    ends = np.minimum(np.arange(1, len(out) + 1) * factor, steps) - 1
    reached = held_controls(out, target, ctrl0)
    # Delta targets and absolute targets agree with the recording at every window's end.
    np.testing.assert_allclose(reached[:, :2], wanted[ends, :2], atol=1e-12)
    np.testing.assert_array_equal(out[:, 2], actions[ends, 2])


def test_clamped_deltas_keep_the_net_motion():
    source = _spec([DELTA], 1)
    target = _spec([DELTA], 4, -0.4, 0.4)
    actions = np.array([[0.1], [0.1], [-0.1], [-0.1]])  # at the clamp, +0.1 +0.1 changes nothing
    out, _ = convert_actions(actions, source, target, np.array([1.0]))
    assert out[0, 0] == pytest.approx(-0.2)  # not the naive sum 0.0


def test_pool_replay_matches_serial_and_keeps_order(expert_demos):
    demos = [expert_demos["single_absolute"], expert_demos["dual_delta"], expert_demos["single_delta"]]
    config = ObservationConfig(privileged_information=True)
    serial = replay_many(demos, config, 50, workers=1, progress=False)
    pooled = replay_many(demos, config, 50, workers=2, progress=True)
    for a, b, demo in zip(serial, pooled, demos):
        assert a.uuid == b.uuid == demo.uuid
        assert same_observations(a.observations, b.observations)
    bad = demos[0].replace(actions=demos[0].actions * 0 + 0.5)
    results = replay_many([bad, demos[1]], workers=2, progress=False, errors="return")
    assert isinstance(results[0], DemoError) and results[1].uuid == demos[1].uuid
    with pytest.raises(DemoError):
        replay_many([bad], workers=2, progress=False)


def test_errors_survive_pickling():
    error = DemoDivergenceError("diverged", step=3, size=0.5, where="qpos[1]", tolerance=0.0)
    copy = pickle.loads(pickle.dumps(error))
    assert type(copy) is DemoDivergenceError and copy.step == 3 and copy.where == "qpos[1]" and str(copy) == "diverged"


def test_ray_is_optional_and_never_imported_unasked(expert_demos, tmp_path):
    path = expert_demos["single_delta"].save(tmp_path)
    script = (
        "import sys\n"
        "from bigym.demonstrations import Demo, replay_many\n"
        f"replay_many([Demo.load({str(path)!r})], frequency=50, progress=False)\n"
        "assert 'ray' not in sys.modules, 'ray was imported'\n"
        "print('no ray')\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "no ray" in done.stdout
    try:
        import ray
    except ImportError:
        with pytest.raises(DemoError, match="pip install"):
            replay_many([expert_demos["single_delta"]], backend="ray", progress=False)
    else:  # ray installed here: the ray backend must give the same replay
        try:
            result = replay_many([expert_demos["single_delta"]], backend="ray", workers=1, progress=False)
        finally:
            ray.shutdown()  # a one-CPU instance left running would starve later tests of Ray workers
        assert same_observations(result[0].observations, replay(expert_demos["single_delta"]).observations)


def test_replay_writes_a_video(expert_demos, tmp_path):
    import imageio.v2 as imageio

    demo = expert_demos["single_delta"]
    video = tmp_path / "demo.mp4"
    result = replay(demo, frequency=50, video=video)
    reader = imageio.get_reader(video)
    frames = reader.count_frames()
    reader.close()
    # 50 Hz -> every second step at 25 fps, plus the reset frame; the video shows the whole
    # recording, the steps after the episode's end included.
    assert frames == result.report.replayed_steps // 2 + 1


def test_replay_states_match_mujoco_state_size(expert_demos):
    demo = expert_demos["single_absolute"]
    env = ReachTargetSingle()
    result = replay(demo, episode_only=False)
    assert result.states.shape == (len(demo) + 1, mujoco.mj_stateSize(env.model, demo.metadata.checkpoint_spec))
    env.close()


def test_task_variant_is_recorded_and_rebuilt_on_replay():
    """A right-hand ReachTargetSingle demo replays in a right-hand env, not the default left."""
    from bigym.policies import ReachPolicy

    env = ReachTargetSingle(hand="right", action_mode=JointPositionActionMode(absolute=True))
    demo = record_episode(env, ReachPolicy(env), seed=3, steps_after_success=5)
    env.close()
    assert demo.metadata.task_kwargs == {"hand": "right"}
    assert demo.metadata.success
    replayed = replay(demo)
    assert replayed.success.any()


def test_a_task_that_places_static_props_at_reset_replays_without_a_model_warning():
    """MovePlate moves its racks (static bodies, so the model itself) at every reset: the
    model a demo was recorded with is the one reset(seed) gives, whatever the env did before."""
    import warnings

    from bigym.demonstrations import DemoVersionWarning, record_episode
    from bigym.envs.move_plates import MovePlate
    from bigym.policies import HoldPolicy

    env = MovePlate(action_mode=JointPositionActionMode(absolute=True), control_frequency=50)
    try:
        demo = record_episode(env, HoldPolicy(env), seed=3, source="random", max_steps=5)
        env.reset(seed=8)  # the racks move elsewhere
        with warnings.catch_warnings():
            warnings.simplefilter("error", DemoVersionWarning)
            replayed = replay(demo, env=env, verify=True)
        assert replayed.report.exact and replayed.report.checkpoints_checked >= 1
        assert replayed.metadata.model_fingerprint == demo.metadata.model_fingerprint
    finally:
        env.close()
