"""Where the tests find the sources and the tactus binary (set by CTest; defaults for a run
from the source tree: PYTHONPATH=build/release/python python3 -m pytest python/tests)."""
import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("TACTUS_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BINARY = pathlib.Path(os.environ.get("TACTUS_BINARY", SOURCE_DIR / "build/release/bin/tactus"))


@pytest.fixture
def scenes():
    return SOURCE_DIR / "scenes"


@pytest.fixture
def tactus_binary():
    if not BINARY.exists():
        pytest.skip(f"no tactus binary at {BINARY}")
    return BINARY
