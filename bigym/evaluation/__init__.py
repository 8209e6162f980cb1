"""The evaluation protocol: a task's official seed block run in parallel, success with a
95% Wilson interval, and a fingerprint of what was evaluated.

``evaluate(policy_factory, task, episodes=...)`` (:mod:`~bigym.evaluation.runner`) runs the
episodes; :mod:`~bigym.evaluation.protocol` says what the official settings are and why a
result is unofficial; :mod:`~bigym.evaluation.policy` is the interface a policy follows;
:mod:`~bigym.evaluation.results` holds the records, the summary and the JSON form.
"""

from __future__ import annotations

from bigym.evaluation.policy import Policy, PolicyFactory, PolicyLoadError, load_factory
from bigym.evaluation.protocol import (
    CONTROL_FREQUENCY,
    EPISODES,
    FIRST_SEED,
    PROTOCOL,
    Settings,
    official_action_mode,
    official_seeds,
    track,
    unofficial_reasons,
)
from bigym.evaluation.results import EpisodeRecord, EvaluationResult, Summary, wilson_interval
from bigym.evaluation.runner import EvaluationError, evaluate, make_env

__all__ = [
    "CONTROL_FREQUENCY",
    "EPISODES",
    "FIRST_SEED",
    "PROTOCOL",
    "EpisodeRecord",
    "EvaluationError",
    "EvaluationResult",
    "Policy",
    "PolicyFactory",
    "PolicyLoadError",
    "Settings",
    "Summary",
    "evaluate",
    "load_factory",
    "make_env",
    "official_action_mode",
    "official_seeds",
    "track",
    "unofficial_reasons",
    "wilson_interval",
]
