# Runs the Blender add-on (client_examples/blender) as a user would, headless, and prints how far
# its cached vertices lie from `sweepctl pose`'s (tests/server/blender_addon_test.cpp judges):
#
#   blender -b --factory-startup --python-exit-code 1 --python blender_addon.py -- \
#       ADDON.zip HOST PORT TOKEN MODEL.glb OUT_DIR FIRST LAST SWEEPCTL [TLS_CA]
#
# TLS_CA: the daemon speaks TLS; the add-on trusts this CA file.
# Installs and enables the zip, imports MODEL.glb (a body with an animation: `sweepctl rom`'s),
# sets the scene's range to FIRST-LAST, runs "Deform with sweepd" against the daemon, then poses
# the .glb the add-on uploaded with sweepctl (the same file, its own animation, frames 0-N) and
# compares, per scene frame, the sweep copy's evaluated vertices with sweepctl's.
# Matching rule (independent of the add-on's own _SWEEPD_VERTEX map): the exporter splits a
# Blender vertex into glTF vertices that share its rest position; each Blender vertex is
# compared with the glTF vertices whose rest position lies within 1e-5 m of its own, and the
# nearest of their posed positions counts (a split copy deforms as the vertex it came from).
# Prints "MODEL refused: ERROR" (a run with a wrong token), "MODEL matched M of V", "MODEL frame K gap G" (metres), "MODEL moved D" (the largest
# vertex move from the first frame to the last, metres) and "MODEL copies ok".
import json
import os
import struct
import subprocess
import sys

import numpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                "../../client_examples/blender/scripts"))
from headless import deform, imported_body  # noqa: E402  (sets numpy.bool before bpy)

import bpy  # noqa: E402
from mathutils import kdtree  # noqa: E402

(addon_zip, host, port, token, model, out_dir, first, last, sweepctl,
 *tls_ca) = sys.argv[sys.argv.index("--") + 1:]
tls_ca = tls_ca[0] if tls_ca else None
first, last = int(first), int(last)
label = os.path.basename(model)


def glb_positions(path):
    """The POSITION of every primitive of the file's one mesh, in file order (float32)."""
    data = open(path, "rb").read()
    json_size = struct.unpack_from("<I", data, 12)[0]
    document = json.loads(data[20:20 + json_size])
    binary = data[20 + json_size + 8:]
    parts = []
    for primitive in document["meshes"][0]["primitives"]:
        accessor = document["accessors"][primitive["attributes"]["POSITION"]]
        view = document["bufferViews"][accessor["bufferView"]]
        start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
        parts.append(numpy.frombuffer(binary, "<f4", accessor["count"] * 3, start).reshape(-1, 3))
    return numpy.concatenate(parts), [a.get("name") for a in document["animations"]]


def read_pc2(path):
    data = open(path, "rb").read()
    assert data[:12] == b"POINTCACHE2\0", path
    points, _start, _sampling, frames = struct.unpack_from("<iffi", data, 16)
    return numpy.frombuffer(data, "<f4", frames * points * 3, 32).reshape(frames, points, 3)


def turned(gltf):  # glTF's +Y up as Blender's +Z up
    return numpy.stack([gltf[:, 0], -gltf[:, 2], gltf[:, 1]], axis=1).astype(numpy.float64)


def evaluated(obj):
    mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    co = numpy.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def in_space(matrix, points):
    m = numpy.array(matrix, dtype=numpy.float64)
    return points @ m[:3, :3].T + m[:3, 3]


body = imported_body(addon_zip, model)
scene, mesh = body.scene, body.mesh
# A wrong token first: the operator's error report (a RuntimeError to a script) names it, and
# nothing is left behind.
try:
    deform(body, host, port, "wrong-" + token, first, last, cache_folder=out_dir, tls_ca=tls_ca)
    sys.exit("a wrong token was not refused")
except RuntimeError as error:
    print(f"{label} refused: {str(error).splitlines()[0]}")
if f"{mesh.name} (sweep)" in bpy.data.objects or os.path.exists(
        os.path.join(out_dir, bpy.path.clean_name(mesh.name) + ".pc2")):
    sys.exit("a refused run left a copy or a cache")
deform(body, host, port, token, first, last, cache_folder=out_dir, tls_ca=tls_ca)

sweep = bpy.data.objects[f"{mesh.name} (sweep)"]
dqs = bpy.data.objects[f"{mesh.name} (DQS)"]
kinds = [m.type for m in sweep.modifiers]
if kinds != ["MESH_CACHE"]:
    sys.exit(f"the sweep copy's modifiers are {kinds}, not one Mesh Cache")
if not any(m.type == "ARMATURE" and m.use_deform_preserve_volume for m in dqs.modifiers):
    sys.exit("the DQS copy has no Armature modifier with Preserve Volume")
if any(m.type == "ARMATURE" and m.use_deform_preserve_volume for m in mesh.modifiers):
    sys.exit("the original mesh was changed to DQS")
print(f"{label} copies ok")

uploaded = os.path.join(out_dir, bpy.path.clean_name(mesh.name) + ".glb")
gltf_rest, animations = glb_positions(uploaded)
reference = os.path.join(out_dir, "reference.pc2")
count = last - first + 1
posing = subprocess.run([sweepctl, "pose", uploaded, "--clip", animations[0], "--frames",
                         f"0-{count - 1}", "-o", reference], capture_output=True, text=True)
if posing.returncode != 0:
    sys.exit(f"sweepctl pose: {posing.stdout}{posing.stderr}")
frames = read_pc2(reference)

# Candidates per Blender vertex, by rest position in world space (Blender's axes).
tree = kdtree.KDTree(len(gltf_rest))
for i, p in enumerate(turned(gltf_rest)):
    tree.insert(p, i)
tree.balance()
rest = numpy.empty(len(mesh.data.vertices) * 3)
mesh.data.vertices.foreach_get("co", rest)
rest_world = in_space(mesh.matrix_world, rest.reshape(-1, 3))
candidates = [[i for _, i, _ in tree.find_range(p, 1e-5)] for p in rest_world]
print(f"{label} matched {sum(1 for c in candidates if c)} of {len(candidates)}")

to_mesh = mesh.matrix_world.inverted()
played = []
for k in range(count):
    scene.frame_set(first + k)
    cached = evaluated(sweep)  # in the mesh's own space: the copy's offset is its object's
    played.append(cached)
    expected = in_space(to_mesh, turned(frames[k]))
    gap = max(min(numpy.linalg.norm(expected[c] - cached[v], axis=1)) if c else numpy.inf
              for v, c in enumerate(candidates))
    print(f"{label} frame {k} gap {gap:.3e}")
# The frames differ from each other: a cache stuck on one frame would fail here.
print(f"{label} moved {numpy.max(numpy.linalg.norm(played[-1] - played[0], axis=1)):.3e}")
