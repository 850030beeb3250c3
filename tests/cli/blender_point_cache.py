# Plays point caches written by `sweepctl pose -o FILE.pc2|FILE.mdd` on a model imported by
# Blender's own glTF importer, through the Mesh Cache modifier, headless; prints how far the
# evaluated vertices lie from sweepctl's (tests/cli/blender_point_cache_test.cpp judges them).
#
#   blender -b --python-exit-code 1 --python blender_point_cache.py -- \
#       MODEL.glb REST.f32 FRAMES.f32 FRAME_COUNT CACHE:AXES...
# REST.f32: sweepd's rest vertices of MODEL, FRAMES.f32: the frames the caches hold, both raw
# float32 x y z per vertex in glTF's axes (+Y up), frame after frame. AXES: blender (the cache
# is Z-up, played with the modifier's default axes) or gltf (Y-up, played with Forward +Z, Up -Y:
# the one pair of the modifier's 24 that turns it as the importer turns the model).
# Prints "rest gap G" and "CACHE frame K gap G" lines: the largest distance in metres, vertex i
# against vertex i.
import sys

import numpy

# Debian 12's Blender 3.4 glTF importer still names numpy.bool, which Debian's numpy 1.24 removed.
numpy.bool = bool

import bpy  # noqa: E402  (after the numpy fix, before the importer is loaded)

args = sys.argv[sys.argv.index("--") + 1:]
model, rest_file, frames_file, frame_count = args[0], args[1], args[2], int(args[3])
caches = [spec.rsplit(":", 1) for spec in args[4:]]


def blender_axes(gltf):
    """glTF's +Y up as Blender's importer turns it: (x, y, z) -> (x, -z, y)."""
    return numpy.stack([gltf[:, 0], -gltf[:, 2], gltf[:, 1]], axis=1)


def vertices(obj):
    mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    co = numpy.empty(len(mesh.vertices) * 3, dtype=numpy.float64)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def largest_gap(a, b):
    if a.shape != b.shape:
        sys.exit(f"vertex counts differ: Blender {len(a)}, sweepd {len(b)}")
    return float(numpy.max(numpy.linalg.norm(a - b, axis=1)))


bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=model)
body = max((o for o in bpy.context.scene.objects if o.type == "MESH"),
           key=lambda o: len(o.data.vertices))
rest = numpy.fromfile(rest_file, dtype="<f4").reshape(-1, 3)
frames = numpy.fromfile(frames_file, dtype="<f4").reshape(frame_count, -1, 3)
# The importer keeps the file's vertices in their order (it drops only unused ones, and with
# "Merge Vertices" off merges none): vertex i of the imported mesh is sweepd's vertex i, which
# is what lets a cache play at all. This line proves it for this model.
print(f"rest gap {largest_gap(vertices(body), blender_axes(rest)):.3e}")

# The cache replaces the vertices; the importer's Armature modifier would move them again.
for modifier in list(body.modifiers):
    body.modifiers.remove(modifier)
cache = body.modifiers.new("sweepd", "MESH_CACHE")
cache.frame_start = 1  # scene frame 1 shows the cache's first frame
for path, axes in caches:
    cache.cache_format = "PC2" if path.endswith(".pc2") else "MDD"
    cache.filepath = path
    if axes == "gltf":
        cache.forward_axis, cache.up_axis = "POS_Z", "NEG_Y"
    else:
        cache.forward_axis, cache.up_axis = "POS_Y", "POS_Z"  # the defaults
    for k in range(frame_count):
        bpy.context.scene.frame_set(1 + k)
        gap = largest_gap(vertices(body), blender_axes(frames[k]))
        print(f"{path} frame {k} gap {gap:.3e}")
