# Renders a glTF binary as Blender imports it (headless, Cycles on the CPU, a three-quarter
# view from the front right, one sun and a grey sky): the picture a TD gets in Blender.
#   blender -b --factory-startup --python bench/texture/blender_render.py -- FILE.glb OUT.png [SIZE] [SKY]
# SKY: the sky's grey (0.8 by default; darker for a white, untextured model).
import math
import sys

import numpy

numpy.bool = bool  # Debian's Blender 3.4 glTF importer still calls the removed numpy.bool

import bpy
from mathutils import Vector

args = sys.argv[sys.argv.index("--") + 1:]
path, out_png = args[0], args[1]
size = int(args[2]) if len(args) > 2 else 480
sky = float(args[3]) if len(args) > 3 else 0.8
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=path)
scene = bpy.context.scene
meshes = [o for o in scene.objects if o.type == "MESH"]
points = [o.matrix_world @ v.co for o in meshes for v in o.data.vertices]
lo = Vector((min(p.x for p in points), min(p.y for p in points), min(p.z for p in points)))
hi = Vector((max(p.x for p in points), max(p.y for p in points), max(p.z for p in points)))
centre, radius = (lo + hi) / 2, (hi - lo).length / 2

scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 32
scene.cycles.use_denoising = False  # Debian's build has no OpenImageDenoise
scene.render.resolution_x = scene.render.resolution_y = size
scene.render.filepath = out_png
scene.world = bpy.data.worlds.new("sky")
scene.world.use_nodes = True
scene.world.node_tree.nodes["Background"].inputs[0].default_value = (sky, sky, sky, 1)

camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
# Blender is Z up and the glTF front (+Z) arrives as -Y: look from the front right, a little above.
camera.location = centre + Vector((0.62, -0.74, 0.36)).normalized() * radius * 2.3
camera.rotation_euler = (centre - camera.location).to_track_quat("-Z", "Y").to_euler()
camera.data.lens = 50
scene.camera = camera
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.data.energy = 2.5
sun.rotation_euler = (math.radians(40), math.radians(10), math.radians(30))
scene.collection.objects.link(sun)
bpy.ops.render.render(write_still=True)
