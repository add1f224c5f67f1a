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


def _read_json(path, missing):
    """The JSON object in `path`; ValueError naming the file when it is missing or not one."""
    if not path.is_file():
        raise ValueError(missing)
    try:
        value = json.loads(path.read_text())
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise ValueError(f"{path} is not valid JSON: {error}") from None
    if not isinstance(value, dict):
        raise ValueError(f"{path} holds a JSON {type(value).__name__}, not an object")
    return value


def _entry(mapping, key, where, kind=None):
    """mapping[key]; ValueError naming `where` and the key when it is missing or not of `kind`."""
    if key not in mapping:
        raise ValueError(f"{where} has no {key!r}")
    value = mapping[key]
    if kind is not None and (not isinstance(value, kind) or isinstance(value, bool)):
        names = " or ".join(k.__name__ for k in (kind if isinstance(kind, tuple) else (kind,)))
        raise ValueError(f"{where}: {key!r} is {value!r}, not a {names}")
    return value


def _count(info, key, where):
    value = _entry(info, key, where, int)
    if value < 0:
        raise ValueError(f"{where}: {key!r} is {value}, a negative count")
    return value


def _vector_width(features, key, where):
    """The length of the 1-D feature `key` (observation.state, action) from info.json's features."""
    feature = _entry(features, key, f"{where} features", dict)
    shape = _entry(feature, "shape", f"{where} features[{key!r}]", list)
    if len(shape) != 1 or not isinstance(shape[0], int) or isinstance(shape[0], bool) or shape[0] < 1:
        raise ValueError(f"{where}: features[{key!r}] has shape {shape!r}, not [N] with N >= 1")
    return shape[0]


def video_file(root, template, where, **fields):
    """root / template.format(**fields); ValueError naming `where` (info.json) and the value when the
    template does not format, gives a path outside the dataset (absolute, or climbing out with
    '..'), or a file that does not exist."""
    try:
        relative = template.format(**fields)
    except (KeyError, IndexError, ValueError, AttributeError) as error:
        raise ValueError(f"{where}: video_path {template!r} does not format with the fields "
                         f"{', '.join(sorted(fields))}: {error!r}") from None
    if not relative or Path(relative).is_absolute() or ".." in Path(relative).parts:
        raise ValueError(f"{where}: video_path {template!r} gives {relative!r}, which is not a path inside the "
                         f"dataset {root} (absolute, or climbing out with '..')")
    path = root / relative
    if not path.is_file():
        raise ValueError(f"{where}: video_path {template!r} gives {path}, which does not exist")
    return path


class DemoDataset:
    def __init__(self, root, camera_keys, image_size=None, episodes=None, decode_threads=None, video_backend=None):
        """root: the dataset folder; camera_keys: the video features to load, e.g.
        "observation.images.OBS_HEAD"; image_size: (height, width) to decode to (None: as stored);
        episodes: the episode indices to keep (None: all); video_backend: "pyav", "opencv" or None
        (PyAV if importable, else OpenCV)."""
        self.root = Path(root)
        info_path = self.root / "meta" / "info.json"
        self._info_path = info_path
        self.info = _read_json(info_path, f"{root} is not a finished LeRobot dataset: {info_path} is missing")
        if self.info.get("codebase_version") != "v3.0":
            raise ValueError(f"{info_path}: codebase_version {self.info.get('codebase_version')!r}, this loader reads v3.0")
        fps = _entry(self.info, "fps", info_path, (int, float))
        if fps <= 0 or fps != int(fps):
            raise ValueError(f"{info_path}: 'fps' is {fps!r}, not a positive whole number")
        self.fps = int(fps)
        self.video_path = _entry(self.info, "video_path", info_path, str) if camera_keys else None
        self.stats_path = stats_path = self.root / "meta" / "stats.json"
        self.stats = _read_json(stats_path, f"{root}: {stats_path} is missing (the normalisation statistics)")
        features = _entry(self.info, "features", info_path, dict)
        for key in camera_keys:
            feature = features.get(key)
            if not isinstance(feature, dict) or feature.get("dtype") != "video":
                videos = [name for name, f in features.items() if isinstance(f, dict) and f.get("dtype") == "video"]
                raise ValueError(f"{info_path} has no video feature {key!r} (it has {', '.join(videos) or 'none'})")
            shape = feature.get("shape")
            if not (isinstance(shape, list) and len(shape) == 3 and all(isinstance(n, int) and n > 0 for n in shape)):
                raise ValueError(f"{info_path}: features[{key!r}] has shape {shape!r}, not [height, width, channels]")
        self.camera_keys = list(camera_keys)
        stored = features[camera_keys[0]]["shape"][:2] if camera_keys else [0, 0]
        self.image_size = tuple(image_size) if image_size else tuple(stored)

        self._read_rows(features)
        self._read_episodes(episodes)
        self._check_totals()
        self.images = self._decode_videos(decode_threads, video_backend)

    # -- Parquet ---------------------------------------------------------------------------------
    def _read_rows(self, features):
        columns = {STATE: [], ACTION: [], "episode_index": [], "frame_index": [], "index": []}
        widths = {name: _vector_width(features, name, self._info_path) for name in (STATE, ACTION)}
        for path in _sorted_parquet(self.root / "data"):
            table = ParquetFile(path)
            for name in columns:
                columns[name].append(table.column(name, widths.get(name)))
        self.state = np.concatenate(columns[STATE]).astype(np.float32)
        self.action = np.concatenate(columns[ACTION]).astype(np.float32)
        self.row_episode = np.concatenate(columns["episode_index"])
        self.frame_index = np.concatenate(columns["frame_index"])
        index = np.concatenate(columns["index"])
        self.total_rows = int(index.size)
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
        self.total_episodes = int(everything.size)
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

    def _check_totals(self):
        """info.json's totals against what the data files and meta/episodes hold."""
        for key, held, where in (("total_frames", self.total_rows, "the data files hold"),
                                 ("total_episodes", self.total_episodes, "meta/episodes holds")):
            said = _count(self.info, key, self._info_path)
            if said != held:
                raise ValueError(f"{self._info_path} says {key} {said}, but {where} {held}: the dataset is "
                                 f"incomplete or its files do not belong together")

    # -- video -----------------------------------------------------------------------------------
    def _decode_videos(self, threads, backend):
        table = self._episode_table
        height, width = self.image_size
        rows = len(self.source_rows)
        jobs = []
        images = {}
        for key in self.camera_keys:
            # Decoded straight into the (N, 3, H, W) tensor training gathers from, through a
            # channels-last view: no second full-size copy (2,000 episodes are ~28 GB a dataset).
            images[key] = torch.zeros((rows, 3, height, width), dtype=torch.uint8)
            out = images[key].permute(0, 2, 3, 1).numpy()
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
                path = video_file(self.root, self.video_path, self._info_path, video_key=key, chunk_index=chunk,
                                  file_index=file)
                frame_rows = np.full(max(first + length for first, length, _ in spans), -1, np.int64)
                for first, length, position in spans:
                    frame_rows[first:first + length] = np.arange(position, position + length)
                jobs.append((path, frame_rows, out))
        with ThreadPoolExecutor(max_workers=threads or min(len(jobs), os.cpu_count() or 1) or 1) as pool:
            list(pool.map(lambda job: video.decode_into(job[0], self.fps, job[1], job[2], backend), jobs))
        return images

    # -- windows ---------------------------------------------------------------------------------
    def __len__(self):
        return len(self.source_rows)

    def to(self, device):
        """Moves the frames and per-row tables to `device` (the GPU: batches are gathered there)."""
        for key in list(self.images):  # one camera at a time, each host copy freed once moved
            self.images[key] = self.images[key].to(device)
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
        action (B, chunk, A), and observation.state_is_pad / <camera>_is_pad / action_is_pad.
        obs_offsets, action_offsets: lists of ints, or int64 tensors on the rows' device."""
        self._tensors()
        rows = rows.to(self._start_t.device)
        start, end = self._start_t[rows], self._end_t[rows]
        # Offsets given as tensors on the rows' device are used as they are (no host copy: the
        # CUDA-graph step samples this way); lists and ranges are converted.
        obs, obs_pad = window_indices(rows, start, end, obs_offsets if torch.is_tensor(obs_offsets) else list(obs_offsets))
        act, act_pad = window_indices(rows, start, end,
                                      action_offsets if torch.is_tensor(action_offsets) else list(action_offsets))
        batch = {STATE: self._state_t[obs], f"{STATE}_is_pad": obs_pad,
                 ACTION: self._action_t[act], f"{ACTION}_is_pad": act_pad}
        for key, frames in self.images.items():
            batch[key] = frames[obs]
            batch[f"{key}_is_pad"] = obs_pad
        return batch
