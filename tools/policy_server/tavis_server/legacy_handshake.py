"""A time limit on the opening handshake for the legacy server of Debian's websockets 10.4, which
has none (websockets >= 13's asyncio server takes open_timeout): without it, a peer that connects
and never sends its HTTP request holds its socket and handler task forever."""

import asyncio
import functools

from websockets.exceptions import InvalidMessage
from websockets.legacy.server import WebSocketServerProtocol


class TimedHandshakeProtocol(WebSocketServerProtocol):
    def __init__(self, *args, handshake_timeout_s, **kwargs):
        super().__init__(*args, **kwargs)
        self._handshake_timeout_s = handshake_timeout_s

    async def handshake(self, *args, **kwargs):
        try:
            return await asyncio.wait_for(super().handshake(*args, **kwargs), self._handshake_timeout_s)
        except asyncio.TimeoutError:
            # An InvalidHandshake: the server answers 400 and closes, without logging an error.
            raise InvalidMessage(f"no opening handshake within {self._handshake_timeout_s} s") from None


def timed_handshake_protocol(handshake_timeout_s):
    """The create_protocol argument of websockets.serve."""
    return functools.partial(TimedHandshakeProtocol, handshake_timeout_s=handshake_timeout_s)
