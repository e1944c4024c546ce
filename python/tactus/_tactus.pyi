"""Type stubs of the compiled module tactus._tactus (python/src/*.cpp)."""
from os import PathLike
from typing import Callable, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, PathLike[str]]
_Index = Union[str, int]
_F64 = npt.NDArray[np.float64]

class InputError(ValueError):
    """A problem in the user's input; str() is 'file:line:column: reason'."""
    file: str
    line: Optional[int]
    column: Optional[int]
    byte_offset: Optional[int]
    reason: str

class Material:
    name: str
    model: str
    young_modulus: float
    poisson_ratio: float
    shear_modulus: float
    bulk_modulus: float
    lame_lambda: float
    c10: float
    c01: float
    density: float
    rayleigh_alpha: float
    rayleigh_beta: float
    nodal_damping: float
    viscoelastic: str

class FixedRegion:
    name: str
    selector: str
    nodes: npt.NDArray[np.int32]

class Probe:
    name: str
    position: tuple[float, float, float]

class Body:
    name: str
    kind: str
    material_index: Optional[int]
    mesh_source: str
    volumetric: bool
    node_count: int
    surface_vertex_count: int
    triangle_count: int
    tet_count: int
    rest_positions: _F64
    surface_vertices: _F64
    triangles: npt.NDArray[np.int32]
    tets: Optional[npt.NDArray[np.int32]]
    fixed: list[FixedRegion]
    probes: list[Probe]
    time_step: float
    integrator: str

class Device:
    name: str
    kind: str
    max_force: float
    max_stiffness: float
    scale: float
    offset: tuple[float, float, float]

class Tool:
    name: str
    kind: str
    device_indices: list[int]
    radius: Optional[float]

class Algorithm:
    name: str
    kind: str
    tool_index: int
    body_indices: list[int]
    enabled: bool

class Model:
    name: str
    description: str
    source: str
    text: str
    gravity: tuple[float, float, float]
    rates: dict[str, float]
    materials: list[Material]
    bodies: list[Body]
    devices: list[Device]
    tools: list[Tool]
    algorithms: list[Algorithm]
    def body(self, name: str) -> Body: ...
    def material(self, name: str) -> Material: ...
    def material_of(self, body: Body) -> Optional[Material]: ...
    def with_changes(self, changes: dict[str, object]) -> Model: ...
    def summary(self, real_time: bool = True) -> str: ...

def load_scene(path: _Path) -> Model: ...
def parse_scene(text: str, name: str = "<python>", allow_file_access: bool = True) -> Model: ...
def default_scene() -> Model: ...

class RunResult:
    devices: list[str]
    simulated_time: float
    wall_time: float
    recorded_frames: int
    recording_bytes: int
    dropped_steps: int
    events: dict[str, int]
    device_reports: list[dict[str, Union[str, int, float]]]
    def frames(self, device: _Index = 0) -> dict[str, np.ndarray]:
        """t, frame, position, orientation_xyzw, force, torque, proxy, contact, flags, buttons."""

def run(model: Model, duration: float = 0.0, max_duration: float = 30.0,
        record: Optional[_Path] = None) -> RunResult: ...

class Simulation:
    def __init__(self, model: Model, controlled: Sequence[str] = ..., record: Optional[_Path] = None,
                 keep_frames: bool = False,
                 force_algorithms: dict[str, Callable[[float, tuple[float, float, float], tuple[float, float, float],
                                                       tuple[float, float, float], bool], Sequence[float]]] = ...
                 ) -> None: ...
    def step(self, frames: int = 1) -> None: ...
    frame: int
    time: float
    model: Model
    devices: list[str]
    finished: bool
    forces: _F64
    device_positions: _F64
    proxies: _F64
    contacts: npt.NDArray[np.uint8]
    def is_controlled(self, device: _Index) -> bool: ...
    def set_device_pose(self, device: _Index, position: Sequence[float],
                        orientation_wxyz: Optional[Sequence[float]] = None, buttons: int = 0) -> None: ...
    def body_positions(self, body: _Index) -> Optional[_F64]: ...
    def surface_positions(self, body: _Index) -> Optional[_F64]: ...
    def set_material(self, body: _Index, young_modulus: float, damping: Optional[float] = None,
                     from_time: Optional[float] = None) -> None: ...
    def set_surface(self, device: _Index, stiffness: float, static_friction: float = 0.0,
                    kinetic_friction: float = 0.0, from_time: Optional[float] = None) -> None: ...
    def emergency_stop(self) -> None: ...
    def finish(self) -> RunResult: ...

def solve(model: Model, *, static: bool = True, until: float = 1.0,
          every: float = 0.0) -> list[dict[str, object]]: ...

class ConfigurationSpace:
    """A precomputed configuration space (`tactus precompute`), queried with the haptic loop's
    interpolators (docs/python.md, "Configuration spaces")."""
    def __init__(self, path: _Path, method: str = "trilinear") -> None: ...
    @property
    def method(self) -> str: ...
    @property
    def body(self) -> str: ...
    @property
    def spacing(self) -> float: ...
    @property
    def counts(self) -> list[int]: ...
    @property
    def points(self) -> _F64: ...
    @property
    def solved(self) -> npt.NDArray[np.bool_]: ...
    @property
    def point_forces(self) -> _F64: ...
    @property
    def point_stiffness(self) -> _F64: ...
    @property
    def point_torques(self) -> _F64: ...
    @property
    def probe(self) -> dict[str, object] | None: ...
    @property
    def level_count(self) -> int: ...
    def level(self, k: int) -> ConfigurationSpace: ...
    def force(self, points: npt.ArrayLike,
              directions: npt.ArrayLike | None = None) -> tuple[_F64, npt.NDArray[np.bool_]]: ...
    def torque(self, points: npt.ArrayLike,
               directions: npt.ArrayLike | None = None) -> tuple[_F64, npt.NDArray[np.bool_]]: ...
    def shape(self, point: npt.ArrayLike, direction: npt.ArrayLike | None = None) -> tuple[_F64, _F64, bool]: ...

def build_space(model: Model, output: _Path, threads: int = 0) -> dict[str, object]: ...

def read_recording(path: _Path) -> dict[str, object]:
    """Header fields, complete, truncation, and 'frames', 'steps', 'events': dicts of read-only
    NumPy views, one row per record (docs/python.md, "Recordings")."""

def read_mesh(path: _Path) -> dict[str, object]:
    """format, skipped, flipped_tets, and 'surface' / 'volume': None or dicts of read-only NumPy
    views of the mesh read (docs/python.md, "Meshes")."""

def write_mesh(path: _Path, vertices: npt.ArrayLike, tets: Optional[npt.ArrayLike] = None,
               triangles: Optional[npt.ArrayLike] = None, regions: Optional[Sequence[int]] = None,
               binary: bool = False, msh_version: int = 41) -> None: ...
