// Stage 0: mesh topology computed once per run, in compressed (CSR) arrays.
//
// Inputs: vertex count and triangles (compact indices). Outputs: per-vertex incident faces, 1-ring
// and 2-ring vertex lists (sorted, without the vertex itself), boundary / non-manifold / isolated
// flags. Positions are not needed; edge statistics are a separate function because positions
// change every iteration while the rings do not.
#pragma once

#include "mesh_arrays.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace vcg_ext {

struct Rings {
  int vertex_count = 0;
  std::vector<int> face_offsets, faces; // faces around vertex v: faces[face_offsets[v] .. +1)
  std::vector<int> ring1_offsets, ring1;
  std::vector<int> ring2_offsets, ring2; // 2-ring includes the 1-ring; see computeRings
  std::vector<std::uint8_t> boundary;    // on an edge used by exactly one face
  std::vector<std::uint8_t> nonmanifold; // on an edge of > 2 faces, or its faces form > 1 fan
  std::vector<std::uint8_t> isolated;    // referenced by no face
  long boundary_edges = 0, nonmanifold_edges = 0; // both zero: the surface encloses a volume

  int ring1Size(int v) const { return ring1_offsets[v + 1] - ring1_offsets[v]; }
  int ring2Size(int v) const { return ring2_offsets[v + 1] - ring2_offsets[v]; }
  const int *ring1Begin(int v) const { return ring1.data() + ring1_offsets[v]; }
  const int *ring1End(int v) const { return ring1.data() + ring1_offsets[v + 1]; }
  const int *ring2Begin(int v) const { return ring2.data() + ring2_offsets[v]; }
  const int *ring2End(int v) const { return ring2.data() + ring2_offsets[v + 1]; }
  const int *facesBegin(int v) const { return faces.data() + face_offsets[v]; }
  const int *facesEnd(int v) const { return faces.data() + face_offsets[v + 1]; }
};

namespace detail {
inline void buildCsr(int n, const std::vector<std::pair<int, int>> &pairs,
                     std::vector<int> &offsets, std::vector<int> &values) {
  offsets.assign(n + 1, 0);
  for (const auto &p : pairs) ++offsets[p.first + 1];
  for (int i = 0; i < n; ++i) offsets[i + 1] += offsets[i];
  values.resize(pairs.size());
  std::vector<int> cursor(offsets.begin(), offsets.end() - 1);
  for (const auto &p : pairs) values[cursor[p.first]++] = p.second;
}
} // namespace detail

// Builds the rings of a triangle mesh with `vertex_count` vertices.
inline Rings computeRings(int vertex_count, const std::vector<Face> &faces) {
  Rings r;
  r.vertex_count = vertex_count;
  const int n = vertex_count;

  std::vector<std::pair<int, int>> vf;
  vf.reserve(faces.size() * 3);
  for (int f = 0; f < int(faces.size()); ++f)
    for (int k = 0; k < 3; ++k) vf.emplace_back(faces[f][k], f);
  detail::buildCsr(n, vf, r.face_offsets, r.faces);

  // Directed half-edges sorted by (min,max) give each undirected edge's face count.
  std::vector<std::pair<int, int>> edges;
  edges.reserve(faces.size() * 3);
  for (const Face &f : faces)
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3];
      if (a != b) edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  r.boundary.assign(n, 0);
  r.nonmanifold.assign(n, 0);
  r.isolated.assign(n, 0);
  std::vector<std::pair<int, int>> adjacency;
  adjacency.reserve(edges.size() * 2);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    const int count = int(j - i), a = edges[i].first, b = edges[i].second;
    if (count == 1) r.boundary[a] = r.boundary[b] = 1, ++r.boundary_edges;
    if (count > 2) r.nonmanifold[a] = r.nonmanifold[b] = 1, ++r.nonmanifold_edges;
    adjacency.emplace_back(a, b);
    adjacency.emplace_back(b, a);
    i = j;
  }
  std::sort(adjacency.begin(), adjacency.end());
  detail::buildCsr(n, adjacency, r.ring1_offsets, r.ring1);

  // A manifold vertex's faces form one fan: its link (the edges opposite to it) is one path or one
  // cycle. Count the link's connected components by repeatedly absorbing faces that share a
  // neighbour with the growing fan; a second component is a "bow-tie".
  std::vector<int> fan_faces, members;
  for (int v = 0; v < n; ++v) {
    const int nf = r.face_offsets[v + 1] - r.face_offsets[v];
    if (nf == 0) {
      r.isolated[v] = 1;
      continue;
    }
    fan_faces.assign(r.facesBegin(v), r.facesEnd(v));
    members.clear();
    auto others = [&](int f, int k) {
      const Face &t = faces[f];
      return t[0] == v ? (k ? t[2] : t[1]) : t[1] == v ? (k ? t[0] : t[2]) : (k ? t[1] : t[0]);
    };
    members.push_back(others(fan_faces.back(), 0));
    members.push_back(others(fan_faces.back(), 1));
    fan_faces.pop_back();
    for (bool grew = true; grew && !fan_faces.empty();) {
      grew = false;
      for (size_t k = 0; k < fan_faces.size();) {
        const int a = others(fan_faces[k], 0), b = others(fan_faces[k], 1);
        const bool touches = std::find(members.begin(), members.end(), a) != members.end() ||
                             std::find(members.begin(), members.end(), b) != members.end();
        if (touches) {
          members.push_back(a);
          members.push_back(b);
          fan_faces[k] = fan_faces.back();
          fan_faces.pop_back();
          grew = true;
        } else {
          ++k;
        }
      }
    }
    if (!fan_faces.empty()) r.nonmanifold[v] = 1;
  }

  // 2-ring: union of the neighbours' 1-rings, sorted, without v itself. A non-manifold neighbour is
  // included but not expanded: its 1-ring reaches into other sheets (a fin, a second fan), which
  // would bend the patch fitted to this one (measured: a fin of height 0.3 on a unit grid lifted
  // its neighbours by 0.07).
  std::vector<int> scratch;
  r.ring2_offsets.assign(n + 1, 0);
  r.ring2.clear();
  r.ring2.reserve(r.ring1.size() * 3);
  for (int v = 0; v < n; ++v) {
    scratch.clear();
    for (const int *a = r.ring1Begin(v); a != r.ring1End(v); ++a) {
      scratch.push_back(*a);
      if (!r.nonmanifold[*a]) scratch.insert(scratch.end(), r.ring1Begin(*a), r.ring1End(*a));
    }
    std::sort(scratch.begin(), scratch.end());
    scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());
    for (int w : scratch)
      if (w != v) r.ring2.push_back(w);
    r.ring2_offsets[v + 1] = int(r.ring2.size());
  }
  return r;
}

struct EdgeStatistics {
  double mean_edge_length = 0;
  double bbox_diagonal = 0;
};

inline EdgeStatistics edgeStatistics(const std::vector<Vec3> &points, const Rings &r) {
  EdgeStatistics s;
  double sum = 0;
  long count = 0;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (int v = 0; v < r.vertex_count; ++v) {
    lo = lo.cwiseMin(points[v]);
    hi = hi.cwiseMax(points[v]);
    for (const int *a = r.ring1Begin(v); a != r.ring1End(v); ++a)
      if (*a > v) {
        sum += (points[*a] - points[v]).norm();
        ++count;
      }
  }
  s.mean_edge_length = count ? sum / count : 0;
  s.bbox_diagonal = r.vertex_count ? (hi - lo).norm() : 0;
  return s;
}

} // namespace vcg_ext
