"""The Meshopt position format (protocol 1.5) decoded with meshoptimizer's own C library.

A PosedVertices reply in that format carries meshoptimizer's vertex codec (version 0) over
int32 grid coordinates, position = position_origin + position_step * q, and over int8 normals,
normal = max(q / 127, -1) (protocol/README.md, "Compact vertex streams"). The codec is not
reimplemented here: it is called through ctypes in the shared library that Debian's
`libmeshoptimizer2d` installs (libmeshoptimizer.so.2d; `libmeshoptimizer-dev` pulls it in), or
the one named by the environment variable SWEEPD_MESHOPTIMIZER (a path). Without one,
asking for encoding="meshopt" raises MeshoptUnavailable before anything is sent; float32 and
float16 need nothing beyond NumPy.
"""

import ctypes
import ctypes.util
import os

import numpy as np

from .errors import ConnectionLost, SweepdError


class MeshoptUnavailable(SweepdError):
    """encoding="meshopt" needs meshoptimizer's shared library, which was not found."""


_library = None


def _candidates():
    named = os.environ.get("SWEEPD_MESHOPTIMIZER")
    if named:
        return [named]
    found = ctypes.util.find_library("meshoptimizer")
    return [name for name in (found, "libmeshoptimizer.so.2d", "libmeshoptimizer.so") if name]


def require():
    """meshoptimizer's library, loaded on first use; MeshoptUnavailable when it cannot be."""
    global _library
    if _library is not None:
        return _library
    problems = []
    for name in _candidates():
        try:
            library = ctypes.CDLL(name)
        except OSError as error:
            problems.append(str(error))
            continue
        decode = library.meshopt_decodeVertexBuffer
        decode.restype = ctypes.c_int
        decode.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_size_t, ctypes.c_void_p,
                           ctypes.c_size_t]
        _library = library
        return library
    raise MeshoptUnavailable(
        "encoding='meshopt' needs meshoptimizer's shared library (Debian: apt install "
        "libmeshoptimizer2d; elsewhere set SWEEPD_MESHOPTIMIZER to the path of a "
        "libmeshoptimizer.so built with MESHOPT_BUILD_SHARED_LIBS): " + "; ".join(problems))


def _decode(encoded, vertex_count, vertex_size, dtype, what):
    """The codec's stream → (vertex_count, vertex_size / itemsize) array of dtype."""
    encoded = np.ascontiguousarray(encoded, np.uint8)
    out = np.empty((vertex_count, vertex_size // np.dtype(dtype).itemsize), dtype)
    status = require().meshopt_decodeVertexBuffer(out.ctypes.data, vertex_count, vertex_size,
                                                  encoded.ctypes.data, encoded.size)
    if status != 0:
        raise ConnectionLost(f"{what}: {encoded.size} meshopt bytes do not decode to "
                             f"{vertex_count} vertices (meshopt error {status})")
    return out


def decode_positions(encoded, vertex_count, origin, step):
    """positions_meshopt → (vertex_count, 3) float32 metres."""
    q = _decode(encoded, vertex_count, 12, np.int32, "positions")
    return np.asarray(origin, np.float32) + np.float32(step) * q.astype(np.float32)


def decode_normals(encoded, vertex_count):
    """normals_meshopt → (vertex_count, 3) float32 (each component within 1/254)."""
    q = _decode(encoded, vertex_count, 4, np.int8, "normals")[:, :3]
    return np.maximum(q.astype(np.float32) / np.float32(127), np.float32(-1))
