"""How the add-on reads reference empties as views (docs/blender.md, "How views are read
from the references"), without running a build: named views from Blender's own views, a
rig turned or tilted as a whole, back/left/bottom, an oblique view, and the refusals.

blender -b --factory-startup --python-exit-code 1 --python tests/blender/test_views.py --
    --addon ZIP --exe BIN --examples examples/spot
"""

import math
import os
import sys

import bpy
from mathutils import Euler, Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rig  # noqa: E402

A = rig.args()
rig.install_addon(A["addon"])
views = sys.modules["conceptmesh_blender.views"]
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


IMG = bpy.data.images.load(os.path.join(A["examples"], "front.png"))


def empty(name, rot_deg, parent=None, scale=(1, 1, 1)):
    e = bpy.data.objects.new(name, None)
    e.empty_display_type = "IMAGE"
    e.data = IMG
    e.empty_display_size = 2.0
    e.rotation_euler = Euler([math.radians(a) for a in rot_deg])
    e.scale = scale
    e.parent = parent
    bpy.context.scene.collection.objects.link(e)
    return e


def read(objs):
    bpy.context.view_layer.update()
    refs = [views.reference_from_empty(o, "x.png") for o in objs]
    frame = views.object_frame(refs)
    return dict(views.describe(refs, frame)), frame


def fresh():
    rig.clear_scene()


BLENDER_VIEWS = rig.view_rotations()

# 1. Blender's six views are the six named views, in Blender's frame (up +Z, front -Y).
fresh()
got, frame = read([empty(n, r) for n, r in BLENDER_VIEWS.items()])
check(got == {n: n for n in BLENDER_VIEWS}, "Blender's views are named views: %s" % got)
check((frame.col[1] - Vector((0, 0, 1))).length < 1e-6 and (frame.col[2] - Vector((0, -1, 0))).length < 1e-6,
      "the object's up is +Z and its front -Y")

# 2. A rig turned about Z and tilted: still front, right, top; the frame turns with the rig.
for rot in [(0, 0, 30), (10, 0, 30), (-35, 20, 140)]:
    fresh()
    parent = bpy.data.objects.new("rig", None)
    bpy.context.scene.collection.objects.link(parent)
    parent.rotation_euler = Euler([math.radians(a) for a in rot])
    parent.scale = (0.7, 0.7, 0.7)
    got, frame = read([empty(n, BLENDER_VIEWS[n], parent) for n in ("front", "right", "top")])
    check(got == {"front": "front", "right": "right", "top": "top"}, "rig turned %s: %s" % (rot, got))
    want_up = parent.matrix_world.to_3x3().normalized() @ Vector((0, 0, 1))
    check((frame.col[1] - want_up).length < 1e-5, "rig turned %s: the up turns with it" % (rot,))

# 3. An oblique drawing: azimuth 45 elevation 30 (front is -Y, right +X in Blender).
fresh()
az, el = math.radians(45), math.radians(30)
toward = Vector((math.sin(az) * math.cos(el), -math.cos(az) * math.cos(el), math.sin(el)))
up = Vector((-math.sin(az) * math.sin(el), math.cos(az) * math.sin(el), math.cos(el)))
right = up.cross(toward)
q = empty("three_quarter", (0, 0, 0))
q.matrix_world = Matrix((right, up, toward)).transposed().to_4x4()
got, _ = read([empty("front", BLENDER_VIEWS["front"]), empty("right", BLENDER_VIEWS["right"]), q])
check(got.get("three_quarter") == "azimuth 45.0, elevation 30.0", "an oblique drawing: %s" % got.get("three_quarter"))

# 3b. Drawings picked by hand: Add Drawing faces each the camera of the view named.
fresh()
bpy.context.scene.cursor.location = (1.0, 2.0, 0.5)
for name in ("front", "right", "top"):
    bpy.ops.conceptmesh.add_drawing(filepath=os.path.join(A["examples"], name + ".png"), view=name, size=1.5)
picked = sorted((o for o in bpy.data.objects if views.is_image_empty(o)), key=lambda o: o.name)
got, _ = read(picked)
check(got == {"front": "front", "right": "right", "top": "top"}, "Add Drawing: %s" % got)
check(all(abs(o.empty_display_size - 1.5) < 1e-9 for o in picked), "Add Drawing: the size given")

# 4. Refusals, naming the reference.
fresh()
try:
    roll = empty("rolled", (90, 15, 0))
    read([empty("front", BLENDER_VIEWS["front"]), empty("top", BLENDER_VIEWS["top"]), empty("right", BLENDER_VIEWS["right"]), roll])
    check(False, "a drawing turned about its line of sight is refused")
except views.ViewsError as e:
    check("rolled" in str(e), "a drawing turned about its line of sight is refused: %s" % e)
fresh()
try:
    read([empty("stretched", BLENDER_VIEWS["front"], scale=(1, 2, 1))])
    check(False, "non-square pixels are refused")
except views.ViewsError as e:
    check("stretched" in str(e) and "not square" in str(e), "non-square pixels are refused: %s" % e)

# 5. The manifest: fixed cameras in full precision, the image point of the frame's origin.
fresh()
objs = [empty(n, BLENDER_VIEWS[n]) for n in ("front", "right", "top")]
objs[0].location = (0.25, 0.5, 0.125)
objs[0].empty_image_offset = (-0.25, -0.75)
bpy.context.view_layer.update()
refs = [views.reference_from_empty(o, "x.png") for o in objs]
frame = views.object_frame(refs)
origin = Vector((0.1, 0.2, 0.3))
entry = views.view_entry(refs[0], frame, origin)
# The empty is 2 units for 512 px; its image's lower-left corner at (-0.5, -1.5) in its plane.
px = 2.0 / 512
want = ((0.1 - (0.25 - 0.5)) / px, ((0.125 + 0.5) - 0.3) / px)
check(entry["view"] == "front" and abs(entry["scale"] - 1 / px) < 1e-6, "front at %.1f px per unit" % entry["scale"])
check(abs(entry["origin"][0] - want[0]) < 1e-4 and abs(entry["origin"][1] - want[1]) < 1e-4,
      "origin %s, expected %s" % (entry["origin"], want))

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("all checks passed")
