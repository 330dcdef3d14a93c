"""Minimal triangle-mesh I/O for the benchmark: PLY (ascii / binary little endian) and OFF in,
binary PLY out, and midpoint subdivision to make the large timing meshes. numpy only."""
import pathlib

import numpy as np

_PLY_TYPES = {"char": "i1", "uchar": "u1", "short": "i2", "ushort": "u2", "int": "i4",
              "uint": "u4", "float": "f4", "double": "f8", "int8": "i1", "uint8": "u1",
              "int16": "i2", "uint16": "u2", "int32": "i4", "uint32": "u4", "float32": "f4",
              "float64": "f8"}


def read_ply(path):
    """(vertex record array, (n,3) int64 triangles) of a PLY whose faces are triangles (none for
    a point cloud); also the end-to-end tests' reader (tests/e2e/conftest.py)."""
    data = pathlib.Path(path).read_bytes()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    fmt, count, props, element, face_count, face_types = None, 0, [], None, 0, None
    for line in data[:end].decode("ascii").splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "format":
            fmt = words[1]
        elif words[0] == "element":
            element = words[1]
            if element == "vertex":
                count = int(words[2])
            elif element == "face":
                face_count = int(words[2])
        elif words[0] == "property" and element == "face" and words[1] == "list":
            face_types = (_PLY_TYPES[words[2]], _PLY_TYPES[words[3]])
        elif words[0] == "property" and element == "vertex":
            if words[1] == "list":
                raise ValueError(f"{path}: list property in the vertex element")
            props.append((words[2], _PLY_TYPES[words[1]]))
    if fmt == "ascii":
        rows = data[end:].decode("ascii").split("\n")
        table = np.array([[float(x) for x in r.split()[:len(props)]] for r in rows[:count]])
        faces = np.array([[int(x) for x in r.split()[1:4]] for r in rows[count:count + face_count]],
                         dtype=np.int64).reshape(-1, 3)
        return np.rec.fromarrays(table.T, names=[p[0] for p in props]), faces
    if fmt != "binary_little_endian":
        raise ValueError(f"{path}: unsupported PLY format {fmt}")
    dtype = np.dtype([(name, "<" + t) for name, t in props])
    vertices = np.frombuffer(data, dtype=dtype, count=count, offset=end)
    if not (face_count and face_types):
        return vertices, np.zeros((0, 3), dtype=np.int64)
    face_dtype = np.dtype([("n", "<" + face_types[0]), ("i", "<" + face_types[1], 3)])
    records = np.frombuffer(data, dtype=face_dtype, count=face_count,
                            offset=end + count * dtype.itemsize)
    if not np.all(records["n"] == 3):
        raise ValueError(f"{path}: only triangle meshes are supported")
    return vertices, records["i"].astype(np.int64)


def read_mesh(path):
    """(points (n,3) float64, triangles (m,3) int64, per-vertex quality or None)."""
    path = pathlib.Path(path)
    if path.suffix.lower() == ".off":
        return read_off(path) + (None,)
    v, f = read_ply(path)
    points = np.stack([v["x"], v["y"], v["z"]], axis=1).astype(np.float64)
    quality = v["quality"].astype(np.float64) if "quality" in v.dtype.names else None
    return points, f, quality


def read_off(path):
    words = []
    for line in pathlib.Path(path).read_text().splitlines():
        line = line.split("#")[0].strip()
        if line:
            words.append(line.split())
    header = words[0]
    if header[0].endswith("OFF") and len(header) > 1:
        counts, body = header[1:], words[1:]
    else:
        counts, body = words[1], words[2:]
    nv, nf = int(counts[0]), int(counts[1])
    points = np.array([[float(x) for x in w[:3]] for w in body[:nv]])
    faces = []
    for w in body[nv:nv + nf]:
        k = int(w[0])
        idx = [int(x) for x in w[1:1 + k]]
        faces.extend([idx[0], idx[j], idx[j + 1]] for j in range(1, k - 1))  # fan
    return points, np.array(faces, dtype=np.int64).reshape(-1, 3)


def write_ply(path, points, faces):
    """Binary little-endian PLY, float32 coordinates, uchar/int face lists."""
    points = np.asarray(points, dtype="<f4")
    faces = np.asarray(faces)
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"element vertex {len(points)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    rec = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", 3)])
    rec["n"] = 3
    rec["i"] = faces
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(points.tobytes())
        f.write(rec.tobytes())


def midpoint_subdivide(points, faces):
    """Each triangle into four at its edge midpoints (connectivity only; the shape is unchanged)."""
    faces = np.asarray(faces, dtype=np.int64)
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    key = np.sort(edges, axis=1)
    unique, inverse = np.unique(key, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    n = len(points)
    mid = 0.5 * (points[unique[:, 0]] + points[unique[:, 1]])
    m = len(faces)
    a, b, c = faces[:, 0], faces[:, 1], faces[:, 2]
    ab, bc, ca = n + inverse[:m], n + inverse[m:2 * m], n + inverse[2 * m:]
    # the four children of a face stay next to each other, so memory order follows the surface
    # as in the input (a blocked order would slow every method down through cache misses)
    new_faces = np.stack([np.stack([a, ab, ca], 1), np.stack([ab, b, bc], 1),
                          np.stack([ca, bc, c], 1), np.stack([ab, bc, ca], 1)], 1).reshape(-1, 3)
    return np.concatenate([points, mid]), new_faces


def check_manifold(faces, vertex_count):
    """(ok, reason): every edge used by one or two faces, two-face edges oriented oppositely,
    every vertex referenced."""
    faces = np.asarray(faces, dtype=np.int64)
    if np.any(faces[:, 0] == faces[:, 1]) or np.any(faces[:, 1] == faces[:, 2]) or \
            np.any(faces[:, 0] == faces[:, 2]):
        return False, "degenerate faces"
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    _, dcount = np.unique(directed, axis=0, return_counts=True)
    if np.any(dcount > 1):
        return False, "inconsistent orientation or non-manifold edges"
    _, ucount = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
    if np.any(ucount > 2):
        return False, "non-manifold edges"
    if len(np.unique(faces)) != vertex_count:
        return False, "unreferenced vertices"
    return True, ""
