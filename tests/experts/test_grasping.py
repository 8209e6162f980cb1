"""Grasping skills: which faces a hand closes on, how the base walks a route, how a pinch is adjusted."""

from __future__ import annotations

import numpy as np
import pytest

from bigym.action_modes import JointPositionActionMode
from bigym.envs.manipulation import StackBlocks
from bigym.experts import make_expert
from bigym.experts.expert import LEFT
from bigym.experts.generate import _env, close_envs
from bigym.experts.grasping import COMFORT, CROUCH_SPEED, LEG_OVERLAP, PEAK, SETTLE_DISTANCE, WALK_SPEED
from bigym.experts.stack_blocks import StackBlocksExpert


@pytest.fixture(scope="module")
def expert():
    env = _env("StackBlocks")
    obs, _ = env.reset(seed=0)
    expert = make_expert(env, seed=0)
    expert(obs)  # starts the script
    yield expert
    close_envs()


@pytest.mark.parametrize("side", [0, 1])
def test_the_hand_closes_across_two_faces_within_reach_after_the_turn(expert, side):
    for object_yaw in np.linspace(-np.pi, np.pi, 37):
        direction, turn = expert.face_closing(side, object_yaw, facing_yaw=0.0)
        normals = [np.array([np.cos(object_yaw + k * np.pi / 2), np.sin(object_yaw + k * np.pi / 2)]) for k in range(4)]
        assert max(abs(float(direction[:2] @ n)) for n in normals) == pytest.approx(1.0, abs=1e-9)
        # turned by ``turn``, the closing direction lies in the hand's comfortable range
        delta = np.arctan2(direction[1], direction[0]) - (0.5 * np.pi + turn)
        delta = float(np.angle(np.exp(2j * delta)) / 2.0)
        low, high = COMFORT[side]
        assert low - 1e-9 <= delta <= high + 1e-9
        assert abs(turn) <= np.pi / 4  # faces every quarter turn: never more than an eighth


@pytest.mark.parametrize("side", [0, 1])
def test_an_upright_grasp_keeps_the_back_of_the_hand_up_whichever_sign_the_closing_has(expert, side):
    """A hand coming in nearly level keeps one posture for either sign of the closing
    direction: the pinch frame's x axis points down (the other sign turns the wrist over,
    which the arm reaching far over a counter cannot do); the frame closes along the
    direction and comes in at the tilt."""
    for closing_yaw in np.linspace(-np.pi, np.pi, 13):
        closing = np.array([np.cos(closing_yaw), np.sin(closing_yaw), 0.0])
        for tilt in (0.2, 0.5):
            frame = expert.grasp_rotation(side, closing, tilt, upright=True)
            np.testing.assert_allclose(frame, expert.grasp_rotation(side, -closing, tilt, upright=True), atol=1e-12)
            assert frame[2, 0] < 0.0
            assert abs(float(frame[:, 1] @ closing)) == pytest.approx(1.0, abs=1e-9)
            assert float(np.arcsin(-frame[2, 2])) == pytest.approx(tilt, abs=1e-9)


def test_a_walk_rounds_its_corners_stays_within_the_base_speed_and_ends_on_the_goal(expert):
    start = expert.commanded_base()
    route = [start + [0.0, 1.0, 0.0, 0.0], start + [1.5, 1.0, 0.0, 0.5]]
    script = expert.walk(route)
    samples = []
    t0 = expert.time
    for _ in script:
        samples.append(expert.base_ref(expert.time)[:2].copy())
        expert.time += expert.dt
    samples = np.array(samples)
    np.testing.assert_allclose(expert.base_ref(expert.time), route[-1], atol=1e-9)
    speeds = np.linalg.norm(np.diff(samples, axis=0), axis=1) / expert.dt
    assert speeds.max() <= WALK_SPEED * 1.05
    # the corner is rounded (the legs overlap), not visited: the path never reaches it
    corner = route[0][:2]
    assert LEG_OVERLAP > 0 and np.linalg.norm(samples - corner, axis=1).min() > 0.01
    assert expert.time - t0 < sum(PEAK * d / WALK_SPEED for d in (1.0, 1.5)) + 2.0


def test_a_crouch_while_carrying_stays_within_the_crouch_speed(expert):
    start = expert.commanded_base()
    route = [start + [0.2, 0.0, -0.45, 0.0]]  # a deep crouch on a short step
    heights = []
    for _ in expert.walk(route):
        heights.append(float(expert.base_ref(expert.time)[2]))
        expert.time += expert.dt
    np.testing.assert_allclose(expert.base_ref(expert.time), route[-1], atol=1e-9)
    speeds = np.abs(np.diff(heights)) / expert.dt
    assert 0.8 * CROUCH_SPEED < speeds.max() <= CROUCH_SPEED * 1.05


def test_a_walk_that_does_not_wait_returns_its_end_at_once_and_the_base_still_gets_there(expert):
    start = expert.commanded_base()
    route = [start + [0.3, -0.4, 0.0, 0.2]]
    script = expert.walk(route, wait=False)
    with pytest.raises(StopIteration) as stop:
        next(script)  # no step of the plan's clock is spent
    end = stop.value.value
    t0 = expert.time
    assert end > t0 + PEAK * 0.5 / WALK_SPEED - 1e-9  # as long as a waited walk of 0.5 m
    np.testing.assert_allclose(expert.base_ref(t0), start, atol=1e-9)
    np.testing.assert_allclose(expert.base_ref(end), route[-1], atol=1e-9)
    np.testing.assert_allclose(expert.base_ref(end + 5.0), route[-1], atol=1e-9)  # and stays


@pytest.mark.parametrize("seed", range(5))
def test_a_plate_turned_in_its_own_plane_is_put_back_face_only(seed):
    from bigym.experts.geometry import aligning_rotation, axis_angle_matrix

    rng = np.random.default_rng(seed)
    stood = axis_angle_matrix(rng.normal(size=3), rng.uniform(0, np.pi))
    # as held: turned about its own face normal, and tilted a little
    held = axis_angle_matrix(rng.normal(size=3), 0.3) @ stood @ axis_angle_matrix([0, 0, 1], rng.uniform(-1, 1))
    goal = aligning_rotation(held[:, 2], stood[:, 2]) @ held
    np.testing.assert_allclose(goal[:, 2], stood[:, 2], atol=1e-9)  # the face as it stood
    np.testing.assert_allclose(goal.T @ goal, np.eye(3), atol=1e-9)
    # the smallest turn: about an axis in the plate's plane, so the in-plane turn stays
    axis = np.cross(held[:, 2], stood[:, 2])
    np.testing.assert_allclose(goal @ held.T @ axis, axis, atol=1e-9)


@pytest.mark.parametrize("tries", [0, 2])
def test_a_pinch_short_of_its_point_is_moved_by_what_it_missed(tries):
    """``adjust_pinch`` (before a plate's rim is closed on): the hand moves by the error it
    sees until its pinch is within ``SETTLE_DISTANCE`` of the point; with no tries it stays."""

    class Adjusting(StackBlocksExpert):
        def plan(self):
            self.point = self.data.site_xpos[self.env.robot.pinch_site_ids[LEFT]] + np.array([0.04, 0.02, 0.03])
            yield from self.adjust_pinch(LEFT, self.point, tries)
            while True:
                yield

    env = StackBlocks(action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500)
    try:
        obs, _ = env.reset(seed=0)
        expert = Adjusting(env, seed=0)
        for _ in range(1500):
            obs, *_ = env.step(expert(obs))
        miss = float(np.linalg.norm(env.data.site_xpos[env.robot.pinch_site_ids[LEFT]] - expert.point))
        if tries:
            assert miss <= SETTLE_DISTANCE + 0.002, [event for event in expert.events if "adjust" in event[1]]
        else:
            assert miss > 0.04
    finally:
        env.close()
