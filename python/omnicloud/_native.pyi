"""Type stubs of the compiled module (see the docstrings for what each option means)."""

import os
from typing import Callable, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, os.PathLike]
Progress = Callable[[int, int], object]
Codes = Union[str, Sequence[int]]

class PointCloud:
    @staticmethod
    def from_arrays(
        xyz: npt.NDArray[Union[np.float64, np.float32]],
        *,
        rgb: Optional[npt.NDArray[Union[np.uint8, np.uint16]]] = None,
        radius: Optional[npt.NDArray[Union[np.float32, np.float64]]] = None,
        intensity: Optional[npt.NDArray[np.uint16]] = None,
        classification: Optional[npt.NDArray[np.uint8]] = None,
        return_number: Optional[npt.NDArray[np.uint8]] = None,
        number_of_returns: Optional[npt.NDArray[np.uint8]] = None,
        unit: str = "metre",
    ) -> PointCloud: ...
    @staticmethod
    def from_laspy(las: object, *, unit: str = "metre") -> PointCloud: ...
    def __len__(self) -> int: ...
    @property
    def xyz(self) -> npt.NDArray[np.float64]: ...
    @property
    def rgb(self) -> Optional[npt.NDArray[np.uint8]]: ...
    @property
    def intensity(self) -> Optional[npt.NDArray[np.uint16]]: ...
    @property
    def classification(self) -> Optional[npt.NDArray[np.uint8]]: ...
    @property
    def return_number(self) -> Optional[npt.NDArray[np.uint8]]: ...
    @property
    def number_of_returns(self) -> Optional[npt.NDArray[np.uint8]]: ...
    @property
    def radius(self) -> Optional[npt.NDArray[np.float32]]: ...
    @property
    def origin(self) -> Tuple[float, float, float]: ...
    @property
    def crs(self) -> Optional[str]: ...
    @property
    def unit(self) -> str: ...
    @property
    def metres_per_unit(self) -> Optional[float]: ...

class Image:
    @property
    def rgba(self) -> npt.NDArray[np.uint8]: ...
    @property
    def depth(self) -> npt.NDArray[np.float32]: ...
    @property
    def left(self) -> Optional[Image]: ...
    @property
    def right(self) -> Optional[Image]: ...
    @property
    def stereo(self) -> bool: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def camera(self) -> Optional[Tuple[float, float, float]]: ...
    def save(
        self,
        path: PathLike,
        *,
        quality: int = 90,
        separate_eyes: bool = False,
        depth: Optional[PathLike] = None,
    ) -> list[os.PathLike]: ...
    def _repr_png_(self) -> bytes: ...

def read(
    path: PathLike,
    *,
    classes: Optional[Codes] = None,
    drop_classes: Optional[Codes] = None,
    returns: str = "all",
    crop: Optional[Union[str, Sequence[float]]] = None,
    up: str = "z",
    progress: Optional[Progress] = None,
) -> PointCloud: ...
def render(
    cloud: PointCloud,
    *,
    width: int = 3840,
    stereo: str = "none",
    projection: str = "equirect",
    camera: Optional[Union[str, Sequence[float]]] = None,
    height: Optional[float] = None,
    yaw: float = 0.0,
    pitch: float = 0.0,
    roll: float = 0.0,
    ipd: float = 0.064,
    pole_merge: str = "comfortable",
    pole_merge_north: Optional[str] = None,
    pole_merge_south: Optional[str] = None,
    ods_offset: str = "exact",
    renderer: str = "raster",
    color: str = "auto",
    shading: str = "unlit",
    radius: Optional[Union[float, str]] = None,
    classes: Optional[Codes] = None,
    drop_classes: Optional[Codes] = None,
    returns: str = "all",
    crop: Optional[Union[str, Sequence[float]]] = None,
    max_distance: Optional[float] = None,
    units: str = "metres",
    edl: Optional[float] = None,
    edl_radius: float = 1.4,
    supersample: int = 1,
    background: Optional[Union[str, Sequence[int]]] = None,
    progress: Optional[Progress] = None,
) -> Image: ...
def compare(reference: Union[Image, PathLike], test: Union[Image, PathLike]) -> dict: ...
def tour(
    cloud: PointCloud,
    path: npt.ArrayLike,
    *,
    output: Optional[PathLike] = None,
    frames: Optional[int] = None,
    speed: float = 1.4,
    fps: float = 30.0,
    height: Optional[float] = None,
    heading_smoothing: float = 2.0,
    yaw: float = 0.0,
    pitch: float = 0.0,
    roll: float = 0.0,
    format: str = "png",
    quality: int = 90,
    overwrite: bool = False,
    width: int = 3840,
    stereo: str = "none",
    projection: str = "equirect",
    ipd: float = 0.064,
    pole_merge: str = "comfortable",
    pole_merge_north: Optional[str] = None,
    pole_merge_south: Optional[str] = None,
    ods_offset: str = "exact",
    renderer: str = "raster",
    color: str = "auto",
    shading: str = "unlit",
    radius: Optional[Union[float, str]] = None,
    classes: Optional[Codes] = None,
    drop_classes: Optional[Codes] = None,
    returns: str = "all",
    crop: Optional[Union[str, Sequence[float]]] = None,
    max_distance: Optional[float] = None,
    units: str = "metres",
    edl: Optional[float] = None,
    edl_radius: float = 1.4,
    supersample: int = 1,
    background: Optional[Union[str, Sequence[int]]] = None,
    progress: Optional[Progress] = None,
) -> Union[dict, list[Image]]: ...
