"""From the scene to a build and back: the references to use, their image files, and the
built mesh imported, placed on the drawings and put into the asset's object."""

import os
import re

import bpy
from mathutils import Matrix

from . import views

MARK = "conceptmesh_asset"  # custom property on the objects and materials the add-on makes


def references(context, which="AUTO"):
    """The image empties to build from: the selected ones when any is selected (AUTO), or
    every one in the view layer, in name order (the first view sets nothing: the cameras are
    fixed, but the order is the manifest's)."""
    everything = [o for o in context.view_layer.objects if views.is_image_empty(o)]
    selected = [o for o in everything if o.select_get()]
    chosen = selected if which == "SELECTED" or (which == "AUTO" and selected) else everything
    return sorted(chosen, key=lambda o: o.name)


def image_file(obj, folder):
    """A file conceptmesh can read for the empty's image: its own file, or (packed or
    generated in Blender) a copy written into `folder`."""
    img = obj.data
    safe = re.sub(r"[^A-Za-z0-9_.-]", "_", img.name)
    if img.packed_file is not None:
        ext = os.path.splitext(img.filepath)[1] or ".png"
        path = os.path.join(folder, "packed-" + safe + ext)
        with open(path, "wb") as f:
            f.write(img.packed_file.data)
        return path
    # "//" paths are relative to the .blend; others (a script's) to the working folder.
    path = os.path.abspath(bpy.path.abspath(img.filepath, library=img.library)) if img.filepath else ""
    if path and os.path.isfile(path):
        return os.path.normpath(path)
    if img.source == "GENERATED" or (img.has_data and not path):
        path = os.path.join(folder, "image-" + safe + ".png")
        img.save_render(path)
        return path
    raise views.ViewsError('reference "%s": its image file "%s" does not exist' % (obj.name, path or img.name))


def read_references(objs, folder):
    if not objs:
        raise views.ViewsError(
            "no reference images in the scene: add the drawings with Add > Image > Reference "
            "(or the panel's Add Drawing)"
        )
    refs = [views.reference_from_empty(o, image_file(o, folder)) for o in objs]
    frame = views.object_frame(refs)
    origin = views.frame_origin(refs)
    return refs, frame, origin


def import_obj(path):
    """The mesh object read from conceptmesh's OBJ (with its .mtl and texture), its data in
    Blender's axes (the file's Y up becomes Z up) and its transform the identity."""
    before = set(bpy.data.objects)
    if hasattr(bpy.ops.wm, "obj_import"):  # Blender 3.3 and later
        bpy.ops.wm.obj_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
    else:
        bpy.ops.import_scene.obj(filepath=path, axis_forward="-Z", axis_up="Y")
    new = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
    if len(new) != 1:
        raise views.ViewsError('reading "%s" gave %d meshes, not one' % (path, len(new)))
    obj = new[0]
    # Some importers turn the object, others the data: the data takes the turn either way.
    obj.data.transform(obj.matrix_basis)
    obj.matrix_basis = Matrix.Identity(4)
    for mat in obj.data.materials:
        if mat is None:
            continue
        mat[MARK] = True
        if mat.node_tree:
            for node in mat.node_tree.nodes:
                if node.type == "TEX_IMAGE" and node.image and not node.image.packed_file:
                    node.image.pack()  # the run's folder goes away; the texture stays in the .blend
    return obj


def find_target(context, name, target):
    if target is not None and target.type == "MESH" and target.name in context.scene.objects:
        return target
    for o in context.scene.objects:
        if o.type == "MESH" and o.get(MARK) == name:
            return o
    return None


def place_result(context, imported, name, matrix, target):
    """Puts the imported mesh into the asset's object: a new object named after the asset,
    or, on a re-build, the existing one with its new mesh (its name, modifiers, transform
    parenting aside, and the materials the user gave it stay)."""
    mesh = imported.data
    if target is None:
        imported.name = name
        mesh.name = name
        obj = imported
    else:
        old = target.data
        for i, m in enumerate(old.materials):
            if m is not None and not m.get(MARK):  # the user's: kept in its slot
                if i < len(mesh.materials):
                    mesh.materials[i] = m
                else:
                    mesh.materials.append(m)
        ours = [m for m in old.materials if m is not None and m.get(MARK)]
        old_name = old.name
        target.data = mesh
        bpy.data.objects.remove(imported)
        if old.users == 0:
            bpy.data.meshes.remove(old)
        mesh.name = old_name
        for m in ours:
            if m.users == 0:
                bpy.data.materials.remove(m)
        obj = target
    obj.matrix_world = matrix
    obj[MARK] = name
    return obj
