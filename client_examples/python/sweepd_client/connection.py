"""Connection: one blocking sweepd session over TCP (plain or TLS) or a Unix socket.

Frames are the protocol's: a little-endian uint32 length, then a FlatBuffers Message with
the file identifier "SWPD" (protocol/README.md). send() writes one finished builder;
receive() returns the next Message, raising Timeout when nothing arrives within `timeout`
seconds (None: wait for ever) and ConnectionLost when the socket breaks or the frame is not
the protocol's.
"""

import ipaddress
import socket
import struct

import flatbuffers
from sweepd.protocol import Message

from .errors import ConnectionLost, Timeout

FRAME_IDENTIFIER = b"SWPD"


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
                self.loopback = ipaddress.ip_address(raw.getpeername()[0]).is_loopback
                self.socket = tls.wrap_socket(raw, server_hostname=host) if self.tls else raw
        except TimeoutError as error:
            raise Timeout(f"cannot connect to {self.address}: no answer in {timeout} s") from error
        except OSError as error:
            raise ConnectionLost(f"cannot connect to {self.address}: "
                                 f"{error.strerror or error}") from error
        self.socket.settimeout(timeout)
        self.timeout = timeout

    def send(self, builder, body_type, body, request_id=0):
        Message.Start(builder)
        Message.AddRequestId(builder, request_id)
        Message.AddBodyType(builder, body_type)
        Message.AddBody(builder, body)
        builder.FinishSizePrefixed(Message.End(builder), FRAME_IDENTIFIER)
        try:
            self.socket.sendall(builder.Output())
        except TimeoutError as error:
            raise Timeout(f"{self.address}: the server took no bytes for {self.timeout} s") \
                from error
        except OSError as error:
            raise ConnectionLost(f"{self.address}: send failed: "
                                 f"{error.strerror or error}") from error

    def _receive_into(self, view):
        got = 0
        while got < len(view):
            try:
                n = self.socket.recv_into(view[got:])
            except TimeoutError as error:
                raise Timeout(f"{self.address}: no reply in {self.timeout} s") from error
            except OSError as error:
                raise ConnectionLost(f"{self.address}: {error.strerror or error}") from error
            if n == 0:
                raise ConnectionLost(f"{self.address}: the server closed the connection")
            got += n

    def receive(self):
        """The next Message (length prefix and body in one buffer: FlatBuffers' alignment
        counts from its first byte)."""
        prefix = bytearray(4)
        self._receive_into(memoryview(prefix))
        (size,) = struct.unpack("<I", prefix)
        frame = bytearray(4 + size)
        frame[:4] = prefix
        self._receive_into(memoryview(frame)[4:])
        if size < 8 or not Message.Message.MessageBufferHasIdentifier(frame, 0, True):
            raise ConnectionLost(f"{self.address}: a frame without the SWPD identifier")
        return Message.Message.GetRootAs(frame, 4)

    def close(self):
        self.socket.close()


def body_of(message, table):
    """The Message's body as an instance of the generated class `table`."""
    body = table()
    body.Init(message.Body().Bytes, message.Body().Pos)
    return body


def new_builder(size=256):
    return flatbuffers.Builder(size)
