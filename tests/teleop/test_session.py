"""Recording human demos: a scripted person drives a reach task through the devices."""

from __future__ import annotations

import json

import numpy as np
import pytest
from teleopkit import reach_with_keyboard, wrist_error

from bigym.demonstrations import DemoStore, replay
from bigym.teleop import DeviceEventError, InputScript, TeleopSession, make_devices, play
from bigym.teleop.controller import MAX_LEAD

SEED = 3


def new_session(tmp_path, devices="keyboard", **kwargs) -> TeleopSession:
    store = DemoStore(tmp_path / "store", on_demand=False)
    return TeleopSession(
        "ReachTargetSingle", make_devices(devices), store, seed=SEED, aside=tmp_path / "aside", **kwargs
    )


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """A person's keyboard session: one reach demo, kept; its input saved as a script."""
    tmp_path = tmp_path_factory.mktemp("teleop")
    session = new_session(tmp_path)
    outcome = reach_with_keyboard(session)
    script = InputScript.from_session(session)
    path = script.save(tmp_path / "reach.jsonl")
    yield session, outcome, path
    session.close()


def test_a_keyboard_session_records_a_verified_human_demo_into_the_store(recorded):
    session, outcome, _ = recorded
    assert outcome is not None and outcome.kind == "kept", outcome
    assert outcome.seed == SEED and outcome.reason is None
    [entry] = session.store.entries(task="ReachTargetSingle")
    demo = session.store.load(entry)
    assert demo.metadata.source == "human" and demo.metadata.success
    assert demo.metadata.seed == SEED and demo.metadata.frequency == 500.0
    assert demo.metadata.extra["teleop_devices"] == ["keyboard"]
    # 1 s recorded after the first success, as in every shipped demo
    assert demo.num_steps - demo.metadata.extra["first_success_step"] == 500
    replayed = replay(demo, frequency=50.0)
    assert replayed.report.first_success_step is not None
    assert session.status.kept == 1 and session.status.seed == SEED + 1  # the next scene is up


def test_a_saved_script_plays_back_to_the_same_demo(recorded, tmp_path):
    session, _, path = recorded
    script = InputScript.load(path)
    assert script.task == "ReachTargetSingle" and script.seed == SEED and script.devices == ["keyboard"]
    again = TeleopSession(script.task, make_devices(script.devices), DemoStore(tmp_path / "store", on_demand=False),
                          seed=script.seed, aside=tmp_path / "aside")  # fmt: skip
    try:
        outcomes = play(script, again, extra_steps=session.outcomes[0].steps)
        assert [o.kind for o in outcomes[:1]] == ["kept"]
        original = session.store.load(session.store.entries(task="ReachTargetSingle")[0])
        copy = again.store.load(again.store.entries(task="ReachTargetSingle")[0])
        np.testing.assert_array_equal(copy.actions, original.actions)
        np.testing.assert_array_equal(copy.initial_state, original.initial_state)
    finally:
        again.close()


def test_a_demo_that_fails_verification_is_put_aside_with_its_reason(tmp_path):
    session = new_session(tmp_path)
    try:
        session.handle({"type": "keydown", "code": "KeyW"})
        session.advance(100)
        session.handle({"type": "keydown", "code": "Enter"})  # keep, though nothing succeeded
        [outcome] = session.advance(1)
        assert outcome.kind == "rejected" and "never succeeded" in outcome.reason
        assert session.store.entries() == []
        folder = tmp_path / "aside" / "ReachTargetSingle"
        record = json.loads((folder / f"{outcome.uuid}.json").read_text())
        assert record["seed"] == SEED and "never succeeded" in record["reason"]
        assert (folder / f"{outcome.uuid}.safetensors").is_file()
    finally:
        session.close()


def test_retry_restarts_the_same_scene_and_discard_the_next(tmp_path):
    session = new_session(tmp_path, "keyboard,gamepad")
    try:
        start = session.env.data.qpos.copy()
        target = session.env.target_positions.copy()
        session.handle({"type": "keydown", "code": "KeyW"})
        session.advance(200)
        session.handle({"type": "session", "action": "retry"})  # a page's button
        [outcome] = session.advance(1)
        assert (outcome.kind, outcome.reason, session.seed) == ("dropped", "retry", SEED)
        np.testing.assert_array_equal(session.env.data.qpos, start)
        np.testing.assert_array_equal(session.env.target_positions, target)
        session.handle({"type": "gamepad", "axes": [0, 0, 0, 0], "buttons": [0, 1] + [0] * 15})  # B: discard
        [outcome] = session.advance(1)
        assert (outcome.kind, outcome.reason, session.seed) == ("dropped", "discarded", SEED + 1)
        assert not np.array_equal(session.env.target_positions, target)
    finally:
        session.close()


def test_an_episode_out_of_time_is_dropped_and_said_so(tmp_path):
    session = new_session(tmp_path)
    try:
        outcomes = session.advance(session.env.max_episode_steps)
        assert [(o.kind, o.reason) for o in outcomes] == [("dropped", "time limit: no success")]
        assert "time limit" in session.status.message and session.store.entries() == []
    finally:
        session.close()


def test_vr_controllers_drive_a_reach_to_a_kept_demo(tmp_path):
    """Synthetic controller poses through the path WebXR feeds: clutch in, carry the
    controller to where the target is, as a person would (the XR frame is y up, -z ahead)."""
    session = new_session(tmp_path, "vr")
    try:
        grip = {"hand": "left", "orientation": [0, 0, 0, 1], "buttons": [0, 1, 0, 0, 0, 0]}
        position = np.array([-0.2, 1.0, -0.3])
        session.handle({"type": "xr", "controllers": [{**grip, "position": position.tolist()}]})
        outcome = None
        for _ in range(60):  # 90 Hz-ish poses, a small step towards the target each
            error = wrist_error(session, 0, session.env.target_positions[0])
            move = np.clip(error, -0.01, 0.01)
            position = position + np.array([-move[1], move[2], -move[0]])  # robot -> XR frame
            session.handle({"type": "xr", "controllers": [{**grip, "position": position.tolist()}]})
            outcomes = session.advance(25)
            if outcomes:
                outcome = outcomes[0]
                break
        else:
            outcome = session.advance(600)[0]
        assert outcome.kind == "kept", outcome
        assert session.store.load(session.store.entries()[0]).metadata.extra["teleop_devices"] == ["vr"]
    finally:
        session.close()


def test_a_hand_target_never_runs_far_ahead_of_the_hand(tmp_path):
    session = new_session(tmp_path)
    try:
        session.handle({"type": "keydown", "code": "KeyW"})  # far beyond the arm's reach
        session.advance(1500)
        target, _ = session.controller.hand_target(1)
        commanded, _ = session.controller.ik.pose(1)
        assert np.linalg.norm(target - commanded) <= MAX_LEAD + 1e-9
        assert session.controller.hand_target(1)[0][0] > 0.6  # it did go forward
    finally:
        session.close()


def test_events_no_device_of_the_session_reads_are_refused(tmp_path):
    session = new_session(tmp_path)
    try:
        with pytest.raises(DeviceEventError, match="no device of this session reads 'xr'"):
            session.handle({"type": "xr", "controllers": []})
        with pytest.raises(DeviceEventError, match="'action' must be one of"):
            session.handle({"type": "session", "action": "save"})
        assert session.input_log == []
    finally:
        session.close()


def test_a_broken_script_is_refused_with_its_line(tmp_path):
    path = tmp_path / "bad.jsonl"
    path.write_text('{"bigym_teleop_script": 1, "task": "ReachTargetSingle", "seed": 1, "devices": ["keyboard"]}\n'
                    '{"step": 5, "event": {"type": "keydown", "code": "KeyW"}}\n{"step": 2}\n')  # fmt: skip
    with pytest.raises(ValueError, match=r"bad.jsonl:3"):
        InputScript.load(path)
    path.write_text("hello\n")
    with pytest.raises(ValueError, match="not a bigym teleop script"):
        InputScript.load(path)


# ---------------------------------------------------------------------- the command line
def test_bigym_teleop_plays_a_script_into_the_store(recorded, tmp_path):
    from typer.testing import CliRunner

    from bigym.cli import app

    _, _, script = recorded
    store, saved = tmp_path / "cli-store", tmp_path / "again.jsonl"
    result = CliRunner().invoke(app, ["teleop", "ReachTargetSingle", "--script", str(script), "--store", str(store),
                                      "--save-input", str(saved), "--aside", str(tmp_path / "aside")])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert f"seed {SEED}: kept" in result.output and "1 demos kept" in result.output
    [entry] = DemoStore(store, on_demand=False).entries(task="ReachTargetSingle")
    assert entry.source == "human"
    assert InputScript.load(saved).events == InputScript.load(script).events


@pytest.mark.parametrize(
    "args, words",
    [
        (["--ui", "vr"], "--ui must be 'browser' or 'window'"),
        (["--device", "joystick"], "unknown device(s) joystick"),
        (["--script", "missing.jsonl"], "missing.jsonl"),
    ],
)
def test_bigym_teleop_refuses_bad_options_clearly(args, words):
    from typer.testing import CliRunner

    from bigym.cli import app

    result = CliRunner().invoke(app, ["teleop", "ReachTargetSingle", *args])
    assert result.exit_code == 1 and words in result.output, result.output


# ---------------------------------------------------------------------- the window front end
class FakeViewer:
    """Stands in for MuJoCo's passive viewer: presses keys on given frames, closes after ``frames``."""

    def __init__(self, key_callback, presses: dict[int, int], frames: int) -> None:
        import mujoco

        self.cam = mujoco.MjvCamera()
        self.key_callback, self.presses, self.frames = key_callback, presses, frames
        self.synced, self.texts = 0, None

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        pass

    def is_running(self) -> bool:
        if self.synced in self.presses:
            self.key_callback(self.presses.pop(self.synced))
        return self.synced < self.frames

    def lock(self):
        import contextlib

        return contextlib.nullcontext()

    def set_texts(self, texts) -> None:
        self.texts = texts

    def sync(self) -> None:
        self.synced += 1


def test_the_window_drives_the_session_in_real_time_from_key_presses(tmp_path):
    from bigym.teleop.window import run_window

    session = new_session(tmp_path)
    viewers = []

    def launch(model, data, key_callback, **kwargs):
        assert model is session.env.model and data is session.env.data
        viewers.append(FakeViewer(key_callback, {5: ord("W")}, frames=45))  # 45 frames at 60 fps: 0.75 s
        return viewers[0]

    try:
        before = session.controller.hand_target(1)[0].copy()
        run_window(session, launch=launch)
        moved = session.controller.hand_target(1)[0] - before
        np.testing.assert_allclose(moved, [0.25 * 0.2, 0.0, 0.0], atol=1e-9)  # one press: 0.2 s of W
        assert 250 <= session.total_steps <= 450  # about 0.75 s of simulated time, in real time
        assert "ReachTargetSingle" in viewers[0].texts[3]
    finally:
        session.close()
