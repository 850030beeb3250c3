"""AsyncConnection: one sweepd session over asyncio streams, TCP (plain or TLS) or a Unix
socket: Connection's counterpart for AsyncClient, with the same frames (connection.py) and the
same exceptions. Every receive waits at most `timeout` seconds (None: for ever).
"""

import asyncio
import socket

from .connection import frame_buffer, is_loopback, parse_frame, receiving, sending
from .errors import ConnectionLost, Timeout


class AsyncConnection:
    def __init__(self, address, reader, writer, tls, loopback, timeout):
        self.address, self.tls, self.loopback, self.timeout = address, tls, loopback, timeout
        self._reader, self._writer = reader, writer

    @classmethod
    async def open(cls, host, port, unix=None, tls=None, timeout=30.0):
        address = unix or f"{host}:{port}"
        try:
            if unix:
                opening = asyncio.open_unix_connection(unix)
            else:
                opening = asyncio.open_connection(host, int(port), ssl=tls,
                                                  server_hostname=host if tls else None)
            async with asyncio.timeout(timeout):
                reader, writer = await opening
        except TimeoutError as error:
            raise Timeout(f"cannot connect to {address}: no answer in {timeout} s") from error
        except OSError as error:
            raise ConnectionLost(f"cannot connect to {address}: "
                                 f"{error.strerror or error}") from error
        loopback = True
        if not unix:
            sock = writer.get_extra_info("socket")
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            loopback = is_loopback(sock)
        return cls(address, reader, writer, tls is not None and not unix, loopback, timeout)

    async def send(self, frame):
        with sending(self.address, self.timeout):
            self._writer.write(frame)
            async with asyncio.timeout(self.timeout):
                await self._writer.drain()

    async def receive(self):
        """The next Message (within one timeout, prefix and body together)."""
        try:
            with receiving(self.address, self.timeout):
                async with asyncio.timeout(self.timeout):  # no task per read, unlike wait_for
                    frame = frame_buffer(await self._reader.readexactly(4))
                    frame[4:] = await self._reader.readexactly(len(frame) - 4)
        except asyncio.IncompleteReadError as error:
            raise ConnectionLost(f"{self.address}: the server closed the connection") from error
        return parse_frame(frame, self.address)

    async def close(self):
        self._writer.close()
        try:
            await self._writer.wait_closed()
        except OSError:
            pass  # already broken: closed all the same
