"""Demo modes: the demos grouped by how they do the task, one label per demo.

Demonstrators choose once per episode between ways of doing a task (which hand opens the
drawer, reaches the target). A policy that only sees the state must make that choice at
the first step, where both ways start from the same state, and a model that learns the
average of the two ways does neither. Grouping whole demos by their action trajectories
(k-means) gives each demo a mode label without knowing who made it; a model that is told
the mode learns each way on its own, and when acting draws one mode per episode. Measured
(README, "Baselines"): the groups are the hands on the drawer and reach tasks, but telling
ACT the hand did not rescue the drawers from dropout, whose failures there are underfitting.
"""

from __future__ import annotations

import numpy as np

#: points each demo's action trajectory is resampled to, so demos of any length compare
TRAJECTORY_POINTS = 32
#: k-means restarts; the grouping with the smallest spread wins
RESTARTS = 10


def trajectory_features(actions: list[np.ndarray]) -> np.ndarray:
    """(demos, TRAJECTORY_POINTS * action_dim): each demo's (normalised) actions at evenly
    spaced moments from its start to its end."""
    features = []
    for demo in actions:
        moments = np.linspace(0.0, len(demo) - 1, TRAJECTORY_POINTS)
        steps = np.arange(len(demo))
        features.append(np.stack([np.interp(moments, steps, demo[:, j]) for j in range(demo.shape[1])], axis=1))
    return np.stack(features).reshape(len(actions), -1)


def demo_modes(actions: list[np.ndarray], modes: int, seed: int = 0) -> np.ndarray:
    """A mode label in ``range(modes)`` per demo, from k-means on the demos' trajectories;
    labels are numbered by each group's first demo, so the grouping reads the same for the
    same demos whatever the restarts found first."""
    if modes < 1:
        raise ValueError(f"modes must be 1 or more, got {modes}")
    if modes > len(actions):
        raise ValueError(f"{modes} modes need at least as many demos, got {len(actions)}")
    points = trajectory_features(actions)
    rng = np.random.default_rng(seed)
    best, best_spread = None, np.inf
    for _ in range(RESTARTS):
        labels, spread = _kmeans(points, modes, rng)
        if spread < best_spread - 1e-9:
            best, best_spread = labels, spread
    order = {label: rank for rank, label in enumerate(dict.fromkeys(best.tolist()))}
    return np.array([order[label] for label in best], dtype=np.int64)


def _kmeans(points: np.ndarray, k: int, rng: np.random.Generator, iterations: int = 100) -> tuple[np.ndarray, float]:
    """One k-means run from a k-means++ start: (labels, summed squared distance)."""
    centres = [points[rng.integers(len(points))]]
    for _ in range(1, k):
        distance = np.min([((points - c) ** 2).sum(axis=1) for c in centres], axis=0)
        total = distance.sum()
        pick = rng.choice(len(points), p=distance / total) if total > 0 else rng.integers(len(points))
        centres.append(points[pick])
    centres = np.stack(centres)
    labels = np.zeros(len(points), dtype=np.int64)
    for _ in range(iterations):
        distances = ((points[:, None, :] - centres[None]) ** 2).sum(axis=2)
        labels = distances.argmin(axis=1)
        moved = np.stack([points[labels == j].mean(axis=0) if (labels == j).any() else centres[j] for j in range(k)])
        if np.allclose(moved, centres):
            break
        centres = moved
    spread = float(((points - centres[labels]) ** 2).sum())
    return labels, spread
