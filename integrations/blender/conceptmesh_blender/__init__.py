"""conceptmesh for Blender: builds a mesh from the reference images in the scene (front,
side, top or any angle) and places it on them. It runs the conceptmesh command
(docs/blender.md)."""

bl_info = {
    "name": "conceptmesh",
    "author": "conceptmesh",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > conceptmesh",
    "description": "A mesh from the reference drawings in the scene, standing on them",
    "category": "Mesh",
}

import bpy  # noqa: E402

from . import ops, ui  # noqa: E402

_classes = ui.classes + ops.classes


def register():
    for c in _classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.conceptmesh = bpy.props.PointerProperty(type=ui.ConceptmeshSettings)


def unregister():
    del bpy.types.Scene.conceptmesh
    for c in reversed(_classes):
        bpy.utils.unregister_class(c)
