"""sweepd for Blender: deform an armature's mesh with sweepd's control sweeps and play the
result beside Blender's own Armature deform (LBS, and "Preserve Volume": DQS).

View3D › Sidebar › sweepd: pick the armature and its mesh, the server (host, port, token, TLS)
and press "Deform with sweepd". docs/blender.md has the whole story.
"""
import os
import sys

# Debian 12's Blender 3.4 glTF add-on still names numpy.bool, which numpy 1.24 removed; the
# exporter this add-on calls is that add-on.
import numpy

if not hasattr(numpy, "bool"):
    numpy.bool = bool

import bpy  # noqa: E402
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, IntProperty,  # noqa: E402
                       PointerProperty, StringProperty)

bl_info = {
    "name": "sweepd",
    "author": "sweepd",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > sweepd",
    "description": "Deform a rigged mesh with sweepd's control sweeps, cached as PC2 beside "
                   "Blender's LBS and DQS",
    "category": "Animation",
}

# The Python client (client_examples/python), copied into the zip's vendor/ folder.
_VENDOR = os.path.join(os.path.dirname(__file__), "vendor")


def _poll_armature(_settings, obj):
    return obj.type == "ARMATURE"


def _poll_mesh(settings, obj):
    return obj.type == "MESH" and (settings.armature is None or any(
        m.type == "ARMATURE" and m.object == settings.armature for m in obj.modifiers))


class SweepdSettings(bpy.types.PropertyGroup):
    armature: PointerProperty(name="Armature", type=bpy.types.Object, poll=_poll_armature)
    mesh: PointerProperty(name="Mesh", type=bpy.types.Object, poll=_poll_mesh,
                          description="a mesh with an Armature modifier on the armature")
    host: StringProperty(name="Host", default="127.0.0.1")
    port: IntProperty(name="Port", default=7878, min=1, max=65535)
    token: StringProperty(name="Token", subtype="PASSWORD",
                          description="sweepd's auth token (empty when it has none)")
    tls: BoolProperty(name="TLS", description="the server's listener speaks TLS")
    plain_token: BoolProperty(name="Token over plain TCP",
                              description="send the token unencrypted to a host that is not "
                                          "this machine (a private network only; else use TLS)")
    tls_ca: StringProperty(name="CA file", subtype="FILE_PATH",
                           description="the certificate authority to trust (empty: the "
                                       "system's)")
    timeout: FloatProperty(name="Timeout", default=60.0, min=1.0, unit="TIME_ABSOLUTE",
                           description="seconds a reply may take")
    method: EnumProperty(name="Method", items=[
        ("sweep", "Sweep", "sweepd's control sweeps"),
        ("lbs", "LBS", "sweepd's linear blend skinning"),
        ("dqs", "DQS", "sweepd's dual quaternion skinning")])
    dqs_copy: BoolProperty(name="DQS copy", default=True,
                           description="also a copy with the Armature modifier's Preserve "
                                       "Volume (Blender's DQS) on the other side")
    cache_folder: StringProperty(name="Cache folder", subtype="DIR_PATH", default="//sweepd",
                                 description="where the .pc2 cache and the uploaded .glb go "
                                             "(the system's temporary folder for an unsaved "
                                             "file)")


class SWEEPD_OT_deform(bpy.types.Operator):
    """Upload the armature and mesh to sweepd, play the action there and cache the result on a
    copy of the mesh"""
    bl_idname = "sweepd.deform"
    bl_label = "Deform with sweepd"
    bl_options = {"REGISTER"}

    _steps = None  # sweep_job.run's generator
    _timer = None
    _last = ""  # the job's latest step, said when it ends
    _result = None

    def execute(self, context):
        from . import sweep_job
        self._steps = sweep_job.run(context, context.scene.sweepd)
        if bpy.app.background or context.window is None:  # headless: no timer events
            while self._advance(context) is None:
                pass
            return self._result
        context.window_manager.progress_begin(0.0, 1.0)
        self._timer = context.window_manager.event_timer_add(0.01, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self._steps.close()  # the cache's .partial file is removed
            return self._end(context, {"CANCELLED"}, "cancelled")
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        result = self._advance(context)
        return {"RUNNING_MODAL"} if result is None else self._end(context, result, None)

    def _advance(self, context):
        """One step of the job: None while it goes on, else the operator's result."""
        from sweepd_client import SweepdError
        from . import sweep_job
        try:
            fraction, what = next(self._steps)
            self._status(context, f"sweepd: {what}", fraction)
            self._last = what
            return None
        except StopIteration:
            self.report({"INFO"}, f"sweepd: {self._last}")
            self._result = {"FINISHED"}
        except (sweep_job.JobError, SweepdError, OSError, ValueError) as error:
            self.report({"ERROR"}, f"sweepd: {error}")
            self._result = {"CANCELLED"}
        return self._result

    def _status(self, context, text, fraction):
        if bpy.app.background:  # no status bar: the console is where progress shows
            print(text, flush=True)
        if context.workspace is not None:
            context.workspace.status_text_set(text)
        if self._timer is not None:
            context.window_manager.progress_update(fraction)

    def _end(self, context, result, why):
        context.window_manager.event_timer_remove(self._timer)
        context.window_manager.progress_end()
        if context.workspace is not None:
            context.workspace.status_text_set(None)
        if why:
            self.report({"WARNING"}, f"sweepd: {why}")
        return result


class SWEEPD_PT_panel(bpy.types.Panel):
    bl_label = "sweepd"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "sweepd"

    def draw(self, context):
        settings = context.scene.sweepd
        layout = self.layout
        for name in ("armature", "mesh", "method", "dqs_copy", "cache_folder"):
            layout.prop(settings, name)
        box = layout.box()
        for name in ("host", "port", "token", "tls"):
            box.prop(settings, name)
        if settings.tls:
            box.prop(settings, "tls_ca")
        else:
            box.prop(settings, "plain_token")
        box.prop(settings, "timeout")
        layout.operator(SWEEPD_OT_deform.bl_idname)


_classes = (SweepdSettings, SWEEPD_OT_deform, SWEEPD_PT_panel)


def register():
    if _VENDOR not in sys.path:
        sys.path.insert(0, _VENDOR)
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.sweepd = PointerProperty(type=SweepdSettings)


def unregister():
    del bpy.types.Scene.sweepd
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
    if _VENDOR in sys.path:
        sys.path.remove(_VENDOR)
