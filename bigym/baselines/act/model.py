"""ACT's conditional VAE: a style variable z summarises the demonstrated chunk (training
only), a transformer decodes the chunk from z, the state and the camera features. At
run time z is the prior's mean (zero), so the policy is deterministic, or with
``sample_latent`` one draw from the prior per episode. With ``modes`` the decoder also
reads the demo's mode (bigym.baselines.modes), drawn once per episode when acting."""

from __future__ import annotations

import torch
from torch import nn

from bigym.baselines.act.config import ACTConfig
from bigym.baselines.common import ChunkModel, masked_l1
from bigym.baselines.vision import Cameras


def _encoder(config: ACTConfig, layers: int) -> nn.TransformerEncoder:
    layer = nn.TransformerEncoderLayer(
        config.hidden, config.heads, config.feedforward, config.dropout, batch_first=True, norm_first=True
    )
    return nn.TransformerEncoder(layer, layers, enable_nested_tensor=False)


class ACTModel(ChunkModel):
    def __init__(self, config: ACTConfig, state_dim: int, action_dim: int, image_shapes: dict) -> None:
        super().__init__()
        d = config.hidden
        self.config, self.action_dim = config, action_dim
        # the posterior q(z | state, chunk): a transformer over [CLS, state, actions]
        self.posterior_state = nn.Linear(state_dim, d)
        self.posterior_actions = nn.Linear(action_dim, d)
        self.cls = nn.Parameter(torch.zeros(1, 1, d))
        self.posterior_position = nn.Parameter(torch.randn(1, 2 + config.chunk, d) * 0.02)
        self.posterior = _encoder(config, config.encoder_layers)
        self.to_latent = nn.Linear(d, 2 * config.latent)
        # the decoder p(chunk | z, state, cameras)
        self.from_latent = nn.Linear(config.latent, d)
        self.state = nn.Linear(state_dim, d)
        self.cameras = Cameras(image_shapes, d) if image_shapes else None
        # the demo's mode: one more token for the decoder, and a classifier of it from the state
        self.mode = nn.Embedding(config.modes, d) if config.modes else None
        self.mode_classifier = (
            nn.Sequential(nn.Linear(state_dim, d), nn.ReLU(), nn.Linear(d, config.modes)) if config.modes else None
        )
        tokens = 2 + (1 if config.modes else 0) + len(image_shapes)
        self.memory_position = nn.Parameter(torch.randn(1, tokens, d) * 0.02)
        self.encoder = _encoder(config, config.encoder_layers)
        self.queries = nn.Parameter(torch.randn(1, config.chunk, d) * 0.02)
        layer = nn.TransformerDecoderLayer(
            d, config.heads, config.feedforward, config.dropout, batch_first=True, norm_first=True
        )
        self.decoder = nn.TransformerDecoder(layer, config.decoder_layers)
        self.head = nn.Linear(d, action_dim)

    def _decode(self, batch: dict[str, torch.Tensor], z: torch.Tensor) -> torch.Tensor:
        tokens = [self.from_latent(z)[:, None], self.state(batch["state"])[:, None]]
        if self.mode is not None:
            tokens.append(self.mode(batch["mode"].to(z.device).expand(len(z)))[:, None])
        if self.cameras is not None:
            tokens.append(self.cameras(batch))
        memory = self.encoder(torch.cat(tokens, dim=1) + self.memory_position)
        queries = self.queries.expand(len(z), -1, -1)
        return self.head(self.decoder(queries, memory))

    def start_episode(self, batch: dict[str, torch.Tensor], generator: torch.Generator) -> dict[str, torch.Tensor]:
        """What stays fixed for an episode, given its first observation: the sampled z
        (``sample_latent``) and the mode, drawn from the classifier's probabilities."""
        fixed = {}
        if self.config.sample_latent:
            fixed["latent"] = torch.randn(1, self.config.latent, generator=generator)
        if self.mode_classifier is not None:
            probabilities = self.mode_classifier(batch["state"][:1]).softmax(dim=1).cpu()
            fixed["mode"] = torch.multinomial(probabilities, 1, generator=generator)[0]
        return fixed

    def predict(self, batch: dict[str, torch.Tensor], generator: torch.Generator | None = None) -> torch.Tensor:
        """The chunk for ``batch["latent"]`` (from :meth:`start_episode`) or for z = 0, and
        for ``batch["mode"]`` or, without one, the classifier's likeliest mode per sample."""
        n, device = len(batch["state"]), batch["state"].device
        latent = batch.get("latent")
        z = torch.zeros(n, self.config.latent, device=device) if latent is None else latent.to(device).expand(n, -1)
        if self.mode_classifier is not None and "mode" not in batch:
            batch = {**batch, "mode": self.mode_classifier(batch["state"]).argmax(dim=1)}
        return self._decode(batch, z)

    def loss(self, batch: dict[str, torch.Tensor], generator: torch.Generator) -> tuple[torch.Tensor, dict]:
        n = len(batch["state"])
        tokens = torch.cat(
            [
                self.cls.expand(n, -1, -1),
                self.posterior_state(batch["state"])[:, None],
                self.posterior_actions(batch["actions"]),
            ],
            dim=1,
        )
        # padded steps of the chunk are hidden from the posterior
        mask = torch.cat([torch.zeros(n, 2, dtype=torch.bool, device=batch["pad"].device), batch["pad"]], dim=1)
        summary = self.posterior(tokens + self.posterior_position, src_key_padding_mask=mask)[:, 0]
        mean, log_var = self.to_latent(summary).chunk(2, dim=1)
        noise = torch.randn(mean.shape, generator=generator).to(mean.device)  # CPU generator: seeded
        z = mean + (0.5 * log_var).exp() * noise
        l1 = masked_l1(self._decode(batch, z), batch["actions"], batch["pad"])
        kl = 0.5 * (mean.pow(2) + log_var.exp() - 1.0 - log_var).sum(dim=1).mean()
        loss, terms = l1 + self.config.kl_weight * kl, {"l1": l1.item(), "kl": kl.item()}
        if self.mode_classifier is not None:
            mode_loss = nn.functional.cross_entropy(self.mode_classifier(batch["state"]), batch["mode"])
            loss, terms["mode"] = loss + mode_loss, mode_loss.item()
        return loss, terms
