"""Layers only point down: every import in a layer's source, also those inside functions.

* the env core knows no task, prop, scene, demo, expert or policy;
* the demonstration system knows no producer of demos (experts, policies) and no CLI;
* tasks know no expert;
* the evaluation protocol knows no policy, expert or baseline (it loads them by name);
* the baselines know no expert and no evaluation (they learn from demos, and are evaluated by name);
* the Ray backend (scale_out.py) knows no layer above it;
* teleoperation knows no policy, evaluation or baseline, and nothing below it knows teleoperation;
* nothing but the command line imports the command line.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "bigym"

ENV_CORE = [
    "env.py",
    "action_modes.py",
    "observations.py",
    "rendering.py",
    "gl_context.py",
    "visual_merge.py",
    "geom_groups.py",
    "layout.py",
    "world.py",
    "robot",
]

RULES = [
    (
        ENV_CORE,
        (
            "bigym.envs",
            "bigym.props",
            "bigym.scenes",
            "bigym.demonstrations",
            "bigym.experts",
            "bigym.policies",
            "bigym.evaluation",
            "bigym.teleop",
            "bigym.cli",
        ),
    ),
    (["demonstrations"], ("bigym.experts", "bigym.policies", "bigym.evaluation", "bigym.teleop", "bigym.cli")),
    (
        ["envs", "props", "scenes"],
        ("bigym.experts", "bigym.policies", "bigym.demonstrations", "bigym.evaluation", "bigym.teleop", "bigym.cli"),
    ),
    (["experts", "policies.py"], ("bigym.evaluation", "bigym.teleop", "bigym.cli")),
    (["evaluation"], ("bigym.experts", "bigym.policies", "bigym.baselines", "bigym.teleop", "bigym.cli")),
    (["baselines"], ("bigym.experts", "bigym.policies", "bigym.evaluation", "bigym.teleop", "bigym.cli")),
    (
        ["scale_out.py"],  # the Ray backend serves every layer, and so knows none of them
        ("bigym.envs", "bigym.demonstrations", "bigym.experts", "bigym.policies", "bigym.evaluation", "bigym.cli"),
    ),
    (["teleop"], ("bigym.policies", "bigym.evaluation", "bigym.baselines", "bigym.cli")),
]


def _files(parts: list[str]) -> list[Path]:
    files = []
    for part in parts:
        path = PACKAGE / part
        files += sorted(path.rglob("*.py")) if path.is_dir() else [path]
    return files


def _imports(path: Path) -> list[str]:
    names = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.append(node.module)
            names += [f"{node.module}.{alias.name}" for alias in node.names]
    return names


@pytest.mark.parametrize(
    "parts, forbidden",
    RULES,
    ids=["env_core", "demonstrations", "tasks", "producers", "evaluation", "baselines", "scale_out", "teleop"],
)
def test_layers_point_down(parts, forbidden):
    files = _files(parts)
    assert len(files) >= len(parts), "premise: the layer's files exist"
    violations = [
        f"{path.relative_to(PACKAGE)} imports {name}"
        for path in files
        for name in _imports(path)
        if any(name == f or name.startswith(f + ".") for f in forbidden)
    ]
    assert not violations, "\n".join(violations)


def test_the_checker_sees_imports_inside_functions(tmp_path):
    """The rule above must catch a lazy import too (the old demos CLI used those)."""
    sample = tmp_path / "sample.py"
    sample.write_text("def f():\n    from bigym.experts import EXPERTS\n    import bigym.policies\n")
    assert _imports(sample) == ["bigym.experts", "bigym.experts.EXPERTS", "bigym.policies"]
