"""conceptmesh: concept-art drawings to 3D meshes, from Python.

Run a pipeline file::

    import conceptmesh
    result = conceptmesh.Pipeline.load("pipelines/paper.yaml", set={"hull.resolution": 512}).run()
    mesh = result.outputs["reduce"]          # conceptmesh.Mesh; mesh.vertices is a numpy (N, 3) array

or a stage on a mesh of your own::

    reduced = conceptmesh.stage("mesh.reduce", max_angle_deg=20)(conceptmesh.Mesh(vertices, faces))

Stages run with the GIL released, on the same executor as the ``conceptmesh`` command;
Ctrl-C raises KeyboardInterrupt and leaves no partial file. See docs/python.md.
"""

from typing import NamedTuple as _NamedTuple

from ._conceptmesh import (  # noqa: F401  (the module's public names)
    Error,
    FileError,
    Mesh,
    ParameterError,
    View,
    Views,
    Volume,
    __version__,
    stage_names,
)


class ProgressEvent(_NamedTuple):
    """One progress event, handed to a run's ``progress`` callback on the calling thread.

    kind: "started", "progress", "finished", or a message level ("info", "warning").
    node: the node id (a stage run alone: the stage's name). stage: set on "started".
    percent: 0-100 of the node ("progress", "finished"), -1 when it has none.
    text: what the node is doing, or the message. seconds: the node's time ("finished").
    """

    kind: str
    node: str
    stage: str
    percent: float
    text: str
    seconds: float


from ._pipeline import Pipeline, Result, Stage, StageResult, stage, stage_info, views_from_images  # noqa: E402,F401

__all__ = [
    "Error",
    "FileError",
    "Mesh",
    "ParameterError",
    "Pipeline",
    "ProgressEvent",
    "Result",
    "Stage",
    "StageResult",
    "View",
    "Views",
    "Volume",
    "stage",
    "stage_info",
    "stage_names",
    "views_from_images",
    "__version__",
]
