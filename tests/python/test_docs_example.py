"""The worked example of docs/python.md runs (at a small size) and writes its figure."""
import importlib.util
import subprocess
import sys

import pytest

from conftest import ROOT


def test_docs_example_runs(tmp_path):
    if importlib.util.find_spec("matplotlib") is None:
        pytest.skip("matplotlib is not installed (python3-matplotlib)")
    out = tmp_path / "example.png"
    done = subprocess.run([sys.executable, str(ROOT / "docs" / "python_example.py"), "--size", "12",
                           "--out", str(out)], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert out.read_bytes()[:4] == b"\x89PNG"
