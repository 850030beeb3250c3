"""A PC2 point cache written from NumPy frames: the format Blender's Mesh Cache modifier reads
(MOD_meshcache_pc2.c), laid out as sweepd's own writer lays it out (io/point_cache/point_cache_save.h):
"POINTCACHE2\\0", int32 version 1, int32 point count, float32 start frame, float32 sampling 1,
int32 sample count, then float32 x y z per point per sample, little-endian."""
import os
import struct

import numpy


class Pc2Writer:
    """Frames go to PATH.partial as they come; finish() renames it to PATH once every promised
    frame is in, so a cancelled run never leaves a cache that promises frames it lacks."""

    def __init__(self, path, point_count, frame_count, start_frame):
        self.path, self.partial = path, path + ".partial"
        self.point_count, self.frame_count, self.written = point_count, frame_count, 0
        self.file = open(self.partial, "wb")
        self.file.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, point_count,
                                                        float(start_frame), 1.0, frame_count))

    def write(self, points):
        points = numpy.ascontiguousarray(points, dtype="<f4")
        if points.shape != (self.point_count, 3):
            raise ValueError(f"a frame of {points.shape} points for a cache of "
                             f"{self.point_count}")
        self.file.write(points.tobytes())
        self.written += 1

    def finish(self):
        self.file.close()
        if self.written != self.frame_count:
            os.remove(self.partial)
            raise ValueError(f"{self.written} frames of the {self.frame_count} promised")
        os.replace(self.partial, self.path)

    def abandon(self):
        if not self.file.closed:
            self.file.close()
        if os.path.exists(self.partial):
            os.remove(self.partial)
