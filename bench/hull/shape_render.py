# Renders OBJ meshes as Blender imports them, from a three-quarter view (front right, from
# above), Workbench engine (fast, solid grey with cavity shading): the pictures of
# docs/results/shape.md.
#   blender -b --factory-startup --python bench/hull/shape_render.py -- SIZE OUT_PREFIX A.obj [B.obj ...]
# writes OUT_PREFIX-0.png, OUT_PREFIX-1.png, ... (one per mesh, same camera for all: framed on
# the first mesh's box, so the pictures compare). SHAPE_AZ=DEG in the environment turns the
# camera about the vertical (45 unless given; 135 looks at a conceptmesh model, front +Z,
# from its front right); SHAPE_EL=DEG raises it (25 unless given; below 0 looks from under).
import math
import os
import sys

import bpy
from mathutils import Vector

args = sys.argv[sys.argv.index("--") + 1:]
size, prefix, paths = int(args[0]), args[1], args[2:]
frame = None
for k, path in enumerate(paths):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
    scene = bpy.context.scene
    meshes = [o for o in scene.objects if o.type == "MESH"]
    for o in meshes:
        for p in o.data.polygons:
            p.use_smooth = False
    if frame is None:
        pts = [o.matrix_world @ v.co for o in meshes for v in o.data.vertices]
        lo = Vector((min(p.x for p in pts), min(p.y for p in pts), min(p.z for p in pts)))
        hi = Vector((max(p.x for p in pts), max(p.y for p in pts), max(p.z for p in pts)))
        frame = ((lo + hi) / 2, (hi - lo).length / 2)
    centre, radius = frame
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.light = "STUDIO"
    scene.display.shading.show_cavity = True
    scene.display.shading.color_type = "SINGLE"
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.film_transparent = False
    scene.world = bpy.data.worlds.new("w")
    # Blender is Z up; the OBJ's front (+Z in conceptmesh's frame) imports as +Y here.
    az, el = math.radians(float(os.environ.get("SHAPE_AZ", 45))), math.radians(float(os.environ.get("SHAPE_EL", 25)))
    d = Vector((math.sin(az) * math.cos(el), math.cos(az) * math.cos(el), math.sin(el)))
    cam_data = bpy.data.cameras.new("cam")
    cam = bpy.data.objects.new("cam", cam_data)
    scene.collection.objects.link(cam)
    cam.location = centre + d * radius * 3.2
    cam.rotation_euler = (-d).to_track_quat("-Z", "Y").to_euler()
    cam_data.lens = 50
    # Meshes in the drawings' units (hundreds of units) lie beyond Blender's default 100.
    cam_data.clip_start, cam_data.clip_end = radius * 0.01, radius * 10
    scene.camera = cam
    scene.render.filepath = f"{prefix}-{k}.png"
    bpy.ops.render.render(write_still=True)
