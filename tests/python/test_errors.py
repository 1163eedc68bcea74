"""Errors as Python exceptions: conceptmesh.Error with .node and .stage, OSError for files,
ValueError for parameters, each with the command's one-line message."""

import pytest

from conftest import run_cli


def cli_message(*args):
    r = run_cli(*args)
    assert r.returncode != 0
    line = [l for l in r.stderr.splitlines() if l.startswith("conceptmesh: error: ")][-1]
    return line[len("conceptmesh: error: "):]


def test_missing_pipeline_file_is_an_oserror(cm, tmp_path):
    missing = tmp_path / "nope.yaml"
    with pytest.raises(OSError) as e:
        cm.Pipeline.load(missing)
    assert isinstance(e.value, cm.Error) and isinstance(e.value, cm.FileError)
    assert str(e.value) == cli_message("run", str(missing))


def test_bad_parameter_is_a_value_error_naming_node_and_stage(cm):
    with pytest.raises(ValueError) as e:
        cm.Pipeline.load("pipelines/paper.yaml", set={"hull.resolution": 3}).validate()
    err = e.value
    assert isinstance(err, cm.ParameterError) and isinstance(err, cm.Error)
    assert err.node == "hull" and err.stage == "hull.carve"
    # The command's message, naming where the value came from in Python's terms.
    cli = cli_message("run", "pipelines/paper.yaml", "--set", "hull.resolution=3")
    assert "(from --set)" in cli
    assert str(err) == cli.replace("(from --set)", "(from set= in Python)")


def test_unknown_parameter_of_a_stage(cm):
    with pytest.raises(ValueError, match=r"unknown parameter \"max_angle\" \(from a keyword argument\)"):
        cm.stage("mesh.reduce", max_angle=20)
    with pytest.raises(ValueError, match="unknown stage"):
        cm.stage("mesh.nope")
    with pytest.raises(OSError) as e:
        cm.stage("views.load", manifest="no/such/views.yaml")
    assert e.value.stage == "views.load" and e.value.node is None


def test_missing_input_file_in_a_run(cm, tmp_path):
    manifest = tmp_path / "views.yaml"
    out = tmp_path / "x.obj"
    sets = {"views.manifest": str(manifest), "write.path": str(out), "preview.path": str(tmp_path / "p.png")}
    with pytest.raises(OSError) as e:
        cm.Pipeline.load("pipelines/paper.yaml", set=sets).run()
    assert e.value.node == "views" and e.value.stage == "views.load"
    args = ["run", "pipelines/paper.yaml"] + [a for k, v in sets.items() for a in ("--set", f"{k}={v}")]
    assert str(e.value) == cli_message(*args)
    assert not out.exists()


def test_graph_mistake_names_the_node(cm, tmp_path):
    # A pipeline built in Python whose stage lacks an input.
    import numpy as np
    flat = cm.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32), np.array([[0, 1, 2]]))
    p = cm.Pipeline([flat]) | cm.stage("volume.write", id="vdb", path=str(tmp_path / "v.vdb"))
    with pytest.raises(ValueError) as e:
        p.validate()
    assert "missing input \"volume\"" in str(e.value) and e.value.node == "vdb"


def test_callback_exception_stops_the_run(cm, tmp_path):
    class Stop(Exception):
        pass

    def progress(event):
        if event.kind == "started" and event.node == "hull":
            raise Stop("enough")

    sets = {"write.path": str(tmp_path / "x.obj"), "preview.path": str(tmp_path / "p.png")}
    with pytest.raises(Stop):
        cm.Pipeline.load("pipelines/paper.yaml", set=sets).run(progress=progress)
    assert list(tmp_path.iterdir()) == []
