# Renders the picture of docs/blender.md: a body at one frame of its animation, deformed by
# sweepd's sweep (the add-on's cached copy, right), by Blender's own Armature modifier (LBS,
# middle) and with its "Preserve Volume" (DQS, left), headless with the Workbench engine:
#
#   blender -b --factory-startup --python-exit-code 1 \
#       --python client_examples/blender/scripts/render_side_by_side.py -- \
#       ADDON.zip HOST PORT TOKEN ANIMATED.glb FRAME OUT.png
#
# ANIMATED.glb: a body with an animation (e.g. `sweepctl rom body.glb -o ANIMATED.glb`);
# FRAME: the animation's frame at its own 30 fps (the scene plays at its rate: the frame is
# converted). Needs a running sweepd at HOST:PORT.
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from headless import deform, imported_body  # noqa: E402  (sets numpy.bool before bpy)

import bpy  # noqa: E402

addon_zip, host, port, token, model, frame, out = sys.argv[sys.argv.index("--") + 1:]

body = imported_body(addon_zip, model)
scene, mesh = body.scene, body.mesh
scene_frame = round(int(frame) * scene.render.fps / 30)
deform(body, host, port, token, scene_frame, scene_frame)
scene.frame_set(scene_frame)

# Labels under the bodies, and an orthographic camera from the front (glTF's +Z, Blender's -Y).
sweep = bpy.data.objects[f"{mesh.name} (sweep)"]
width = sweep.matrix_world.translation.x - mesh.matrix_world.translation.x  # the add-on's spacing
for x, text in ((-width, "DQS (Blender)"), (0.0, "LBS (Blender)"), (width, "sweep (sweepd)")):
    curve = bpy.data.curves.new(text, "FONT")
    curve.body, curve.align_x, curve.size = text, "CENTER", 0.08
    label = bpy.data.objects.new(text, curve)
    label.location, label.rotation_euler = (x, 0.0, -0.15), (math.pi / 2, 0.0, 0.0)
    scene.collection.objects.link(label)
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
camera.data.type, camera.data.ortho_scale = "ORTHO", 2 * width + 1.0
camera.location, camera.rotation_euler = (0.0, -10.0, 0.9), (math.pi / 2, 0.0, 0.0)
scene.collection.objects.link(camera)
scene.camera = camera
scene.render.engine = "BLENDER_WORKBENCH"
scene.display.shading.light = "STUDIO"
scene.display.shading.color_type = "SINGLE"
scene.display.shading.single_color = (0.8, 0.62, 0.5)
scene.display.shading.show_cavity = True
scene.render.resolution_x, scene.render.resolution_y = 1100, 644
scene.render.image_settings.color_mode = "RGB"  # no alpha: a smaller PNG
scene.render.image_settings.compression = 100
scene.render.film_transparent = False
scene.world = bpy.data.worlds.new("world") if scene.world is None else scene.world
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
print(f"rendered {out}: scene frame {scene_frame}")
