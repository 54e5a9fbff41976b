"""Shared helpers of the Python module's tests (run by ctest as `python3 -m pytest tests/python`
with PYTHONPATH at build/python and PT_CLI naming the command-line binary)."""
import json
import os
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

import pathtracer

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"


def cli_path():
    path = os.environ.get("PT_CLI", str(ROOT / "build" / "pathtracer"))
    if not Path(path).exists():
        pytest.skip(f"no pathtracer binary at {path} (set PT_CLI)")
    return path


def scene_dict(path):
    """A project scene file as a dict (its // comments removed)."""
    text = re.sub(r"^\s*//.*$|\s//[^\"\n]*$", "", Path(path).read_text(), flags=re.M)
    return json.loads(text)


def cli_options(options):
    """Keyword options as the command line's flags (max_depth=4 -> --max-depth 4)."""
    args = []
    for key, value in options.items():
        if isinstance(value, bool):
            value = "on" if value else "off"
        args += ["--" + key.replace("_", "-"), str(value)]
    return args


def run_cli(scene_path, out_dir, options, extra=()):
    """Renders with the CLI to out.pfm and (with extras) out.exr; returns the PFM's pixels."""
    pfm = Path(out_dir) / "out.pfm"
    cmd = [cli_path(), str(scene_path), "-o", str(pfm), "--quiet", *cli_options(options), *extra]
    done = subprocess.run(cmd, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return read_pfm(pfm)


def read_pfm(path):
    """A little-endian colour PFM as float32 (H, W, 3), rows top to bottom (numpy only)."""
    data = Path(path).read_bytes()
    header, pos = [], 0
    while len(header) < 3:
        end = data.index(b"\n", pos)
        header.append(data[pos:end].decode())
        pos = end + 1
    assert header[0] == "PF" and float(header[2]) < 0
    width, height = map(int, header[1].split())
    pixels = np.frombuffer(data[pos:], dtype="<f4").reshape(height, width, 3)
    return pixels[::-1].copy()


def bits(a):
    """The exact bits of a float32 array, for bit-for-bit comparisons."""
    return np.ascontiguousarray(a, dtype=np.float32).view(np.uint32)


def assert_identical(a, b):
    assert a.shape == b.shape
    diff = np.count_nonzero(bits(a) != bits(b))
    assert diff == 0, f"{diff} of {a.size} values differ (max |d| {np.max(np.abs(a - b))})"


def cli_error(args):
    """The CLI's exit status and its message (stderr's last line, without the prefix)."""
    done = subprocess.run([cli_path(), *map(str, args)], capture_output=True, text=True)
    lines = [l for l in done.stderr.splitlines() if l.startswith("pathtracer: ")]
    message = lines[-1][len("pathtracer: "):] if lines else ""
    return done.returncode, re.sub(r" \(see --help\)$", "", message)


@pytest.fixture
def cornell():
    return pathtracer.Scene(SCENES / "cornell_box.json")


# Small renders: every test here runs in a fraction of a second of CPU.
SMALL = dict(width=24, height=20, spp=4, max_depth=4, seed=7, backend="cpu")
