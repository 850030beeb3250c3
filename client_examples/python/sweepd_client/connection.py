"""Connection: one blocking sweepd session over TCP (plain or TLS) or a Unix socket, and the
framing that it shares with AsyncConnection (async_connection.py).

Frames are the protocol's: a little-endian uint32 length, then a FlatBuffers Message with
the file identifier "SWPD" (protocol/README.md). finish_frame() makes one from a builder's
body; frame_buffer() and parse_frame() read one. send() writes a frame;
receive() returns the next Message, raising Timeout when nothing arrives within `timeout`
seconds (None: wait for ever) and ConnectionLost when the socket breaks or the frame is not
the protocol's.
"""

import contextlib
import ipaddress
import os
import socket
import struct

import flatbuffers
from sweepd.protocol import Message

from .errors import ConnectionLost, Timeout

FRAME_IDENTIFIER = b"SWPD"


def finish_frame(builder, body_type, body, request_id=0):
    """A Message around `body` (of union type `body_type`) finished in `builder` → the frame's
    bytes, length prefix included."""
    Message.Start(builder)
    Message.AddRequestId(builder, request_id)
    Message.AddBodyType(builder, body_type)
    Message.AddBody(builder, body)
    builder.FinishSizePrefixed(Message.End(builder), FRAME_IDENTIFIER)
    return builder.Output()


def frame_buffer(prefix):
    """The buffer for the frame whose 4-byte length prefix is `prefix`, the prefix in its first
    bytes: prefix and body share one buffer (FlatBuffers' alignment counts from its first
    byte), the body to be read into buffer[4:]."""
    (size,) = struct.unpack("<I", prefix)
    frame = bytearray(4 + size)
    frame[:4] = prefix
    return frame


def parse_frame(frame, address):
    """A whole frame (frame_buffer, filled) → its Message; ConnectionLost when it is not the
    protocol's."""
    if len(frame) < 12 or not Message.Message.MessageBufferHasIdentifier(frame, 0, True):
        raise ConnectionLost(f"{address}: a frame without the SWPD identifier")
    return Message.Message.GetRootAs(frame, 4)


@contextlib.contextmanager
def sending(address, timeout):
    """Maps a send's failures to the package's exceptions (blocking or asyncio alike)."""
    try:
        yield
    except TimeoutError as error:
        raise Timeout(f"{address}: the server took no bytes for {timeout} s") from error
    except OSError as error:
        raise ConnectionLost(f"{address}: send failed: {error.strerror or error}") from error


@contextlib.contextmanager
def receiving(address, timeout):
    """Maps a receive's failures to the package's exceptions (blocking or asyncio alike)."""
    try:
        yield
    except TimeoutError as error:
        raise Timeout(f"{address}: no reply in {timeout} s") from error
    except OSError as error:
        raise ConnectionLost(f"{address}: {error.strerror or error}") from error


class Connection:
    def __init__(self, host, port, unix=None, tls=None, timeout=30.0):
        self.address = unix or f"{host}:{port}"
        self.tls = tls is not None and not unix
        try:
            if unix:
                self.socket = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
                self.socket.settimeout(timeout)
                self.socket.connect(unix)
                self.loopback = True
            else:
                raw = socket.create_connection((host, int(port)), timeout=timeout)
                raw.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                self.loopback = is_loopback(raw)
                self.socket = tls.wrap_socket(raw, server_hostname=host) if self.tls else raw
        except TimeoutError as error:
            raise Timeout(f"cannot connect to {self.address}: no answer in {timeout} s") from error
        except OSError as error:
            raise ConnectionLost(f"cannot connect to {self.address}: "
                                 f"{error.strerror or error}") from error
        self.socket.settimeout(timeout)
        self.timeout = timeout

    def send(self, frame):
        with sending(self.address, self.timeout):
            self.socket.sendall(frame)

    def _receive_into(self, view):
        got = 0
        while got < len(view):
            with receiving(self.address, self.timeout):
                n = self.socket.recv_into(view[got:])
            if n == 0:
                raise ConnectionLost(f"{self.address}: the server closed the connection")
            got += n

    def receive(self):
        """The next Message."""
        return self.receive_with_descriptor(descriptors=False)[0]

    def receive_with_descriptor(self, descriptors=True):
        """The next Message and the file descriptor its first bytes carried as SCM_RIGHTS
        (None without one): recvmsg on a Unix socket, where a plain read would drop it. TLS
        and TCP carry none."""
        prefix = bytearray(4)
        descriptor, got = None, 0
        try:
            if descriptors and self.socket.family == socket.AF_UNIX:
                with receiving(self.address, self.timeout):
                    data, fds, _, _ = socket.recv_fds(self.socket, 4, 4)
                for extra in fds[1:]:
                    os.close(extra)  # the protocol sends one; more are not ours to keep
                descriptor = fds[0] if fds else None
                if not data:
                    raise ConnectionLost(f"{self.address}: the server closed the connection")
                prefix[:len(data)] = data
                got = len(data)
            self._receive_into(memoryview(prefix)[got:])
            frame = frame_buffer(prefix)
            self._receive_into(memoryview(frame)[4:])
            return parse_frame(frame, self.address), descriptor
        except BaseException:
            if descriptor is not None:
                os.close(descriptor)
            raise

    def close(self):
        self.socket.close()


def is_loopback(sock):
    """Whether a connected TCP socket's peer is on this host."""
    return ipaddress.ip_address(sock.getpeername()[0]).is_loopback


def body_of(message, table):
    """The Message's body as an instance of the generated class `table`."""
    body = table()
    body.Init(message.Body().Bytes, message.Body().Pos)
    return body


def new_builder(size=256):
    return flatbuffers.Builder(size)
