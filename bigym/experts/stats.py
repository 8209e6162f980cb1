"""Figures that show whether demos are diverse and human-like, and a top-view plot.

For a set of demos of one task (replayed from their lightweight files) and for the same
number of episodes of a *plain* controller (the same task scripts with
:meth:`HumanStyle.plain`: straight lines at constant speed, no variability), this
module measures, from the wrist trajectories:

* **hand split**: how often the left, the right or both hands do the work (the hand
  whose wrist moves most relative to the pelvis; both when the other moves at least
  60% as much);
* **plans**: how many distinct plans (every discrete choice the expert recorded: which
  hand does each job, in which order, which slot, burner or route) the episodes follow,
  and the share of the most common one;
* **duration**: mean, standard deviation and coefficient of variation;
* **path straightness**: per hand movement (a stretch where the active wrist moves
  faster than 5 cm/s for at least 0.2 s), path length over straight distance (1 =
  straight, more = curved);
* **velocity profile**: per movement, the correlation of the speed profile with the
  bell-shaped minimum-jerk one (1 = bell-shaped, low = flat), the number of speed peaks
  (more than one: corrective sub-movements) and the log dimensionless jerk (LDLJ,
  higher = smoother);
* **path spread**: how far apart the demos' active-wrist paths are (mean distance to
  the mean path, on a normalised time axis): the diversity of the set.

:func:`plot_wrist_paths` draws the wrist paths seen from above (PNG, with Pillow).
"""

from __future__ import annotations

import dataclasses
import json
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bigym.experts.motion import HumanStyle

SAMPLE_EVERY = 5  # physics steps between wrist samples (100 Hz at 500 Hz)
MOVING_SPEED = 0.05  # m/s
MIN_MOVEMENT = 0.2  # s
BOTH_HANDS = 0.6


@dataclass
class Trajectory:
    """Wrist positions of one episode, world and pelvis frame, at ``rate`` Hz."""

    wrists: np.ndarray  # (T, 2, 3) world
    local: np.ndarray  # (T, 2, 3) in the pelvis frame
    rate: float
    duration: float
    success: bool = True
    plan: str = ""  # the expert's discrete choices, canonical JSON


@dataclass
class Figures:
    """The figures of one set of episodes (see the module docstring)."""

    label: str
    count: int
    hand_split: dict[str, float]
    plans: int
    top_plan_share: float
    duration_mean: float
    duration_std: float
    duration_cv: float
    straightness: float
    bell_correlation: float
    speed_peaks: float
    ldlj: float
    path_spread: float
    success_rate: float = 1.0

    def rows(self) -> list[tuple[str, str]]:
        split = ", ".join(f"{k} {100 * v:.0f}%" for k, v in self.hand_split.items())
        return [
            ("episodes", f"{self.count}"),
            ("hand split", split),
            ("distinct plans (discrete choices)", f"{self.plans} (most common {100 * self.top_plan_share:.0f}%)"),
            ("duration (s)", f"{self.duration_mean:.2f} ± {self.duration_std:.2f} (cv {self.duration_cv:.2f})"),
            ("path length / straight distance", f"{self.straightness:.3f}"),
            ("bell-shaped speed (corr.)", f"{self.bell_correlation:.2f}"),
            ("speed peaks / movement", f"{self.speed_peaks:.2f}"),
            ("log dimensionless jerk", f"{self.ldlj:.2f}"),
            ("path spread (m)", f"{self.path_spread:.3f}"),
        ]


@dataclass
class StatsReport:
    task: str
    demos: Figures
    plain: Figures | None
    plot: Path | None = None
    trajectories: dict[str, list[Trajectory]] = field(default_factory=dict, repr=False)

    def to_dict(self) -> dict:
        """The figures as plain data (JSON-ready)."""
        return {
            "task": self.task,
            "demos": dataclasses.asdict(self.demos),
            "plain": dataclasses.asdict(self.plain) if self.plain is not None else None,
            "plot": str(self.plot) if self.plot is not None else None,
        }

    def table(self) -> str:
        """The figures side by side, as plain text."""
        rows = self.demos.rows()
        other = self.plain.rows() if self.plain is not None else [("", "")] * len(rows)
        width = max(len(name) for name, _ in rows)
        col = max(len(v) for _, v in rows) + 2
        lines = [f"{self.task}", f"{'':{width}}  {'demos':{col}}{'plain controller' if self.plain else ''}"]
        for (name, value), (_, base) in zip(rows, other):
            lines.append(f"{name:{width}}  {value:{col}}{base}")
        if self.plot is not None:
            lines.append(f"wrist paths from above: {self.plot}")
        return "\n".join(lines)


# ---------------------------------------------------------------------- trajectories
def _pelvis_frame(env) -> tuple[np.ndarray, np.ndarray]:
    robot = env.robot
    pose = robot.base_pose(env.data)
    c, s = np.cos(pose[3]), np.sin(pose[3])
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return env.data.xpos[robot.pelvis_id].copy(), rotation


def _sample(env, wrists: list, local: list) -> None:
    positions = env.robot.wrist_positions(env.data).copy()
    origin, rotation = _pelvis_frame(env)
    wrists.append(positions)
    local.append((positions - origin) @ rotation)


def plan_key(choices: dict | None) -> str:
    """An expert's discrete choices (hands, order, slot, burner, route: every choice it
    records as a name or a list of names; numbers are not plans) as one string."""
    discrete = {
        key: value
        for key, value in (choices or {}).items()
        if isinstance(value, str) or (isinstance(value, list) and all(isinstance(v, str) for v in value))
    }
    return json.dumps(discrete, sort_keys=True)


def replay_trajectory(demo, env=None) -> Trajectory:
    """Step a demo's actions (no verification) and sample its wrist positions."""
    from bigym.demonstrations.player import make_env

    own = env is None
    env = make_env(demo.metadata) if own else env
    base = env.unwrapped
    try:
        base.reset(seed=demo.metadata.seed)
        wrists: list = []
        local: list = []
        _sample(base, wrists, local)
        success = False
        for step, action in enumerate(demo.actions):
            _, _, _, _, info = base.step(action)
            success = success or bool(info.get("is_success"))
            if (step + 1) % SAMPLE_EVERY == 0:
                _sample(base, wrists, local)
        rate = base.control_frequency / SAMPLE_EVERY
        duration = len(demo.actions) / base.control_frequency
        plan = plan_key(demo.metadata.extra.get("expert_choices"))
        return Trajectory(np.array(wrists), np.array(local), rate, duration, success, plan)
    finally:
        if own:
            env.close()


def expert_trajectory(env, seed: int, style: HumanStyle) -> Trajectory:
    """Run the task's expert with ``style`` on ``seed`` and sample its wrist positions."""
    from bigym.experts import make_expert

    base = env.unwrapped
    obs, _ = base.reset(seed=seed)
    expert = make_expert(base, seed=seed, style=style)
    wrists: list = []
    local: list = []
    _sample(base, wrists, local)
    success = False
    steps = 0
    for steps in range(1, base.max_episode_steps + 1):
        obs, _, terminated, truncated, info = base.step(expert(obs))
        if steps % SAMPLE_EVERY == 0:
            _sample(base, wrists, local)
        if info.get("is_success"):
            success = True
            break
        if terminated or truncated:
            break
    return Trajectory(
        np.array(wrists),
        np.array(local),
        base.control_frequency / SAMPLE_EVERY,
        steps / base.control_frequency,
        success,
        plan_key(expert.choices),
    )


# ---------------------------------------------------------------------- figures
def _path_length(points: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum()) if len(points) > 1 else 0.0


def active_hands(trajectory: Trajectory) -> str:
    """ "left", "right" or "both": whose wrist moves most relative to the pelvis."""
    effort = [_path_length(trajectory.local[:, side]) for side in (0, 1)]
    big, small = max(effort), min(effort)
    if big <= 1e-9 or small >= BOTH_HANDS * big:
        return "both"
    return "left" if effort[0] > effort[1] else "right"


def _movements(points: np.ndarray, rate: float) -> list[np.ndarray]:
    speed = np.linalg.norm(np.diff(points, axis=0), axis=1) * rate
    moving = speed > MOVING_SPEED
    segments, start = [], None
    for i, flag in enumerate(np.append(moving, False)):
        if flag and start is None:
            start = i
        elif not flag and start is not None:
            if (i - start) / rate >= MIN_MOVEMENT:
                segments.append(points[start : i + 1])
            start = None
    return segments


def _count_peaks(speed: np.ndarray, prominence: float = 0.25) -> int:
    """Speed peaks separated by dips of at least ``prominence`` times the largest speed."""
    if len(speed) < 3 or speed.max() <= 0:
        return 1
    drop = prominence * float(speed.max())
    peaks, rising, top, bottom = 0, True, float(speed[0]), float(speed[0])
    for value in speed[1:]:
        value = float(value)
        if rising:
            if value > top:
                top = value
            elif top - value >= drop:  # a peak, confirmed by the fall after it
                peaks += 1
                rising, bottom = False, value
        else:
            if value < bottom:
                bottom = value
            elif value - bottom >= drop:
                rising, top = True, value
    if rising and top - float(speed[-1]) >= 0.0 and top > drop:
        peaks += 1
    return max(peaks, 1)


def _movement_figures(segment: np.ndarray, rate: float) -> tuple[float, float, float, float]:
    """(straightness, bell correlation, speed peaks, LDLJ) of one movement."""
    chord = float(np.linalg.norm(segment[-1] - segment[0]))
    length = _path_length(segment)
    straightness = length / chord if chord > 1e-6 else 1.0
    velocity = np.diff(segment, axis=0) * rate
    speed = np.linalg.norm(velocity, axis=1)
    n = len(speed)
    tau = (np.arange(n) + 0.5) / n
    bell = tau**2 * (1.0 - tau) ** 2
    correlation = float(np.corrcoef(speed, bell)[0, 1]) if n > 2 and speed.std() > 0 else 0.0
    peaks = _count_peaks(np.convolve(speed, np.ones(7) / 7.0, mode="same"))
    duration = n / rate
    jerk = np.diff(velocity, n=2, axis=0) * rate * rate
    if len(jerk) and speed.max() > 0:
        dimensionless = duration**3 / speed.max() ** 2 * float(np.sum(np.sum(jerk**2, axis=1)) / rate)
        ldlj = -float(np.log(max(dimensionless, 1e-12)))
    else:
        ldlj = 0.0
    return straightness, correlation, float(max(peaks, 1)), ldlj


def measure(trajectories: list[Trajectory], label: str) -> Figures:
    """The figures of a set of episodes."""
    if not trajectories:
        raise ValueError("no trajectories to measure")
    hands = [active_hands(t) for t in trajectories]
    split = {name: hands.count(name) / len(hands) for name in ("left", "right", "both")}
    plans = Counter(t.plan for t in trajectories)
    durations = np.array([t.duration for t in trajectories])
    per_movement = []
    actives = []
    for trajectory, hand in zip(trajectories, hands):
        sides = (0, 1) if hand == "both" else ((0,) if hand == "left" else (1,))
        for side in sides:
            for segment in _movements(trajectory.wrists[:, side], trajectory.rate):
                per_movement.append(_movement_figures(segment, trajectory.rate))
        actives.append(trajectory.local[:, sides[0]])
    figures = np.array(per_movement) if per_movement else np.full((1, 4), np.nan)
    # spread: resample each active-wrist path (pelvis frame) to 50 points in normalised time
    resampled = np.array([a[np.linspace(0, len(a) - 1, 50).round().astype(int)] for a in actives])
    spread = float(np.mean(np.linalg.norm(resampled - resampled.mean(axis=0), axis=2)))
    return Figures(
        label=label,
        count=len(trajectories),
        hand_split=split,
        plans=len(plans),
        top_plan_share=max(plans.values()) / len(trajectories),
        duration_mean=float(durations.mean()),
        duration_std=float(durations.std()),
        duration_cv=float(durations.std() / durations.mean()) if durations.mean() > 0 else 0.0,
        straightness=float(np.nanmean(figures[:, 0])),
        bell_correlation=float(np.nanmean(figures[:, 1])),
        speed_peaks=float(np.nanmean(figures[:, 2])),
        ldlj=float(np.nanmean(figures[:, 3])),
        path_spread=spread,
        success_rate=float(np.mean([t.success for t in trajectories])),
    )


# ---------------------------------------------------------------------- plot
def plot_wrist_paths(panels: dict[str, list[Trajectory]], path: Path | str, title: str = "", size: int = 520) -> Path:
    """Wrist paths seen from above (x forward/up, y left), one panel per set; left wrist
    blue, right wrist orange. Written as PNG with Pillow."""
    from PIL import Image, ImageDraw

    everything = np.concatenate([t.wrists.reshape(-1, 3) for ts in panels.values() for t in ts])
    lo, hi = everything[:, :2].min(axis=0), everything[:, :2].max(axis=0)
    centre, span = (lo + hi) / 2.0, float(max(hi - lo)) * 1.1 + 1e-6
    margin, header = 30, 40
    image = Image.new("RGB", (size * len(panels), size + header), "white")
    draw = ImageDraw.Draw(image)
    if title:
        draw.text((10, 5), title, fill="black")
    colours = ((40, 90, 220), (235, 130, 20))

    def to_pixel(offset: int, xy: np.ndarray) -> list[tuple[float, float]]:
        # world x points up the image, world y to the left
        u = offset + margin + (0.5 - (xy[:, 1] - centre[1]) / span) * (size - 2 * margin)
        v = header + margin + (0.5 - (xy[:, 0] - centre[0]) / span) * (size - 2 * margin)
        return list(zip(u.tolist(), v.tolist()))

    for index, (name, trajectories) in enumerate(panels.items()):
        offset = index * size
        draw.rectangle([offset + 2, header, offset + size - 3, header + size - 3], outline=(180, 180, 180))
        draw.text((offset + 10, header + 5), f"{name} ({len(trajectories)})", fill="black")
        for trajectory in trajectories:
            for side in (0, 1):
                points = to_pixel(offset, trajectory.wrists[:, side, :2])
                if len(points) > 1:
                    draw.line(points, fill=colours[side], width=1)
        scale = 0.5  # a 50 cm scale bar
        bar = scale / span * (size - 2 * margin)
        draw.line([(offset + 15, header + size - 20), (offset + 15 + bar, header + size - 20)], fill="black", width=2)
        draw.text((offset + 20, header + size - 35), "0.5 m", fill="black")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    image.save(path)
    return path


# ---------------------------------------------------------------------- the whole thing
def demo_stats(
    task: str,
    demos: list | None = None,
    n: int | None = None,
    seed: int = 0,
    plain: bool = True,
    plot: Path | str | None = None,
    progress: bool = True,
) -> StatsReport:
    """Figures of ``demos`` (Demo objects or files; by default ``n`` fresh expert
    episodes from ``seed``) next to the plain controller's on the same seeds."""
    from bigym.action_modes import JointPositionActionMode
    from bigym.demonstrations import Demo
    from bigym.demonstrations.player import resolve_task

    cls = resolve_task(task)
    env = cls(action_mode=JointPositionActionMode(floating_base=True, absolute=True), control_frequency=500)
    try:
        if demos is not None:
            demos = [d if isinstance(d, Demo) else Demo.load(d) for d in demos]
            seeds = [int(d.metadata.seed) for d in demos]
            trajectories = [replay_trajectory(d, env) for d in demos]
        else:
            seeds = list(range(seed, seed + (n or 20)))
            trajectories = [expert_trajectory(env, s, HumanStyle()) for s in seeds]
        figures = measure(trajectories, "demos")
        panels = {"human-like demos": trajectories}
        plain_figures = None
        if plain:
            baseline = [expert_trajectory(env, s, HumanStyle.plain()) for s in seeds]
            plain_figures = measure(baseline, "plain controller")
            panels["plain controller"] = baseline
        plot_path = plot_wrist_paths(panels, plot, title=f"{cls.__name__}: wrist paths from above") if plot else None
        return StatsReport(cls.__name__, figures, plain_figures, plot_path, panels)
    finally:
        env.close()


__all__ = [
    "Figures",
    "StatsReport",
    "Trajectory",
    "active_hands",
    "demo_stats",
    "expert_trajectory",
    "measure",
    "plot_wrist_paths",
    "replay_trajectory",
]
