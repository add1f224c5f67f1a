"""Observations -> the batch a LeRobot policy reads: arrays stacked over envs (and over the
observation history when it is longer than one), images HWC uint8 -> float CHW in [0, 1], on the
chosen device as torch tensors, or as numpy arrays (float32) without torch. torch is imported only
when asked for: it takes seconds to import, which the stand-ins need not wait."""

import numpy as np


def import_torch():
    """torch, or None when it is not installed."""
    try:
        import torch
    except ImportError:
        return None
    return torch

IMAGE_PREFIX = "observation.images."


def is_image(key, array):
    return key.startswith(IMAGE_PREFIX) and array.dtype == np.uint8 and array.shape[-1:] == (3,)


def stack_histories(histories, keys_of):
    """histories: per env a sequence of observation-array dicts (oldest first), all of one length n.
    Returns {key: (B, n, ...)} or {key: (B, ...)} when n == 1, as LeRobot batches are shaped.
    keys_of names the request for errors when envs disagree on keys or shapes."""
    keys = sorted(histories[0][-1])
    stacked = {}
    for key in keys:
        frames = []
        for env, history in enumerate(histories):
            if sorted(history[-1]) != keys:
                raise ValueError(f"{keys_of(env)} has keys {sorted(history[-1])}, another env {keys}")
            frames.append(np.stack([observation[key] for observation in history]))
        shapes = {frame.shape for frame in frames}
        if len(shapes) != 1:
            raise ValueError(f"{key}: envs of one batch differ in shape {sorted(shapes)}")
        array = np.stack(frames)
        stacked[key] = array[:, 0] if array.shape[1] == 1 else array
    return stacked


def request_ids(observations):
    """The ids of the newest request of each env, (B,) int64 under the requests' own names
    (env_index, episode_index, step): a policy that draws noise keys it on them, so that a served
    episode repeats run after run. Policies that read only their own keys never see them."""
    return {key: np.array([getattr(observation, key) for observation in observations], dtype=np.int64)
            for key in ("env_index", "episode_index", "step")}


def to_policy_batch(stacked, tasks, device, torch=None):
    """The policy's input: images float CHW in [0, 1], other arrays as sent, "task" the list of
    prompts (LeRobot's language key). torch None: numpy arrays; device is then ignored."""
    batch = {}
    for key, array in stacked.items():
        if torch is None:
            batch[key] = (np.moveaxis(array, -1, -3).astype(np.float32) / 255.0 if is_image(key, array)
                          else array)
            continue
        tensor = torch.from_numpy(np.ascontiguousarray(array)).to(device)
        if is_image(key, array):  # convert on the device: the uint8 copy is 4x smaller
            tensor = tensor.movedim(-1, -3).float().div_(255.0).contiguous()
        batch[key] = tensor
    batch["task"] = list(tasks)
    return batch


def to_numpy(actions):
    if hasattr(actions, "detach"):  # a torch tensor, on any device
        return actions.detach().float().cpu().numpy()
    return np.asarray(actions, dtype=np.float32)
