"""Pipelines and stages from Python: the pure-Python side of conceptmesh.

A pipeline built here is written out as pipeline YAML and parsed by the same reader as a
pipeline file, then run by the same executor as ``conceptmesh run``; data the caller holds
(a Mesh, Views, a Volume) enters it as a ``memory.*`` node.
"""

import atexit
import json
import os
import shutil
import tempfile
import weakref

from . import _conceptmesh as _native

_KINDS = {_native.Mesh: "mesh", _native.Views: "views", _native.Volume: "volume"}


def _kind_of(data):
    for cls, kind in _KINDS.items():
        if isinstance(data, cls):
            return kind
    return None


def stage_info(name):
    """A stage's declaration as a dict: name, summary, inputs, output, params, doc."""
    return _native.stage_info(name)


class Stage:
    """A configured stage. Call it on data to run it alone, or chain it with ``|`` into a
    Pipeline. Made by :func:`conceptmesh.stage`, whose class carries the stage's parameters in
    its docstring (``help(conceptmesh.stage("mesh.reduce"))``)."""

    name = ""
    id: "str | None"
    inputs: dict
    params: dict

    def __init__(self, id=None, inputs=None, **params):
        self.id = id
        self.inputs = dict(inputs or {})
        self.params = params
        _native.check_stage_params(self.name, params)

    @property
    def info(self):
        return stage_info(self.name)

    def _bind(self, data, ports):
        """Positional data to ports: each to the first free port of its kind."""
        bound = {}
        for port, value in ports.items():
            bound[port] = value
        for value in data:
            kind = _kind_of(value)
            port = next(
                (p["name"] for p in self.info["inputs"] if p["kind"] == kind and p["name"] not in bound),
                None,
            )
            if port is None:
                raise _native.ParameterError(
                    f"stage {self.name}: no free input port takes {kind or type(value).__name__}"
                )
            bound[port] = value
        return bound

    def run(self, *data, progress=None, side_output_dir=".", **ports):
        """Runs the stage on `data` (each to the first free input port of its kind) and on the
        named `ports`. Returns a StageResult: output, metrics, warnings, files."""
        r = _native.run_stage(self.name, self.params, self._bind(data, ports), progress, os.fspath(side_output_dir))
        return StageResult(r["output"], r["metrics"], r["warnings"], r["files"])

    def __call__(self, *data, progress=None, **ports):
        """Runs the stage and returns its output (a Mesh, Views, Volume, the files written, or
        a report dict)."""
        return self.run(*data, progress=progress, **ports).output

    def __or__(self, other):
        return Pipeline([self]) | other

    def __ror__(self, data):
        return Pipeline([data]) | self

    def __repr__(self):
        args = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
        return f"conceptmesh.stage({self.name!r}{', ' if args else ''}{args})"


class StageResult:
    """What one stage run gave: output, metrics (dict), warnings (list), files (written)."""

    output: object
    metrics: dict
    warnings: list
    files: list

    def __init__(self, output, metrics, warnings, files):
        self.output, self.metrics, self.warnings, self.files = output, metrics, warnings, files

    def __repr__(self):
        return f"<conceptmesh.StageResult {self.output!r}, {len(self.metrics)} metrics>"


_stage_classes = {}


def stage(name, id=None, inputs=None, **params):
    """The stage `name` with its parameters: ``conceptmesh.stage("mesh.reduce", max_angle_deg=20)``.

    Parameters are checked now against the stage's declaration (ParameterError, a ValueError).
    `id` and `inputs` ({port: node id}) matter only in a Pipeline. help() on the result lists
    the stage's inputs and parameters with their defaults, ranges and units."""
    cls = _stage_classes.get(name)
    if cls is None:
        info = _native.stage_info(name)
        cls = type(name.replace(".", "_"), (Stage,), {"name": name, "__doc__": info["doc"]})
        cls.__module__ = "conceptmesh"
        _stage_classes[name] = cls
    return cls(id=id, inputs=inputs, **params)


class Result:
    """A pipeline run: every node's output (``outputs``, by node id: Mesh, Views, Volume, the
    paths a writer wrote, a report dict), ``metrics`` and ``warnings`` by node, ``files`` (the
    outputs committed), ``report`` (the JSON text ``--report`` writes) and ``seconds``."""

    outputs: dict
    metrics: dict
    warnings: dict
    files: list
    report: str
    seconds: float
    peak_rss_bytes: int

    def __init__(self, r, order):
        self.outputs = r["outputs"]
        self.metrics = r["metrics"]
        self.warnings = r["warnings"]
        self.files = r["files"]
        self.report = r["report"]
        self.seconds = r["seconds"]
        self.peak_rss_bytes = r["peak_rss_bytes"]
        self._order = order

    @property
    def report_dict(self):
        """The run report, parsed."""
        return json.loads(self.report)

    @property
    def mesh(self):
        """The last mesh the pipeline made (in dependency order), or None."""
        meshes = [o for o in self.outputs.values() if isinstance(o, _native.Mesh)]
        return meshes[-1] if meshes else None

    def __getitem__(self, node):
        return self.outputs[node]

    def __repr__(self):
        return f"<conceptmesh.Result {len(self.outputs)} nodes, {len(self.files)} files, {self.seconds:.2f} s>"


class Pipeline:
    """A pipeline: loaded from a file (:meth:`load`), or built from stages and data::

        p = views | conceptmesh.stage("hull.carve", resolution=256) | conceptmesh.stage(...)

    Each input port of an added stage takes the latest node whose output is of the port's
    kind, unless the stage names it in ``inputs={port: node_id}``. ``run()`` goes through
    ``run_pipeline``, as ``conceptmesh run`` does."""

    name: str

    def __init__(self, stages=(), name="python"):
        self.name = name
        self._nodes = []
        self._keys = []
        self._held = []
        self._sets = {}
        self._native = None
        weakref.finalize(self, _drop_keys, self._keys)
        for s in stages:
            self.add(s)

    @classmethod
    def load(cls, path, set=None):
        """Reads a pipeline file; `set` overrides parameters as --set does: {"hull.resolution": 512}."""
        p = cls()
        p._native = _native.NativePipeline.load(os.fspath(path))
        p.name = p._native.name
        if set:
            p._native.set(dict(set))
        return p

    @property
    def nodes(self):
        """The nodes: dicts of id, stage, inputs ({port: node}) and params."""
        if self._native is not None:
            return self._native.nodes
        return [dict(n) for n in self._nodes]

    def _unique_id(self, base):
        ids = {n["id"] for n in self._nodes}
        if base not in ids:
            return base
        k = 2
        while f"{base}_{k}" in ids:
            k += 1
        return f"{base}_{k}"

    def add(self, item, id=None, inputs=None):
        """Adds a Stage, or data the caller holds (Mesh, Views, Volume) as a memory.* node;
        returns the node id."""
        if self._native is not None:
            raise _native.ParameterError("a pipeline loaded from a file takes no more nodes; use set= to change it")
        kind = _kind_of(item)
        if kind is not None:
            key = _native.memory_put(item)
            self._keys.append(key)
            self._held.append(item)
            node = {"id": self._unique_id(id or kind), "stage": "memory." + kind, "inputs": {}, "params": {"key": key}}
            self._nodes.append(node)
            return node["id"]
        if not isinstance(item, Stage):
            raise TypeError(f"a pipeline takes stages and Mesh, Views or Volume data, not {type(item).__name__}")
        info = item.info
        node_id = self._unique_id(id or item.id or item.name.split(".")[-1])
        wired = dict(item.inputs)
        wired.update(inputs or {})
        for port in info["inputs"]:
            if port["name"] in wired:
                continue
            source = next((n for n in reversed(self._nodes) if _output_kind(n) == port["kind"]), None)
            if source is not None:
                wired[port["name"]] = source["id"]
        self._nodes.append({"id": node_id, "stage": item.name, "inputs": wired, "params": dict(item.params)})
        return node_id

    def __or__(self, other):
        p = Pipeline(name=self.name)
        if self._native is not None:
            raise _native.ParameterError("a pipeline loaded from a file cannot be chained; build it from stages")
        p._nodes = [dict(n) for n in self._nodes]
        p._keys.extend(self._keys)
        p._held = list(self._held) + [self]  # the keys stay held while the new pipeline lives
        p._sets = dict(self._sets)
        p.add(other)
        return p

    def set(self, values):
        """Overrides parameters as --set does: {"node.param": value}. Returns the pipeline."""
        if self._native is not None:
            self._native.set(dict(values))
        else:
            self._sets.update(values)
        return self

    @property
    def yaml(self):
        """The pipeline as pipeline YAML (what a built pipeline is parsed from)."""
        if self._native is not None:
            with open(self._native.file, encoding="utf-8") as f:
                return f.read()
        lines = [f"pipeline: {json.dumps(self.name)}", "nodes:"]
        for n in self._nodes:
            lines.append(f"  - id: {json.dumps(n['id'])}")
            lines.append(f"    stage: {json.dumps(n['stage'])}")
            if n["inputs"]:
                lines.append(f"    inputs: {json.dumps(n['inputs'])}")
            if n["params"]:
                params = {k: os.fspath(v) if hasattr(v, "__fspath__") else v for k, v in n["params"].items()}
                lines.append(f"    params: {json.dumps(params)}")
        return "\n".join(lines) + "\n"

    def _built(self):
        if self._native is not None:
            return self._native
        native = _native.NativePipeline.parse(self.yaml, f"<pipeline {self.name}>")
        if self._sets:
            native.set(dict(self._sets))
        return native

    def validate(self):
        """Checks every stage, parameter and connection, and configures every stage; raises
        ParameterError (a ValueError), FileError (an OSError) or Error. Returns the pipeline."""
        self._built().validate()
        return self

    def run(self, progress=None, report=None, labels=None, side_output_dir=None, keep=None):
        """Runs the pipeline and returns a Result. `progress(event)` is called on this thread
        with each ProgressEvent; `report` writes the run report there, as --report does;
        `keep` (node ids) hands back only those nodes' outputs (the others are None and freed
        during the run, as the command frees them), every node's by default."""
        native = self._built()
        r = native.run(
            progress=progress,
            report=os.fspath(report) if report else "",
            labels=dict(labels or {}),
            side_output_dir=os.fspath(side_output_dir) if side_output_dir else "",
            keep=None if keep is None else [str(k) for k in keep],
        )
        return Result(r, [n["id"] for n in native.nodes])

    def __repr__(self):
        return f"<conceptmesh.Pipeline {self.name!r}, {len(self.nodes)} nodes>"


def _output_kind(node):
    return _native.stage_info(node["stage"])["output"]


def _drop_keys(keys):
    for key in keys:
        _native.memory_drop(key)


_image_dirs = []


def _remove_image_dirs():
    for d in _image_dirs:
        shutil.rmtree(d, ignore_errors=True)


atexit.register(_remove_image_dirs)


def views_from_images(images, folder=None, **params):
    """Views from numpy images: {name: image} or {name: (image, camera)}, an image (H, W[, C])
    uint8 or float in [0, 1], a camera a dict of the views manifest's keys ({"view": "right"},
    {"azimuth": 30, "elevation": 10}, {"matrix": P}, ...); a name that is a view name (front,
    right, top, ...) needs none. They are written as PNG with a views.yaml into `folder` (a
    temporary folder, removed at exit, by default) and read by the views.load stage, so the
    silhouettes are found as from files. `params` are views.load's."""
    if folder is None:
        folder = tempfile.mkdtemp(prefix="conceptmesh-views-")
        _image_dirs.append(folder)
    os.makedirs(folder, exist_ok=True)
    entries = {}
    for name, value in images.items():
        image, camera = value if isinstance(value, tuple) else (value, {})
        file = f"{name}.png"
        _native.write_png(image, os.path.join(folder, file))
        entry = {"image": file}
        entry.update({k: (v.tolist() if hasattr(v, "tolist") else v) for k, v in camera.items()})
        entries[name] = entry
    manifest = os.path.join(folder, "views.yaml")
    with open(manifest, "w", encoding="utf-8") as f:
        f.write(json.dumps({"views": entries}, indent=2) + "\n")
    return stage("views.load", manifest=manifest, **params)()


def _volume_save(self, path, mesh=None, **params):
    """Writes the hull as an OpenVDB level set (.vdb) with the volume.write stage; `mesh` (the
    Marching Cubes surface) makes it follow the surface below a voxel. Returns the path."""
    ports = {"mesh": mesh} if mesh is not None else {}
    stage("volume.write", path=os.fspath(path), **params)(self, **ports)
    return os.fspath(path)


def _volume_grid(self, **params):
    """The hull as a pyopenvdb FloatGrid (a level set), where Debian's python3-openvdb is
    installed; ImportError otherwise. It goes through a .vdb file: see docs/python.md."""
    try:
        import pyopenvdb
    except ImportError as e:
        raise ImportError(
            "Volume.grid() needs pyopenvdb (Debian: python3-openvdb); Volume.save(path) writes the .vdb "
            "without it"
        ) from e
    with tempfile.TemporaryDirectory(prefix="conceptmesh-vdb-") as d:
        path = _volume_save(self, os.path.join(d, "hull.vdb"), **params)
        grids = pyopenvdb.readAllGridMetadata(path)
        return pyopenvdb.read(path, grids[0].name)


_native.Volume.save = _volume_save
_native.Volume.grid = _volume_grid
