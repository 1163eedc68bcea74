"""The operators: conceptmesh.build (modal from the panel, synchronous from scripts) and
conceptmesh.add_drawing."""

import math
import os
import shutil
import tempfile

import bpy
from bpy.props import EnumProperty, FloatProperty, StringProperty
from mathutils import Euler

from . import run, scene, views

# What the last build did, for scripts and tests: state (idle, running, done, error,
# cancelled), overall (0-1), events (count), message, folder, pid, object.
STATUS = {"state": "idle", "overall": 0.0, "events": 0, "message": "", "folder": "", "pid": None, "object": ""}


def _prefs(context):
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon else None


class Job:
    """One build: the references read into a manifest in a folder of its own, the command."""

    def __init__(self, context, executable, which):
        s = context.scene.conceptmesh
        prefs = _prefs(context)
        exe = run.find_executable(executable or (prefs.executable if prefs else ""))
        if s.pipeline == "FILE":
            pipeline = bpy.path.abspath(s.pipeline_file)
            if not os.path.isfile(pipeline):
                raise run.RunError('the pipeline file "%s" does not exist' % (s.pipeline_file or ""))
        else:
            pipeline = run.bundled_pipeline(s.pipeline)
        self.folder = tempfile.mkdtemp(prefix="conceptmesh-")
        try:
            objs = scene.references(context, which)
            self.refs, self.frame, self.origin = scene.read_references(objs, self.folder)
            self.name = s.asset_name or views.asset_name_from([r.image_path for r in self.refs])
            manifest = views.write_manifest(os.path.join(self.folder, "views.yaml"), self.refs, self.frame, self.origin)
            self.mesh_path = os.path.join(self.folder, "out", _file_name(self.name) + ".obj")
            sets = ["hull.resolution=%d" % s.resolution, "smooth.iterations=%d" % s.smoothing]
            if s.face_budget > 0:
                sets.append("reduce.target_faces=%d" % s.face_budget)
            self.cmd = run.command(exe, pipeline, manifest, self.mesh_path, sets)
            self.target = scene.find_target(context, self.name, s.target)
            self.run = None
        except BaseException:
            self.cleanup()
            raise

    def start(self):
        self.run = run.Run(self.cmd, self.folder)
        STATUS.update(state="running", overall=0.0, events=0, message="", folder=self.folder, pid=self.run.proc.pid)

    def note(self, ev):
        STATUS["events"] += 1
        if "overall" in ev:
            STATUS["overall"] = float(ev["overall"])

    def finish(self, context):
        """After the command ended: the mesh into the scene, or the one-line error."""
        ok = self.run.proc.returncode == 0 and (self.run.end or {}).get("status") == "ok"
        if not ok:
            raise run.RunError(self.run.error_line())
        imported = scene.import_obj(self.mesh_path)
        obj = scene.place_result(context, imported, self.name, views.placement(self.frame, self.origin), self.target)
        context.scene.conceptmesh.target = obj
        for o in context.view_layer.objects:
            o.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        STATUS.update(state="done", overall=1.0, object=obj.name, message="")
        return obj

    def cleanup(self):
        shutil.rmtree(self.folder, ignore_errors=True)


def _file_name(name):
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name) or "conceptmesh"


REFERENCE_CHOICES = [
    ("AUTO", "Auto", "The selected reference images, or all of them when none is selected"),
    ("SELECTED", "Selected", "The selected reference images"),
    ("ALL", "All", "Every reference image in the view layer"),
]


class CONCEPTMESH_OT_build(bpy.types.Operator):
    """Build a mesh from the scene's reference images and place it on them"""

    bl_idname = "conceptmesh.build"
    bl_label = "Build"
    bl_options = {"REGISTER", "UNDO"}

    executable: StringProperty(
        name="Executable", description="The conceptmesh command (empty: preferences, then beside the add-on, then PATH)"
    )
    references: EnumProperty(name="References", items=REFERENCE_CHOICES, default="AUTO")

    _job = None
    _timer = None

    def _fail(self, text, state="error"):
        STATUS.update(state=state, message=text)
        self.report({"ERROR"} if state == "error" else {"WARNING"}, text)
        return {"CANCELLED"}

    def execute(self, context):
        """Synchronous: scripts and background mode (blender -b) wait for the result."""
        try:
            job = Job(context, self.executable, self.references)
        except (views.ViewsError, run.RunError, OSError) as e:
            return self._fail(str(e))
        try:
            job.start()
            job.run.wait(job.note)
            job.finish(context)
        except (views.ViewsError, run.RunError, OSError, RuntimeError) as e:
            return self._fail(str(e))
        finally:
            job.cleanup()
        return {"FINISHED"}

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        try:
            self._job = Job(context, self.executable, self.references)
            self._job.start()
        except (views.ViewsError, run.RunError, OSError) as e:
            if self._job:
                self._job.cleanup()
            return self._fail(str(e))
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        self._status(context, "starting")
        return {"RUNNING_MODAL"}

    def _status(self, context, text):
        if context.workspace:
            context.workspace.status_text_set("conceptmesh: %s (Esc: cancel)" % text if text else None)

    def _end(self, context):
        wm = context.window_manager
        if self._timer:
            wm.event_timer_remove(self._timer)
            self._timer = None
        wm.progress_end()
        self._status(context, None)
        self._job.cleanup()

    def modal(self, context, event):
        job = self._job
        if event.type == "ESC" and event.value == "PRESS":
            job.run.cancel()
            self._end(context)
            return self._fail("conceptmesh: build cancelled; the scene is as it was", state="cancelled")
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        for ev in job.run.poll():
            job.note(ev)
            if ev.get("event") in ("progress", "start"):
                pct = 100.0 * float(ev.get("fraction", 0.0))
                self._status(context, "%s (%s) %d%%" % (ev.get("node", ""), ev.get("stage", ""), pct))
        context.window_manager.progress_update(100.0 * STATUS["overall"])
        if not job.run.finished():
            return {"PASS_THROUGH"}
        try:
            obj = job.finish(context)
        except (views.ViewsError, run.RunError, OSError, RuntimeError) as e:
            self._end(context)
            return self._fail(str(e))
        self._end(context)
        self.report({"INFO"}, 'conceptmesh: built "%s"' % obj.name)
        return {"FINISHED"}


VIEW_ROTATIONS = {  # Blender's own views: the drawing faces the camera of that view
    "front": (90, 0, 0),
    "back": (90, 0, 180),
    "right": (90, 0, 90),
    "left": (90, 0, -90),
    "top": (0, 0, 0),
    "bottom": (180, 0, 0),
}


class CONCEPTMESH_OT_add_drawing(bpy.types.Operator):
    """Add a drawing from a file as a reference image facing its view, at the 3D cursor"""

    bl_idname = "conceptmesh.add_drawing"
    bl_label = "Add Drawing"
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(subtype="FILE_PATH")
    filter_image: bpy.props.BoolProperty(default=True, options={"HIDDEN", "SKIP_SAVE"})
    view: EnumProperty(name="View", items=[(k, k.capitalize(), "The drawing is the %s view" % k) for k in VIEW_ROTATIONS])
    size: FloatProperty(name="Size", default=2.0, min=1e-6, description="The drawing's larger side in scene units")

    def execute(self, context):
        try:
            img = bpy.data.images.load(bpy.path.abspath(self.filepath), check_existing=True)
        except RuntimeError as e:
            self.report({"ERROR"}, 'cannot read "%s": %s' % (self.filepath, e))
            return {"CANCELLED"}
        obj = bpy.data.objects.new(os.path.splitext(os.path.basename(self.filepath))[0] or self.view, None)
        obj.empty_display_type = "IMAGE"
        obj.data = img
        obj.empty_display_size = self.size
        obj.rotation_euler = Euler([math.radians(a) for a in VIEW_ROTATIONS[self.view]])
        # Behind the object as that view sees it, so the model is built in front of it.
        toward = obj.rotation_euler.to_matrix().col[2]
        obj.location = context.scene.cursor.location - toward * (self.size / 2)
        context.collection.objects.link(obj)
        return {"FINISHED"}

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}


classes = (CONCEPTMESH_OT_build, CONCEPTMESH_OT_add_drawing)
