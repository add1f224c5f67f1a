"""The ResNet-18 camera encoder of Diffusion Policy (as LeRobot's diffusion policy builds it with
use_group_norm and no pretrained weights), in plain torch so that it needs no torchvision.

ResNet-18's layout (7x7 stride-2 stem, 3x3 max pool, four stages of two BasicBlocks with `width`,
2x, 4x, 8x channels, stages 2-4 halving the resolution) with every BatchNorm replaced by GroupNorm
(channels // 16 groups, as Diffusion Policy's replace_bn_with_gn): a batch statistic would differ
between a training batch and one served env, and GroupNorm has none. The global average pool is
replaced by a spatial softmax: each of 32 keypoint maps (a 1x1 convolution) becomes a distribution
over the feature map whose expected (x, y) in [-1, 1] is kept, i.e. *where* things are, which a
manipulation policy needs and a global pool throws away. A linear layer (and a ReLU, as LeRobot's)
maps the 64 coordinates to the feature size the heads take.

Every shape is fixed at construction (the feature map's size is computed from the input size), and
forward has no data-dependent branch: the trainer's torch.compile + CUDA-graph step captures it."""

import torch
import torch.nn.functional as F
from torch import nn

KEYPOINTS = 32


def group_norm(channels):
    """Diffusion Policy's GroupNorm for `channels`: 16 channels a group (at least one group)."""
    return nn.GroupNorm(max(1, channels // 16), channels)


def halved(size):
    """A side after a stride-2 layer with 'same' padding (the stem, the pool, a stage): ceil(size / 2)."""
    return (size + 1) // 2


class BasicBlock(nn.Module):
    """ResNet's two 3x3 convolutions with a residual; a 1x1 convolution on the residual where the
    block changes the resolution or the channel count."""

    def __init__(self, inputs, channels, stride):
        super().__init__()
        self.conv1 = nn.Conv2d(inputs, channels, 3, stride=stride, padding=1, bias=False)
        self.norm1 = group_norm(channels)
        self.conv2 = nn.Conv2d(channels, channels, 3, padding=1, bias=False)
        self.norm2 = group_norm(channels)
        self.shortcut = nn.Identity()
        if stride != 1 or inputs != channels:
            self.shortcut = nn.Sequential(nn.Conv2d(inputs, channels, 1, stride=stride, bias=False), group_norm(channels))

    def forward(self, x):
        out = F.relu(self.norm1(self.conv1(x)))
        return F.relu(self.norm2(self.conv2(out)) + self.shortcut(x))


class SpatialSoftmax(nn.Module):
    """(B, C, H, W) -> (B, 2 * keypoints): per keypoint map the expected (x, y) under its softmax."""

    def __init__(self, channels, feature_size, keypoints=KEYPOINTS):
        super().__init__()
        self.keypoints = nn.Conv2d(channels, keypoints, 1)
        height, width = feature_size
        ys, xs = torch.meshgrid(torch.linspace(-1.0, 1.0, height), torch.linspace(-1.0, 1.0, width), indexing="ij")
        # Not saved with the weights: it is a function of the input size, which config.json holds.
        self.register_buffer("grid", torch.stack([xs.reshape(-1), ys.reshape(-1)], dim=-1), persistent=False)

    def forward(self, features):
        attention = F.softmax(self.keypoints(features).flatten(2), dim=-1)  # (B, K, H * W)
        return (attention @ self.grid.to(attention.dtype)).flatten(1)       # (B, K * 2): x, y per keypoint


class ResNet18Encoder(nn.Module):
    """images (N, 3, H, W) float in [0, 1], H x W = image_size -> (N, feature_dim)."""

    def __init__(self, width, image_size, feature_dim, keypoints=KEYPOINTS):
        super().__init__()
        self.stem = nn.Sequential(nn.Conv2d(3, width, 7, stride=2, padding=3, bias=False), group_norm(width), nn.ReLU(),
                                  nn.MaxPool2d(3, stride=2, padding=1))
        blocks, channels = [], width
        for stage in range(4):
            out = width * 2 ** stage
            blocks += [BasicBlock(channels, out, 1 if stage == 0 else 2), BasicBlock(out, out, 1)]
            channels = out
        self.blocks = nn.Sequential(*blocks)
        height, width_px = image_size
        for _ in range(5):  # the stem, the pool and stages 2-4 each halve the resolution
            height, width_px = halved(height), halved(width_px)
        self.pool = SpatialSoftmax(channels, (height, width_px), keypoints)
        self.project = nn.Sequential(nn.Linear(2 * keypoints, feature_dim), nn.ReLU())
        for module in self.modules():  # torchvision's ResNet initialisation
            if isinstance(module, nn.Conv2d):
                nn.init.kaiming_normal_(module.weight, mode="fan_out", nonlinearity="relu")

    def forward(self, images):
        return self.project(self.pool(self.blocks(self.stem(images - 0.5))))
