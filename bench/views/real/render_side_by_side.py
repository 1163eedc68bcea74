# Meshes side by side from one angle, for the before/after pictures of
# docs/results/disagree.md (Blender 3.4, headless, Cycles on the CPU):
#
#   blender -b --factory-startup --python bench/views/real/render_side_by_side.py -- \
#       OUT.png AZIMUTH ELEVATION A.ply B.ply ...
#
# The meshes are in the output frame (Y up); the angle is the camera's, in degrees, azimuth
# from the front towards the right, elevation above. Each mesh is centred on its own box.
import math
import sys

import bpy
import mathutils

argv = sys.argv[sys.argv.index("--") + 1:]
out, az, el, meshes = argv[0], math.radians(float(argv[1])), math.radians(float(argv[2])), argv[3:]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
mat = bpy.data.materials.new("clay")
mat.use_nodes = True
mat.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.55, 0.5, 0.45, 1)
# From the object towards the camera (Blender is Z up: the output frame's Y is Blender's Z).
d = mathutils.Vector((math.sin(az) * math.cos(el), -math.cos(az) * math.cos(el), math.sin(el)))
right = d.cross(mathutils.Vector((0, 0, 1))).normalized() * -1
objects, radius = [], 0.0
for path in meshes:
    bpy.ops.import_mesh.ply(filepath=path)
    ob = bpy.context.selected_objects[0]
    ob.rotation_euler = (math.radians(90), 0, 0)
    ob.data.materials.append(mat)
    bpy.context.view_layer.update()
    pts = [ob.matrix_world @ v.co for v in ob.data.vertices]
    lo = mathutils.Vector([min(p[i] for p in pts) for i in range(3)])
    hi = mathutils.Vector([max(p[i] for p in pts) for i in range(3)])
    ob.location -= (lo + hi) / 2
    objects.append(ob)
    radius = max(radius, (hi - lo).length / 2)
for i, ob in enumerate(objects):
    ob.location += right * (1.6 * radius * (i - (len(objects) - 1) / 2))
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 24
scene.cycles.use_denoising = False
scene.render.resolution_x, scene.render.resolution_y = 380 * len(objects), 380
cam = bpy.data.cameras.new("camera")
cam.type = "ORTHO"
cam.ortho_scale = 1.6 * radius * len(objects)
cam.clip_end = 20 * radius
camera = bpy.data.objects.new("camera", cam)
scene.collection.objects.link(camera)
scene.camera = camera
camera.location = d * 4 * radius
camera.rotation_euler = (-d).to_track_quat("-Z", "Y").to_euler()
sun = bpy.data.lights.new("sun", "SUN")
sun.energy = 4.0
light = bpy.data.objects.new("sun", sun)
scene.collection.objects.link(light)
light.rotation_euler = (math.radians(40), math.radians(10), math.radians(-30))
world = bpy.data.worlds.new("world")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.9, 0.9, 0.9, 1)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.25
scene.world = world
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
