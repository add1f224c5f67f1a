"""Random-shift augmentation (DrQ): pad each image by `pad` pixels (edge replicated) and crop it
back at a random offset. One offset per sample and camera, the same for all its history steps, so
the history still shows motion rather than jitter. Runs on whatever device the images are on.

Two ways to draw the offsets, the same distribution (uniform in 0..2*pad, dy then dx):
random_shift draws them on the CPU from a torch.Generator (a seed gives the same offsets on every
device: the eager trainer's path), random_shift_on_device draws them where the images are, from
that device's default generator, with no host round trip (the CUDA-graph step).

Random crop (LeRobot's diffusion policy, Diffusion Policy's crop randomizer): a window of `size`
at a random place in training (random_crop, drawn either way; one place per sample and camera, the
same for its history steps), the centre window when served or validated (center_crop). A crop as
large as the image draws nothing and changes nothing."""

import torch
import torch.nn.functional as F


def random_shift(images, pad, generator):
    """images: (B, T, C, H, W) float; generator: a CPU torch.Generator."""
    if pad <= 0:
        return images
    dy, dx = draw_offsets(images, 2 * pad + 1, 2 * pad + 1, generator)
    return shift_by(images, pad, dy, dx)


def random_shift_on_device(images, pad):
    """random_shift with the offsets drawn on the images' device (capturable in a CUDA graph)."""
    if pad <= 0:
        return images
    dy, dx = draw_offsets(images, 2 * pad + 1, 2 * pad + 1)
    return shift_by(images, pad, dy, dx)


def draw_offsets(images, rows, cols, generator=None):
    """One (dy, dx) per sample of images (B, ...), dy uniform in 0..rows-1 and dx in 0..cols-1 (dy
    drawn first), as (B,) tensors on the images' device: from the CPU `generator`, or with None on
    the images' device from its default generator."""
    batch = images.shape[0]
    if generator is None:
        return (torch.randint(0, rows, (batch,), device=images.device),
                torch.randint(0, cols, (batch,), device=images.device))
    return (torch.randint(0, rows, (batch,), generator=generator).to(images.device),
            torch.randint(0, cols, (batch,), generator=generator).to(images.device))


def random_crop(images, size, generator=None):
    """images (B, T, C, H, W) cropped to size (height, width) at a random place per sample (the same
    for its T steps); generator: a CPU torch.Generator, or None to draw on the images' device
    (capturable in a CUDA graph)."""
    height, width = size
    if tuple(images.shape[-2:]) == (height, width):
        return images
    dy, dx = draw_offsets(images, images.shape[-2] - height + 1, images.shape[-1] - width + 1, generator)
    return crop_at(images, dy, dx, size)


def center_crop(images, size):
    """images (..., H, W) cut to their centre window of size (height, width) (torchvision's
    CenterCrop's rounding); unchanged when size is theirs."""
    height, width = size
    top = int(round((images.shape[-2] - height) / 2.0))
    left = int(round((images.shape[-1] - width) / 2.0))
    return images[..., top:top + height, left:left + width]


def crop_at(images, dy, dx, size):
    """images (B, T, C, H, W) cropped to size (height, width) at (dy, dx) (each (B,))."""
    batch, steps, channels = images.shape[:3]
    height, width = size
    return windows(images.flatten(1, 2), dy, dx, height, width).reshape(batch, steps, channels, height, width)


def shift_by(images, pad, dy, dx):
    """images (B, T, C, H, W) cropped at (dy, dx) (each (B,), on the images' device) of the
    replicate-padded images: dy = dx = pad is no shift."""
    batch, steps, channels, height, width = images.shape
    padded = F.pad(images.flatten(1, 2), (pad, pad, pad, pad), mode="replicate")
    return windows(padded, dy, dx, height, width).reshape(batch, steps, channels, height, width)


def windows(flat, dy, dx, height, width):
    """flat (B, K, H', W'): per sample b its window of height x width at (dy[b], dx[b]), (B, K,
    height, width), gathered by index tensors (no per-sample Python loop, no host sync)."""
    batch = flat.shape[0]
    rows = (dy[:, None] + torch.arange(height, device=flat.device))[:, :, None]  # (B, H, 1)
    cols = (dx[:, None] + torch.arange(width, device=flat.device))[:, None, :]   # (B, 1, W)
    samples = torch.arange(batch, device=flat.device)[:, None, None]
    cropped = flat.permute(0, 2, 3, 1)[samples, rows, cols]                      # (B, H, W, K)
    return cropped.permute(0, 3, 1, 2)
