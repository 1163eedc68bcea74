"""What the Blender tests share: the add-on installed from the build's zip, the bundled
example's three drawings set up as reference empties on a rig that is moved, turned and
scaled, and an independent measure of a mesh against each drawing (its own projection
through the empty, not the add-on's)."""

import math
import os
import sys

import bpy
import numpy as np
from mathutils import Euler, Matrix, Vector


def args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    out = {}
    for i in range(0, len(argv) - 1, 2):
        out[argv[i].lstrip("-")] = argv[i + 1]
    return out


def install_addon(zip_path):
    bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
    bpy.ops.preferences.addon_enable(module="conceptmesh_blender")
    import conceptmesh_blender  # noqa: F401

    return sys.modules["conceptmesh_blender"]


# The rig: where the drawings are in the scene. Not the identity anywhere: moved, turned
# about the vertical and tilted, and scaled.
RIG_LOCATION = (3.0, -2.0, 1.5)
RIG_ROTATION = (math.radians(10), 0.0, math.radians(30))
RIG_SCALE = 1.3
DRAWING_SIZE = 2.5  # each drawing's side in the rig's units

VIEWS = ("front", "right", "top")


def view_rotations():
    """Blender's own views, as the add-on's Add Drawing turns a drawing to face the camera
    of each (as Add > Image > Reference in that view does); test_views.py checks that they
    read as those views."""
    return sys.modules["conceptmesh_blender.ops"].VIEW_ROTATIONS


def clear_scene():
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)


def build_rig(examples):
    rig = bpy.data.objects.new("rig", None)
    bpy.context.scene.collection.objects.link(rig)
    rig.location = RIG_LOCATION
    rig.rotation_euler = Euler(RIG_ROTATION)
    rig.scale = (RIG_SCALE,) * 3
    empties = []
    for name in VIEWS:
        rot = view_rotations()[name]
        img = bpy.data.images.load(os.path.join(examples, name + ".png"))
        e = bpy.data.objects.new("ref_" + name, None)
        e.empty_display_type = "IMAGE"
        e.data = img
        e.empty_display_size = DRAWING_SIZE
        e.rotation_euler = Euler([math.radians(a) for a in rot])
        toward = e.rotation_euler.to_matrix().col[2]
        e.location = -toward * (DRAWING_SIZE * 0.6)  # behind the object, as the view sees it
        e.parent = rig
        bpy.context.scene.collection.objects.link(e)
        empties.append(e)
    bpy.context.view_layer.update()
    return rig, empties


def drawing_mask(img):
    """The drawing's silhouette: pixels far in colour from the paper (the border's median),
    row 0 at the top."""
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    rgb = px.reshape(h, w, 4)[::-1, :, :3]
    border = np.concatenate([rgb[0], rgb[-1], rgb[:, 0], rgb[:, -1]])
    paper = np.median(border, axis=0)
    return np.linalg.norm(rgb - paper, axis=2) > 0.2


def to_pixels(empty, points):
    """Scene points -> pixel coordinates (x right, y down, pixel centres at +0.5) of the
    empty's image, from Blender's drawing of image empties: the larger side is
    empty_display_size long, the lower-left corner at empty_image_offset."""
    img = empty.data
    w, h = img.size
    big = max(w, h)
    sx, sy = empty.empty_display_size * w / big, empty.empty_display_size * h / big
    ox, oy = empty.empty_image_offset
    inv = empty.matrix_world.inverted()
    local = np.array([(inv @ Vector(p))[:2] for p in points])
    x = (local[:, 0] - sx * ox) / sx * w
    y = (sy * (oy + 1.0) - local[:, 1]) / sy * h
    return np.stack([x, y], axis=1)


def mesh_world(obj):
    m = obj.matrix_world
    verts = [m @ v.co for v in obj.data.vertices]
    obj.data.calc_loop_triangles()
    tris = np.array([t.vertices[:] for t in obj.data.loop_triangles])
    return verts, tris


def rasterise(pts, tris, w, h):
    """Pixels whose centre is inside a projected triangle."""
    out = np.zeros((h, w), dtype=bool)
    for a, b, c in pts[tris]:
        lo = np.floor(np.minimum(np.minimum(a, b), c)).astype(int)
        hi = np.ceil(np.maximum(np.maximum(a, b), c)).astype(int)
        x0, y0 = max(lo[0], 0), max(lo[1], 0)
        x1, y1 = min(hi[0], w), min(hi[1], h)
        if x0 >= x1 or y0 >= y1:
            continue
        gx, gy = np.meshgrid(np.arange(x0, x1) + 0.5, np.arange(y0, y1) + 0.5)

        def edge(p, q):
            return (q[0] - p[0]) * (gy - p[1]) - (q[1] - p[1]) * (gx - p[0])

        e0, e1, e2 = edge(a, b), edge(b, c), edge(c, a)
        inside = ((e0 >= 0) & (e1 >= 0) & (e2 >= 0)) | ((e0 <= 0) & (e1 <= 0) & (e2 <= 0))
        out[y0:y1, x0:x1] |= inside
    return out


def measure(obj, empty):
    """Per drawing: the mesh's extent against the drawing's along image x and y (as a
    fraction of the drawing's), and the silhouette's coverage of the drawing and IoU."""
    verts, tris = mesh_world(obj)
    pts = to_pixels(empty, verts)
    mask = drawing_mask(empty.data)
    h, w = mask.shape
    ys, xs = np.nonzero(mask)
    drawn = np.array([xs.min(), ys.min(), xs.max() + 1, ys.max() + 1], dtype=float)
    built = np.array([pts[:, 0].min(), pts[:, 1].min(), pts[:, 0].max(), pts[:, 1].max()])
    size = np.array([drawn[2] - drawn[0], drawn[3] - drawn[1]] * 2)
    sil = rasterise(pts, tris, w, h)
    both = np.count_nonzero(sil & mask)
    return {
        "extent_error": float(np.max(np.abs(built - drawn) / size)),
        # The middle of the extents: where the mesh is, apart from how far inside the outline.
        "centre_error": float(
            np.max(np.abs((built[:2] + built[2:]) - (drawn[:2] + drawn[2:])) / 2 / size[:2])
        ),
        "drawn": drawn.tolist(),
        "built": built.tolist(),
        "coverage": both / np.count_nonzero(mask),
        "iou": both / np.count_nonzero(sil | mask),
    }
