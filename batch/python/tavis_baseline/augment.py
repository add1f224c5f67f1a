"""Random-shift augmentation (DrQ): pad each image by `pad` pixels (edge replicated) and crop it
back at a random offset. One offset per sample and camera, the same for all its history steps, so
the history still shows motion rather than jitter. Runs on whatever device the images are on.

Two ways to draw the offsets, the same distribution (uniform in 0..2*pad, dy then dx):
random_shift draws them on the CPU from a torch.Generator (a seed gives the same offsets on every
device: the eager trainer's path), random_shift_on_device draws them where the images are, from
that device's default generator, with no host round trip (the CUDA-graph step)."""

import torch
import torch.nn.functional as F


def random_shift(images, pad, generator):
    """images: (B, T, C, H, W) float; generator: a CPU torch.Generator."""
    if pad <= 0:
        return images
    batch = images.shape[0]
    dy = torch.randint(0, 2 * pad + 1, (batch,), generator=generator).to(images.device)
    dx = torch.randint(0, 2 * pad + 1, (batch,), generator=generator).to(images.device)
    return shift_by(images, pad, dy, dx)


def random_shift_on_device(images, pad):
    """random_shift with the offsets drawn on the images' device (capturable in a CUDA graph)."""
    if pad <= 0:
        return images
    batch = images.shape[0]
    dy = torch.randint(0, 2 * pad + 1, (batch,), device=images.device)
    dx = torch.randint(0, 2 * pad + 1, (batch,), device=images.device)
    return shift_by(images, pad, dy, dx)


def shift_by(images, pad, dy, dx):
    """images (B, T, C, H, W) cropped at (dy, dx) (each (B,), on the images' device) of the
    replicate-padded images: dy = dx = pad is no shift."""
    batch, steps, channels, height, width = images.shape
    padded = F.pad(images.flatten(1, 2), (pad, pad, pad, pad), mode="replicate")
    rows = (dy[:, None] + torch.arange(height, device=images.device))[:, :, None]  # (B, H, 1)
    cols = (dx[:, None] + torch.arange(width, device=images.device))[:, None, :]   # (B, 1, W)
    samples = torch.arange(batch, device=images.device)[:, None, None]
    cropped = padded.permute(0, 2, 3, 1)[samples, rows, cols]                         # (B, H, W, T*C)
    return cropped.permute(0, 3, 1, 2).reshape(batch, steps, channels, height, width)
