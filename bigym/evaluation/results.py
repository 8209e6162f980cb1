"""Episode records, the summary of an evaluation, and its JSON form."""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

#: how an episode ended
OUTCOMES = ("success", "failure", "time_limit", "unstable")


def wilson_interval(successes: int, n: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """The Wilson score interval of a success rate (95% by default).

    Unlike the normal approximation it stays inside [0, 1] and is not empty at 0 or n
    successes, which is where small evaluations of robot policies usually land.
    """
    if n <= 0:
        raise ValueError("an interval needs at least one episode")
    if not 0 <= successes <= n:
        raise ValueError(f"successes must be within [0, {n}], got {successes}")
    p = successes / n
    z2 = z * z
    centre = (p + z2 / (2 * n)) / (1 + z2 / n)
    half = z / (1 + z2 / n) * math.sqrt(p * (1 - p) / n + z2 / (4 * n * n))
    low = 0.0 if successes == 0 else max(0.0, centre - half)
    high = 1.0 if successes == n else min(1.0, centre + half)
    return low, high


@dataclass(frozen=True)
class EpisodeRecord:
    """One episode: its seed, how it ended and after how many control steps.

    Everything but ``wall_time`` is a function of the seed and the policy: the same for
    any number of workers and any vector-env mode.
    """

    seed: int
    success: bool
    outcome: str  # one of OUTCOMES
    steps: int
    sim_time: float  # seconds of simulated time
    wall_time: float  # seconds it took here (policy and env)
    detail: str = ""  # what made the physics unstable, if it did
    start: str = ""  # digest of the start state (BiGymEnv.state_digest): which scene it ran
    video: str | None = None

    def comparable(self) -> dict[str, Any]:
        """The record without what depends on the machine (wall time) or the call (video path)."""
        record = asdict(self)
        del record["wall_time"], record["video"]
        return record


@dataclass(frozen=True)
class Summary:
    episodes: int
    successes: int
    success_rate: float
    interval: tuple[float, float]  # 95% Wilson
    mean_steps: float
    mean_sim_time: float
    outcomes: dict[str, int]

    @classmethod
    def of(cls, records: list[EpisodeRecord]) -> Summary:
        n = len(records)
        successes = sum(r.success for r in records)
        return cls(
            episodes=n,
            successes=successes,
            success_rate=successes / n,
            interval=wilson_interval(successes, n),
            mean_steps=sum(r.steps for r in records) / n,
            mean_sim_time=sum(r.sim_time for r in records) / n,
            outcomes={o: sum(r.outcome == o for r in records) for o in OUTCOMES},
        )

    def line(self) -> str:
        low, high = self.interval
        return (
            f"{self.successes}/{self.episodes} = {100 * self.success_rate:.1f}% "
            f"(95% CI {100 * low:.1f}-{100 * high:.1f}%), mean {self.mean_sim_time:.2f} s per episode"
        )


@dataclass
class EvaluationResult:
    """What :func:`bigym.evaluation.evaluate` returns, and ``bigym eval --json`` writes."""

    task: str
    policy: str
    episodes: list[EpisodeRecord]
    fingerprint: dict[str, Any]
    unofficial_reasons: list[str] = field(default_factory=list)
    workers: int = 1
    vector: str | None = None
    wall_time: float = 0.0
    backend: str = "process"  # or "ray": where the episodes ran (the records do not depend on it)

    @property
    def official(self) -> bool:
        return not self.unofficial_reasons

    @property
    def summary(self) -> Summary:
        return Summary.of(self.episodes)

    def to_dict(self) -> dict[str, Any]:
        summary = asdict(self.summary)
        summary["interval"] = list(summary["interval"])
        return {
            "task": self.task,
            "policy": self.policy,
            "official": self.official,
            "unofficial_reasons": list(self.unofficial_reasons),
            "summary": summary,
            "fingerprint": self.fingerprint,
            "workers": self.workers,
            "vector": self.vector,
            "backend": self.backend,
            "wall_time": self.wall_time,
            "episodes": [asdict(r) for r in self.episodes],
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> EvaluationResult:
        return cls(
            task=data["task"],
            policy=data["policy"],
            episodes=[EpisodeRecord(**r) for r in data["episodes"]],
            fingerprint=data["fingerprint"],
            unofficial_reasons=list(data.get("unofficial_reasons", [])),
            workers=data.get("workers", 1),
            vector=data.get("vector"),
            wall_time=data.get("wall_time", 0.0),
            backend=data.get("backend", "process"),
        )

    def save(self, path: str | Path) -> Path:
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(self.to_dict(), indent=1) + "\n")
        return path

    @classmethod
    def load(cls, path: str | Path) -> EvaluationResult:
        return cls.from_dict(json.loads(Path(path).read_text()))
