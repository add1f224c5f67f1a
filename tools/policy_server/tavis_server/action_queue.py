"""The server-side action queue of each env slot (a connection's env: observation.slot), as LeRobot's select_action keeps one: a forward
pass answers an env's chunk of n_action_steps rows, row k is the action of the step k steps after
the pass, and the env gets no new pass until its chunk is used up (or a new episode starts).

Rows are looked up by step rather than popped, so looking one up changes nothing: a request that
fails later (another env's forward pass raises) leaves every queue as it was."""


from .slots import drop_connection


class ActionQueues:
    def __init__(self):
        self._chunks = {}  # (connection, env_index) -> (episode_index, step of the pass, rows (n, 19))

    def queued_action(self, observation, start):
        """The queued row for this observation's step, or None when the env needs a forward pass:
        a new episode (start), no chunk yet, or a chunk used up. The caller (EpisodeTracker) has
        made sure steps are consecutive within an episode."""
        chunk = self._chunks.get(observation.slot)
        if start or chunk is None:
            return None
        episode, first_step, rows = chunk
        if episode != observation.episode_index:
            return None
        offset = observation.step - first_step
        return rows[offset] if 0 <= offset < len(rows) else None

    def fill(self, observation, rows):
        """Queues the chunk a forward pass answered at this observation's step (rows[0] is its action)."""
        self._chunks[observation.slot] = (observation.episode_index, observation.step, rows)

    def forget(self, connection):
        """Drops the chunks of a closed connection's env slots."""
        drop_connection(self._chunks, connection)
