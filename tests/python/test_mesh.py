"""Meshes as numpy: handed out without copying, and taken in from a TD's own arrays."""

import gc
import weakref

import numpy as np
import pytest


def icosphere(subdivisions=3):
    """A closed unit sphere of triangles, built in numpy (as a TD's own mesh would be)."""
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
         (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        mid = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = verts[a] + verts[b]
                verts.append(p / np.linalg.norm(p))
                mid[key] = len(verts) - 1
            return mid[key]

        nf = []
        for a, b, c in f:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return np.array(verts, np.float32), np.array(f, np.int64)


def test_mesh_arrays_are_views_of_the_cpp_mesh(cm):
    v, f = icosphere(2)
    mesh = cm.Mesh(v, f)
    a = mesh.vertices
    assert a.shape == (len(v), 3) and a.dtype == np.float32
    assert mesh.faces.shape == (len(f), 3) and mesh.faces.dtype == np.uint32
    np.testing.assert_array_equal(a, v)
    np.testing.assert_array_equal(mesh.faces, f)
    # Zero-copy: the base is a capsule that owns the C++ mesh, and two arrays share its memory.
    assert type(a.base).__name__ == "PyCapsule"
    b = mesh.vertices
    assert a.__array_interface__["data"][0] == b.__array_interface__["data"][0]
    assert not a.flags.writeable and not a.flags.owndata
    with pytest.raises(ValueError):
        a[0, 0] = 1.0
    # The array keeps the mesh alive once the Python Mesh is gone.
    expected = v.copy()
    del mesh, b
    gc.collect()
    np.testing.assert_array_equal(a, expected)


def test_numpy_mesh_through_reduce_and_back(cm):
    v, f = icosphere(4)  # 5120 faces
    mesh = cm.Mesh(v, f)
    events = []
    reducer = cm.stage("mesh.reduce", max_angle_deg=20)
    run = reducer.run(mesh, progress=events.append)
    out = run.output
    assert isinstance(out, cm.Mesh)
    assert 0 < len(out.faces) < len(f)
    assert out.faces.max() < len(out.vertices)
    # Every face a real triangle, every vertex still on the sphere.
    ff = out.faces.astype(np.int64)
    assert np.all((ff[:, 0] != ff[:, 1]) & (ff[:, 1] != ff[:, 2]) & (ff[:, 0] != ff[:, 2]))
    r = np.linalg.norm(out.vertices, axis=1)
    assert np.all(np.abs(r - 1) < 0.05)
    assert run.metrics, "the stage reports its figures"
    assert any(e.kind == "started" for e in events) or any(e.kind == "progress" for e in events)
    # The call form gives the output alone, the same mesh.
    again = reducer(mesh)
    np.testing.assert_array_equal(again.faces, out.faces)
    # Back into another stage.
    smoothed = cm.stage("mesh.laplacian_smooth", iterations=2)(out)
    assert smoothed.vertices.shape == out.vertices.shape


def test_optional_arrays(cm):
    v, f = icosphere(1)
    n = v / np.linalg.norm(v, axis=1, keepdims=True)
    colors = np.ones((len(v), 4), np.float32)
    corner = np.zeros((len(f), 3, 2), np.float32)
    tex = np.zeros((4, 8, 4), np.uint8)
    m = cm.Mesh(v, f, normals=n, colors=colors, corner_uvs=corner, texture=tex)
    assert m.normals.shape == v.shape
    assert m.colors.shape == (len(v), 4)
    assert m.corner_uvs.shape == (len(f), 3, 2)
    assert m.texture.shape == (4, 8, 4) and m.texture.dtype == np.uint8
    assert m.uvs is None
    assert cm.Mesh(v, f).normals is None


def test_bad_arrays_are_value_errors(cm):
    v, f = icosphere(0)
    with pytest.raises(ValueError, match="shape"):
        cm.Mesh(v[:, :2], f)
    bad = f.copy()
    bad[3, 1] = len(v)
    with pytest.raises(ValueError, match=r"faces\[3\]"):
        cm.Mesh(v, bad)
    bad = f.copy()
    bad[2] = (1, 1, 2)
    with pytest.raises(ValueError, match="degenerate"):
        cm.Mesh(v, bad)
    with pytest.raises(ValueError, match="one row per vertex"):
        cm.Mesh(v, f, normals=v[:3])


def test_numpy_mesh_into_a_pipeline_with_a_writer(cm, tmp_path):
    v, f = icosphere(3)
    p = cm.Mesh(v, f) | cm.stage("mesh.reduce", max_angle_deg=20) | cm.stage("mesh.write", path=str(tmp_path / "m.obj"))
    assert [n["stage"] for n in p.nodes] == ["memory.mesh", "mesh.reduce", "mesh.write"]
    assert p.nodes[1]["inputs"] == {"mesh": "mesh"} and p.nodes[2]["inputs"] == {"mesh": "reduce"}
    r = p.run()
    assert r.files == [str(tmp_path / "m.obj")]
    text = (tmp_path / "m.obj").read_text()
    assert text.count("\nf ") == len(r.outputs["reduce"].faces)
    assert [n["stage"] for n in r.report_dict["nodes"]] == ["memory.mesh", "mesh.reduce", "mesh.write"]
