#!/usr/bin/env python3
"""The peers of bench/reproduce, each a whole process timed from outside (/usr/bin/time -v):

  peers.py dense  VIEWS_YAML RES OUT.obj TARGET_FACES
      the dense script a user would write: numpy carve of a RES grid (along the longest side
      of the views' bounds), scikit-image marching cubes, Open3D Laplacian smoothing (10
      iterations) and quadric decimation to TARGET_FACES;
  peers.py vdb    VIEWS_YAML RES OUT.obj
      the same numpy carve, meshed by OpenVDB's volumeToMesh (pyopenvdb convertToPolygons);
  peers.py o3d    VIEWS_YAML RES
      Open3D's VoxelGrid.carve_silhouette over the same grid (carve only, no mesh): each view
      as a pinhole camera 1000 bounding-box diagonals away, which is orthographic to within
      a thousandth of a pixel.

Views are orthographic with scale and origin (conceptmesh render-views manifests), cameras as
docs/conventions.md. Bench code only: never a dependency of the product.
"""
import math
import sys

import numpy as np
import yaml

NAMED = {"front": (0, 0), "right": (90, 0), "back": (180, 0), "left": (270, 0), "top": (0, 90), "bottom": (0, -90)}


def axes(az, el):
    az, el = math.radians(az), math.radians(el)
    c = np.array([math.sin(az) * math.cos(el), math.sin(el), math.cos(az) * math.cos(el)])
    d = -c
    u = np.array([-math.sin(az) * math.sin(el), math.cos(el), -math.cos(az) * math.sin(el)])
    return d, u, np.cross(d, u)


def load_views(path):
    import os
    from PIL import Image
    m = yaml.safe_load(open(path))
    base = os.path.dirname(path)
    views = []
    for name, v in m["views"].items():
        az, el = NAMED[name] if name in NAMED else (v["azimuth"], v["elevation"])
        grey = np.asarray(Image.open(os.path.join(base, v["image"])).convert("L"))
        img = (grey >= 128) if grey[0, 0] < 128 else (grey < 128)  # the object: unlike the corner
        d, u, r = axes(v.get("azimuth", az), v.get("elevation", el))
        views.append({"mask": img, "s": float(v["scale"]), "o": v["origin"], "d": d, "u": u, "r": r})
    return views, np.array(m["bounds"], dtype=float)


def grid(bounds, res):
    lo, hi = bounds[:3], bounds[3:]
    h = (hi - lo).max() / res
    n = np.maximum(1, np.ceil((hi - lo) / h).astype(int))
    return lo, h, n


def carve(views, bounds, res):
    """Occupancy of the voxel centres, a (nx, ny, nz) bool array, carved one z slice at a time."""
    lo, h, n = grid(bounds, res)
    xs = lo[0] + (np.arange(n[0]) + 0.5) * h
    ys = lo[1] + (np.arange(n[1]) + 0.5) * h
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    occ = np.zeros(tuple(n), dtype=bool)
    for k in range(n[2]):
        z = lo[2] + (k + 0.5) * h
        inside = np.ones(X.shape, dtype=bool)
        for v in views:
            px = v["o"][0] + v["s"] * (X * v["r"][0] + Y * v["r"][1] + z * v["r"][2])
            py = v["o"][1] - v["s"] * (X * v["u"][0] + Y * v["u"][1] + z * v["u"][2])
            i, j = np.floor(px).astype(np.int64), np.floor(py).astype(np.int64)
            hgt, wid = v["mask"].shape
            ok = (i >= 0) & (j >= 0) & (i < wid) & (j < hgt)
            m = np.zeros(X.shape, dtype=bool)
            m[ok] = v["mask"][j[ok], i[ok]]
            inside &= m
        occ[:, :, k] = inside
    return occ, lo, h


def write_obj(path, verts, faces):
    with open(path, "w") as f:
        np.savetxt(f, verts, fmt="v %.7g %.7g %.7g")
        np.savetxt(f, faces + 1, fmt="f %d %d %d")


def dense(views_yaml, res, out, target):
    import open3d as o3d
    from skimage import measure
    views, bounds = load_views(views_yaml)
    occ, lo, h = carve(views, bounds, res)
    vol = np.pad(occ, 1).astype(np.float32)
    verts, faces, _, _ = measure.marching_cubes(vol, 0.5)
    verts = lo + (verts - 1 + 0.5) * h
    m = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(verts), o3d.utility.Vector3iVector(faces[:, ::-1]))
    m = m.filter_smooth_laplacian(number_of_iterations=10)
    m = m.simplify_quadric_decimation(target_number_of_triangles=int(target))
    write_obj(out, np.asarray(m.vertices), np.asarray(m.triangles))
    print("faces_mc %d faces %d" % (len(faces), len(m.triangles)))


def vdb(views_yaml, res, out):
    import pyopenvdb as vdb
    views, bounds = load_views(views_yaml)
    occ, lo, h = carve(views, bounds, res)
    g = vdb.FloatGrid()
    g.copyFromArray(np.pad(occ, 1).astype(np.float32))
    pts, tris, quads = g.convertToPolygons(isovalue=0.5)
    tris = np.asarray(tris).reshape(-1, 3)
    quads = np.asarray(quads).reshape(-1, 4)
    faces = np.concatenate([tris, quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    verts = lo + (np.asarray(pts) - 1 + 0.5) * h
    write_obj(out, verts, faces[:, ::-1])
    print("faces %d" % len(faces))


def o3d_carve(views_yaml, res):
    import open3d as o3d
    views, bounds = load_views(views_yaml)
    lo, h, n = grid(bounds, res)
    vg = o3d.geometry.VoxelGrid.create_dense(origin=lo, color=[0.5, 0.5, 0.5], voxel_size=h,
                                             width=n[0] * h, height=n[1] * h, depth=n[2] * h)
    centre = (bounds[:3] + bounds[3:]) / 2
    far = 1000 * np.linalg.norm(bounds[3:] - bounds[:3])
    for v in views:
        hgt, wid = v["mask"].shape
        f = v["s"] * far  # focal length in px giving the view's scale at the object
        cam = o3d.camera.PinholeCameraParameters()
        # Principal point: where the line of sight through the bounding-box centre lands.
        cx = v["o"][0] + v["s"] * centre.dot(v["r"])
        cy = v["o"][1] - v["s"] * centre.dot(v["u"])
        cam.intrinsic = o3d.camera.PinholeCameraIntrinsic(wid, hgt, f, f, cx, cy)
        eye = centre - far * v["d"]
        R = np.stack([v["r"], -v["u"], v["d"]])  # camera x right, y down, z forward
        ext = np.eye(4)
        ext[:3, :3] = R
        ext[:3, 3] = -R @ eye
        cam.extrinsic = ext
        sil = o3d.geometry.Image(v["mask"].astype(np.float32))
        vg.carve_silhouette(sil, cam, keep_voxels_outside_image=False)
    print("voxels %d" % len(vg.get_voxels()))


if __name__ == "__main__":
    mode = sys.argv[1]
    if mode == "dense":
        dense(sys.argv[2], int(sys.argv[3]), sys.argv[4], int(sys.argv[5]))
    elif mode == "vdb":
        vdb(sys.argv[2], int(sys.argv[3]), sys.argv[4])
    elif mode == "o3d":
        o3d_carve(sys.argv[2], int(sys.argv[3]))
    else:
        sys.exit("unknown peer " + mode)
