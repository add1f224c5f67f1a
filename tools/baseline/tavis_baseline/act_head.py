"""ACT's model as an action head (Zhao et al. 2023, "Action Chunking with Transformers"; LeRobot's
`act` policy has the same structure): a conditional VAE over the action chunk whose decoder is a
transformer encoder-decoder, so that the chunk can follow one of several modes (which arm, which
side) where an L1 regression averages them.

- Encoder of the CVAE (training only): a small transformer over [CLS, the newest state, the target
  chunk's rows] (the padded rows masked out); its CLS output gives the posterior's mean and
  log-variance of a latent z (latent_dim), z = mu + sigma * eps.
- Decoder of the CVAE: a transformer encoder over [z, one token per history frame's state, every
  position of every camera's last feature map of every history frame] (learned position
  embeddings: the image size is fixed per checkpoint), and a transformer decoder whose chunk_size
  learned queries attend to it; a linear layer turns each query into one row of the chunk.
- Loss: the masked L1 between the predicted and the target normalised chunk + kl_weight x the KL
  divergence of the posterior from N(0, I) (summed over z's dims, averaged over the batch).
- Serving: z = 0, the prior's mean, so the chunk is a deterministic function of the observation.

eps is an argument, never drawn here (as flow_head.py's noise): the trainer draws it from its CPU
generator, or on the GPU inside the CUDA graph. The layers' dropout draws from torch's default
generator of the device: on the CPU the one train.py seeds (torch.manual_seed), on CUDA the one
the graph registers at capture and that GraphedStep seeds after it, as the step's row draws are,
so the captured step replays fresh, seeded masks. No host sync, no data-dependent Python branch
(self.training is a module flag, fixed per compiled graph); the nested-tensor fast path, which
inspects the padding mask on the host, is switched off."""

import torch
from torch import nn


def transformer_encoder(width, heads, feedforward, dropout, layers):
    layer = nn.TransformerEncoderLayer(width, heads, feedforward, dropout, batch_first=True)
    return nn.TransformerEncoder(layer, layers, enable_nested_tensor=False)


def learned_positions(count, width):
    return nn.Parameter(torch.randn(1, count, width) * 0.02)


class ActHead(nn.Module):
    def __init__(self, map_channels, image_tokens, state_features, history_frames, chunk_size, action_dim,
                 d_model=256, heads=8, encoder_layers=4, decoder_layers=1, vae_layers=4, feedforward=1024,
                 dropout=0.1, latent_dim=32):
        """map_channels: channels of the cameras' feature maps; image_tokens: their positions over all
        cameras and history frames; state_features: width of the policy's state features."""
        super().__init__()
        self.chunk_size, self.latent_dim = chunk_size, latent_dim
        # The CVAE's encoder: [CLS, state, rows] -> (mu, log sigma^2).
        self.cls = learned_positions(1, d_model)
        self.vae_state = nn.Linear(state_features, d_model)
        self.vae_action = nn.Linear(action_dim, d_model)
        self.vae_positions = learned_positions(2 + chunk_size, d_model)
        self.vae_encoder = transformer_encoder(d_model, heads, feedforward, dropout, vae_layers)
        self.posterior = nn.Linear(d_model, 2 * latent_dim)
        # The decoder: [z, states, image positions] -> memory; chunk_size queries -> rows.
        self.latent = nn.Linear(latent_dim, d_model)
        self.state = nn.Linear(state_features, d_model)
        self.image = nn.Linear(map_channels, d_model)
        self.memory_positions = learned_positions(1 + history_frames + image_tokens, d_model)
        self.encoder = transformer_encoder(d_model, heads, feedforward, dropout, encoder_layers)
        decoder_layer = nn.TransformerDecoderLayer(d_model, heads, feedforward, dropout, batch_first=True)
        self.decoder = nn.TransformerDecoder(decoder_layer, decoder_layers, norm=nn.LayerNorm(d_model))
        self.queries = learned_positions(chunk_size, d_model)
        self.rows = nn.Linear(d_model, action_dim)

    def encode_posterior(self, states, target, valid):
        """(mu, log sigma^2), each (B, latent_dim) float, of z given the newest state's features and the
        target chunk (B, chunk, A) whose rows `valid` (B, chunk) marks."""
        batch = target.shape[0]
        tokens = torch.cat([self.cls.expand(batch, -1, -1), self.vae_state(states[:, -1:]),
                            self.vae_action(target.to(states.dtype))], dim=1) + self.vae_positions
        ignored = torch.cat([torch.zeros((batch, 2), dtype=torch.bool, device=valid.device), ~valid], dim=1)
        summary = self.vae_encoder(tokens, src_key_padding_mask=ignored)[:, 0]
        mu, log_variance = self.posterior(summary).float().chunk(2, dim=-1)
        return mu, log_variance

    def decode(self, image_tokens, states, z):
        """The normalised chunk (B, chunk, A) from the image tokens (B, N, map_channels), the states'
        features (B, T, state_features) and z (B, latent_dim)."""
        memory = torch.cat([self.latent(z.to(states.dtype)).unsqueeze(1), self.state(states),
                            self.image(image_tokens)], dim=1) + self.memory_positions
        memory = self.encoder(memory)
        queries = self.queries.expand(memory.shape[0], -1, -1)
        return self.rows(self.decoder(queries, memory)).float()

    def chunk_and_kl(self, image_tokens, states, target, valid, eps):
        """Training: the chunk decoded with z drawn from the posterior by eps (B, latent_dim), and the
        posterior's KL divergence from N(0, I); the policy's loss is L1 + kl_weight x KL. In eval mode
        (the trainer's validation) the served chunk, z = 0, and a KL of 0: validation_l1 is then the
        served prediction's L1."""
        if not self.training:
            return self.sample(image_tokens, states), 0.0
        mu, log_variance = self.encode_posterior(states, target, valid)
        z = mu + torch.exp(0.5 * log_variance) * eps.float()
        kl = (-0.5 * (1 + log_variance - mu.pow(2) - log_variance.exp())).sum(-1).mean()
        return self.decode(image_tokens, states, z), kl

    def sample(self, image_tokens, states):
        """The served chunk: the decoder at z = 0."""
        z = torch.zeros((states.shape[0], self.latent_dim), device=states.device)
        return self.decode(image_tokens, states, z)
