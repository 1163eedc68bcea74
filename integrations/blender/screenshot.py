"""The README's picture of the add-on: Blender's viewport with the bundled example's three
drawings as reference images and the model built on them (paper pipeline), seen from a
three-quarter angle, the conceptmesh tab open in the sidebar. Needs a window (OpenGL):

xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup --enable-event-simulate -p 0 0 1600 1000
    --python integrations/blender/screenshot.py -- --addon build/release/conceptmesh_blender.zip
    --exe build/release/bin/conceptmesh --examples examples/spot --out docs/images/blender.png
"""

import math
import os
import sys

import bpy
from mathutils import Euler, Vector

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "blender"))
import rig  # noqa: E402

A = rig.args()
bpy.context.preferences.view.show_splash = False
rig.install_addon(A["addon"])
rig.clear_scene()
rig.RIG_LOCATION, rig.RIG_ROTATION, rig.RIG_SCALE = (0, 0, 1.25), (0, 0, 0), 1.0
_, empties = rig.build_rig(A["examples"])
s = bpy.context.scene.conceptmesh
s.pipeline = "paper"
s.resolution = 256


def view3d():
    win = bpy.context.window_manager.windows[0]
    area = max((a for a in win.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    return win, area, next(r for r in area.regions if r.type == "WINDOW")


def setup():
    r = bpy.ops.conceptmesh.build(executable=A["exe"])
    if r != {"FINISHED"}:
        print("build failed")
        os._exit(1)
    bpy.app.timers.register(frame, first_interval=1.0)


def frame():
    win, area, region = view3d()
    space = area.spaces.active
    space.shading.type = "SOLID"
    space.shading.color_type = "MATERIAL"
    space.show_region_ui = True
    space.overlay.show_floor = True
    r3d = space.region_3d
    r3d.view_perspective = "PERSP"
    r3d.view_rotation = Euler((math.radians(70), 0, math.radians(42))).to_quaternion()
    r3d.view_location = Vector((0.15, 0.0, 1.1))
    r3d.view_distance = 5.6
    bpy.context.view_layer.objects.active = bpy.data.objects.get("spot")
    bpy.app.timers.register(open_tab, first_interval=1.0)


def open_tab():
    # Blender 3.4 cannot choose a sidebar tab from Python: click it (--enable-event-simulate).
    win, area, region = view3d()
    ui = next(r for r in area.regions if r.type == "UI")
    x, y = ui.x + ui.width - 12, ui.y + ui.height - 180
    print("tab click at", x, y, "ui", ui.x, ui.y, ui.width, ui.height)
    win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    win.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
    win.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
    bpy.app.timers.register(shoot, first_interval=2.0)


def shoot():
    win, area, region = view3d()
    with bpy.context.temp_override(window=win, area=area, region=region):
        bpy.ops.screen.screenshot_area(filepath=os.path.abspath(A["out"]))
    print("wrote", A["out"])
    os._exit(0)


bpy.app.timers.register(setup, first_interval=1.0)
