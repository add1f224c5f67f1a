"""Which episode each env slot (connection, env_index) is in and which step it asked last: the
server's check that requests arrive as the protocol promises, before any policy state is touched."""

from .slots import drop_connection


class EpisodeTracker:
    """Per env slot: (episode_index, last step). `consecutive_steps` demands step == previous + 1
    (an observation history and a server-side action queue need every step: a skip means the
    client executed rows the server did not plan for, an error rather than a silent replan);
    otherwise steps only have to grow, since a client executing H-step chunks asks every H steps."""

    def __init__(self, consecutive_steps):
        self.consecutive_steps = consecutive_steps
        self._slots = {}  # (connection, env_index) -> (episode_index, last step)

    def check(self, observations):
        """Raises ValueError naming env, episode and steps if any observation is out of order;
        returns, per observation, whether it starts a new episode. Records nothing on error."""
        starts = []
        for observation in observations:
            where = f"env {observation.env_index} episode {observation.episode_index} step {observation.step}"
            if observation.is_first != (observation.step == 0):
                raise ValueError(f"{where}: is_first={observation.is_first}, but is_first is true exactly at step 0")
            if observation.is_first:
                starts.append(True)
                continue
            current = self._slots.get(observation.slot)
            if current is None or current[0] != observation.episode_index:
                started = "no episode" if current is None else f"episode {current[0]}"
                raise ValueError(f"{where}: the episode's first observation (step 0, is_first) never came; "
                                 f"this env slot is in {started}")
            previous = current[1]
            if observation.step <= previous:
                raise ValueError(f"{where}: comes after step {previous}; steps must grow")
            if self.consecutive_steps and observation.step != previous + 1:
                raise ValueError(f"{where}: skips from step {previous}; this policy keeps an observation history or "
                                 f"an action queue, so every step must be asked (run the client with "
                                 f"--replan-steps 1, or serve a policy with n_obs_steps 1 and --action-queue off)")
            starts.append(False)
        for observation in observations:
            self._slots[observation.slot] = (observation.episode_index, observation.step)
        return starts

    def forget(self, connection):
        """Drops a closed connection's env slots."""
        drop_connection(self._slots, connection)
