"""The module as a Python library: import, docstrings from the declarations, type stubs."""

import ast
import pathlib
import subprocess

from conftest import SOURCE_DIR


def test_imports_with_debian_python(cm):
    assert cm.__version__
    assert "mesh.reduce" in cm.stage_names()
    assert "memory.mesh" in cm.stage_names()
    # The README's first check, as a fresh interpreter runs it.
    env_path = pathlib.Path(cm.__file__).parent.parent
    r = subprocess.run(["/usr/bin/python3", "-c", "import conceptmesh; print(conceptmesh.__version__)"],
                       env={"PYTHONPATH": str(env_path)}, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == cm.__version__


def test_help_lists_parameters_with_ranges_and_units(cm):
    s = cm.stage("mesh.reduce", max_angle_deg=20)
    doc = type(s).__doc__
    assert doc.startswith("mesh.reduce: ")
    line = next(l for l in doc.splitlines() if l.strip().startswith("max_angle_deg:"))
    # "max_angle_deg: float = 15 [0.1, 89] deg" (the default, range and unit of the declaration)
    info = {p["name"]: p for p in cm.stage_info("mesh.reduce")["params"]}["max_angle_deg"]
    assert f"[{info['min']:g}, {info['max']:g}]" in line
    assert line.rstrip().endswith("deg")
    assert "Inputs:" in doc and "mesh: mesh" in doc
    import pydoc
    text = pydoc.render_doc(s, renderer=pydoc.plaintext)
    assert "max_angle_deg" in text and "deg" in text


def test_stubs_name_what_the_module_has(cm):
    stub = pathlib.Path(cm.__file__).with_name("__init__.pyi")
    assert stub.exists(), "the stubs are shipped next to the module"
    tree = ast.parse(stub.read_text())
    stubbed = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            methods = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
            fields = {n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
            stubbed[node.name] = methods | fields
        elif isinstance(node, ast.FunctionDef):
            stubbed[node.name] = set()
    for name in cm.__all__:
        if name == "__version__":
            continue
        assert name in stubbed, f"{name} is not in the stubs"
    for name, members in stubbed.items():
        assert hasattr(cm, name), f"the stubs name {name}, which the module lacks"
        obj = getattr(cm, name)
        for m in members:
            if m.startswith("__") and m != "__call__":
                continue
            declared = set(getattr(obj, "_fields", ())) | set(getattr(obj, "__annotations__", {}))
            assert hasattr(obj, m) or m in declared, f"the stubs name {name}.{m}, which it lacks"
    # Every public method of the classes is in the stubs too.
    for cls in ("Mesh", "Views", "View", "Volume", "Pipeline", "Result", "Stage"):
        public = {m for m in dir(getattr(cm, cls)) if not m.startswith("_")}
        assert public <= stubbed[cls], f"{cls}: {sorted(public - stubbed[cls])} missing from the stubs"


def test_source_tree_is_the_one_tested():
    assert (SOURCE_DIR / "pipelines/paper.yaml").exists()
