"""The exceptions of sweepd_client.

SweepdError is the base of all. ConnectionLost: the server cannot be reached or the
connection broke (a timeout is a Timeout, one kind of ConnectionLost). ServerError: the server
answered with an Error; it has one subclass per protocol ErrorCode (UnknownModel, InvalidPose,
AuthFailed, ...), so callers catch exactly what they handle, and .code, .name and .fatal say
which it was.
"""

from sweepd.protocol.ErrorCode import ErrorCode


class SweepdError(Exception):
    """Anything sweepd_client raises."""


class ConnectionLost(SweepdError):
    """The server cannot be reached, or the connection broke or sent something unreadable."""


class Timeout(ConnectionLost):
    """No reply within the client's timeout (the connection is unusable afterwards)."""


class ServerError(SweepdError):
    """An Error reply. `code` is the protocol's ErrorCode value, `name` its name."""

    code = None

    def __init__(self, message, fatal=False, sequence=0):
        super().__init__(f"{self.name}: {message}")
        self.message, self.fatal, self.sequence = message, fatal, sequence

    @property
    def name(self):
        return type(self).__name__


def _error_classes():
    classes = {}
    for name, code in vars(ErrorCode).items():
        if not name.startswith("_"):
            classes[code] = type(name, (ServerError,), {"code": code, "__module__": __name__})
    return classes


ERROR_CLASSES = _error_classes()
globals().update({cls.__name__: cls for cls in ERROR_CLASSES.values()})


def server_error(code, message, fatal=False, sequence=0):
    """The ServerError subclass for `code` (a plain ServerError for a code from a newer server)."""
    cls = ERROR_CLASSES.get(code)
    if cls is None:
        error = ServerError(f"error code {code}: {message}", fatal, sequence)
        error.code = code
        return error
    return cls(message, fatal, sequence)
