"""Tactus from Python: scenes, lockstep runs, frame-by-frame simulation, static solves,
recordings, configuration spaces, meshes.

Build the module with the project (CMake option TACTUS_BUILD_PYTHON) and put the build's
python folder on the path:

    PYTHONPATH=build/release/python python3 -c "import tactus"

docs/python.md describes the API and the lifetime of the arrays it returns.
"""
from ._tactus import (  # noqa: F401  (re-exported)
    __version__,
    InputError,
    Model,
    Material,
    Body,
    FixedRegion,
    Probe,
    Device,
    Tool,
    Algorithm,
    RunResult,
    Simulation,
    load_scene,
    parse_scene,
    default_scene,
    run,
    solve,
    read_recording,
    ConfigurationSpace,
    build_space,
    read_mesh,
    write_mesh,
)

__all__ = [
    "InputError", "Model", "Material", "Body", "FixedRegion", "Probe", "Device", "Tool",
    "Algorithm", "RunResult", "Simulation", "load_scene", "parse_scene", "default_scene", "run", "solve",
    "read_recording", "ConfigurationSpace", "build_space", "read_mesh", "write_mesh",
]
