"""One "Deform with sweepd" run, as a generator of progress so that the operator can run it in
steps (the status bar moves between them) or at once (headless):

1. export the armature and its mesh with Blender's own glTF exporter (selected objects only,
   the scene's frame range baked at every frame as the action's animation, the mesh's vertex
   indices as the custom attribute _SWEEPD_VERTEX: glb_vertex_map.py);
2. upload it to sweepd (the Python client, sweepd_client), and the same file's animation as a
   clip played on the model's own joints (protocol 1.7), so that sweepd plays exactly the joints
   Blender exported;
3. stream the frames (up to the server's window in flight) and write each posed frame, brought
   back to Blender's vertices and axes (glTF's +Y up is Blender's +Z: (x, y, z) -> (x, -z, y))
   and into the mesh object's space, as a PC2 cache;
4. put the result on a copy of the mesh beside the original: Armature modifier removed, a Mesh
   Cache modifier playing the cache; optionally a second copy on a copy of the armature with the
   Armature modifier's "Preserve Volume" (Blender's dual quaternion skinning), so that the
   sweep, LBS (the original) and DQS play side by side.
"""
import hashlib
import os
import ssl
import tempfile

import bpy
import numpy
from mathutils import Matrix

from . import glb_vertex_map
from .point_cache import Pc2Writer


class JobError(Exception):
    """A problem the user can fix; its text goes to Blender's reports."""


def _check_pair(armature, mesh):
    if armature is None or armature.type != "ARMATURE":
        raise JobError("pick an armature")
    if mesh is None or mesh.type != "MESH":
        raise JobError("pick the armature's mesh")
    if not any(m.type == "ARMATURE" and m.object == armature for m in mesh.modifiers):
        raise JobError(f"the mesh '{mesh.name}' has no Armature modifier on '{armature.name}'")
    if armature.animation_data is None or armature.animation_data.action is None:
        raise JobError(f"the armature '{armature.name}' has no action to play")


def _cache_folder(settings):
    folder = bpy.path.abspath(settings.cache_folder) if settings.cache_folder else ""
    if not folder or (settings.cache_folder.startswith("//") and not bpy.data.filepath):
        folder = os.path.join(tempfile.gettempdir(), "sweepd")  # an unsaved .blend
    os.makedirs(folder, exist_ok=True)
    return folder


def _export(context, armature, mesh, path):
    """The pair as a .glb, with the mesh's vertex indices and the action baked over the scene's
    range; the selection and the action's range are restored after."""
    # Blender 3.4's exporter bakes an action over its own range (its "Manual Frame Range" when
    # set), not the scene's: the scene's range is lent to the action for the export.
    action = armature.animation_data.action
    action_range = (action.use_frame_range, action.frame_start, action.frame_end)
    action.use_frame_range = True
    action.frame_start, action.frame_end = context.scene.frame_start, context.scene.frame_end
    attribute = mesh.data.attributes.get(glb_vertex_map.ATTRIBUTE)
    if attribute is not None:
        mesh.data.attributes.remove(attribute)
    attribute = mesh.data.attributes.new(glb_vertex_map.ATTRIBUTE, "INT", "POINT")
    attribute.data.foreach_set("value", numpy.arange(len(mesh.data.vertices), dtype=numpy.int32))
    selected = [o for o in context.view_layer.objects if o.select_get()]
    try:
        for o in selected:
            o.select_set(False)
        armature.select_set(True)
        mesh.select_set(True)
        result = bpy.ops.export_scene.gltf(
            filepath=path, export_format="GLB", use_selection=True, export_attributes=True,
            export_animations=True, export_frame_range=True, export_force_sampling=True,
            export_optimize_animation_size=False, export_def_bones=False, export_colors=False,
            export_morph=False, export_apply=False, export_current_frame=False)
        if "FINISHED" not in result:
            raise JobError(f"Blender's glTF exporter did not finish: {result}")
    finally:
        action.use_frame_range, action.frame_start, action.frame_end = action_range
        mesh.data.attributes.remove(mesh.data.attributes[glb_vertex_map.ATTRIBUTE])
        armature.select_set(False)
        mesh.select_set(False)
        for o in selected:
            o.select_set(True)


def _animation_name(glb, action):
    """The exported animation of the action: by the action's name, else the only one."""
    document, _ = glb_vertex_map.glb_chunks(glb)
    names = [a.get("name", "") for a in document.get("animations", [])]
    if action.name in names:
        return action.name
    if len(names) == 1:
        return 0
    raise JobError(f"the exported file holds the animations {names}, none named after the "
                   f"action '{action.name}'")


def _client(settings):
    # Imported here: the add-on's folder holds the client (vendor/), put on sys.path at register.
    from sweepd_client import Client
    tls = None
    if settings.tls:
        ca = bpy.path.abspath(settings.tls_ca) if settings.tls_ca else None
        tls = ssl.create_default_context(cafile=ca)
    return Client(settings.host, settings.port, token=settings.token, tls=tls,
                  client_name="sweepd-blender", timeout=settings.timeout,
                  allow_plaintext=settings.plain_token)


def _copy(source, name, offset):
    """A copy of `source` in its collections, `offset` (Blender units along X) beside it."""
    copy = source.copy()
    copy.name = name
    for collection in source.users_collection:
        collection.objects.link(copy)
    copy.matrix_world = Matrix.Translation((offset, 0.0, 0.0)) @ source.matrix_world
    return copy


def run(context, settings):
    """Yields (fraction done, what) while it works; returns the sweep copy's name. Raises
    JobError, and the client's errors (SweepdError and its kinds, OSError)."""
    scene = context.scene
    armature, mesh = settings.armature, settings.mesh
    _check_pair(armature, mesh)
    folder = _cache_folder(settings)
    stem = bpy.path.clean_name(mesh.name)
    glb_path = os.path.join(folder, stem + ".glb")
    cache_path = os.path.join(folder, stem + ".pc2")
    # Every frame of the range (the cache plays one sample per scene frame; the exporter bakes
    # every frame).
    frames = list(range(scene.frame_start, scene.frame_end + 1))

    yield 0.0, "exporting glTF"
    _export(context, armature, mesh, glb_path)
    with open(glb_path, "rb") as file:
        glb = file.read()
    try:
        gltf_to_blender = glb_vertex_map.blender_vertex_of_gltf_vertex(glb)
        vertex_count = len(mesh.data.vertices)
        first_copy = glb_vertex_map.first_gltf_vertex_of_blender_vertex(gltf_to_blender,
                                                                        vertex_count)
    except ValueError as error:
        raise JobError(f"{glb_path}: {error}") from None
    animation = _animation_name(glb, armature.animation_data.action)

    yield 0.05, "uploading"
    with _client(settings) as sweepd:
        # The name carries the bytes' hash: the server refuses another model under a name it
        # holds, and each export (another range, an edited mesh) is another file.
        body = sweepd.upload(glb, name=f"{stem}-{hashlib.sha256(glb).hexdigest()[:12]}")
        if body.vertex_count != len(gltf_to_blender):
            raise JobError(f"sweepd holds {body.vertex_count} vertices, the exported file "
                           f"{len(gltf_to_blender)}")
        clip = sweepd.upload_clip(glb, name=stem, animation=animation, own_skeleton=True,
                                  model=body)
        if clip.frame_count != len(frames):
            raise JobError(f"the exported animation has {clip.frame_count} frames, the scene's "
                           f"range {len(frames)} ({scene.frame_start}-{scene.frame_end})")
        # World (Blender's axes) to the mesh object's own space, where the cache's points live.
        to_mesh = numpy.array(mesh.matrix_world.inverted(), dtype=numpy.float64)
        rest = numpy.empty(vertex_count * 3, dtype=numpy.float32)
        mesh.data.vertices.foreach_get("co", rest)
        rest = rest.reshape(-1, 3)
        dropped = first_copy < 0
        writer = Pc2Writer(cache_path, vertex_count, len(frames), scene.frame_start)
        try:
            for k, posed in enumerate(sweepd.poses(body, range(len(frames)), clip=clip,
                                                   method=settings.method)):
                p = posed.positions.astype(numpy.float64)
                world = numpy.stack([p[:, 0], -p[:, 2], p[:, 1]], axis=1)
                local = world @ to_mesh[:3, :3].T + to_mesh[:3, 3]
                points = numpy.where(dropped[:, None], rest, local[numpy.maximum(first_copy, 0)])
                writer.write(points)
                yield 0.1 + 0.85 * (k + 1) / len(frames), f"frame {k + 1} of {len(frames)}"
            writer.finish()
        except BaseException:
            writer.abandon()
            raise

    yield 0.97, "setting up the copies"
    # The copies' spacing: the rest mesh's width and half again (room for arms that reach out),
    # the same at whichever frame the scene stands.
    width = max(float(numpy.ptp(rest[:, 0])) * mesh.matrix_world.to_scale().x, 0.5) * 1.5
    sweep = _copy(mesh, f"{mesh.name} (sweep)", width)
    world = sweep.matrix_world.copy()
    sweep.parent = None  # the cache alone moves it: nothing of the armature applies
    sweep.matrix_world = world
    for modifier in list(sweep.modifiers):
        if modifier.type == "ARMATURE":
            sweep.modifiers.remove(modifier)
    cache = sweep.modifiers.new("sweepd", "MESH_CACHE")
    cache.cache_format = "PC2"
    cache.filepath = cache_path
    cache.frame_start = scene.frame_start  # the scene frame that shows the cache's first frame
    if settings.dqs_copy:
        # A copy of the armature and of the mesh, moved together so that the deformation is
        # the original's: the Armature modifier works in the armature's space.
        rig = _copy(armature, f"{armature.name} (DQS)", -width)
        dqs = _copy(mesh, f"{mesh.name} (DQS)", -width)
        if mesh.parent == armature:
            dqs.parent = rig
            dqs.matrix_parent_inverse = mesh.matrix_parent_inverse.copy()
            dqs.matrix_basis = mesh.matrix_basis.copy()
        for modifier in dqs.modifiers:
            if modifier.type == "ARMATURE":
                modifier.object = rig
                modifier.use_deform_preserve_volume = True
    skipped = int(dropped.sum())
    note = f"; {skipped} vertices in no face stay at rest" if skipped else ""
    yield 1.0, f"{len(frames)} frames of {vertex_count} vertices cached in {cache_path}{note}"
    return sweep.name
