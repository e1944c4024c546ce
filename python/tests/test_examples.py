"""The Python examples run and write what they say."""
import os
import subprocess
import sys

from conftest import SOURCE_DIR


def test_force_indentation_example_writes_a_png(tmp_path):
    out = tmp_path / "curve.png"
    script = SOURCE_DIR / "examples/python/force_indentation.py"
    done = subprocess.run([sys.executable, script, out], check=True, capture_output=True, text=True,
                          env={**os.environ, "MPLBACKEND": "Agg"})
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "peak force" in done.stdout
