"""The protocol's settings, its unofficial flags, the Wilson interval and the result's JSON form."""

from __future__ import annotations

import json
import math
from importlib import resources

import pytest
from hypothesis import given
from hypothesis import strategies as st

from bigym.action_modes import JointPositionActionMode, TorqueActionMode
from bigym.evaluation import (
    EPISODES,
    FIRST_SEED,
    EpisodeRecord,
    EvaluationResult,
    Settings,
    official_seeds,
    track,
    unofficial_reasons,
    wilson_interval,
)
from bigym.observations import CameraConfig, ObservationConfig


def test_wilson_interval_matches_published_values():
    # Newcombe (1998), Table I: 81/263 -> 0.2553-0.3662 (95%, Wilson score), and
    # the textbook case 8/10 -> 0.4902-0.9433.
    low, high = wilson_interval(81, 263)
    assert (round(low, 4), round(high, 4)) == (0.2553, 0.3662)
    low, high = wilson_interval(8, 10)
    assert (round(low, 4), round(high, 4)) == (0.4902, 0.9433)
    assert wilson_interval(0, 10)[0] == 0.0 and wilson_interval(10, 10)[1] == 1.0
    with pytest.raises(ValueError):
        wilson_interval(3, 0)
    with pytest.raises(ValueError):
        wilson_interval(11, 10)


@given(st.integers(1, 500).flatmap(lambda n: st.tuples(st.integers(0, n), st.just(n))))
def test_wilson_interval_holds_the_rate_and_narrows(case):
    successes, n = case
    low, high = wilson_interval(successes, n)
    assert 0.0 <= low <= successes / n <= high <= 1.0
    assert high - low > 0.0
    wider_low, wider_high = wilson_interval(successes, n, z=2.58)  # 99%
    assert wider_low <= low + 1e-12 and wider_high >= high - 1e-12


def test_official_seeds_are_a_fixed_block_apart_from_every_shipped_demo():
    assert official_seeds() == list(range(FIRST_SEED, FIRST_SEED + EPISODES))
    assert official_seeds(10) == official_seeds()[:10]
    with pytest.raises(ValueError):
        official_seeds(0)
    manifests = resources.files("bigym.experts") / "manifests"
    demo_seeds = set()
    for manifest in manifests.iterdir():
        if manifest.name.endswith(".json") and not manifest.name.endswith("-build.json"):
            demo_seeds |= {demo["seed"] for demo in json.loads(manifest.read_text())["demos"]}
    assert len(demo_seeds) > 50, "premise: the shipped datasets were read"
    assert demo_seeds.isdisjoint(official_seeds())


def test_the_official_settings_have_no_reasons_and_each_change_has_one():
    official = Settings("ReachTargetDual", tuple(official_seeds()))
    assert unofficial_reasons(official, 10.0) == []
    delta = Settings("ReachTargetDual", tuple(official_seeds()), action_mode=JointPositionActionMode(absolute=False))
    assert unofficial_reasons(delta, 10.0) == [], "absolute or delta targets are the method's choice"
    pixels = ObservationConfig.robot_cameras(privileged_information=True)
    assert (
        unofficial_reasons(Settings("ReachTargetDual", tuple(official_seeds()), observation_config=pixels), 10.0) == []
    )

    changes = {
        "episodes instead of 100": dict(seeds=tuple(official_seeds(20))),
        "not the official block": dict(seeds=tuple(range(100))),
        "control rate 100 Hz": dict(control_frequency=100.0),
        "time limit 20 s": dict(time_limit=20.0),
        "task variant": dict(task_kwargs={"hand": "right"}),
        "TorqueActionMode": dict(action_mode=TorqueActionMode()),
        "floating base: False": dict(action_mode=JointPositionActionMode(floating_base=False)),
        "instead of x, y, z and yaw": dict(action_mode=JointPositionActionMode(floating_dofs=("x", "y", "rz"))),
        "'external' is not one of the robot's": dict(
            observation_config=ObservationConfig(cameras=(CameraConfig("external"),))
        ),
        "moved from its mount": dict(
            observation_config=ObservationConfig(cameras=(CameraConfig("head", pos=(0.1, 0.0, 0.0)),))
        ),
        "at 128x128 instead of 84x84": dict(
            observation_config=ObservationConfig(cameras=(CameraConfig("head", resolution=(128, 128)),))
        ),
    }
    for expected, change in changes.items():
        settings = Settings("ReachTargetDual", **{"seeds": tuple(official_seeds()), **change})
        reasons = unofficial_reasons(settings, 10.0)
        assert any(expected in reason for reason in reasons), (expected, reasons)


def test_settings_refuse_what_cannot_be_an_evaluation():
    with pytest.raises(ValueError, match="at least one seed"):
        Settings("ReachTargetDual", ())
    with pytest.raises(ValueError, match="twice"):
        Settings("ReachTargetDual", (1, 2, 1))
    with pytest.raises(ValueError, match="non-negative"):
        Settings("ReachTargetDual", (-1,))
    with pytest.raises(ValueError, match="time_limit"):
        Settings("ReachTargetDual", (1,), time_limit=math.nan)


def test_track_names_the_inputs():
    assert track(ObservationConfig()) == "proprioception"
    assert track(ObservationConfig(privileged_information=True)) == "state"
    assert track(ObservationConfig.robot_cameras()) == "pixels"
    assert track(ObservationConfig.robot_cameras(privileged_information=True)) == "state+pixels"


def test_result_summary_and_json_round_trip(tmp_path):
    records = [
        EpisodeRecord(1, True, "success", 40, 0.8, 0.1, start="a"),
        EpisodeRecord(2, False, "time_limit", 500, 10.0, 1.0, start="b"),
        EpisodeRecord(3, False, "unstable", 7, 0.14, 0.1, detail="bad qacc", start="c"),
        EpisodeRecord(4, True, "success", 60, 1.2, 0.1, start="d"),
    ]
    result = EvaluationResult(
        "ReachTargetDual", "my:policy", records, {"track": "state"}, ["4 episodes instead of 100"]
    )
    summary = result.summary
    assert (summary.episodes, summary.successes, summary.success_rate) == (4, 2, 0.5)
    assert summary.interval == wilson_interval(2, 4)
    assert summary.mean_steps == (40 + 500 + 7 + 60) / 4
    assert summary.outcomes == {"success": 2, "failure": 0, "time_limit": 1, "unstable": 1}
    assert not result.official
    loaded = EvaluationResult.load(result.save(tmp_path / "out" / "result.json"))
    assert loaded.episodes == records and loaded.unofficial_reasons == result.unofficial_reasons
    data = json.loads((tmp_path / "out" / "result.json").read_text())
    assert data["official"] is False and data["summary"]["successes"] == 2
