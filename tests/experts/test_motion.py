"""Human-like motion primitives: minimum-jerk via-point splines, timing, tremor, style."""

from __future__ import annotations

import numpy as np
import pytest

from bigym.experts.motion import (
    Human,
    HumanStyle,
    LinearPath,
    MinimumJerkSpline,
    Tremor,
    fitts_duration,
    minimum_jerk_profile,
)


def test_profile_is_minimum_jerk():
    tau = np.linspace(0.0, 1.0, 11)
    profile = minimum_jerk_profile(tau)
    assert profile[0] == 0.0 and profile[-1] == 1.0
    assert np.all(np.diff(profile) > 0.0)
    assert minimum_jerk_profile(0.5) == pytest.approx(0.5)


def test_spline_passes_through_via_points_and_starts_and_ends_at_rest():
    points = np.array([[0.0, 0.0, 0.0], [0.2, 0.1, 0.05], [0.5, -0.1, 0.1], [0.6, 0.0, 0.0]])
    times = np.array([0.0, 0.4, 0.9, 1.2])
    spline = MinimumJerkSpline(points, times)
    for point, t in zip(points, times):
        np.testing.assert_allclose(spline(t), point, atol=1e-9)
    np.testing.assert_allclose(spline.velocity(1e-6), 0.0, atol=1e-4)
    np.testing.assert_allclose(spline.velocity(1.2 - 1e-6), 0.0, atol=1e-4)
    # smooth: the velocity is continuous across an interior via-point
    np.testing.assert_allclose(spline.velocity(0.4 - 1e-7), spline.velocity(0.4 + 1e-7), atol=1e-4)
    # holds its ends outside the time span
    np.testing.assert_allclose(spline(-1.0), points[0], atol=1e-12)
    np.testing.assert_allclose(spline(5.0), points[-1], atol=1e-12)


def test_two_point_spline_is_the_minimum_jerk_profile():
    spline = MinimumJerkSpline(np.array([[0.0], [1.0]]), np.array([0.0, 2.0]))
    for t in (0.3, 1.0, 1.7):
        assert spline(t)[0] == pytest.approx(float(minimum_jerk_profile(t / 2.0)))


def test_linear_path_has_constant_speed():
    path = LinearPath([np.zeros(3), np.array([0.3, 0.0, 0.0]), np.array([0.3, 0.3, 0.0])], 2.0)
    samples = np.array([path(t) for t in np.linspace(0.0, 2.0, 201)])
    speeds = np.linalg.norm(np.diff(samples, axis=0), axis=1)
    assert speeds.max() - speeds.min() < 1e-9 + 0.02 * speeds.mean()
    np.testing.assert_allclose(path(2.0), [0.3, 0.3, 0.0])


def test_fitts_law_longer_and_more_precise_takes_longer():
    assert fitts_duration(0.5, 0.02) > fitts_duration(0.1, 0.02)
    assert fitts_duration(0.3, 0.005) > fitts_duration(0.3, 0.05)


def test_tremor_has_the_requested_amplitude_and_zero_is_exactly_zero():
    rng = np.random.default_rng(0)
    tremor = Tremor(rng, 0.002)
    samples = np.array([tremor(t) for t in np.linspace(0.0, 60.0, 6001)])
    assert np.all(np.abs(samples.std(axis=0) - 0.002) < 0.0008)
    assert np.all(Tremor(rng, 0.0)(1.23) == 0.0)


def test_human_draws_are_seeded():
    a, b = Human(HumanStyle(), np.random.default_rng(7)), Human(HumanStyle(), np.random.default_rng(7))
    start, goal = np.zeros(3), np.array([0.5, 0.2, 0.1])
    np.testing.assert_array_equal(a.via_points(start, goal), b.via_points(start, goal))
    assert a.duration(0.4) == b.duration(0.4)


def test_human_via_points_bend_the_path_but_exact_style_is_straight():
    start, goal = np.zeros(3), np.array([0.6, 0.0, 0.0])
    bent = [Human(HumanStyle(), np.random.default_rng(s)).via_points(start, goal) for s in range(20)]
    assert any(np.abs(p[1:-1, 1:]).max() > 0.01 for p in bent)
    straight = Human(HumanStyle.exact(), np.random.default_rng(0)).via_points(start, goal)
    np.testing.assert_array_equal(straight, np.stack([start, goal]))


def test_plain_style_has_no_variability():
    human = Human(HumanStyle.plain(), np.random.default_rng(3))
    assert human.speed == 1.0 and human.reaction() == 0.0 and human.hesitation() == 0.0
    assert human.endpoint_error(np.ones(3)) is None
    assert human.profile(0.25) == 0.25
    assert Human(HumanStyle(), np.random.default_rng(3)).profile(0.25) == pytest.approx(
        float(minimum_jerk_profile(0.25))
    )
