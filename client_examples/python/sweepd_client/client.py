"""Client: a blocking sweepd session with NumPy in and out.

    with Client("127.0.0.1", 7878, token="SECRET") as sweepd:
        body = sweepd.upload("body.glb")                  # or sweepd.load("mannequin")
        posed = sweepd.pose(body, rotations)              # rotations: (joints, 4) x, y, z, w
        posed.positions                                    # (vertices, 3) float32, metres
        compact = sweepd.pose(body, rotations, encoding="meshopt")  # about 1/3 of the bytes
        exr = sweepd.position_map(body, rotations, width=512, height=512)

The constructor's arguments (Exchanges.__init__) and the requests — models, load, upload,
mesh, upload_clip, pose, poses, pose_by_name, position_map, stream, stats: their arguments and
results are the exchanges' (exchanges.py) — run here over a blocking socket; AsyncClient
(async_client.py) runs the same ones under asyncio. Errors raise the exceptions of
sweepd_client.errors.
"""

import functools
import os

from .connection import Connection
from .errors import ConnectionLost, SweepdError
from .exchanges import (Exchanges, Posed, Receive, ReceiveDescriptor, Run, reply_body,
                        with_requests)


def _request(exchange):
    """An exchange as a method that runs it and returns its result."""
    @functools.wraps(exchange)
    def request(self, *args, **kwargs):
        run = Run(exchange(self, *args, **kwargs))
        for _ in self._drive(run):
            pass  # a request yields nothing for the caller
        return run.result
    return request


@with_requests(_request)
class Client(Exchanges):
    def __init__(self, *args, **options):
        super().__init__(*args, **options)
        self._connection = Connection(*self._endpoint)
        try:
            _request(Exchanges._hello)(self, self._connection)
        except BaseException:
            self._connection.close()
            raise

    def __enter__(self):
        return self

    def __exit__(self, *exception):
        self.close()

    def close(self, reason="done"):
        """Bye, then the socket is closed. Safe to call twice."""
        if self._connection is None:
            return
        try:
            self._connection.send(self._bye(reason))
        except ConnectionLost:
            pass  # already gone: nothing to say goodbye to
        self._connection.close()
        self._connection = None

    def _drive(self, run):
        """Sends the frames of `run`, answers its Receives and yields its Posed results."""
        step = run.step()
        while step is not None:
            if isinstance(step, Posed):
                yield step
                step = run.step()
                continue
            try:
                reply = self._perform(step)
            except SweepdError as error:
                step = run.step(error=error)
            else:
                step = run.step(reply)

    def _perform(self, step):
        if self._connection is None:
            raise SweepdError("the client is closed")
        if isinstance(step, Receive):
            return reply_body(self._connection.receive(), step.table, self._connection.address)
        if isinstance(step, ReceiveDescriptor):
            message, descriptor = self._connection.receive_with_descriptor()
            try:
                return reply_body(message, step.table, self._connection.address), descriptor
            except BaseException:
                if descriptor is not None:
                    os.close(descriptor)
                raise
        self._connection.send(step.frame)
        return None
