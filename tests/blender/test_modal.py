"""The add-on's modal build in a real Blender window (under xvfb-run, with
--enable-event-simulate): progress comes in while Blender keeps running, Esc cancels (the
command stops, no object, no file, the scene as it was), and a build left to finish lands
its object.

xvfb-run -a blender --factory-startup --enable-event-simulate --python-exit-code 1
    --python tests/blender/test_modal.py -- --addon ZIP --exe BIN --examples examples/spot
"""

import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rig  # noqa: E402

A = rig.args()
failures = []
T0 = time.monotonic()


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def leave():
    print(("%d check(s) failed" % len(failures)) if failures else "all checks passed", flush=True)
    os._exit(1 if failures else 0)


addon = rig.install_addon(A["addon"])
STATUS = sys.modules["conceptmesh_blender.ops"].STATUS
rig.clear_scene()
rig.build_rig(A["examples"])
before = sorted(o.name for o in bpy.data.objects)
meshes_before = sorted(m.name for m in bpy.data.meshes)


def view3d():
    win = bpy.context.window_manager.windows[0]
    for area in win.screen.areas:
        if area.type == "VIEW_3D":
            region = next(r for r in area.regions if r.type == "WINDOW")
            return win, area, region
    raise RuntimeError("no 3D view")


def invoke():
    win, area, region = view3d()
    with bpy.context.temp_override(window=win, area=area, region=region):
        return bpy.ops.conceptmesh.build("INVOKE_DEFAULT", executable=A["exe"])


state = {"step": "cancel-start", "progress_seen": 0.0, "ticks_while_running": 0}


def tick():
    if time.monotonic() - T0 > 240:
        check(False, "the test finished within 4 minutes (at step %s)" % state["step"])
        leave()
    step = state["step"]
    if step == "cancel-start":
        bpy.context.scene.conceptmesh.resolution = 1024  # long enough to cancel mid-run
        r = invoke()
        check(r == {"RUNNING_MODAL"}, "the build runs modal: %s" % r)
        state["step"] = "cancel-wait"
        return 0.05
    if step == "cancel-wait":
        # Blender's timers run while the build runs: it is not frozen. Esc once the build is
        # past 0.3 and at least two ticks saw it running (a fast start can pass 0.3 before the
        # second tick on a busy machine); a build no longer running goes to the checks at once.
        if STATUS["state"] == "running":
            state["ticks_while_running"] += 1
            if STATUS["overall"] <= 0.3 or state["ticks_while_running"] < 2:
                return 0.05
        state["progress_seen"] = STATUS["overall"]
        state["pid"], state["folder"] = STATUS["pid"], STATUS["folder"]
        bpy.context.window_manager.windows[0].event_simulate(type="ESC", value="PRESS")
        state["step"] = "cancel-check"
        return 0.5
    if step == "cancel-check":
        check(state["progress_seen"] > 0.3, "progress reported before Esc: %.2f" % state["progress_seen"])
        check(state["ticks_while_running"] >= 2, "Blender kept running (%d timer ticks)" % state["ticks_while_running"])
        check(STATUS["state"] == "cancelled", "Esc cancelled the build: %s" % STATUS["state"])
        alive = True
        try:
            os.kill(state["pid"], 0)
        except ProcessLookupError:
            alive = False
        check(not alive, "the conceptmesh process is gone")
        check(not os.path.exists(state["folder"]), "no file left (the run's folder is removed)")
        check(sorted(o.name for o in bpy.data.objects) == before, "the scene is as it was")
        check(sorted(m.name for m in bpy.data.meshes) == meshes_before, "no mesh data left behind")
        bpy.context.scene.conceptmesh.resolution = 128
        check(invoke() == {"RUNNING_MODAL"}, "a second build runs modal")
        state["step"] = "finish-wait"
        return 0.1
    if step == "finish-wait":
        if STATUS["state"] == "running":
            return 0.1
        check(STATUS["state"] == "done", "the build finished: %s %s" % (STATUS["state"], STATUS["message"]))
        obj = bpy.data.objects.get("spot")
        check(obj is not None and obj.type == "MESH" and len(obj.data.polygons) > 1000, "the object is in the scene")
        leave()
    return None


bpy.app.timers.register(tick, first_interval=1.0)
