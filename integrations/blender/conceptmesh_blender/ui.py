"""The panel (3D View > Sidebar > conceptmesh), the scene's settings and the preferences."""

import bpy
from bpy.props import EnumProperty, IntProperty, PointerProperty, StringProperty

from . import run, scene, views

PIPELINES = [
    ("loft", "Loft", "The best model from the drawings: round between the views, machined parts kept: the default"),
    ("paper", "Paper", "The seed paper's method: the visual hull, square in section between the views"),
    ("organic", "Organic", "Rounder volume behind the same outlines: characters, creatures"),
    ("dmc", "Dual Marching Cubes", "Fewer faces, crisp creases: hard-surface props"),
    ("quadric", "Quadric", "Taubin smoothing and quadric decimation"),
    ("textured", "Textured", "The model in the colours of its drawings (a material with the texture)"),
    ("FILE", "File...", "A pipeline file of your own"),
]


class ConceptmeshSettings(bpy.types.PropertyGroup):
    pipeline: EnumProperty(name="Pipeline", items=PIPELINES, default="loft")
    pipeline_file: StringProperty(name="Pipeline File", subtype="FILE_PATH")
    resolution: IntProperty(
        name="Resolution", default=256, min=16, max=4096, description="Grid cells along the largest side (hull.resolution)"
    )
    smoothing: IntProperty(
        name="Smoothing", default=10, min=0, max=1000, description="Smoothing iterations (smooth.iterations)"
    )
    face_budget: IntProperty(
        name="Max Faces", default=0, min=0, description="Reduce to at most this many faces (reduce.target_faces; 0: no limit)"
    )
    asset_name: StringProperty(name="Name", description="The object's name (empty: the drawings' folder)")
    target: PointerProperty(name="Object", type=bpy.types.Object, description="The object a re-build replaces the mesh of")


class ConceptmeshPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    executable: StringProperty(
        name="conceptmesh command",
        subtype="FILE_PATH",
        description="Path of the conceptmesh executable (empty: beside the add-on, then PATH)",
    )

    def draw(self, context):
        self.layout.prop(self, "executable")
        try:
            self.layout.label(text="Using " + run.find_executable(self.executable))
        except run.RunError as e:
            self.layout.label(text=str(e), icon="ERROR")


class CONCEPTMESH_PT_panel(bpy.types.Panel):
    bl_label = "conceptmesh"
    bl_idname = "CONCEPTMESH_PT_panel"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "conceptmesh"

    def draw(self, context):
        s = context.scene.conceptmesh
        layout = self.layout
        box = layout.box()
        objs = scene.references(context)
        box.label(text="References: %d" % len(objs), icon="IMAGE_REFERENCE")
        try:
            if objs:
                refs = [views.reference_from_empty(o, "") for o in objs]
                for name, how in views.describe(refs, views.object_frame(refs)):
                    box.label(text="%s: %s" % (name, how))
        except views.ViewsError as e:
            box.label(text=str(e), icon="ERROR")
        box.operator("conceptmesh.add_drawing", icon="FILE_IMAGE")
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(s, "pipeline")
        if s.pipeline == "FILE":
            layout.prop(s, "pipeline_file")
        layout.prop(s, "resolution")
        layout.prop(s, "smoothing")
        layout.prop(s, "face_budget")
        layout.prop(s, "asset_name")
        layout.prop(s, "target")
        layout.operator("conceptmesh.build", icon="MESH_MONKEY")


classes = (ConceptmeshSettings, ConceptmeshPreferences, CONCEPTMESH_PT_panel)
