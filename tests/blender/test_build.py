"""The add-on in background mode (blender -b), from the build's zip: the bundled example's
three drawings as reference empties on a moved, turned, tilted and scaled rig; the operator
builds the mesh, which must land on the drawings (extents within 1 %, silhouette covering
each drawing); a re-build keeps the object; the textured pipeline gives a material with its
texture; errors are one line.

blender -b --factory-startup --python-exit-code 1 --python tests/blender/test_build.py --
    --addon build/release/conceptmesh_blender.zip --exe build/release/bin/conceptmesh
    --examples examples/spot
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rig  # noqa: E402

A = rig.args()
failures = []


def build(**kw):
    """The operator as a script calls it: an error it reports is a RuntimeError."""
    try:
        return bpy.ops.conceptmesh.build(**kw)
    except RuntimeError as e:
        print("     raised: %s" % e)
        return {"CANCELLED"}


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


addon = rig.install_addon(A["addon"])
STATUS = sys.modules["conceptmesh_blender.ops"].STATUS
rig.clear_scene()
_, empties = rig.build_rig(A["examples"])
s = bpy.context.scene.conceptmesh
s.resolution = 256

# 1. A build lands on the drawings.
r = build(executable=A["exe"])
check(r == {"FINISHED"}, "build finished: %s %s" % (r, STATUS["message"]))
meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
check(len(meshes) == 1 and meshes[0].name == "spot", "one object, named after the asset: %s" % [o.name for o in meshes])
check(STATUS["events"] > 10, "progress events read: %d" % STATUS["events"])
check(not os.path.exists(STATUS["folder"]), "the run's folder is removed")
if len(meshes) != 1:
    sys.exit(1)
obj = meshes[0]
for e in empties:
    m = rig.measure(obj, e)
    print("     %s: drawn %s built %s" % (e.name, [round(v, 1) for v in m["drawn"]], [round(v, 1) for v in m["built"]]))
    check(m["extent_error"] < 0.01, "%s: extents within 1%% (%.3f%%)" % (e.name, 100 * m["extent_error"]))
    check(m["centre_error"] < 0.002, "%s: centred on the drawing (%.3f%% off)" % (e.name, 100 * m["centre_error"]))
    check(m["coverage"] > 0.98, "%s: silhouette covers the drawing (%.2f%%)" % (e.name, 100 * m["coverage"]))
    check(m["iou"] > 0.95, "%s: silhouette IoU %.4f" % (e.name, m["iou"]))

# 2. A re-build replaces the mesh and keeps the object's name, modifiers and materials.
obj.name = "spot_hero"
mod = obj.modifiers.new("subdiv", "SUBSURF")
mine = bpy.data.materials.new("artist_paint")
obj.data.materials.append(mine)
old_mesh = obj.data.name
old_faces = len(obj.data.polygons)
s.resolution = 128
r = build(executable=A["exe"])
meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
check(r == {"FINISHED"} and len(meshes) == 1, "re-build: still one object (%s)" % [o.name for o in meshes])
obj = meshes[0]
check(obj.name == "spot_hero", "re-build keeps the name: %s" % obj.name)
check([m.name for m in obj.modifiers] == ["subdiv"], "re-build keeps the modifiers")
check(mine.name in [m.name for m in obj.data.materials if m], "re-build keeps the artist's material")
check(len(obj.data.polygons) != old_faces, "re-build replaced the mesh (%d -> %d faces)" % (old_faces, len(obj.data.polygons)))
check(obj.data.name == old_mesh, "the mesh keeps its name")

# 3. The textured pipeline: a material with the texture, packed into the .blend.
bpy.data.objects.remove(obj)
s.pipeline = "textured"
s.asset_name = "cow"
r = build(executable=A["exe"])
obj = bpy.data.objects.get("cow")
check(r == {"FINISHED"} and obj is not None, "textured build: %s %s" % (r, STATUS["message"]))
if obj:
    imgs = [n.image for m in obj.data.materials if m and m.node_tree for n in m.node_tree.nodes if n.type == "TEX_IMAGE"]
    check(len(imgs) == 1 and imgs[0].packed_file is not None and imgs[0].size[0] > 0, "its texture is a packed image")
    check(len(obj.data.uv_layers) == 1, "with its UVs")
    m = rig.measure(obj, empties[0])
    check(m["extent_error"] < 0.01, "textured: on the drawings too (%.3f%%)" % (100 * m["extent_error"]))
    bpy.data.objects.remove(obj)
s.pipeline = "paper"
s.asset_name = ""

# 4. Errors: one line naming the cause, no object, no traceback.
n_before = len(bpy.data.objects)
empties[1].scale = (1.0, 1.2, 1.0)
r = build(executable=A["exe"])
check(r == {"CANCELLED"} and "ref_right" in STATUS["message"] and "not square" in STATUS["message"],
      "non-square pixels: %s" % STATUS["message"])
empties[1].scale = (1.0, 1.0, 1.0)
blank = bpy.data.images.new("blank", 64, 64)
blank.generated_color = (1, 1, 1, 1)
empties[2].data = blank
r = build(executable=A["exe"])
msg = STATUS["message"]
check(r == {"CANCELLED"} and 'node "views" (views.load)' in msg and "\n" not in msg and "Traceback" not in msg,
      "an error of the run is its one line from the stream: %s" % msg)
check(len(bpy.data.objects) == n_before, "a failed build adds no object")
r = build(executable="/nonexistent/conceptmesh")
check(r == {"CANCELLED"} and "/nonexistent/conceptmesh" in STATUS["message"], "a missing command: %s" % STATUS["message"])

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("all checks passed")
