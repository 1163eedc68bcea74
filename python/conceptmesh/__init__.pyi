# Type stubs of the conceptmesh module (docs/python.md), for editor completion and type checkers.
# tests/python/test_module.py checks that they name what the module has.
import os
from typing import Any, Callable, Iterable, Mapping, NamedTuple, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str
_Path = Union[str, os.PathLike[str]]
_Data = Union["Mesh", "Views", "Volume"]

class Error(Exception):
    """A conceptmesh failure, with the command's one-line message."""

    node: Optional[str]
    stage: Optional[str]

class FileError(Error, OSError):
    """A file that cannot be read or written."""

class ParameterError(Error, ValueError):
    """A parameter, input or graph the stages refuse."""

class ProgressEvent(NamedTuple):
    kind: str
    node: str
    stage: str
    percent: float
    text: str
    seconds: float

class Mesh:
    def __init__(
        self,
        vertices: npt.ArrayLike,
        faces: npt.ArrayLike,
        *,
        normals: Optional[npt.ArrayLike] = ...,
        uvs: Optional[npt.ArrayLike] = ...,
        colors: Optional[npt.ArrayLike] = ...,
        corner_uvs: Optional[npt.ArrayLike] = ...,
        texture: Optional[npt.ArrayLike] = ...,
    ) -> None: ...
    @property
    def vertices(self) -> npt.NDArray[np.float32]: ...
    @property
    def faces(self) -> npt.NDArray[np.uint32]: ...
    @property
    def normals(self) -> Optional[npt.NDArray[np.float32]]: ...
    @property
    def uvs(self) -> Optional[npt.NDArray[np.float32]]: ...
    @property
    def corner_uvs(self) -> Optional[npt.NDArray[np.float32]]: ...
    @property
    def colors(self) -> Optional[npt.NDArray[np.float32]]: ...
    @property
    def texture(self) -> Optional[np.ndarray]: ...

class View:
    @property
    def name(self) -> str: ...
    @property
    def source(self) -> str: ...
    @property
    def image(self) -> np.ndarray: ...
    @property
    def coverage(self) -> npt.NDArray[np.float32]: ...
    @property
    def camera(self) -> dict[str, Any]: ...

class Views:
    def __len__(self) -> int: ...
    def __getitem__(self, key: Union[int, str]) -> View: ...
    @property
    def names(self) -> list[str]: ...
    @property
    def calibrated(self) -> bool: ...
    @property
    def bounds(self) -> Optional[tuple[tuple[float, float, float], tuple[float, float, float]]]: ...
    @property
    def units_per_pixel(self) -> float: ...

class Volume:
    @property
    def voxel_size(self) -> float: ...
    @property
    def active_voxels(self) -> int: ...
    @property
    def bounds(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]: ...
    @property
    def refined(self) -> bool: ...
    def save(self, path: _Path, mesh: Optional[Mesh] = ..., **params: Any) -> str: ...
    def grid(self, **params: Any) -> Any: ...

class StageResult:
    output: Any
    metrics: dict[str, Any]
    warnings: list[str]
    files: list[str]

class Stage:
    name: str
    id: Optional[str]
    inputs: dict[str, str]
    params: dict[str, Any]
    def __init__(self, id: Optional[str] = ..., inputs: Optional[Mapping[str, str]] = ..., **params: Any) -> None: ...
    @property
    def info(self) -> dict[str, Any]: ...
    def run(
        self,
        *data: _Data,
        progress: Optional[Callable[[ProgressEvent], None]] = ...,
        side_output_dir: _Path = ...,
        **ports: _Data,
    ) -> StageResult: ...
    def __call__(self, *data: _Data, progress: Optional[Callable[[ProgressEvent], None]] = ..., **ports: _Data) -> Any: ...
    def __or__(self, other: Union["Stage", _Data]) -> "Pipeline": ...
    def __ror__(self, data: _Data) -> "Pipeline": ...

class Result:
    outputs: dict[str, Any]
    metrics: dict[str, dict[str, Any]]
    warnings: dict[str, list[str]]
    files: list[str]
    report: str
    seconds: float
    peak_rss_bytes: int
    @property
    def report_dict(self) -> dict[str, Any]: ...
    @property
    def mesh(self) -> Optional[Mesh]: ...
    def __getitem__(self, node: str) -> Any: ...

class Pipeline:
    name: str
    def __init__(self, stages: Iterable[Union[Stage, _Data]] = ..., name: str = ...) -> None: ...
    @classmethod
    def load(cls, path: _Path, set: Optional[Mapping[str, Any]] = ...) -> "Pipeline": ...
    @property
    def nodes(self) -> list[dict[str, Any]]: ...
    @property
    def yaml(self) -> str: ...
    def add(self, item: Union[Stage, _Data], id: Optional[str] = ..., inputs: Optional[Mapping[str, str]] = ...) -> str: ...
    def set(self, values: Mapping[str, Any]) -> "Pipeline": ...
    def validate(self) -> "Pipeline": ...
    def run(
        self,
        progress: Optional[Callable[[ProgressEvent], None]] = ...,
        report: Optional[_Path] = ...,
        labels: Optional[Mapping[str, str]] = ...,
        side_output_dir: Optional[_Path] = ...,
        keep: Optional[Iterable[str]] = ...,
    ) -> Result: ...
    def __or__(self, other: Union[Stage, _Data]) -> "Pipeline": ...

def stage(name: str, id: Optional[str] = ..., inputs: Optional[Mapping[str, str]] = ..., **params: Any) -> Stage: ...
def stage_info(name: str) -> dict[str, Any]: ...
def stage_names() -> list[str]: ...
def views_from_images(
    images: Mapping[str, Union[npt.ArrayLike, tuple[npt.ArrayLike, Mapping[str, Any]]]],
    folder: Optional[_Path] = ...,
    **params: Any,
) -> Views: ...
