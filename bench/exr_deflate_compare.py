#!/usr/bin/python3
"""exr_deflate_compare: how long OpenEXR's ZIP compression of a position map would take with
zlib (what OpenEXR 3.1 calls) and with libdeflate (Debian's libdeflate0, through ctypes), on the
same blocks — the measurement behind docs/performance.md, "Position maps: where a frame's time goes".

    sweepctl positionmap body.glb --bvh clip.bvh --frame 300 --compression none -o map.exr
    /usr/bin/python3 bench/exr_deflate_compare.py map.exr [rounds, default 7]

Reads an uncompressed scan-line EXR, groups its lines 16 at a time as ZIP does, prepares each
block as OpenEXR does (bytes split into even and odd halves, then each byte minus the one before
plus 128), and times zlib levels 1 and 6 and libdeflate levels 1, 2, 4 and 6 on every block,
interleaved round by round so that the machine's load falls on all alike. Prints a Markdown
table: median ms for the whole map, ÷ zlib level 1, compressed bytes; and the load average.
"""

import ctypes
import os
import struct
import sys
import time
import zlib

import numpy as np


def scanlines(data):
    """The pixel data of each line of an uncompressed single-part scan-line EXR, in order."""
    if data[:4] != b"\x76\x2f\x31\x01":
        sys.exit("not an OpenEXR file")
    pos, attributes = 8, {}
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        (size,) = struct.unpack_from("<i", data, type_end + 1)
        value_at = type_end + 5
        attributes[data[pos:name_end].decode()] = data[value_at:value_at + size]
        pos = value_at + size
    if attributes["compression"] != b"\0":
        sys.exit("the EXR is compressed: write it with --compression none")
    xmin, ymin, xmax, ymax = struct.unpack("<4i", attributes["dataWindow"])
    height = ymax - ymin + 1
    offsets = struct.unpack_from(f"<{height}Q", data, pos + 1)
    lines = []
    for offset in offsets:
        _, size = struct.unpack_from("<ii", data, offset)
        lines.append(data[offset + 8:offset + 8 + size])
    return lines


def prepared(raw):
    """A block as OpenEXR's ZIP hands it to deflate: interleaved halves, then the predictor."""
    a = np.frombuffer(raw, np.uint8)
    t = np.concatenate([a[0::2], a[1::2]]).astype(np.int16)
    out = np.empty(len(t), np.uint8)
    out[0] = t[0]
    out[1:] = ((t[1:] - t[:-1] + 128 + 256) & 0xFF).astype(np.uint8)
    return out.tobytes()


def main(path, rounds=7):
    lines = scanlines(open(path, "rb").read())
    blocks = [prepared(b"".join(lines[i:i + 16])) for i in range(0, len(lines), 16)]
    lib = ctypes.CDLL("libdeflate.so.0")
    lib.libdeflate_alloc_compressor.restype = ctypes.c_void_p
    lib.libdeflate_alloc_compressor.argtypes = [ctypes.c_int]
    lib.libdeflate_zlib_compress.restype = ctypes.c_size_t
    lib.libdeflate_zlib_compress.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_size_t,
                                             ctypes.c_char_p, ctypes.c_size_t]
    out = ctypes.create_string_buffer(2 * max(len(b) for b in blocks) + 1024)

    def libdeflate(level):
        compressor = lib.libdeflate_alloc_compressor(level)
        return lambda block: lib.libdeflate_zlib_compress(compressor, block, len(block), out,
                                                          len(out))

    variants = {"zlib level 1": lambda block: len(zlib.compress(block, 1)),
                "zlib level 6": lambda block: len(zlib.compress(block, 6))}
    for level in (1, 2, 4, 6):
        variants[f"libdeflate level {level}"] = libdeflate(level)
    times = {name: [] for name in variants}
    sizes = {}
    for _ in range(rounds):
        for name, compress in variants.items():
            start = time.perf_counter()
            sizes[name] = sum(compress(block) for block in blocks)
            times[name].append(time.perf_counter() - start)
    median = {name: sorted(t)[len(t) // 2] for name, t in times.items()}
    print(f"| {len(blocks)} blocks of 16 lines, {rounds} rounds | ms | ÷ zlib level 1 | bytes |")
    print("|---|---|---|---|")
    for name in variants:
        print(f"| {name} | {median[name] * 1000:.1f} | "
              f"{median[name] / median['zlib level 1']:.3f} | {sizes[name]} |")
    print(f"\nload average: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main(sys.argv[1], *(int(a) for a in sys.argv[2:3]))
