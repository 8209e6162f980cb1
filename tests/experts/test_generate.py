"""Where a recorded expert demo ends: a whole AFTER_SUCCESS after the first success, or,
for an expert whose success can flicker (``success_must_last``), after a success that held,
or, for one that may succeed on the way (``success_after_plan``), after its plan ended."""

import numpy as np

from bigym.demonstrations import Demo, replay
from bigym.experts.expert import LEFT
from bigym.experts.generate import AFTER_SUCCESS, CONTROL_FREQUENCY, record_attempt
from bigym.experts.reach import ReachExpert

MARGIN = round(AFTER_SUCCESS * CONTROL_FREQUENCY)
DATE = "2026-01-01T00:00:00Z"


class LastingReach(ReachExpert):
    success_must_last = True


class FlickeringReach(ReachExpert):
    """Reaches the target, draws the wrist 25 cm back for a second, and reaches it again:
    the task is successful, then not, then for good."""

    def plan(self):
        target = self.env.target_positions[0].copy()
        yield from self.until(self.move_hand(LEFT, target, frame="wrist", duration=1.0))
        yield from self.wait(0.2)
        away = target - np.array([0.25, 0.0, 0.0])
        yield from self.until(self.move_hand(LEFT, away, frame="wrist", duration=0.4))
        yield from self.wait(1.0)
        yield from self.until(self.move_hand(LEFT, target, frame="wrist", duration=0.5))
        while True:
            yield


class LastingFlickeringReach(FlickeringReach):
    success_must_last = True


def recorded_success(expert_class) -> np.ndarray:
    attempt = record_attempt("ReachTargetSingle", 0, 3, verify=False, date=DATE, expert_class=expert_class)
    assert attempt.success, attempt.reason
    return replay(Demo.from_bytes(attempt.data), episode_only=False).success


def test_a_success_that_holds_ends_the_recording_where_the_plain_rule_does():
    plain = record_attempt("ReachTargetSingle", 0, 3, verify=False, date=DATE, expert_class=ReachExpert)
    lasting = record_attempt("ReachTargetSingle", 0, 3, verify=False, date=DATE, expert_class=LastingReach)
    assert plain.success and lasting.success
    assert lasting.data == plain.data


def test_a_momentary_success_ends_the_plain_recording_but_not_one_that_must_last():
    plain = recorded_success(FlickeringReach)
    first = int(np.argmax(plain))
    assert len(plain) == first + 1 + MARGIN
    assert not plain[-1]  # drawn back: the plain recording ends on a failing state

    lasting = recorded_success(LastingFlickeringReach)
    assert int(np.argmax(lasting)) == first
    assert len(lasting) > len(plain)
    assert lasting[-(MARGIN + 1) :].all()  # it ends after a whole margin of success
    assert not lasting[-(MARGIN + 2)]  # and no later than that


class ReachThenWait(ReachExpert):
    """Reaches the target, holds it for two seconds, and ends its plan."""

    success_after_plan = True

    def plan(self):
        target = self.env.target_positions[0].copy()
        yield from self.until(self.move_hand(LEFT, target, frame="wrist", duration=1.0))
        yield from self.wait(2.0)


def test_a_success_on_the_way_does_not_end_the_recording_before_the_plan_has():
    plain = recorded_success(type("PlainReachThenWait", (ReachThenWait,), {"success_after_plan": False}))
    after_plan = recorded_success(ReachThenWait)
    first = int(np.argmax(plain))
    assert len(plain) == first + 1 + MARGIN
    assert int(np.argmax(after_plan)) == first  # the same success on the way
    # the plan ends two seconds after the reach: the recording a whole margin later
    assert len(after_plan) > len(plain) + 0.8 * MARGIN
    assert after_plan[-(MARGIN + 1) :].all()


def test_a_success_that_never_lasts_is_not_a_demo():
    class NeverLasting(FlickeringReach):
        success_must_last = True

        def plan(self):
            target = self.env.target_positions[0].copy()
            yield from self.until(self.move_hand(LEFT, target, frame="wrist", duration=1.0))
            away = target - np.array([0.25, 0.0, 0.0])
            yield from self.until(self.move_hand(LEFT, away, frame="wrist", duration=0.4))
            while True:
                yield

    attempt = record_attempt("ReachTargetSingle", 0, 3, verify=False, date=DATE, expert_class=NeverLasting)
    assert not attempt.success
    assert attempt.reason == "success did not last"


def test_a_mishap_the_incident_watch_names_rejects_the_attempt_unless_the_bytes_are_known(monkeypatch):
    # the watch's own cases are in test_incidents.py; here, that the generator acts on it
    from bigym.experts import generate

    plain = record_attempt("ReachTargetSingle", 0, 3, verify=False, date=DATE, expert_class=ReachExpert)
    assert plain.success and plain.duration > 1.5

    def a_mishap_after_a_second(watch):
        return "block knocked over at t=1.00 s" if watch.env.data.time >= 1.0 else None

    monkeypatch.setattr(generate.IncidentWatch, "check", a_mishap_after_a_second)
    rejected = record_attempt("ReachTargetSingle", 0, 3, verify=False, date=DATE, expert_class=ReachExpert)
    assert not rejected.success and rejected.data is None
    assert rejected.reason == "rejected: block knocked over at t=1.00 s"
    # regenerating a shipped file (its sha256 decides) records it whatever the watch says
    kept = record_attempt("ReachTargetSingle", 0, 3, None, False, DATE, False, expert_class=ReachExpert)
    assert kept.success and kept.data == plain.data
