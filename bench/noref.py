"""No-reference figures for meshes without a clean version (real scans), numpy only:

- median dihedral spread (degrees): per face, the largest minus the smallest signed dihedral angle
  across its three edges, median over the faces with three neighbours (the definition of
  vcg_ext/methods/feature/normal_filter.h's medianDihedralSpreadDeg, re-implemented here so that the figure does
  not depend on the plugin being measured). Curvature bends a face's three edges alike (a sphere:
  all equal, spread near 0), noise bends them at random, convex and concave: the spread measures
  noise, not shape. Smoothing that removes noise lowers it; it cannot tell noise from fine relief,
  hence the pictures beside it.
- displacement of a result against its input, in the input's mean edge lengths: the mean (issue
  16's "moves vertices by at least as much as MeshLab's Taubin x10") and the mean signed part along
  the input's vertex normals (negative = the surface moved inwards: shrinkage, the one-sided error
  of plain Laplacian smoothing; a volume-preserving smoother stays near 0 on average).
"""
import numpy as np


def area_normals(points, faces):
    """Face normals scaled by twice the face area."""
    a, b, c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
    return np.cross(b - a, c - a)


def face_normals(points, faces):
    """(unit face normals, which faces have a non-zero area)."""
    fn = area_normals(points, faces)
    return fn / np.maximum(np.linalg.norm(fn, axis=1, keepdims=True), 1e-300), \
        np.linalg.norm(fn, axis=1) > 0


def unique_edges(faces):
    """(k,2) vertex pairs, each undirected edge once."""
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    return np.unique(np.sort(e, axis=1), axis=0)


def edge_neighbours(faces):
    """(m,3) index of the face across edge k = (faces[f][k], faces[f][k+1]); -1 on a boundary or a
    non-manifold edge."""
    m = len(faces)
    a = faces.reshape(-1)
    b = faces[:, [1, 2, 0]].reshape(-1)
    n = int(faces.max()) + 1
    key = np.minimum(a, b) * n + np.maximum(a, b)
    order = np.argsort(key, kind="stable")
    ks = key[order]
    out = np.full(3 * m, -1, dtype=np.int64)
    start = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
    count = np.diff(np.r_[start, len(ks)])
    pairs = start[count == 2]
    h0, h1 = order[pairs], order[pairs + 1]
    out[h0], out[h1] = h1 // 3, h0 // 3
    return out.reshape(m, 3)


def median_dihedral_spread_deg(points, faces):
    points = np.asarray(points, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    normals, ok = face_normals(points, faces)
    nb = edge_neighbours(faces)
    complete = ok & np.all(nb >= 0, axis=1)
    complete &= np.all(ok[np.maximum(nb, 0)], axis=1)
    f = np.flatnonzero(complete)
    angles = np.empty((len(f), 3))
    for k in range(3):
        e = points[faces[f, (k + 1) % 3]] - points[faces[f, k]]
        e /= np.maximum(np.linalg.norm(e, axis=1, keepdims=True), 1e-300)
        a, b = normals[f], normals[nb[f, k]]
        angles[:, k] = np.degrees(np.arctan2(np.einsum("ij,ij->i", np.cross(a, b), e),
                                             np.einsum("ij,ij->i", a, b)))
    if len(f) == 0:
        return 0.0
    return float(np.median(angles.max(1) - angles.min(1)))


def mean_edge_length(points, faces):
    e = unique_edges(faces)
    return float(np.linalg.norm(points[e[:, 0]] - points[e[:, 1]], axis=1).mean())


def vertex_normals(points, faces):
    """Area-weighted unit vertex normals."""
    fn = area_normals(points, faces)
    vn = np.zeros_like(points)
    for k in range(3):
        np.add.at(vn, faces[:, k], fn)
    return vn / np.maximum(np.linalg.norm(vn, axis=1, keepdims=True), 1e-300)


def displacement(before, after, faces):
    """{mean, p99, normal_mean, normal, tangential}: |after - before| per vertex, in the input's
    mean edge lengths: its mean and 99th percentile, the mean of its signed part along the input's
    vertex normals (negative: inwards), and the means of the lengths of its part along the normals
    and of its part across them. Only the part along the normals changes the surface; the part
    across slides vertices within it (a uniform Laplacian such as Taubin's evens out an irregular
    triangulation that way), so the two say what a displacement did."""
    before = np.asarray(before, dtype=np.float64)
    after = np.asarray(after, dtype=np.float64)
    edge = mean_edge_length(before, faces)
    d = after - before
    length = np.linalg.norm(d, axis=1) / edge
    normals = vertex_normals(before, faces)
    along = np.einsum("ij,ij->i", d, normals)
    across = np.linalg.norm(d - along[:, None] * normals, axis=1)
    return {"mean": float(length.mean()), "p99": float(np.percentile(length, 99)),
            "normal_mean": float(along.mean() / edge),
            "normal": float(np.abs(along).mean() / edge),
            "tangential": float(across.mean() / edge)}
