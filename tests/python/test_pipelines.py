"""Every bundled pipeline through the module gives the bytes the command gives, and the
result holds every node's output, its metrics and the --report JSON."""

import json
import pathlib

import numpy as np
import pytest

from conftest import SOURCE_DIR, output_params, run_cli

PIPELINES = sorted(p.name for p in (SOURCE_DIR / "pipelines").glob("*.yaml"))


@pytest.mark.parametrize("name", PIPELINES)
def test_bundled_pipeline_same_bytes_as_the_command(cm, tmp_path, name):
    file = f"pipelines/{name}"
    nodes = cm.Pipeline.load(file).nodes
    outputs = output_params(nodes, cm.stage_info)
    assert outputs, f"{name} writes files"

    def overrides(folder):
        return {f"{node}.{param}": str(folder / pathlib.Path(path).name) for node, param, path in outputs}

    cli_dir, py_dir = tmp_path / "cli", tmp_path / "py"
    cli_dir.mkdir()
    py_dir.mkdir()
    args = ["run", "-q", file, "--report", str(cli_dir / "report.json")]
    for k, v in overrides(cli_dir).items():
        args += ["--set", f"{k}={v}"]
    r = run_cli(*args)
    assert r.returncode == 0, r.stderr

    threads = []
    import threading
    result = cm.Pipeline.load(file, set=overrides(py_dir)).run(
        progress=lambda e: threads.append(threading.get_ident()), report=py_dir / "report.json")
    assert threads and set(threads) == {threading.get_ident()}, "progress comes on the calling thread"

    for node, param, path in outputs:
        a = (cli_dir / pathlib.Path(path).name).read_bytes()
        b = (py_dir / pathlib.Path(path).name).read_bytes()
        assert a == b, f"{name}: {node}.{param} differs between the command and the module"
    assert sorted(p.name for p in py_dir.iterdir()) == sorted(p.name for p in cli_dir.iterdir())

    # The result: every node's output, its metrics, and the report --report writes.
    ids = [n["id"] for n in nodes]
    assert sorted(result.outputs) == sorted(ids)
    assert all(result.outputs[i] is not None for i in ids)
    report = json.loads((py_dir / "report.json").read_text())
    assert result.report == (py_dir / "report.json").read_text(), "Result.report is the JSON --report wrote"
    cli_report = json.loads((cli_dir / "report.json").read_text())
    assert [n["id"] for n in report["nodes"]] == [n["id"] for n in cli_report["nodes"]]
    for mine, theirs in zip(report["nodes"], cli_report["nodes"]):
        assert mine["metrics"].keys() == theirs["metrics"].keys()
        assert result.metrics[mine["id"]] == mine["metrics"]
    mesh = result.mesh
    assert isinstance(mesh, cm.Mesh) and len(mesh.faces) > 0
    if name == "textured.yaml":
        tex = mesh.texture
        assert tex is not None and tex.ndim == 3 and tex.shape[2] in (3, 4)
        assert mesh.corner_uvs is not None and mesh.corner_uvs.shape == (len(mesh.faces), 3, 2)


def test_views_volume_and_chained_pipeline(cm, tmp_path):
    """paper.yaml built from stages in Python gives the mesh the file gives; the views come out
    as images with cameras, the hull as a .vdb (and a pyopenvdb grid where it is installed)."""
    base = {"hull.resolution": 96, "write.path": str(tmp_path / "a.obj"), "preview.path": str(tmp_path / "a.png")}
    loaded = cm.Pipeline.load("pipelines/paper.yaml", set=base).run()

    views = loaded.outputs["views"]
    assert isinstance(views, cm.Views) and views.names == ["front", "right", "top"]
    front = views["front"]
    assert front.image.ndim == 3 and front.image.shape[:2] == front.coverage.shape
    assert front.camera["matrix"].shape == (3, 4) and front.camera["kind"] == "orthographic"
    assert 0 < front.coverage.mean() < 1

    chain = (cm.stage("views.load", id="views", manifest="examples/spot/views.yaml")
             | cm.stage("hull.carve", id="hull", resolution=96)
             | cm.stage("hull.marching_intersections", id="refine")
             | cm.stage("extract.marching_cubes", id="surface", check="off")
             | cm.stage("mesh.laplacian_smooth", id="smooth", iterations=10, constrain="hull")
             | cm.stage("mesh.reduce", id="reduce", max_angle_deg=20, crease_straightness=2, constrain="silhouette"))
    assert [n["inputs"] for n in chain.nodes][2] == {"volume": "hull", "views": "views"}
    built = chain.run()
    np.testing.assert_array_equal(built.outputs["reduce"].vertices, loaded.outputs["reduce"].vertices)
    np.testing.assert_array_equal(built.outputs["reduce"].faces, loaded.outputs["reduce"].faces)

    # Only the outputs asked for.
    only = cm.Pipeline.load("pipelines/paper.yaml", set=base).run(keep=["reduce"])
    assert isinstance(only.outputs["reduce"], cm.Mesh) and only.outputs["hull"] is None

    # In-memory views into a pipeline, and numpy images in as views.
    again = (views | cm.stage("hull.carve", resolution=96)).run()
    hull = again.outputs["carve"]
    assert isinstance(hull, cm.Volume) and hull.active_voxels == loaded.outputs["hull"].active_voxels
    from_images = cm.views_from_images({v.name: np.asarray(v.image) for v in views})
    np.testing.assert_array_equal(from_images["right"].coverage, views["right"].coverage)
    # A view by its camera rather than its name: azimuth 90 is the right view.
    by_camera = cm.views_from_images({"front": views["front"].image, "side": (views["right"].image, {"azimuth": 90}),
                                      "top": views["top"].image})
    np.testing.assert_array_equal(by_camera["side"].camera["matrix"], views["right"].camera["matrix"])

    vdb = hull.save(tmp_path / "hull.vdb")
    assert pathlib.Path(vdb).stat().st_size > 0
    try:
        import pyopenvdb  # noqa: F401
    except ImportError:
        pytest.skip("pyopenvdb (python3-openvdb) is not installed: Volume.grid() is optional")
    grid = hull.grid()
    assert grid.activeVoxelCount() > 0
