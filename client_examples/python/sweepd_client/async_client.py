"""AsyncClient: Client under asyncio — the same constructor arguments and requests
(exchanges.py), with the same results and exceptions, each awaited, over asyncio streams.

    async with AsyncClient("127.0.0.1", 7878, token="SECRET") as sweepd:
        body = await sweepd.load("mannequin")
        posed = await sweepd.pose(body, rotations)
        async for posed in sweepd.poses(body, many_rotations):   # pipelined, in order
            ...

One connection carries one request at a time: await each before the next on the same client
(open more clients for concurrency). Without `async with`, `await client.connect()` first and
`await client.close()` at the end.
"""

import functools

from .async_connection import AsyncConnection
from .errors import ConnectionLost, SweepdError
from .exchanges import Exchanges, Posed, Receive, Run, reply_body, with_requests


def _request(exchange):
    """An exchange as a coroutine method that runs it and returns its result."""
    @functools.wraps(exchange)
    async def request(self, *args, **kwargs):
        run = Run(exchange(self, *args, **kwargs))
        async for _ in self._drive(run):
            pass  # a request yields nothing for the caller
        return run.result
    return request


@with_requests(_request)
class AsyncClient(Exchanges):
    # asyncio's streams read with recv, which drops the SCM_RIGHTS of map_shared_memory.
    receives_descriptors = False

    def __init__(self, *args, **options):
        """As Client's; nothing is connected until connect() (or `async with`)."""
        super().__init__(*args, **options)
        self._connection = None

    async def connect(self):
        """Connects and says Hello; returns the client."""
        self._connection = await AsyncConnection.open(*self._endpoint)
        try:
            await _request(Exchanges._hello)(self, self._connection)
        except BaseException:
            await self._connection.close()
            self._connection = None
            raise
        return self

    async def __aenter__(self):
        return await self.connect()

    async def __aexit__(self, *exception):
        await self.close()

    async def close(self, reason="done"):
        """Bye, then the connection is closed. Safe to call twice."""
        if self._connection is None:
            return
        try:
            await self._connection.send(self._bye(reason))
        except ConnectionLost:
            pass  # already gone: nothing to say goodbye to
        await self._connection.close()
        self._connection = None

    async def _drive(self, run):
        """Client._drive, each step awaited."""
        step = run.step()
        while step is not None:
            if isinstance(step, Posed):
                yield step
                step = run.step()
                continue
            try:
                reply = await self._perform(step)
            except SweepdError as error:
                step = run.step(error=error)
            else:
                step = run.step(reply)

    async def _perform(self, step):
        if self._connection is None:
            raise SweepdError("the client is closed")
        if isinstance(step, Receive):
            message = await self._connection.receive()
            return reply_body(message, step.table, self._connection.address)
        await self._connection.send(step.frame)
        return None
