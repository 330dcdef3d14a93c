"""Shared helpers for the end-to-end tests: the private meshlabserver, the scoring tool, PLY I/O."""
import json
import os
import pathlib
import subprocess
import sys

import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "bench"))
import meshio  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[2]
BUILD = pathlib.Path(os.environ.get("SBS_BUILD_DIR", REPO / "build"))
SHARED = pathlib.Path(os.environ.get("SBS_SHARED_DIR", REPO.parent / "shared"))
PRIVATE_MESHLAB = BUILD / "meshlab"
MESHLAB_LIB = "/usr/lib/x86_64-linux-gnu/meshlab"


def meshlab_env():
    env = dict(os.environ)
    env["LD_LIBRARY_PATH"] = MESHLAB_LIB + ":" + env.get("LD_LIBRARY_PATH", "")
    return env


def run_meshlabserver(args, timeout=600):
    """Runs the private copy of meshlabserver (our plugin + links to the system ones) under Xvfb."""
    cmd = ["xvfb-run", "-a", str(PRIVATE_MESHLAB / "meshlabserver")] + [str(a) for a in args]
    return subprocess.run(cmd, env=meshlab_env(), capture_output=True, text=True, timeout=timeout)


def write_mlx(tmp_path, filter_kind, *overrides):
    """A script for our filter at its defaults, with name=value overrides (tools/write_mlx)."""
    text = subprocess.run([str(BUILD / "tools" / "write_mlx"), filter_kind, *overrides],
                          check=True, capture_output=True, text=True).stdout
    path = tmp_path / f"{filter_kind}.mlx"
    path.write_text(text)
    return path


def mesh_compare(result, reference):
    out = subprocess.run([str(BUILD / "tools" / "mesh_compare"), str(result), str(reference)],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def read_ply_vertices(path):
    """The vertex element of a PLY file (ascii or binary little endian) as a numpy record array."""
    return read_ply(path)[0]


# (vertices as a numpy record array, triangles as an (n,3) int array) of a PLY file: the
# benchmark's reader, which the bench harness's own tests check too.
read_ply = meshio.read_ply


@pytest.fixture
def shared():
    if not SHARED.is_dir():
        pytest.fail(f"shared data folder not found at {SHARED}")
    return SHARED
