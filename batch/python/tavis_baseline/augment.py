"""Random-shift augmentation (DrQ): pad each image by `pad` pixels (edge replicated) and crop it
back at a random offset. One offset per sample and camera, the same for all its history steps, so
the history still shows motion rather than jitter. Runs on whatever device the images are on."""

import torch
import torch.nn.functional as F


def random_shift(images, pad, generator):
    """images: (B, T, C, H, W) float; generator: a CPU torch.Generator (the offsets are drawn on the
    CPU so a seed gives the same offsets on every device)."""
    if pad <= 0:
        return images
    batch, steps, channels, height, width = images.shape
    padded = F.pad(images.flatten(1, 2), (pad, pad, pad, pad), mode="replicate")
    dy = torch.randint(0, 2 * pad + 1, (batch,), generator=generator).to(images.device)
    dx = torch.randint(0, 2 * pad + 1, (batch,), generator=generator).to(images.device)
    rows = (dy[:, None] + torch.arange(height, device=images.device))[:, :, None]  # (B, H, 1)
    cols = (dx[:, None] + torch.arange(width, device=images.device))[:, None, :]   # (B, 1, W)
    samples = torch.arange(batch, device=images.device)[:, None, None]
    cropped = padded.permute(0, 2, 3, 1)[samples, rows, cols]                         # (B, H, W, T*C)
    return cropped.permute(0, 3, 1, 2).reshape(batch, steps, channels, height, width)
