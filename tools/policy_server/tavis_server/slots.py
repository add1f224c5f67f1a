"""Env slots: the key of all per-episode state, (connection, env_index). Each client numbers its
envs from 0 (a sweep's cells run side by side, each on its own connection), so a key by
env_index alone would mix the episodes of different cells. A connection's entries are dropped
when it closes, which bounds the server's memory by the envs of the connections open now."""


def drop_connection(table, connection):
    """Deletes every entry of `connection` from `table`, a dict keyed by slot."""
    for slot in [slot for slot in table if slot[0] == connection]:
        del table[slot]
