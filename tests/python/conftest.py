"""Shared by the Python module's tests: the module (skipped with a message when it was not
built), the source tree, the conceptmesh command of the same build."""

import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("CM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
CM_EXE = os.environ.get("CM_EXE", str(SOURCE_DIR / "build/release/bin/conceptmesh"))


@pytest.fixture(scope="session")
def cm():
    try:
        import conceptmesh
    except ImportError as e:
        pytest.skip(f"the conceptmesh module was not built (CONCEPTMESH_PYTHON, pybind11-dev): {e}")
    return conceptmesh


@pytest.fixture(autouse=True)
def in_source_dir(monkeypatch):
    # The bundled pipelines name their inputs relative to the source tree, as the README runs them.
    monkeypatch.chdir(SOURCE_DIR)


def run_cli(*args, **kw):
    return subprocess.run([CM_EXE, *args], capture_output=True, text=True, **kw)


def output_params(pipeline_nodes, stage_info):
    """(node, param, path) of every file a pipeline writes (the OutputPath parameters set)."""
    out = []
    for n in pipeline_nodes:
        specs = {p["name"]: p for p in stage_info(n["stage"])["params"]}
        for name, value in n["params"].items():
            if specs.get(name, {}).get("extensions"):
                out.append((n["id"], name, value))
    return out
