"""The add-on run headless on a glTF body (`blender -b`): what render_side_by_side.py and the
add-on's test (tests/server/blender_addon.py) share. A folder of its own beside the add-on's, so
that putting it on sys.path does not put the add-on's source (without its vendor/ folder) there.

    body = imported_body(addon_zip, "body.glb")      # a fresh scene, the add-on installed
    deform(body, host, port, token, first, last)     # "Deform with sweepd" over first-last
"""
import sys
from dataclasses import dataclass

import numpy

numpy.bool = bool  # Debian 12's Blender 3.4 glTF importer names it; numpy 1.24 removed it

import bpy  # noqa: E402


@dataclass
class Body:
    scene: object
    armature: object
    mesh: object  # the mesh with most vertices


def imported_body(addon_zip, model):
    """An empty scene, the add-on installed from its zip (into the user scripts folder:
    BLENDER_USER_SCRIPTS chooses it) and enabled, and `model` imported by Blender's importer."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.preferences.addon_install(filepath=addon_zip, overwrite=True)
    bpy.ops.preferences.addon_enable(module="sweepd_blender")
    bpy.ops.import_scene.gltf(filepath=model)
    scene = bpy.context.scene
    armature = next(o for o in scene.objects if o.type == "ARMATURE")
    mesh = max((o for o in scene.objects if o.type == "MESH"),
               key=lambda o: len(o.data.vertices))
    return Body(scene, armature, mesh)


def deform(body, host, port, token, first, last, cache_folder=None, tls_ca=None):
    """Runs Deform with sweepd over scene frames first-last (over TLS trusting the CA file
    `tls_ca` when given); exits naming the result when it does not finish (the operator's
    error is in the output above)."""
    body.scene.frame_start, body.scene.frame_end = first, last
    settings = body.scene.sweepd
    settings.armature, settings.mesh = body.armature, body.mesh
    settings.host, settings.port, settings.token = host, int(port), token
    settings.tls, settings.tls_ca = tls_ca is not None, tls_ca or ""
    if cache_folder:
        settings.cache_folder = cache_folder
    result = bpy.ops.sweepd.deform()
    if result != {"FINISHED"}:
        sys.exit(f"Deform with sweepd: {result}")
