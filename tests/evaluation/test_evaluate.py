"""``evaluate``: the same records for any number of workers and either vector-env mode, every
episode on its seed's scene, a fingerprint of what ran, and clear errors."""

from __future__ import annotations

import imageio.v3 as iio
import numpy as np
import pytest

from bigym.demonstrations.metadata import model_fingerprint
from bigym.envs.reach_target import ReachTargetMultiModal
from bigym.evaluation import EvaluationError, PolicyLoadError, evaluate, load_factory, official_seeds
from bigym.experts import make_expert
from bigym.observations import ObservationConfig
from bigym.policies import RandomPolicy

TASK = "ReachTargetMultiModal"
STATE = ObservationConfig(privileged_information=True)


def comparable(result):
    return [record.comparable() for record in result.episodes]


@pytest.fixture(scope="module")
def expert_reference():
    return evaluate("bigym.experts:make_expert", TASK, episodes=6, workers=1)


def test_expert_records_do_not_depend_on_workers_or_a_sync_vector_env(expert_reference):
    records = comparable(expert_reference)
    assert [r["seed"] for r in records] == official_seeds(6)
    assert len({r["steps"] for r in records}) > 1, "premise: episodes differ from seed to seed"
    assert len({r["start"] for r in records}) == 6, "premise: every seed is its own scene"
    assert comparable(evaluate("bigym.experts:make_expert", TASK, episodes=6, workers=2)) == records
    sync = evaluate("bigym.experts:make_expert", TASK, episodes=6, workers=1, vector="sync", envs_per_worker=4)
    assert comparable(sync) == records


def test_an_async_vector_env_gives_every_sub_env_its_seed():
    by_workers = evaluate("evalkit:observed_reach", TASK, episodes=6, workers=2, observation_config=STATE)
    records = comparable(by_workers)
    assert len({r["steps"] for r in records}) > 1, "premise: episodes differ from seed to seed"
    by_async = evaluate(
        "evalkit:observed_reach", TASK, episodes=6, workers=1, vector="async", envs_per_worker=4,
        observation_config=STATE,
    )  # fmt: skip
    assert comparable(by_async) == records


def test_records_name_the_scene_the_seed_gives(expert_reference):
    env = ReachTargetMultiModal()
    try:
        for record in expert_reference.episodes[:2]:
            env.reset(seed=record.seed)
            assert record.start == env.state_digest()
        env.reset(seed=0)
        assert env.state_digest() not in {r.start for r in expert_reference.episodes}
    finally:
        env.close()


def test_the_fingerprint_describes_what_ran(expert_reference):
    env = ReachTargetMultiModal()
    try:
        physics = model_fingerprint(env.model)
    finally:
        env.close()
    fingerprint = expert_reference.fingerprint
    assert fingerprint["model_fingerprint"] == physics
    assert fingerprint["control_frequency"] == 50.0 and fingerprint["time_limit"] == ReachTargetMultiModal.time_limit
    assert fingerprint["action_mode"]["absolute"] is True and fingerprint["track"] == "proprioception"
    assert fingerprint["episodes"] == 6 and fingerprint["first_seed"] == official_seeds()[0]
    assert expert_reference.unofficial_reasons == ["6 episodes instead of 100"]
    summary = expert_reference.summary
    assert summary.successes == sum(r.success for r in expert_reference.episodes) >= 5
    assert all(r.outcome == "success" for r in expert_reference.episodes if r.success)


def test_a_shorter_time_limit_truncates_and_is_flagged():
    result = evaluate(RandomPolicy, TASK, seeds=[3, 4], workers=1, time_limit=0.5, control_frequency=20)
    assert [(r.outcome, r.steps, r.sim_time) for r in result.episodes] == [("time_limit", 10, 0.5)] * 2
    assert result.fingerprint["max_episode_steps"] == 10
    reasons = " ".join(result.unofficial_reasons)
    assert "time limit 0.5 s" in reasons and "control rate 20 Hz" in reasons and "official block" in reasons
    assert result.policy == "bigym.policies:RandomPolicy"


def test_videos_of_the_first_episodes(tmp_path):
    result = evaluate("bigym.experts:make_expert", TASK, episodes=2, workers=1, video_dir=tmp_path, videos=1)
    first, second = result.episodes
    assert second.video is None and first.video is not None
    frames = iio.imread(first.video)
    assert first.sim_time * 20 <= len(frames) <= first.sim_time * 30 + 1  # 20-30 frames per simulated second
    assert frames.shape[1:] == (480, 640, 3)
    assert np.abs(frames[-1].astype(int) - frames[0].astype(int)).mean() > 0.5, "the robot moves in the video"


def test_async_refuses_a_policy_that_reads_the_simulator():
    with pytest.raises(EvaluationError, match="reads the simulator"):
        evaluate("bigym.experts:make_expert", TASK, episodes=2, workers=1, vector="async")


def test_policy_errors_name_the_episode():
    with pytest.raises(EvaluationError, match=r"seed 1000000, step 0: RuntimeError: this policy is broken"):
        evaluate("evalkit:broken", TASK, episodes=2, workers=1)
    with pytest.raises(EvaluationError, match="not callable"):
        evaluate("evalkit:not_callable", TASK, episodes=1, workers=1)


def test_policy_factories_by_name_by_file_or_by_reference(tmp_path):
    assert load_factory("bigym.experts:make_expert") is make_expert
    assert load_factory(RandomPolicy) is RandomPolicy
    source = tmp_path / "my_policy.py"
    source.write_text("def factory(env):\n    return lambda obs: env.action_space.sample()\n")
    assert callable(load_factory(f"{source}:factory"))
    for spec, message in [
        ("no_colon", "package.module:function"),
        ("bigym.nothing_here:f", "cannot import"),
        ("bigym.experts:nothing_here", "has no 'nothing_here'"),
        (f"{tmp_path / 'missing.py'}:f", "no such policy file"),
        ("bigym:__version__", "not callable"),
    ]:
        with pytest.raises(PolicyLoadError, match=message):
            load_factory(spec)
    with pytest.raises(PolicyLoadError, match="cannot be sent to worker processes"):
        evaluate(lambda env: RandomPolicy(env), TASK, episodes=1)


def test_bad_arguments_fail_before_any_worker_starts():
    with pytest.raises(ValueError, match="not both"):
        evaluate(RandomPolicy, TASK, episodes=2, seeds=[1, 2])
    with pytest.raises(ValueError, match="vector"):
        evaluate(RandomPolicy, TASK, episodes=2, vector="threads")
    with pytest.raises(ValueError, match="without a vector env"):
        evaluate(RandomPolicy, TASK, episodes=2, vector="sync", video_dir="videos")
    with pytest.raises(Exception, match="unknown task"):
        evaluate(RandomPolicy, "NoSuchTask", episodes=2)


def test_random_policy_reset_repeats_its_actions():
    env = ReachTargetMultiModal()
    try:
        policy = RandomPolicy(env, seed=1)
        policy.reset(7)
        first = [policy({}) for _ in range(3)]
        policy({})
        policy.reset(7)
        assert all(np.array_equal(a, b) for a, b in zip(first, [policy({}) for _ in range(3)]))
    finally:
        env.close()


def test_workers_end_when_the_evaluating_process_is_killed(tmp_path):
    """``timeout`` or ``kill`` stops only the evaluating process: its pool workers must not
    run on (or wait forever) without it."""
    import os
    import signal
    import subprocess
    import sys
    import time

    script = tmp_path / "evaluating.py"
    script.write_text(
        "import multiprocessing\n"
        "from bigym.evaluation import evaluate\n"
        "def progress(record):\n"
        "    print('WORKERS', *[p.pid for p in multiprocessing.active_children()], flush=True)\n"
        "if __name__ == '__main__':\n"
        f"    evaluate('bigym.policies:RandomPolicy', {TASK!r}, episodes=100, workers=2, progress=progress)\n"
    )
    parent = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    try:
        line = parent.stdout.readline()
        assert line.startswith("WORKERS"), f"premise: the evaluation reports its workers ({line!r})"
        workers = [int(pid) for pid in line.split()[1:]]
        assert len(workers) == 2
    finally:
        parent.send_signal(signal.SIGKILL)
        parent.wait()

    def running(pid: int) -> bool:
        try:
            with open(f"/proc/{pid}/stat") as stat:
                return stat.read().rsplit(")", 1)[1].split()[0] != "Z"  # an unreaped zombie has ended
        except FileNotFoundError:
            return False

    deadline = time.monotonic() + 30
    while any(running(pid) for pid in workers) and time.monotonic() < deadline:
        time.sleep(0.2)
    left = [pid for pid in workers if running(pid)]
    for pid in left:
        os.kill(pid, signal.SIGKILL)
    assert not left, f"workers {left} outlived the killed evaluation"
