"""The baselines: training lowers the loss, resumes to the same weights, round-trips its
checkpoint, and the checkpoint acts in ``evaluate`` and ``bigym eval``."""

from __future__ import annotations

import json

import numpy as np
import pytest
import torch
from typer.testing import CliRunner

from bigym.action_modes import JointPositionActionMode
from bigym.baselines import Checkpoint, ChunkPolicy, checkpoint_factory, load_policy, temporal_ensemble, train
from bigym.baselines.train import resolve_device
from bigym.cli import app
from bigym.envs.reach_target import ReachTargetDual, ReachTargetMultiModal
from bigym.evaluation import evaluate
from bigym.observations import ObservationConfig

SMALL = {
    "bc": {"hidden": 64, "layers": 2, "batch_size": 32},
    "act": {"hidden": 32, "heads": 2, "encoder_layers": 1, "decoder_layers": 1, "feedforward": 64, "batch_size": 32},
    "dp": {"hidden": 32, "channels": [16, 32], "batch_size": 32, "inference_steps": 4},
}
STATE = ObservationConfig(privileged_information=True)
TASK = "ReachTargetMultiModal"  # the demo_store fixture's task


def small_run(method, demo_store, out, steps, ema=0.0, settings=None, **kwargs):
    settings = {**SMALL[method], "steps": steps, "chunk": 8, "ema": ema, **(settings or {})}
    return train(method, TASK, out, demos=4, store=demo_store, settings=settings, **kwargs)


@pytest.mark.parametrize("method", ["bc", "act", "dp"])
def test_training_lowers_the_loss_and_the_checkpoint_acts(method, demo_store, tmp_path):
    checkpoint = small_run(method, demo_store, tmp_path / "model.pt", 300, checkpoint_every=100)
    losses = [loss for _, loss in checkpoint.losses]
    assert checkpoint.step == 300 and len(losses) == 6
    assert losses[-1] < 0.7 * losses[0], losses
    # the loss's parts, averaged over the same steps: ACT's is l1 + kl_weight * kl
    assert len(checkpoint.loss_terms) == len(losses)
    assert set(checkpoint.loss_terms[-1]) == {"bc": {"l1"}, "act": {"l1", "kl"}, "dp": {"mse"}}[method]
    kl_weight = checkpoint.config.get("kl_weight", 0.0)
    for (_, loss), terms in zip(checkpoint.losses, checkpoint.loss_terms):
        parts = terms.get("l1", 0.0) + kl_weight * terms.get("kl", 0.0) + terms.get("mse", 0.0)
        assert loss == pytest.approx(parts, rel=1e-5)
    assert checkpoint.task == TASK and len(checkpoint.demos) == 4
    assert "target_position" in checkpoint.state_keys

    env = ReachTargetMultiModal(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), observation_config=STATE
    )
    try:
        policy = load_policy(env, tmp_path / "model.pt")
        obs, _ = env.reset(seed=5)
        policy.reset(5)
        first = [policy(obs) for _ in range(3)]
        policy.reset(5)
        again = [policy(obs) for _ in range(3)]
        assert all(np.array_equal(a, b) for a, b in zip(first, again)), "reset(seed) repeats the actions"
        assert all(env.action_space.contains(a) for a in first)
    finally:
        env.close()


def test_resuming_gives_the_weights_of_an_uninterrupted_run(demo_store, tmp_path):
    for method, ema in (("bc", 0.0), ("act", 0.9)):
        straight = small_run(method, demo_store, tmp_path / f"{method}-straight.pt", 120, checkpoint_every=60, ema=ema)
        small_run(method, demo_store, tmp_path / f"{method}-resumed.pt", 60, ema=ema)
        resumed = small_run(method, demo_store, tmp_path / f"{method}-resumed.pt", 120, checkpoint_every=60, ema=ema)
        assert resumed.step == 120
        # the first part's log is kept: entries at 50 and 60, then the resumed part's 100 and 120
        assert [step for step, _ in resumed.losses] == [50, 60, 100, 120] and len(resumed.loss_terms) == 4
        for name, tensor in straight.model.items():
            assert torch.equal(tensor, resumed.model[name]), (method, name)
        assert bool(resumed.ema) == (ema > 0) and straight.ema.keys() == resumed.ema.keys()
        for name, tensor in straight.ema.get("weights", {}).items():
            assert torch.equal(tensor, resumed.ema["weights"][name]), (method, "average", name)
        again = small_run(method, demo_store, tmp_path / f"{method}-resumed.pt", 120, ema=ema)
        assert again.step == 120, "a finished run is not trained again"
    with pytest.raises(ValueError, match="different training run"):
        train("bc", TASK, tmp_path / "bc-resumed.pt", demos=4, store=demo_store, settings={"steps": 200})


def test_checkpoint_round_trip_and_errors(demo_store, tmp_path):
    path = tmp_path / "model.pt"
    trained = small_run("bc", demo_store, path, 50)
    loaded = Checkpoint.load(path)
    batch = {"state": torch.randn(3, loaded.state_dim)}
    with torch.no_grad():
        assert torch.equal(trained.build_model().eval().predict(batch), loaded.build_model().eval().predict(batch))
    assert np.array_equal(loaded.make_normalizer().action_center, trained.make_normalizer().action_center)
    (tmp_path / "junk.pt").write_bytes(b"not a checkpoint")
    with pytest.raises(ValueError, match="not a readable bigym checkpoint"):
        Checkpoint.load(tmp_path / "junk.pt")
    with pytest.raises(FileNotFoundError):
        Checkpoint.load(tmp_path / "missing.pt")
    for env, message in [
        (ReachTargetDual(observation_config=STATE), "trained on ReachTargetMultiModal"),
        (ReachTargetMultiModal(action_mode=JointPositionActionMode(absolute=True)), "lack target_position"),
        (ReachTargetMultiModal(observation_config=STATE), "action mode"),
    ]:
        with pytest.raises(ValueError, match=message):
            ChunkPolicy(env, loaded)
        env.close()
    with pytest.raises(ValueError, match="no setting"):
        train("bc", TASK, tmp_path / "x.pt", store=demo_store, settings={"widht": 3})
    with pytest.raises(ValueError, match="unknown method"):
        train("gpt", TASK, tmp_path / "x.pt", store=demo_store)


def test_settings_take_their_fields_types():
    from bigym.baselines import make_config

    config = make_config("act", {"ema": 0, "steps": 2000.0, "sample_latent": True})
    assert (config.ema, type(config.ema), config.steps, type(config.steps)) == (0.0, float, 2000, int)
    assert make_config("dp", {"channels": [16, 32]}).channels == (16, 32)
    for name, value, message in [
        ("ema", "0.9", "takes a number"),
        ("lr", True, "takes a number"),
        ("steps", 10.5, "takes a whole number"),
        ("sample_latent", "yes", "takes true or false"),
        ("sample_latent", 1, "takes true or false"),
    ]:
        with pytest.raises(ValueError, match=f"setting {name} {message}"):
            make_config("act", {name: value})
    with pytest.raises(ValueError, match="setting channels takes a list"):
        make_config("dp", {"channels": 64})


def test_temporal_ensemble_weighs_the_oldest_prediction_most():
    old, new = np.zeros(2), np.ones(2)
    assert np.array_equal(temporal_ensemble([old], 0.5), old)
    mixed = temporal_ensemble([old, new], 0.5)
    assert np.allclose(mixed, np.exp(-0.5) / (1 + np.exp(-0.5)))
    assert np.allclose(temporal_ensemble([old, new], 0.0), 0.5)


def test_a_checkpoint_in_evaluate_and_bigym_eval(demo_store, tmp_path):
    path = tmp_path / "model.pt"
    small_run("bc", demo_store, path, 50)
    result = evaluate(checkpoint_factory(path), TASK, episodes=2, workers=1, observation_config=STATE)
    assert len(result.episodes) == 2 and result.fingerprint["track"] == "state"
    assert "load_policy" in result.policy and "model.pt" in result.policy
    out = tmp_path / "result.json"
    cli = CliRunner().invoke(app, ["eval", TASK, "--policy", str(path), "--episodes", "2", "--workers", "1",
                                   "--json", str(out)])  # fmt: skip
    assert cli.exit_code == 0, cli.output
    record = json.loads(out.read_text())
    assert record["fingerprint"]["track"] == "state", "the checkpoint's observations were used"
    assert [e["start"] for e in record["episodes"]] == [e.start for e in result.episodes]
    cli = CliRunner().invoke(app, ["eval", TASK, "--policy", str(path), "--privileged"])
    assert cli.exit_code == 1 and "brings its own observations" in cli.output


def test_a_checkpoint_acts_with_another_temporal_ensembling_when_asked(demo_store, tmp_path):
    path = tmp_path / "model.pt"
    small_run("bc", demo_store, path, 20)
    assert "ensemble_decay" not in checkpoint_factory(path).keywords, "ACT's own is the default"
    factory = checkpoint_factory(path, 1.0)
    assert factory.keywords["ensemble_decay"] == 1.0
    env = ReachTargetMultiModal(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), observation_config=STATE
    )
    try:
        assert factory(env).decay == 1.0 and checkpoint_factory(path)(env).decay == 0.01
    finally:
        env.close()
    with pytest.raises(ValueError, match="finite"):
        checkpoint_factory(path, float("inf"))
    out = tmp_path / "result.json"
    cli = CliRunner().invoke(app, ["eval", TASK, "--policy", str(path), "--episodes", "1", "--workers", "1",
                                   "--ensemble-decay", "1.0", "--json", str(out)])  # fmt: skip
    assert cli.exit_code == 0, cli.output
    assert "ensemble_decay=1.0" in json.loads(out.read_text())["policy"], "the record says how it acted"
    cli = CliRunner().invoke(app, ["eval", TASK, "--policy", "random", "--ensemble-decay", "1.0"])
    assert cli.exit_code == 1 and "setting of a trained checkpoint" in cli.output


def test_bigym_train_command(demo_store, tmp_path):
    out = tmp_path / "cli.pt"
    args = ["train", "bc", "reach_target_multi_modal", "--store", str(demo_store.url), "--demos", "4", "--steps", "60",
            "--set", "hidden=32", "--set", "chunk=8", "--out", str(out), "--checkpoint-every", "20"]  # fmt: skip
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "evaluate it: bigym eval ReachTargetMultiModal" in result.output
    logged = [line.split()[1] for line in result.output.splitlines() if line.startswith("step ")]
    assert logged == ["20/60", "40/60", "60/60"], "not a terminal: one line per checkpoint"
    assert Checkpoint.load(out).config["hidden"] == 32
    for bad, message in [
        (["train", "gpt", "reach_target_multi_modal"], "unknown method"),
        (["train", "bc", "reach_target_multi_modal", "--set", "oops"], "name=value"),
        (["train", "bc", "reach_target_multi_modal", "--set", "hidden=wide"], "setting hidden takes a whole number"),
        (["train", "bc", "reach_target_multi_modal", "--cameras", "tail"], "unknown camera(s) tail"),
        (
            ["train", "bc", "reach_target_multi_modal", "--store", str(demo_store.url), "--device", "gpu7"],
            "unknown device 'gpu7'",
        ),
    ]:
        result = CliRunner().invoke(app, bad)
        assert result.exit_code == 1 and message in result.output, result.output


def test_training_devices():
    assert resolve_device("cpu") == torch.device("cpu")
    assert resolve_device("auto").type == ("cuda" if torch.cuda.is_available() else "cpu")
    with pytest.raises(ValueError, match="unknown device"):
        resolve_device("abacus")
    if not torch.cuda.is_available():
        with pytest.raises(ValueError, match="no CUDA GPU"):
            resolve_device("cuda")


def test_training_and_acting_from_a_camera(demo_store, tmp_path):
    checkpoint = train(
        "act", TASK, tmp_path / "pixels.pt", demos=2, store=demo_store, cameras=("head",), depth=True,
        privileged=False, settings={**SMALL["act"], "steps": 20, "chunk": 4, "ema": 0.0},
    )  # fmt: skip  (the last weights: after 20 steps the average's pull of the image is below float32's grain)
    assert checkpoint.image_shapes == {"depth_head": [1, 84, 84], "rgb_head": [3, 84, 84]}
    assert "target_position" not in checkpoint.state_keys
    config = ObservationConfig.from_dict(checkpoint.observation_config)
    env = ReachTargetMultiModal(action_mode=JointPositionActionMode(floating_base=True, absolute=True),
                                observation_config=config)  # fmt: skip
    try:
        policy = load_policy(env, tmp_path / "pixels.pt")
        obs, _ = env.reset(seed=1)
        policy.reset(1)
        action = policy(obs)
        assert env.action_space.contains(action)
        obs, *_ = env.step(action)
        # compared before the policy clamps its chunk to the demos' range and clips it to the
        # action bounds: after 20 steps every entry the image moves may sit at a bound
        raw = []
        predict = policy.model.predict
        policy.model.predict = lambda batch, generator: raw.append(predict(batch, generator)) or raw[-1]
        blind = dict(obs, rgb_head=np.zeros_like(obs["rgb_head"]))
        for seen in (obs, blind):
            policy.reset(1)
            policy(seen)
        assert not torch.equal(raw[0], raw[1]), "the image reaches the action"
    finally:
        env.close()


class _Demo:
    """The parts of a replayed demo a ChunkDataset reads: 5 steps, 2 actions, no base."""

    def __init__(self) -> None:
        self.actions = np.arange(10, dtype=np.float64).reshape(5, 2)
        self.observations = {"proprioception": np.arange(12, dtype=np.float32).reshape(6, 2)}
        self.metadata = type("Metadata", (), {"action_names": ["arm_a", "arm_b"]})()


@pytest.mark.parametrize("hold_end", [False, True])
def test_chunks_past_a_demos_end_are_masked_or_held(hold_end):
    from bigym.baselines.data import ChunkDataset

    dataset = ChunkDataset([_Demo()], chunk=4, image_keys=[], hold_end=hold_end)
    last = dataset.normalizer.unnormalize_actions(dataset.chunks[4].numpy())
    assert np.allclose(last, [[8, 9]] * 4), "the chunk from the last step repeats the last action"
    pads = dataset.pad.numpy()
    if hold_end:
        assert not pads.any(), "every step of every chunk is trained"
    else:
        assert pads[4].tolist() == [False, True, True, True] and pads[1].tolist() == [False] * 4


class _RecordedDemo(_Demo):
    """A demo replayed with its whole recording: 8 steps, of which the episode is 5."""

    def __init__(self, whole: bool = True) -> None:
        super().__init__()
        steps = 8 if whole else 5
        self.actions = np.arange(16, dtype=np.float64).reshape(8, 2)[:steps]
        self.observations = {"proprioception": np.arange(18, dtype=np.float32).reshape(9, 2)[: steps + 1]}
        self.report = type("Report", (), {"episode_steps": 5, "replayed_steps": 8})()
        self.uuid = "recorded"


def test_tail_trains_the_chunks_past_an_episodes_end_on_the_recording():
    from bigym.baselines.data import ChunkDataset

    dataset = ChunkDataset([_RecordedDemo()], chunk=4, image_keys=[], tail=True)
    assert len(dataset) == 5, "the samples are the episode's steps only"
    last = dataset.normalizer.unnormalize_actions(dataset.chunks[4].numpy())
    assert np.allclose(last, [[8, 9], [10, 11], [12, 13], [14, 15]]), "what the demonstrator went on doing"
    assert dataset.pad.numpy()[3:].tolist() == [[False] * 4, [False] * 4]
    masked = ChunkDataset([_RecordedDemo()], chunk=4, image_keys=[])
    assert len(masked) == 8, "without tail every replayed step is a sample (episode replays hold only the episode)"
    with pytest.raises(ValueError, match="without the steps after its episode's end"):
        ChunkDataset([_RecordedDemo(whole=False)], chunk=4, image_keys=[], tail=True)


def test_tail_replays_the_whole_recording_and_trains_on_it(demo_store, tmp_path):
    from bigym.demonstrations import Metadata

    env = ReachTargetMultiModal(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), observation_config=STATE
    )
    try:
        metadata = Metadata.from_env(env)
    finally:
        env.close()
    episodes = demo_store.get_demos(metadata, amount=2)
    whole = demo_store.get_demos(metadata, amount=2, episode_only=False)
    for episode, recording in zip(episodes, whole):
        assert len(episode) == episode.report.episode_steps < len(recording) == recording.report.replayed_steps
        assert np.array_equal(recording.actions[: len(episode)], episode.actions)
        assert recording.terminated[len(episode) - 1] and not episode.terminated[:-1].any()
    again = demo_store.get_demos(metadata, amount=2)  # the cache keeps the two apart
    assert [len(d) for d in again] == [len(d) for d in episodes]
    checkpoint = small_run("bc", demo_store, tmp_path / "tail.pt", 20, settings={"tail": True})
    assert checkpoint.config["tail"] is True and checkpoint.step == 20


def test_a_checkpoint_from_before_the_hold_end_setting_resumes(demo_store, tmp_path):
    path = tmp_path / "old.pt"
    small_run("bc", demo_store, path, 20)
    old = Checkpoint.load(path)
    del old.config["hold_end"]  # written before the setting existed: it trained with masked chunk ends
    old.save(path)
    assert Checkpoint.load(path).config["hold_end"] is False
    assert small_run("bc", demo_store, path, 40).step == 40
    with pytest.raises(ValueError, match="different training run"):
        train("bc", TASK, path, demos=4, store=demo_store, settings={**SMALL["bc"], "steps": 60, "chunk": 8, "hold_end": True})


def test_the_weight_average_acts_when_a_run_keeps_one(demo_store, tmp_path):
    from bigym.baselines.ema import WeightAverage

    checkpoint = small_run("act", demo_store, tmp_path / "ema.pt", 60, ema=0.99)
    assert checkpoint.ema["updates"] == 60
    last, acting = checkpoint.model, checkpoint.build_model().state_dict()
    moved = [name for name in last if last[name].is_floating_point() and not torch.equal(last[name], acting[name])]
    assert moved, "the acting weights are the average, not the last weights"
    for name, value in acting.items():
        assert torch.equal(value, checkpoint.ema["weights"][name]), name

    # the average itself: after the warm-up the decay caps at the setting
    layer = torch.nn.Linear(1, 1, bias=False)
    average = WeightAverage(layer, 0.5)
    with torch.no_grad():
        layer.weight.fill_(0.0)
    average.weights["weight"].fill_(1.0)
    average.updates = 100
    average.update(layer)
    assert average.weights["weight"].item() == 0.5
    for wrong in (1.5, -0.1, "0.9"):
        with pytest.raises(ValueError, match="decay"):
            WeightAverage(layer, wrong)


def test_a_checkpoint_from_before_the_ema_setting_acts_with_its_last_weights(demo_store, tmp_path):
    path = tmp_path / "old.pt"
    small_run("bc", demo_store, path, 20)
    old = Checkpoint.load(path)
    del old.config["ema"]
    old.save(path)
    loaded = Checkpoint.load(path)
    assert loaded.config["ema"] == 0.0 and loaded.ema == {}
    for name, value in loaded.build_model().state_dict().items():
        assert torch.equal(value, old.model[name]), name
    assert small_run("bc", demo_store, path, 40).step == 40
    with pytest.raises(ValueError, match="different training run"):
        small_run("bc", demo_store, path, 60, ema=0.999)


@pytest.mark.parametrize("sample_latent", [False, True])
def test_acts_latent_is_zero_or_one_draw_per_episode(demo_store, tmp_path, sample_latent):
    path = tmp_path / "act.pt"
    small_run("act", demo_store, path, 30, settings={"sample_latent": sample_latent, "kl_weight": 0.01})
    env = ReachTargetMultiModal(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), observation_config=STATE
    )
    try:
        policy = load_policy(env, path)
        obs, _ = env.reset(seed=3)

        def first_actions(seed):
            policy.reset(seed)
            return np.stack([policy(obs) for _ in range(3)])

        a, b, again = first_actions(1), first_actions(2), first_actions(1)
        assert np.array_equal(a, again), "the episode's seed fixes its draw"
        # z = 0 whatever the seed; a sampled z differs between episodes
        assert np.array_equal(a, b) != sample_latent
        first = {"state": torch.zeros(1, policy.checkpoint.state_dim)}
        latents = [policy.model.start_episode(first, torch.Generator().manual_seed(s)) for s in (1, 1, 2)]
        if sample_latent:
            assert torch.equal(latents[0]["latent"], latents[1]["latent"])
            assert not torch.equal(latents[0]["latent"], latents[2]["latent"])
        else:
            assert latents == [{}, {}, {}]
    finally:
        env.close()


def test_state_noise_perturbs_the_training_states_only_when_asked():
    from bigym.baselines.data import ChunkDataset

    dataset = ChunkDataset([_Demo()], chunk=4, image_keys=[])
    plain = dataset.batch(64, torch.Generator().manual_seed(3))
    again = dataset.batch(64, torch.Generator().manual_seed(3), state_noise=0.0)
    noisy = dataset.batch(64, torch.Generator().manual_seed(3), state_noise=0.5)
    assert torch.equal(plain["state"], again["state"]), "no noise: the states as stored"
    assert torch.equal(plain["actions"], noisy["actions"]), "the same samples are drawn"
    offsets = (noisy["state"] - plain["state"]).flatten()
    assert 0.35 < offsets.std().item() < 0.65 and abs(offsets.mean().item()) < 0.15
    with pytest.raises(ValueError, match="state_noise"):
        train("act", TASK, "unused.pt", demos=1, settings={"state_noise": -0.1})


def _two_ways(count: int, seed: int) -> tuple[list[np.ndarray], list[int]]:
    """Demos that use one of two arms (entries 0-1 or 2-3), at random lengths and reaches."""
    rng = np.random.default_rng(seed)
    demos, ways = [], []
    for _ in range(count):
        way, steps = int(rng.integers(2)), int(rng.integers(40, 120))
        actions = rng.normal(0.0, 0.02, (steps, 4))
        actions[:, 2 * way : 2 * way + 2] += np.linspace(0, rng.uniform(0.6, 1.0), steps)[:, None]
        demos.append(actions)
        ways.append(way)
    return demos, ways


def test_demo_modes_group_the_demos_by_the_way_they_do_the_task():
    from bigym.baselines.modes import demo_modes

    demos, ways = _two_ways(30, seed=1)
    labels = demo_modes(demos, 2)
    assert labels[0] == 0, "modes are numbered in the order the demos show them"
    assert (labels == np.array(ways)).all() or (labels == 1 - np.array(ways)).all()
    assert np.array_equal(labels, demo_modes(demos, 2)), "the same demos, the same labels"
    assert len(set(demo_modes(demos, 3).tolist())) == 3
    with pytest.raises(ValueError, match="at least as many demos"):
        demo_modes(demos[:2], 3)
    with pytest.raises(ValueError, match="setting modes"):
        train("act", TASK, "unused.pt", demos=1, settings={"modes": -1})


def test_act_with_modes_is_told_the_demos_mode_and_draws_one_per_episode(demo_store, tmp_path):
    path = tmp_path / "modes.pt"
    checkpoint = small_run("act", demo_store, path, 40, settings={"modes": 2})
    assert sorted(set(checkpoint.demo_modes)) == [0, 1] and len(checkpoint.demo_modes) == 4
    assert {"l1", "kl", "mode"} == set(checkpoint.loss_terms[-1])
    env = ReachTargetMultiModal(
        action_mode=JointPositionActionMode(floating_base=True, absolute=True), observation_config=STATE
    )
    try:
        policy = load_policy(env, path)
        obs, _ = env.reset(seed=3)
        policy.reset(3)
        policy(obs)
        first = policy._episode["mode"]
        state = {"state": torch.zeros(1, checkpoint.state_dim)}
        chunks = [policy.model.predict({**state, "mode": torch.tensor([m])}) for m in (0, 1)]
        assert not torch.equal(*chunks), "the mode reaches the decoder"
        draws = []
        for seed in range(12):
            policy.reset(seed)
            policy(obs)
            draws.append(int(policy._episode["mode"]))
            policy(obs)
            assert int(policy._episode["mode"]) == draws[-1], "one mode for the whole episode"
        policy.reset(3)
        policy(obs)
        assert torch.equal(policy._episode["mode"], first), "the episode's seed fixes its mode"
        assert set(draws) == {0, 1}, "an untrained classifier draws either mode"
    finally:
        env.close()


def test_baseline_fit_measures_the_acting_model_on_its_training_samples(demo_store, tmp_path):
    import importlib.util
    from pathlib import Path

    path = Path(__file__).parents[2] / "benchmarks" / "baseline_fit.py"
    spec = importlib.util.spec_from_file_location("baseline_fit", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    early = module.acting_fit(small_run("bc", demo_store, tmp_path / "early.pt", 5), demo_store)
    late = module.acting_fit(small_run("bc", demo_store, tmp_path / "late.pt", 300), demo_store)
    assert 0 < late < 0.7 * early, (early, late)
