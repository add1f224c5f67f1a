"""Stand-in policies for tests and benchmarks: no model, replies that are valid tavis actions.

echo     (served directly) encodes what it received into each action, so a test can read back which
         env, episode and step an action answers: per chunk row t,
           a[0], a[1], a[2] = env_index, episode_index, step       times 1e-3 (decode: round(a * 1000))
           a[7]  = (crc32 of observation.state's bytes as sent) % 10000 * 1e-3
           a[8]  = (sum of every uint8 array's bytes) % 10000 * 1e-3
           a[9]  = (UTF-8 length of the task/prompt) * 1e-3
           a[14] = t * 1e-3 (the row), a[15] = 1.0 if is_first else 0.0, a[16] = 0
           quaternions a[3:7] = a[10:14] = (1, 0, 0, 0), grippers a[17] = a[18] = -1 (open).
         Ids must be below 10000 (a 10 m arm target).
sleep    sleeps sleep_ms per forward pass whatever the batch size and answers a fixed row
         (NEUTRAL_ACTION or a CSV row) repeated `chunk` times. Served directly it costs nothing but
         the sleep; it also has LeRobot's interface, so that LeRobotServedPolicy can serve it like a
         checkpoint, input tensors built on a device included (the CLI does so under --device).
stateful (served directly) records per (connection, env, episode) the steps and is_first flags it
         received, answers them in each reply ("received") and rewrites a JSON file after every
         request. Its record is its output, so unlike a policy's state it is kept after a
         connection closes.

Their arrays come through the server's decoder (msgpack_numpy.py), which admits only numeric and
bool arrays whose bytes fill their shape, so a stand-in reads nothing a policy could not."""

import json
import os
import time
import zlib

import numpy as np

from .actions import NEUTRAL_ACTION

ECHO_SCALE = 1e-3
ECHO_ID_LIMIT = 10000


def _uint8_sum(arrays):
    return sum(int(array.sum(dtype=np.uint64)) for array in arrays.values() if array.dtype == np.uint8)


class EchoPolicy:
    def __init__(self, chunk=1):
        if chunk < 1:
            raise ValueError(f"echo: --chunk {chunk} must be at least 1")
        self.chunk = chunk
        self.name = "echo"
        self.history_length = 1
        self.metadata = {"action_horizon": chunk}

    def infer(self, observations, starts):
        return np.stack([self._echo(observation) for observation in observations])

    def _echo(self, observation):
        ids = {"env_index": observation.env_index, "episode_index": observation.episode_index, "step": observation.step}
        for key, value in ids.items():
            if not 0 <= value < ECHO_ID_LIMIT:
                raise ValueError(f"echo: {key} {value} is outside [0, {ECHO_ID_LIMIT}), beyond what an action can carry")
        state = observation.arrays.get("observation.state")
        state_crc = zlib.crc32(np.ascontiguousarray(state).tobytes()) if state is not None else 0
        row = NEUTRAL_ACTION.astype(np.float64)
        row[0:3] = [ids["env_index"], ids["episode_index"], ids["step"]]
        row[7:10] = [state_crc % 10000, _uint8_sum(observation.arrays) % 10000, len(observation.task.encode("utf-8"))]
        row[0:3] *= ECHO_SCALE
        row[7:10] *= ECHO_SCALE
        row[15] = 1.0 if observation.is_first else 0.0
        chunk = np.tile(row, (self.chunk, 1))
        chunk[:, 14] = np.arange(self.chunk) * ECHO_SCALE
        return chunk.astype(np.float32)

    def close(self):
        pass


class SleepPolicyConfig:
    def __init__(self, chunk):
        self.n_obs_steps = 1
        self.n_action_steps = chunk


class SleepPolicy:
    """One forward pass costs sleep_ms whatever the batch size. Both a served policy (infer) and a
    LeRobot-interface policy (reset, select_action, predict_action_chunk, config)."""

    def __init__(self, sleep_ms=30.0, chunk=10, action_row=NEUTRAL_ACTION):
        if sleep_ms < 0 or chunk < 1:
            raise ValueError(f"sleep: --sleep-ms {sleep_ms} must be >= 0 and --chunk {chunk} >= 1")
        self.name = "sleep"
        self.history_length = 1
        self.sleep_ms = sleep_ms
        self.config = SleepPolicyConfig(chunk)
        self.row = np.asarray(action_row, dtype=np.float32)
        self.metadata = {"sleep_ms": sleep_ms, "action_horizon": chunk}

    def _forward(self, batch_size):
        time.sleep(self.sleep_ms / 1000.0)
        return np.tile(self.row, (batch_size, self.config.n_action_steps, 1))

    def infer(self, observations, starts):
        return self._forward(len(observations))

    def close(self):
        pass

    def reset(self):
        pass

    def predict_action_chunk(self, batch):
        return self._forward(len(batch["task"]))

    def select_action(self, batch):
        return self.predict_action_chunk(batch)[:, 0]


class StatefulCheckPolicy:
    def __init__(self, chunk=1, history=1, record_path=None, action_row=NEUTRAL_ACTION):
        if chunk < 1 or history < 1:
            raise ValueError(f"stateful: --chunk {chunk} and --history {history} must be at least 1")
        self.name = "stateful"
        self.chunk = chunk
        self.history_length = history  # > 1: the server demands consecutive steps
        self.record_path = record_path
        self.row = np.asarray(action_row, dtype=np.float32)
        self.metadata = {"action_horizon": chunk, "history": history}
        self.episodes = {}  # (connection, env_index, episode_index) -> {"steps": [...], "is_first": [...]}
        self.requests = []  # per request: the env indices it held, in order
        self.layouts = []  # every distinct {key: {"shape", "dtype"}} of one env's arrays received

    def infer(self, observations, starts):
        self.requests.append([observation.env_index for observation in observations])
        for observation in observations:
            layout = {key: {"shape": list(value.shape), "dtype": value.dtype.str}
                      for key, value in sorted(observation.arrays.items())}
            if layout not in self.layouts:
                self.layouts.append(layout)
            record = self.episodes.setdefault(self._key(observation), {"steps": [], "is_first": []})
            record["steps"].append(observation.step)
            record["is_first"].append(observation.is_first)
        if self.record_path:
            self._write()
        return np.tile(self.row, (len(observations), self.chunk, 1))

    @staticmethod
    def _key(observation):
        return (observation.connection, observation.env_index, observation.episode_index)

    def received(self, observation):
        record = self.episodes[self._key(observation)]
        return {"connection": observation.connection, "env_index": observation.env_index,
                "episode_index": observation.episode_index, **record}

    def report(self):
        return {"episodes": [{"connection": connection, "env_index": env, "episode_index": episode, **record}
                             for (connection, env, episode), record in sorted(self.episodes.items())],
                "requests": self.requests, "layouts": self.layouts}

    def _write(self):
        temporary = f"{self.record_path}.tmp"
        with open(temporary, "w") as out:
            json.dump(self.report(), out)
        os.replace(temporary, self.record_path)

    def close(self):
        if self.record_path:
            self._write()

    def reply_extras(self, observations, batched):
        received = [self.received(observation) for observation in observations]
        return {"received": received if batched else received[0]}
