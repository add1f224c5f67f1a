"""A TAVIS-C++ LeRobot v3.0 dataset (as `tavis demos` writes it) held entirely in memory.

No LeRobot: the Parquet is read by tavis_baseline.parquet, the videos by tavis_baseline.video.
Every frame of the chosen cameras is decoded once into a uint8 tensor (N, 3, H, W) at the
training resolution, so a training step gathers a batch by indexing (on the GPU when the tensors
are moved there) instead of seeking in videos. Windows follow LeRobot's delta_timestamps rules
(tavis_baseline.windows).

    data = DemoDataset("datasets/x", ["observation.images.OBS_HEAD", ...], image_size=(96, 96))
    batch = data.sample(torch.tensor([0, 5]), obs_offsets=[-10, 0], action_offsets=range(1, 21))
"""

import json
import os
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import torch

from . import video
from .parquet import ParquetFile
from .windows import window_indices

STATE = "observation.state"
ACTION = "action"


def _sorted_parquet(folder):
    files = sorted(folder.glob("*/*.parquet"))
    if not files:
        raise ValueError(f"{folder} holds no */*.parquet files")
    return files


class DemoDataset:
    def __init__(self, root, camera_keys, image_size=None, episodes=None, decode_threads=None, video_backend=None):
        """root: the dataset folder; camera_keys: the video features to load, e.g.
        "observation.images.OBS_HEAD"; image_size: (height, width) to decode to (None: as stored);
        episodes: the episode indices to keep (None: all); video_backend: "pyav", "opencv" or None
        (PyAV if importable, else OpenCV)."""
        self.root = Path(root)
        info_path = self.root / "meta" / "info.json"
        if not info_path.is_file():
            raise ValueError(f"{root} is not a finished LeRobot dataset: {info_path} is missing")
        self.info = json.loads(info_path.read_text())
        if self.info.get("codebase_version") != "v3.0":
            raise ValueError(f"{root}: codebase_version {self.info.get('codebase_version')!r}, this loader reads v3.0")
        self.fps = int(self.info["fps"])
        self.stats = json.loads((self.root / "meta" / "stats.json").read_text())
        features = self.info["features"]
        for key in camera_keys:
            if features.get(key, {}).get("dtype") != "video":
                videos = [name for name, f in features.items() if f.get("dtype") == "video"]
                raise ValueError(f"{root} has no video feature {key!r} (it has {', '.join(videos)})")
        self.camera_keys = list(camera_keys)
        stored = features[camera_keys[0]]["shape"][:2] if camera_keys else [0, 0]
        self.image_size = tuple(image_size) if image_size else tuple(stored)

        self._read_rows(features)
        self._read_episodes(episodes)
        self.images = self._decode_videos(decode_threads, video_backend)

    # -- Parquet ---------------------------------------------------------------------------------
    def _read_rows(self, features):
        columns = {STATE: [], ACTION: [], "episode_index": [], "frame_index": [], "index": []}
        for path in _sorted_parquet(self.root / "data"):
            table = ParquetFile(path)
            for name in columns:
                width = features[name]["shape"][0] if name in (STATE, ACTION) else None
                columns[name].append(table.column(name, width))
        self.state = np.concatenate(columns[STATE]).astype(np.float32)
        self.action = np.concatenate(columns[ACTION]).astype(np.float32)
        self.row_episode = np.concatenate(columns["episode_index"])
        self.frame_index = np.concatenate(columns["frame_index"])
        index = np.concatenate(columns["index"])
        if not np.array_equal(index, np.arange(index.size)):
            raise ValueError(f"{self.root}: the data files' `index` column is not 0..{index.size - 1} in file order")

    def _read_episodes(self, keep):
        names = ["episode_index", "dataset_from_index", "dataset_to_index"]
        for key in self.camera_keys:
            names += [f"videos/{key}/chunk_index", f"videos/{key}/file_index", f"videos/{key}/from_timestamp"]
        parts = {name: [] for name in names}
        for path in _sorted_parquet(self.root / "meta" / "episodes"):
            table = ParquetFile(path)
            for name in names:
                parts[name].append(table.column(name))
        table = {name: np.concatenate(values) for name, values in parts.items()}
        everything = table["episode_index"]
        if not np.array_equal(everything, np.arange(everything.size)):
            raise ValueError(f"{self.root}: meta/episodes rows are not episodes 0..{everything.size - 1} in order")
        chosen = everything if keep is None else np.asarray(sorted(set(int(e) for e in keep)), np.int64)
        unknown = [int(e) for e in chosen if e < 0 or e >= everything.size]
        if unknown:
            raise ValueError(f"{self.root} has episodes 0..{everything.size - 1}; asked for {unknown}")
        self.episodes = chosen
        self._episode_table = table
        # The kept episodes' rows, renumbered 0..N-1 (row r of this dataset = source row source_rows[r]).
        starts = table["dataset_from_index"][chosen]
        ends = table["dataset_to_index"][chosen]
        self.source_rows = np.concatenate([np.arange(a, b) for a, b in zip(starts, ends)]) if chosen.size else np.zeros(0, np.int64)
        lengths = ends - starts
        new_starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
        self.episode_start = np.repeat(new_starts, lengths)
        self.episode_end = np.repeat(new_starts + lengths, lengths)
        self.state = self.state[self.source_rows]
        self.action = self.action[self.source_rows]
        if not np.array_equal(self.row_episode[self.source_rows], np.repeat(chosen, lengths)):
            raise ValueError(f"{self.root}: episode_index of the data rows disagrees with meta/episodes")
        self.row_episode = self.row_episode[self.source_rows]
        self.frame_index = self.frame_index[self.source_rows]

    # -- video -----------------------------------------------------------------------------------
    def _decode_videos(self, threads, backend):
        table = self._episode_table
        height, width = self.image_size
        rows = len(self.source_rows)
        jobs = []
        images = {}
        for key in self.camera_keys:
            out = np.zeros((rows, height, width, 3), np.uint8)
            images[key] = out
            files = {}
            position = 0
            for episode in self.episodes:
                start = int(table["dataset_from_index"][episode])
                length = int(table["dataset_to_index"][episode]) - start
                file_key = (int(table[f"videos/{key}/chunk_index"][episode]), int(table[f"videos/{key}/file_index"][episode]))
                first = int(round(float(table[f"videos/{key}/from_timestamp"][episode]) * self.fps))
                files.setdefault(file_key, []).append((first, length, position))
                position += length
            for (chunk, file), spans in files.items():
                path = self.root / self.info["video_path"].format(video_key=key, chunk_index=chunk, file_index=file)
                frame_rows = np.full(max(first + length for first, length, _ in spans), -1, np.int64)
                for first, length, position in spans:
                    frame_rows[first:first + length] = np.arange(position, position + length)
                jobs.append((path, frame_rows, out))
        with ThreadPoolExecutor(max_workers=threads or min(len(jobs), os.cpu_count() or 1) or 1) as pool:
            list(pool.map(lambda job: video.decode_into(job[0], self.fps, job[1], job[2], backend), jobs))
        return {key: torch.from_numpy(frames).permute(0, 3, 1, 2).contiguous() for key, frames in images.items()}

    # -- windows ---------------------------------------------------------------------------------
    def __len__(self):
        return len(self.source_rows)

    def to(self, device):
        """Moves the frames and per-row tables to `device` (the GPU: batches are gathered there)."""
        self.images = {key: frames.to(device) for key, frames in self.images.items()}
        self._tensors(device)
        return self

    def _tensors(self, device=None):
        if getattr(self, "_state_t", None) is None or device is not None:
            device = device or "cpu"
            self._state_t = torch.from_numpy(self.state).to(device)
            self._action_t = torch.from_numpy(self.action).to(device)
            self._start_t = torch.from_numpy(self.episode_start).to(device)
            self._end_t = torch.from_numpy(self.episode_end).to(device)

    def sample(self, rows, obs_offsets, action_offsets):
        """The LeRobot-style item of each row in `rows` (int64 tensor (B,)), stacked:
        images uint8 (B, n_obs, 3, H, W) per camera key, observation.state (B, n_obs, D),
        action (B, chunk, A), and observation.state_is_pad / <camera>_is_pad / action_is_pad."""
        self._tensors()
        rows = rows.to(self._start_t.device)
        start, end = self._start_t[rows], self._end_t[rows]
        obs, obs_pad = window_indices(rows, start, end, list(obs_offsets))
        act, act_pad = window_indices(rows, start, end, list(action_offsets))
        batch = {STATE: self._state_t[obs], f"{STATE}_is_pad": obs_pad,
                 ACTION: self._action_t[act], f"{ACTION}_is_pad": act_pad}
        for key, frames in self.images.items():
            batch[key] = frames[obs]
            batch[f"{key}_is_pad"] = obs_pad
        return batch
