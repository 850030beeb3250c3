"""Which Blender vertex each vertex of an exported .glb is.

Blender's glTF exporter writes one glTF vertex per distinct (vertex, normal, UV, ...) corner
combination, per material primitive, in its own order: it splits vertices at UV seams and
sharp edges and reorders them. sweepd poses the file's vertices (its mesh's primitives in file
order, appended). To bring a posed frame back onto Blender's mesh, the add-on gives the mesh a
point attribute holding each vertex's index before exporting; the exporter writes it as the
custom attribute `_SWEEPD_VERTEX` (float32, exact for indices below 2^24) beside POSITION, and
this module reads it back, primitive after primitive.
"""
import json
import struct

import numpy

ATTRIBUTE = "sweepd_vertex"  # the Blender attribute; the exporter writes it as _SWEEPD_VERTEX
GLTF_ATTRIBUTE = "_SWEEPD_VERTEX"
_FLOAT = 5126


def glb_chunks(glb):
    """A .glb's JSON document and its binary chunk."""
    magic, _version, length = struct.unpack_from("<4sII", glb, 0)
    if magic != b"glTF" or length > len(glb):
        raise ValueError("the exported file is not a whole .glb")
    offset, chunks = 12, {}
    while offset + 8 <= length:
        size, kind = struct.unpack_from("<I4s", glb, offset)
        chunks[kind] = glb[offset + 8:offset + 8 + size]
        offset += 8 + size
    return json.loads(chunks[b"JSON"]), chunks.get(b"BIN\x00", b"")


def _scalar_floats(document, binary, index):
    accessor = document["accessors"][index]
    if accessor["componentType"] != _FLOAT or accessor["type"] != "SCALAR":
        raise ValueError(f"{GLTF_ATTRIBUTE} is not float32 scalars")
    view = document["bufferViews"][accessor["bufferView"]]
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    stride = view.get("byteStride", 4)
    count = accessor["count"]
    raw = numpy.frombuffer(binary, dtype="<u1", count=stride * (count - 1) + 4, offset=start)
    return numpy.lib.stride_tricks.as_strided(raw, shape=(count, 4), strides=(stride, 1)) \
        .copy().view("<f4").reshape(count)


def blender_vertex_of_gltf_vertex(glb):
    """For each vertex sweepd reads from `glb` (bytes of a file holding one mesh), the index of
    the Blender vertex it came from, as an int64 array. Raises ValueError when the file holds
    other than one mesh or a primitive lacks the attribute."""
    document, binary = glb_chunks(glb)
    meshes = document.get("meshes", [])
    if len(meshes) != 1:
        raise ValueError(f"the exported file holds {len(meshes)} meshes, not 1")
    parts = []
    for primitive in meshes[0]["primitives"]:
        index = primitive["attributes"].get(GLTF_ATTRIBUTE)
        if index is None:
            raise ValueError(f"a primitive of the exported mesh lacks {GLTF_ATTRIBUTE}: the "
                             "exporter did not write the vertex indices")
        parts.append(numpy.rint(_scalar_floats(document, binary, index)).astype(numpy.int64))
    return numpy.concatenate(parts)


def first_gltf_vertex_of_blender_vertex(gltf_to_blender, blender_vertex_count):
    """The rule: each Blender vertex takes the frame position of its first glTF copy (the copies
    a split makes share position and skin weights, so they deform alike). -1 for a Blender
    vertex the exporter dropped (one in no face)."""
    if len(gltf_to_blender) and (gltf_to_blender.min() < 0 or
                                 gltf_to_blender.max() >= blender_vertex_count):
        raise ValueError(f"{GLTF_ATTRIBUTE} names vertices outside the mesh's "
                         f"{blender_vertex_count}")
    first = numpy.full(blender_vertex_count, -1, dtype=numpy.int64)
    blender_vertices, first_copies = numpy.unique(gltf_to_blender, return_index=True)
    first[blender_vertices] = first_copies
    return first
