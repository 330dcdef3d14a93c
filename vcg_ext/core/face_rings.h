// Per-face geometry (unit normal, area, centroid) and face rings: the faces sharing a vertex with
// each face, and the up to three sharing an edge.
//
// Inputs: positions, triangles, Rings (rings.h). Outputs, per face in input order. The normal
// filter, the dihedral spread, the face patches and the mode choice read them.
#pragma once

#include "vcg_ext/core/rings.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace vcg_ext {

struct FaceGeometry {
  std::vector<Vec3> normal;   // unit; zero for a degenerate face
  std::vector<double> area;
  std::vector<Vec3> centroid;
};

namespace detail {
// A face's unit normal (zero when degenerate) and the length of its cross product (twice its area).
inline Vec3 unitFaceNormal(const Vec3 &a, const Vec3 &b, const Vec3 &c, double &cross_length) {
  const Vec3 cross = (b - a).cross(c - a);
  cross_length = cross.norm();
  return cross_length > 0 && std::isfinite(cross_length) ? Vec3(cross / cross_length)
                                                         : Vec3::Zero();
}
} // namespace detail

inline void computeFaceGeometry(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                                FaceGeometry &out) {
  const int m = int(faces.size());
  out.normal.resize(m);
  out.area.resize(m);
  out.centroid.resize(m);
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
  for (int f = 0; f < m; ++f) {
    const Vec3 &a = points[faces[f][0]], &b = points[faces[f][1]], &c = points[faces[f][2]];
    double len;
    out.normal[f] = detail::unitFaceNormal(a, b, c, len);
    out.area[f] = 0.5 * len;
    out.centroid[f] = (a + b + c) / 3.0;
  }
}

// The face centroids alone (computeFaceGeometry's).
inline void computeFaceCentroids(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                                 std::vector<Vec3> &centroid) {
  const int m = int(faces.size());
  centroid.resize(m);
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
  for (int f = 0; f < m; ++f)
    centroid[f] = (points[faces[f][0]] + points[faces[f][1]] + points[faces[f][2]]) / 3.0;
}

// The unit face normals alone (computeFaceGeometry's, without areas and centroids).
inline void computeFaceNormals(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                               std::vector<Vec3> &normals) {
  const int m = int(faces.size());
  normals.resize(m);
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
  for (int f = 0; f < m; ++f) {
    double len;
    normals[f] = detail::unitFaceNormal(points[faces[f][0]], points[faces[f][1]],
                                        points[faces[f][2]], len);
  }
}

// Per face, the sorted faces sharing at least one vertex with it, itself included (CSR), and the
// up to three faces sharing an edge with it (−1 where none; one of them on a non-manifold edge).
struct FaceRings {
  std::vector<int> offsets, faces;
  std::vector<std::array<int, 3>> edge_neighbours;
  const int *begin(int f) const { return faces.data() + offsets[f]; }
  const int *end(int f) const { return faces.data() + offsets[f + 1]; }
  int size(int f) const { return offsets[f + 1] - offsets[f]; }
  bool contains(int f, int g) const { return std::binary_search(begin(f), end(f), g); }
};

namespace detail {
// Appends the union of three ascending lists to `out`, ascending and without repeats: a vertex's
// faces are listed in face order (rings.h), so a face's ring is a merge, not a sort.
inline void mergeSortedUnique(const int *a, const int *a_end, const int *b, const int *b_end,
                              const int *c, const int *c_end, std::vector<int> &out) {
  int last = -1;
  for (;;) {
    int m = INT_MAX;
    if (a != a_end) m = *a;
    if (b != b_end && *b < m) m = *b;
    if (c != c_end && *c < m) m = *c;
    if (m == INT_MAX) return;
    if (m != last) out.push_back(m), last = m;
    a += a != a_end && *a == m;
    b += b != b_end && *b == m;
    c += c != c_end && *c == m;
  }
}
} // namespace detail

namespace detail {
// The faces sharing each of f's edges with it (−1 where none; one of them on a non-manifold edge).
inline std::array<int, 3> faceEdgeNeighbours(int f, const std::vector<Face> &faces,
                                             const Rings &rings) {
  std::array<int, 3> out = {-1, -1, -1};
  for (int k = 0; k < 3; ++k) {
    const int a = faces[f][k], b = faces[f][(k + 1) % 3];
    for (const int *g = rings.facesBegin(a); g != rings.facesEnd(a); ++g) {
      const Face &t = faces[*g];
      if (*g != f && (t[0] == b || t[1] == b || t[2] == b)) {
        out[k] = *g;
        break;
      }
    }
  }
  return out;
}
} // namespace detail

// `with_edge_neighbours` false leaves edge_neighbours empty (only the normal filter, the
// dihedral spread and the mode choice read them; the face patches do not); `with_lists` false
// leaves the ring lists empty (the noise estimate and the windowed mode choice read only the edge
// neighbours: addFaceRingLists adds the lists when a whole-mesh normal filter needs them).
inline FaceRings computeFaceRings(const std::vector<Face> &faces, const Rings &rings,
                                  bool with_edge_neighbours = true, bool with_lists = true) {
  FaceRings r;
  const int m = int(faces.size());
  if (with_edge_neighbours) r.edge_neighbours.resize(m);
  if (!with_lists) {
    if (with_edge_neighbours) {
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
      for (int f = 0; f < m; ++f) r.edge_neighbours[f] = detail::faceEdgeNeighbours(f, faces, rings);
    }
    return r;
  }
  // In parallel blocks, each list exactly sized (rings.h's buildCsrInBlocks).
  detail::buildCsrInBlocks(m, r.offsets, r.faces, [&](int f, std::vector<int> &out) {
    detail::mergeSortedUnique(rings.facesBegin(faces[f][0]), rings.facesEnd(faces[f][0]),
                              rings.facesBegin(faces[f][1]), rings.facesEnd(faces[f][1]),
                              rings.facesBegin(faces[f][2]), rings.facesEnd(faces[f][2]), out);
    if (with_edge_neighbours) r.edge_neighbours[f] = detail::faceEdgeNeighbours(f, faces, rings);
  });
  return r;
}

// Adds the ring lists to face rings built without them (computeFaceRings' `with_lists`).
inline void addFaceRingLists(FaceRings &face_rings, const std::vector<Face> &faces,
                             const Rings &rings) {
  if (!face_rings.offsets.empty() || faces.empty()) return;
  FaceRings lists = computeFaceRings(faces, rings, /*with_edge_neighbours=*/false);
  face_rings.offsets.swap(lists.offsets);
  face_rings.faces.swap(lists.faces);
}

} // namespace vcg_ext
