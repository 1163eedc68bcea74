# Imports a glTF binary into Blender (headless) and prints what a TD would look at, as one
# JSON line starting with "IMPORTED ": the objects, their size in metres, their UV layers
# and materials, and per face its normal in Blender's frame (Z up) with the colour of the
# base-colour texture at the face's UV centre, read from the image Blender loaded.
#   blender -b --factory-startup --python blender_import.py -- FILE.glb
import json
import sys

import numpy

numpy.bool = bool  # Debian's Blender 3.4 glTF importer still calls the removed numpy.bool

import bpy

path = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=path)
out = {"objects": []}
for ob in bpy.context.scene.objects:
    if ob.type != "MESH":
        continue
    me = ob.data
    image = None
    mats = []
    for m in me.materials:
        nodes = [n for n in m.node_tree.nodes if n.type == "TEX_IMAGE" and n.image] if m and m.use_nodes else []
        mats.append({"name": m.name if m else "", "images": [n.image.name for n in nodes]})
        if nodes and image is None:
            image = nodes[0].image
    faces = []
    if image is not None and me.uv_layers:
        w, h = image.size
        px = numpy.array(image.pixels[:], dtype=numpy.float32).reshape(h, w, image.channels)
        uv = me.uv_layers.active.data
        for p in me.polygons:
            u = sum(uv[i].uv[0] for i in p.loop_indices) / len(p.loop_indices)
            v = sum(uv[i].uv[1] for i in p.loop_indices) / len(p.loop_indices)
            x = min(w - 1, max(0, int(u * w)))
            y = min(h - 1, max(0, int(v * h)))  # Blender's pixel rows start at the bottom
            n = ob.matrix_world.to_3x3() @ p.normal
            faces.append([round(n.x, 4), round(n.y, 4), round(n.z, 4)] + [round(float(c), 4) for c in px[y, x, :3]])
    out["objects"].append({
        "name": ob.name,
        "mesh": me.name,
        "dimensions": [round(d, 5) for d in ob.dimensions],
        "uv_layers": [u.name for u in me.uv_layers],
        "materials": mats,
        "colourspace": image.colorspace_settings.name if image is not None else "",
        "faces": faces,
    })
print("IMPORTED " + json.dumps(out))
