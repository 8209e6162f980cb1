"""The browser front end in a real headless Chromium: the page loads, shows frames that
change when keys are pressed, and a demo recorded from the page lands in the store."""

from __future__ import annotations

import io
import os
import shutil
import time

import numpy as np
import pytest
from PIL import Image
from teleopkit import keys_towards, wrist_error

from bigym.demonstrations import DemoStore
from bigym.teleop import TeleopSession, make_devices
from bigym.teleop.browser import TeleopServer

CHROMIUM_FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-sync",
                  "--disable-background-networking", "--disable-component-update"]  # fmt: skip


def chromium() -> str:
    """Debian's Chromium (what .ci/run installs), or the one named by $BIGYM_CHROMIUM."""
    path = os.environ.get("BIGYM_CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")
    if path is None:
        raise RuntimeError("the browser tests need Chromium: apt-get install chromium (or set BIGYM_CHROMIUM)")
    return path


@pytest.fixture()
def served(tmp_path):
    session = TeleopSession("ReachTargetSingle", make_devices("keyboard,vr"), DemoStore(tmp_path / "store", on_demand=False),
                            seed=5, aside=tmp_path / "aside")  # fmt: skip
    server = TeleopServer(session, port=0)
    url = server.start()
    yield session, server, url
    server.stop()
    session.close()


@pytest.fixture()
def page(served):
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=chromium(), args=CHROMIUM_FLAGS)
        page = browser.new_page(viewport={"width": 1100, "height": 800})
        page.goto(served[2])
        page.wait_for_function(
            "window.bigymTeleop.state.frames[0] > 2 && window.bigymTeleop.state.status", timeout=60_000
        )
        yield page
        browser.close()


def scene(page) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(page.locator("#view-0").screenshot())).convert("RGB"), np.int16)


def test_the_page_shows_the_task_and_frames_that_change_when_keys_are_pressed(served, page):
    session, _, _ = served
    assert page.locator("#task").inner_text() == "ReachTargetSingle"
    assert "hand forward / back" in page.locator("#keys").inner_text()
    still = [scene(page) for _ in range(2)]
    time.sleep(0.3)
    still.append(scene(page))
    assert np.abs(still[2] - still[0]).max() <= 8, "premise: without input the picture stays (JPEG noise aside)"
    before = session.controller.hand_target(1)[0].copy()
    page.keyboard.down("KeyW")
    page.keyboard.down("KeyR")
    time.sleep(0.8)
    page.keyboard.up("KeyW")
    page.keyboard.up("KeyR")
    time.sleep(0.6)
    moved = session.controller.hand_target(1)[0] - before
    assert moved[0] > 0.08 and moved[2] > 0.08, moved  # forward and up, through the page's key events
    changed = np.abs(scene(page) - still[2]).max(axis=-1)
    assert (changed > 40).sum() > 200, "the scene view shows the arm where it went"
    assert int(page.locator("#seed").inner_text()) == 5


def test_a_demo_recorded_from_the_page_lands_in_the_store(served, page):
    session, _, _ = served
    page.keyboard.press("Digit1")  # the left hand
    held: set[str] = set()
    deadline = time.monotonic() + 45
    while not session.outcomes and time.monotonic() < deadline:
        want = keys_towards(wrist_error(session, 0, session.env.target_positions[0]))
        for code in held - want:
            page.keyboard.up(code)
        for code in want - held:
            page.keyboard.down(code)
        held = want
        time.sleep(0.05)
    for code in held:
        page.keyboard.up(code)
    assert session.outcomes and session.outcomes[0].kind == "kept", session.outcomes
    page.wait_for_function("document.getElementById('kept').textContent === '1'", timeout=30_000)
    assert "seed 5: kept" in page.locator("#log").inner_text()
    [entry] = session.store.entries(task="ReachTargetSingle")
    assert session.store.load(entry).metadata.source == "human"
    if os.environ.get("BIGYM_TELEOP_SCREENSHOT"):  # docs/images/teleop-browser.png is made this way
        page.screenshot(path=os.environ["BIGYM_TELEOP_SCREENSHOT"])


def test_synthetic_vr_controller_poses_move_the_hand_through_the_page(served, page):
    """What the page's WebXR loop does each frame: xrFrame(controllers) -> the server's VR device."""
    session, _, _ = served
    before = session.controller.hand_target(1)[0].copy()
    grip = {"hand": "right", "orientation": [0, 0, 0, 1], "buttons": [0, 1, 0, 0, 0, 0], "axes": [0, 0, 0, 0]}
    for z in np.linspace(-0.3, -0.4, 11):  # the controller carried 0.1 m ahead (-z), grip held
        assert page.evaluate("(c) => window.bigymTeleop.xrFrame(c)", [{**grip, "position": [0.2, 1.0, float(z)]}])
        time.sleep(0.03)
    time.sleep(0.5)
    moved = session.controller.hand_target(1)[0] - before
    np.testing.assert_allclose(moved, [0.1, 0.0, 0.0], atol=0.01)
    xr_events = [e for _, e in session.input_log if e["type"] == "xr"]
    assert len(xr_events) == 11
