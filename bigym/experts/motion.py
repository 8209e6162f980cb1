"""Human-like motion primitives: minimum-jerk paths through via-points, timing, tremor.

People do not move their hands along straight lines at constant speed. Their reaching
movements follow gently curved paths with bell-shaped speed profiles (the minimum-jerk
model of Flash and Hogan), take longer for longer and more precise movements (Fitts'
law), end with small corrective sub-movements when the first one falls short, and carry
a little low-frequency tremor. This module provides those pieces as plain functions of
time, so that the demonstrators can sample them at any control rate.

Everything random takes an explicit :class:`numpy.random.Generator`; nothing here
touches a global random state.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields

import numpy as np


# --------------------------------------------------------------------------- minimum jerk
def minimum_jerk_profile(tau: np.ndarray | float) -> np.ndarray | float:
    """The normalised minimum-jerk position profile ``10 s^3 - 15 s^4 + 6 s^5`` on [0, 1]."""
    s = np.clip(tau, 0.0, 1.0)
    return s * s * s * (10.0 + s * (-15.0 + 6.0 * s))


class MinimumJerkSpline:
    """The minimum-jerk trajectory through via-points at given times.

    Between consecutive knots the trajectory is a quintic polynomial; at interior knots
    the position is prescribed and the first four derivatives are continuous, which is
    the exact solution of minimising the integral of squared jerk through the
    via-points (Flash and Hogan, 1985). Start and end velocity and acceleration are
    prescribed (zero by default: the hand starts and ends at rest).

    ``points`` is ``(n + 1, d)``, ``times`` ``(n + 1,)`` strictly increasing. Outside
    ``[times[0], times[-1]]`` the trajectory holds its end points.
    """

    def __init__(
        self,
        points: np.ndarray,
        times: np.ndarray,
        start_velocity: np.ndarray | None = None,
        end_velocity: np.ndarray | None = None,
    ) -> None:
        points = np.atleast_2d(np.asarray(points, float))
        times = np.asarray(times, float)
        if len(points) != len(times) or len(points) < 2:
            raise ValueError("need at least two points and one time per point")
        if np.any(np.diff(times) <= 0.0):
            raise ValueError("knot times must increase strictly")
        self.points, self.times = points, times
        n, dim = len(points) - 1, points.shape[1]
        v0 = np.zeros(dim) if start_velocity is None else np.asarray(start_velocity, float)
        v1 = np.zeros(dim) if end_velocity is None else np.asarray(end_velocity, float)
        a = np.zeros((6 * n, 6 * n))
        b = np.zeros((6 * n, dim))
        row = 0

        def derivative_row(h: float, order: int) -> np.ndarray:
            """Coefficients of the ``order``-th derivative of a quintic at local time ``h``."""
            out = np.zeros(6)
            for k in range(order, 6):
                coefficient = 1.0
                for j in range(order):
                    coefficient *= k - j
                out[k] = coefficient * h ** (k - order)
            return out

        durations = np.diff(times)
        # start: position, velocity, acceleration
        for order, value in ((0, points[0]), (1, v0), (2, np.zeros(dim))):
            a[row, 0:6] = derivative_row(0.0, order)
            b[row] = value
            row += 1
        for i in range(n - 1):
            h = durations[i]
            left, right = slice(6 * i, 6 * i + 6), slice(6 * i + 6, 6 * i + 12)
            # segment i ends at the via-point, segment i + 1 starts there
            a[row, left] = derivative_row(h, 0)
            b[row] = points[i + 1]
            row += 1
            a[row, right] = derivative_row(0.0, 0)
            b[row] = points[i + 1]
            row += 1
            for order in (1, 2, 3, 4):
                a[row, left] = derivative_row(h, order)
                a[row, right] = -derivative_row(0.0, order)
                row += 1
        last = slice(6 * (n - 1), 6 * n)
        for order, value in ((0, points[-1]), (1, v1), (2, np.zeros(dim))):
            a[row, last] = derivative_row(durations[-1], order)
            b[row] = value
            row += 1
        self._coefficients = np.linalg.solve(a, b).reshape(n, 6, dim)
        self._durations = durations

    @property
    def duration(self) -> float:
        return float(self.times[-1] - self.times[0])

    def _locate(self, t: float) -> tuple[int, float]:
        if t <= self.times[0]:
            return 0, 0.0
        if t >= self.times[-1]:
            return len(self._durations) - 1, float(self._durations[-1])
        i = int(np.searchsorted(self.times, t, side="right") - 1)
        return i, t - self.times[i]

    def __call__(self, t: float) -> np.ndarray:
        i, h = self._locate(t)
        c = self._coefficients[i]
        return c[0] + h * (c[1] + h * (c[2] + h * (c[3] + h * (c[4] + h * c[5]))))

    def velocity(self, t: float) -> np.ndarray:
        if t <= self.times[0] or t >= self.times[-1]:
            return np.zeros(self.points.shape[1])
        i, h = self._locate(t)
        c = self._coefficients[i]
        return c[1] + h * (2 * c[2] + h * (3 * c[3] + h * (4 * c[4] + h * 5 * c[5])))


def via_point_times(points: np.ndarray, duration: float, exponent: float = 0.75) -> np.ndarray:
    """Passage times for via-points: each segment takes time in proportion to its length
    to the power ``exponent`` (< 1: short segments are relatively slower, as in people)."""
    lengths = np.linalg.norm(np.diff(points, axis=0), axis=1)
    weights = np.maximum(lengths, 1e-3) ** exponent
    return np.concatenate([[0.0], np.cumsum(weights / weights.sum())]) * duration


def fitts_duration(distance: float, width: float = 0.02, a: float = 0.22, b: float = 0.14) -> float:
    """Movement time from Fitts' law: ``a + b log2(1 + distance / width)`` seconds."""
    return a + b * float(np.log2(1.0 + max(distance, 0.0) / width))


# --------------------------------------------------------------------------- tremor
class Tremor:
    """Smooth, low-frequency hand tremor: a few sinusoids per axis with random phases.

    The amplitude is the standard deviation of each coordinate (metres); frequencies are
    drawn in ``band`` (Hz). Zero amplitude gives exactly zero.
    """

    def __init__(
        self,
        rng: np.random.Generator,
        amplitude: float,
        band: tuple[float, float] = (0.8, 4.0),
        dim: int = 3,
        components: int = 3,
    ) -> None:
        self.amplitude = float(amplitude)
        self.frequencies = rng.uniform(band[0], band[1], (components, dim))
        self.phases = rng.uniform(0.0, 2.0 * np.pi, (components, dim))
        weights = rng.uniform(0.5, 1.0, (components, dim))
        # sum of sinusoids with amplitudes w has variance sum(w^2)/2
        self.weights = weights * (self.amplitude * np.sqrt(2.0 / np.sum(weights**2, axis=0)))

    def __call__(self, t: float) -> np.ndarray:
        if self.amplitude == 0.0:
            return np.zeros(self.weights.shape[1])
        return np.sum(self.weights * np.sin(2.0 * np.pi * self.frequencies * t + self.phases), axis=0)


# --------------------------------------------------------------------------- style
@dataclass
class HumanStyle:
    """The knobs of human-like variability; each is the parameter of a seeded draw.

    Set a knob to zero (or ``exact()``) to turn that variability off: a plain,
    straight-line, constant-style demonstrator for comparisons.
    """

    #: log-normal sigma of the per-demo speed factor (1 = nominal speed)
    speed_spread: float = 0.18
    #: log-normal sigma of the per-movement duration jitter
    movement_jitter: float = 0.12
    #: overall duration scale (> 1 slower)
    slowness: float = 1.0
    #: lateral deviation of random via-points, as a fraction of the movement distance
    via_point_spread: float = 0.12
    #: probability of an extra via-point (a second bend) in a free movement
    extra_via_probability: float = 0.35
    #: mean reaction time before the first movement (s), log-normal spread 0.35
    reaction_time: float = 0.35
    #: probability of a hesitation pause between two movements
    hesitation_probability: float = 0.3
    #: mean length of a hesitation (s)
    hesitation_time: float = 0.3
    #: probability that a movement to a precise goal ends off the goal and is corrected
    correction_probability: float = 0.45
    #: endpoint error of a corrected movement (m, standard deviation per axis)
    correction_error: float = 0.012
    #: tremor amplitude (m, per axis standard deviation)
    tremor_amplitude: float = 0.0015
    #: spread of the base stance (m, per axis) and yaw (rad)
    stance_spread: float = 0.06
    stance_yaw_spread: float = 0.1
    #: spread of the idle arm's posture (rad per joint)
    posture_spread: float = 0.12
    #: the arm-swing/grasp randomisation of the hand's approach (rad)
    approach_spread: float = 0.12
    #: bell-shaped (minimum-jerk) speed profiles; False: constant speed, like a plain
    #: straight-line controller
    minimum_jerk: bool = True

    @classmethod
    def exact(cls) -> HumanStyle:
        """No variability at all: straight lines, nominal speed, no pauses or tremor."""
        return cls(
            speed_spread=0.0,
            movement_jitter=0.0,
            via_point_spread=0.0,
            extra_via_probability=0.0,
            reaction_time=0.0,
            hesitation_probability=0.0,
            correction_probability=0.0,
            correction_error=0.0,
            tremor_amplitude=0.0,
            stance_spread=0.0,
            stance_yaw_spread=0.0,
            posture_spread=0.0,
            approach_spread=0.0,
        )

    @classmethod
    def plain(cls) -> HumanStyle:
        """The baseline the human-like demos are compared with: straight lines at
        constant speed, no variability at all."""
        style = cls.exact()
        style.minimum_jerk = False
        return style

    def to_dict(self) -> dict[str, float]:
        return {f.name: float(getattr(self, f.name)) for f in fields(self)}


class Human:
    """One demonstrator: a style plus the seeded draws that make each demo different."""

    def __init__(self, style: HumanStyle, rng: np.random.Generator) -> None:
        self.style = style
        self.rng = rng
        self.speed = float(np.exp(rng.normal(0.0, style.speed_spread))) if style.speed_spread else 1.0

    # ---- timing
    def duration(self, distance: float, precision: float = 0.02, minimum: float = 0.3) -> float:
        """How long a movement over ``distance`` metres to a ``precision``-wide goal takes."""
        jitter = float(np.exp(self.rng.normal(0.0, self.style.movement_jitter))) if self.style.movement_jitter else 1.0
        base = fitts_duration(distance, precision)
        return max(minimum, base * jitter * self.style.slowness / self.speed)

    def reaction(self) -> float:
        if self.style.reaction_time <= 0.0:
            return 0.0
        return float(self.style.reaction_time * np.exp(self.rng.normal(-0.06, 0.35)) / self.speed)

    def hesitation(self) -> float:
        """A pause before the next movement, usually none."""
        if self.style.hesitation_probability <= 0.0 or self.rng.random() >= self.style.hesitation_probability:
            return 0.0
        return float(self.style.hesitation_time * np.exp(self.rng.normal(-0.1, 0.45)) / self.speed)

    def profile(self, tau: float) -> float:
        """Progress (0..1) along a movement at normalised time ``tau``."""
        if self.style.minimum_jerk:
            return float(minimum_jerk_profile(tau))
        return float(np.clip(tau, 0.0, 1.0))

    def path(self, points: Sequence[np.ndarray], duration: float) -> Callable[[float], np.ndarray]:
        """A path through ``points`` over ``duration`` (minimum jerk, or constant speed)."""
        if self.style.minimum_jerk:
            return path_from_points(points, duration)
        return LinearPath(points, duration)

    def chance(self, probability: float) -> bool:
        return bool(self.rng.random() < probability)

    # ---- paths
    def via_points(
        self, start: np.ndarray, goal: np.ndarray, lift: float = 0.0, spread_scale: float = 1.0
    ) -> np.ndarray:
        """Start, one or two randomised intermediate points, goal.

        Intermediate points lie near the straight line, displaced sideways by a random
        amount proportional to the distance and raised by ``lift`` (metres); with no
        spread and no lift the path is the straight line itself.
        """
        start, goal = np.asarray(start, float), np.asarray(goal, float)
        delta = goal - start
        distance = float(np.linalg.norm(delta))
        spread = self.style.via_point_spread * spread_scale * distance
        if distance < 1e-6 or (spread <= 0.0 and lift == 0.0):
            return np.stack([start, goal])
        count = 2 if self.chance(self.style.extra_via_probability) else 1
        fractions = np.sort(self.rng.uniform(0.3, 0.7, count)) if count > 1 else np.array([self.rng.uniform(0.4, 0.6)])
        if spread <= 0.0:
            fractions = np.full(count, 0.5) if count == 1 else fractions
        points = [start]
        for f in fractions:
            offset = self.rng.normal(0.0, spread, 3) if spread > 0.0 else np.zeros(3)
            offset -= delta * (offset @ delta) / (distance * distance)  # sideways only
            bump = 4.0 * f * (1.0 - f)  # lift is largest mid-way
            points.append(start + f * delta + offset + np.array([0.0, 0.0, lift * bump]))
        points.append(goal)
        return np.stack(points)

    def endpoint_error(self, direction: np.ndarray | None = None) -> np.ndarray | None:
        """The miss of a primary movement that will be corrected, or ``None`` (no correction).

        People's first sub-movement tends to undershoot: the error leans back along the
        movement ``direction`` when one is given.
        """
        style = self.style
        if style.correction_error <= 0.0 or not self.chance(style.correction_probability):
            return None
        error = self.rng.normal(0.0, style.correction_error, 3)
        if direction is not None:
            norm = float(np.linalg.norm(direction))
            if norm > 1e-6:
                error -= (direction / norm) * abs(self.rng.normal(0.0, style.correction_error))
        return error

    def tremor(self) -> Tremor:
        return Tremor(self.rng, self.style.tremor_amplitude)

    def jitter(self, scale: float, size: int | None = None) -> np.ndarray | float:
        """Zero-mean normal noise of standard deviation ``scale`` (0 gives exact zeros)."""
        if scale <= 0.0:
            return 0.0 if size is None else np.zeros(size)
        return self.rng.normal(0.0, scale, size)


# --------------------------------------------------------------------------- path helpers
PathFunction = Callable[[float], np.ndarray]


def path_from_points(points: Sequence[np.ndarray], duration: float, exponent: float = 0.75) -> MinimumJerkSpline:
    """Minimum-jerk spline through ``points`` over ``duration`` seconds."""
    points = np.asarray(points, float)
    if len(points) == 2:
        times = np.array([0.0, duration])
    else:
        times = via_point_times(points, duration, exponent)
    return MinimumJerkSpline(points, times)


class LinearPath:
    """Straight segments through ``points`` at constant speed over ``duration``."""

    def __init__(self, points: Sequence[np.ndarray], duration: float) -> None:
        self.points = np.asarray(points, float)
        lengths = np.linalg.norm(np.diff(self.points, axis=0), axis=1)
        total = float(lengths.sum())
        self.duration = float(duration)
        self.arc = np.concatenate([[0.0], np.cumsum(lengths)]) / (total if total > 0 else 1.0)

    def __call__(self, t: float) -> np.ndarray:
        s = float(np.clip(t / self.duration, 0.0, 1.0)) if self.duration > 0 else 1.0
        i = int(np.clip(np.searchsorted(self.arc, s, side="right") - 1, 0, len(self.points) - 2))
        span = self.arc[i + 1] - self.arc[i]
        f = 0.0 if span <= 0 else (s - self.arc[i]) / span
        return self.points[i] + f * (self.points[i + 1] - self.points[i])


__all__ = [
    "Human",
    "HumanStyle",
    "LinearPath",
    "MinimumJerkSpline",
    "Tremor",
    "fitts_duration",
    "minimum_jerk_profile",
    "path_from_points",
    "via_point_times",
]
