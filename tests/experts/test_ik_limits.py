"""The IK's half-planes for the arms: an arm reaching out past a plane keeps its elbow,
forearm and wrist on the near side (the open door beside a crouched body), and an
expert's planes are gone at the next episode."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from bigym.experts import make_expert
from bigym.experts.expert import LEFT
from bigym.experts.generate import _env, close_envs
from bigym.experts.groceries import CUPBOARD, DOOR
from bigym.experts.ik import ARM_POINTS, WholeBodyIK, self_collision_pairs


@pytest.fixture(scope="module")
def env():
    env = _env("StoreGroceriesLower")
    yield env
    close_envs()


def _left_arm_points(ik) -> list[tuple[np.ndarray, float]]:
    data = ik.configuration.data
    points = []
    for link, local, radius in ARM_POINTS:
        body = ik.model.body(f"left_{link}").id
        points.append((data.xpos[body] + data.xmat[body].reshape(3, 3) @ np.array(local), radius))
    return points


def _reach_out(ik, goal: np.ndarray, steps: int = 300) -> None:
    """Drive the left hand towards ``goal`` (position only), the base held where it is."""
    base = ik.base()
    posture = np.zeros(len(ik.joint_names))
    for _ in range(steps):
        ik.solve(0.01, [("pinch", goal, np.eye(3), 0.0, 1.0), None], base, {k: 50.0 for k in base}, posture, posture)


def test_an_arm_reaching_out_keeps_its_elbow_inside_its_plane(env):
    env.reset(seed=0)
    expert = make_expert(env, seed=0)
    ik = expert.ik
    ik.reset(env.data.qpos)
    pelvis = ik.configuration.data.xpos[ik.model.body("pelvis").id].copy()
    goal = pelvis + np.array([0.25, 0.55, 0.2])  # far out to the left, at the chest
    plane_y = pelvis[1] + 0.3

    _reach_out(ik, goal)
    free = max(float(p[1]) + r for p, r in _left_arm_points(ik))
    assert free > plane_y + 0.05  # unconstrained, the elbow or wrist goes well past the plane

    ik.reset(env.data.qpos)
    ik.arm_planes.planes.append((LEFT, np.array([0.0, 1.0, 0.0]), plane_y))
    _reach_out(ik, goal)
    held = max(float(p[1]) + r for p, r in _left_arm_points(ik))
    assert held <= plane_y + 0.005
    hand, _ = ik.pose(LEFT)
    assert hand[1] > plane_y - 0.1  # the hand still reaches towards the goal as far as it can


def test_the_groceries_expert_keeps_its_arms_off_the_open_door_and_forgets_it_next_episode(env):
    """After the door the expert sets one plane per arm just inside the door's inner face;
    the next episode starts without them."""
    obs, _ = env.reset(seed=0)
    expert = make_expert(env, seed=0)
    expert(obs)
    expert.keep_arms_clear_of_open_door(CUPBOARD, DOOR)
    planes = expert.ik.arm_planes.planes
    assert sorted(side for side, _, _ in planes) == [0, 1]
    prop = env.props[CUPBOARD]
    hinge = env.data.xanchor[prop.joint_ids[prop.joint_index(DOOR)]]
    for _, a, b in planes:
        assert np.linalg.norm(a) == pytest.approx(1.0)
        # the cabinet's middle is on the allowed side, the hinge (on the door) is not
        assert a @ env.data.xpos[prop.root_body_id] < b < a @ hinge
    obs, _ = env.reset(seed=1)
    mujoco.mj_forward(env.model, env.data)
    expert(obs)
    assert expert.ik.arm_planes.planes == []


def _gripper_torso_distance(ik, side: int) -> float:
    """Least distance (m) between a gripper's root (``GRIPPER_ROOT_BODIES``) and the torso,
    over the geom groups ``self_collision_pairs`` names for them (its last two pairs)."""
    model, data = ik.model, ik.configuration.data
    gripper, torso = self_collision_pairs(model, grippers=True)[-2 + side]
    fromto = np.zeros(6)
    return min(mujoco.mj_geomDistance(model, data, g, t, 0.5, fromto) for g in gripper for t in torso)


def test_the_ik_keeps_a_gripper_off_the_torso_when_asked(env):
    """A right hand sent to a point just in front of the middle of the chest: the IK alone
    puts the gripper's root into the torso; asked to keep it off, it stays clear."""
    env.reset(seed=0)
    distances = {}
    for off_torso in (False, True):
        ik = WholeBodyIK(env.unwrapped, grippers_off_torso=off_torso)
        ik.reset(env.unwrapped.data.qpos)
        pelvis = ik.configuration.data.xpos[ik.model.body("pelvis").id].copy()
        goal = pelvis + np.array([0.06, 0.0, 0.3])
        base = ik.base()
        posture = np.zeros(len(ik.joint_names))
        for _ in range(300):
            ik.solve(
                0.01, [None, ("pinch", goal, np.eye(3), 0.0, 1.0)], base, {k: 50.0 for k in base}, posture, posture
            )
        distances[off_torso] = _gripper_torso_distance(ik, 1)
    assert distances[False] < 0.0, distances  # left to itself, the gripper is in the torso
    assert distances[True] > 0.005, distances
