"""Shared helpers for the end-to-end tests: the private meshlabserver, the scoring tool, PLY I/O."""
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

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


_PLY_TYPES = {"char": "i1", "uchar": "u1", "short": "i2", "ushort": "u2", "int": "i4",
              "uint": "u4", "float": "f4", "double": "f8", "int8": "i1", "uint8": "u1",
              "int16": "i2", "uint16": "u2", "int32": "i4", "uint32": "u4", "float32": "f4",
              "float64": "f8"}


def read_ply_vertices(path):
    """The vertex element of a PLY file (ascii or binary little endian) as a numpy record array."""
    return read_ply(path)[0]


def read_ply(path):
    """(vertices as a numpy record array, triangles as an (n,3) int array) of a PLY file, ascii or
    binary little endian, whose faces are triangles with one list property."""
    data = pathlib.Path(path).read_bytes()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt, count, props, in_vertex, face_count, face_types = None, 0, [], False, 0, None
    for line in header:
        words = line.split()
        if not words:
            continue
        if words[0] == "format":
            fmt = words[1]
        elif words[0] == "element":
            in_vertex = words[1] == "vertex"
            if in_vertex:
                count = int(words[2])
            elif words[1] == "face":
                face_count = int(words[2])
        elif words[0] == "property" and not in_vertex and words[1] == "list":
            face_types = (_PLY_TYPES[words[2]], _PLY_TYPES[words[3]])
        elif words[0] == "property" and in_vertex:
            if words[1] == "list":
                raise ValueError("list property in vertex element")
            props.append((words[2], _PLY_TYPES[words[1]]))
    if fmt == "ascii":
        rows = data[end:].decode("ascii").split("\n")
        table = np.array([[float(x) for x in r.split()[:len(props)]] for r in rows[:count]])
        faces = np.array([[int(x) for x in r.split()[1:4]] for r in rows[count:count + face_count]],
                         dtype=np.int64).reshape(-1, 3)
        return np.rec.fromarrays(table.T, names=[p[0] for p in props]), faces
    if fmt != "binary_little_endian":
        raise ValueError(fmt)
    dtype = np.dtype([(name, "<" + t) for name, t in props])
    vertices = np.frombuffer(data, dtype=dtype, count=count, offset=end)
    faces = np.zeros((0, 3), dtype=np.int64)
    if face_count and face_types:
        face_dtype = np.dtype([("n", "<" + face_types[0]), ("i", "<" + face_types[1], 3)])
        records = np.frombuffer(data, dtype=face_dtype, count=face_count,
                                offset=end + count * dtype.itemsize)
        if not np.all(records["n"] == 3):
            raise ValueError("only triangle meshes are supported")
        faces = records["i"].astype(np.int64)
    return vertices, faces


@pytest.fixture
def shared():
    if not SHARED.is_dir():
        pytest.fail(f"shared data folder not found at {SHARED}")
    return SHARED
