// A mesh's vertices along a Morton (Z-order) curve of their positions, and its faces in the order
// of their renumbered corners: a copy of the mesh that the drivers run on and whose results they
// map back.
//
// Inputs: MeshArrays. Output: SpatialOrder (the reordered copy, and the map back to the input's
// order). Morton 1966; the use for mesh locality as in Isenburg & Lindstrom 2005 ("Streaming
// meshes").
//
// Why: every stage of the feature and organic modes reads each vertex's or face's neighbours, and
// many meshes come with a spatially scattered vertex order (midpoint subdivision and many
// exporters append new vertices at the end), where nearly every such read misses the cache
// (docs/studies/performance.md). And because the order depends only on the positions and the
// connectivity, the result does not depend on the input's vertex or face order to the last bit
// (sums over neighbours run in the same order whatever the input order); only vertices at
// exactly the same position keep their input order among themselves.
// vertices at exactly the same position keep their input order among themselves.
#pragma once

#include "vcg_ext/core/mesh_arrays.h"
#include "vcg_ext/core/rings.h" // min_parallel_vertices, parallelSort

#include <algorithm>
#include <array>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace vcg_ext {

// The vertices sorted along the Morton curve of a 2^21 lattice over their bounding box; equal codes
// by coordinates, then index; non-finite positions last.
inline std::vector<int> mortonOrder(const std::vector<Vec3> &points) {
  const int n = int(points.size());
  Vec3 lowest = Vec3::Constant(INFINITY), highest = Vec3::Constant(-INFINITY);
  for (const Vec3 &p : points)
    if (p.allFinite()) lowest = lowest.cwiseMin(p), highest = highest.cwiseMax(p);
  const double extent = (highest - lowest).maxCoeff();
  auto spread = [](std::uint64_t x) { // 21 bits to every third bit of 63
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
  };
  // (code, vertex) pairs sorted in parallel, then the rare runs of equal codes by position: the
  // order is a strict total order, so it is the same whatever the sort or the thread count.
  std::vector<std::pair<std::uint64_t, int>> keyed(n);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v) {
    std::uint64_t code = ~0ull;
    if (points[v].allFinite()) {
      code = 0;
      for (int k = 0; k < 3; ++k) {
        // In [0, 1] for any finite extent; NaN (an infinite or zero extent) counts as 0.
        const double t = (points[v][k] - lowest[k]) / extent;
        const double c = t >= 0 ? std::min(t, 1.0) * double(0x1fffff) : 0.0;
        code |= spread(std::uint64_t(c)) << k;
      }
    }
    keyed[v] = {code, v};
  }
  detail::parallelSort(keyed);
  for (int begin = 0, end; begin < n; begin = end) {
    for (end = begin + 1; end < n && keyed[end].first == keyed[begin].first;) ++end;
    if (end - begin > 1)
      std::sort(keyed.begin() + begin, keyed.begin() + end, [&](const auto &x, const auto &y) {
        const int a = x.second, b = y.second;
        if (points[a].allFinite() && points[b].allFinite()) {
          for (int k = 0; k < 3; ++k)
            if (points[a][k] != points[b][k]) return points[a][k] < points[b][k];
        }
        return a < b;
      });
  }
  std::vector<int> order(n);
  for (int v = 0; v < n; ++v) order[v] = keyed[v].second;
  return order;
}

struct SpatialOrder {
  MeshArrays mesh;           // points, faces and selection in the new order (no mesh slots)
  std::vector<int> input_of; // new vertex index -> the input's

  // Per-vertex values computed on `mesh`, put back in the input's order.
  template <class T> void toInputOrder(std::vector<T> &values) const {
    if (values.size() != input_of.size()) return;
    std::vector<T> out(values.size());
    for (size_t v = 0; v < values.size(); ++v) out[input_of[v]] = std::move(values[v]);
    values.swap(out);
  }
};

namespace detail {

// Sorts faces into lexicographic order (the order std::sort gives) in linear time: by first corner
// with a counting sort, then each first corner's few faces by the other two. First corners out of
// [0, vertex_count) (which validation rejects later) get a bucket before and one after the others.
inline void sortFacesByCorners(std::vector<Face> &faces, int vertex_count) {
  const long count = long(faces.size());
  if (count < 2) return;
  // Bucket 0: first corner below 0; 1 + c: first corner c; vertex_count + 1: the rest.
  auto bucket = [&](const Face &f) -> size_t {
    return f[0] < 0 ? 0 : f[0] < vertex_count ? size_t(f[0]) + 1 : size_t(vertex_count) + 1;
  };
  const size_t buckets = size_t(vertex_count) + 2;
  std::vector<long> start(buckets + 1, 0);
  for (const Face &f : faces) ++start[bucket(f) + 1];
  for (size_t k = 1; k <= buckets; ++k) start[k] += start[k - 1];
  std::vector<Face> sorted(faces.size());
  {
    std::vector<long> at(start.begin(), start.end() - 1);
    for (const Face &f : faces) sorted[size_t(at[bucket(f)]++)] = f;
  }
  faces.swap(sorted);
  const long bucket_count = long(buckets);
#pragma omp parallel for schedule(static) if (bucket_count >= min_parallel_vertices)
  for (long k = 0; k < bucket_count; ++k)
    if (start[size_t(k) + 1] - start[size_t(k)] > 1)
      std::sort(faces.begin() + start[size_t(k)], faces.begin() + start[size_t(k) + 1]);
}

} // namespace detail

// Renumbers `mesh` in place: vertices along the Morton curve, faces' corners renumbered and
// rotated to start at the lowest (orientation kept), faces sorted; the selection, the mesh slots
// and the slot map follow. Returns the map from the new vertex index to the old one.
inline std::vector<int> putInSpatialOrder(MeshArrays &mesh) {
  const int n = int(mesh.points.size());
  std::vector<int> input_of = mortonOrder(mesh.points);
  // Every loop writes each element once from other arrays: in parallel (on one thread the
  // renumbering of a large mesh mostly waits on scattered reads).
  auto permute = [&](auto &values) {
    if (values.size() != size_t(n)) return;
    std::remove_reference_t<decltype(values)> out(n);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
    for (int v = 0; v < n; ++v) out[v] = values[input_of[v]];
    values.swap(out);
  };
  permute(mesh.points);
  permute(mesh.selected);
  permute(mesh.mesh_slot);
  std::vector<int> new_of(n);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v) new_of[input_of[v]] = v;
  const long slot_count = long(mesh.compact_index.size());
#pragma omp parallel for schedule(static) if (slot_count >= min_parallel_vertices)
  for (long i = 0; i < slot_count; ++i) {
    int &c = mesh.compact_index[i];
    if (c >= 0 && c < n) c = new_of[c];
  }
  const long face_count = long(mesh.faces.size());
#pragma omp parallel for schedule(static) if (face_count >= min_parallel_vertices)
  for (long i = 0; i < face_count; ++i) {
    const Face &f = mesh.faces[i];
    Face g = {new_of[f[0]], new_of[f[1]], new_of[f[2]]};
    std::rotate(g.begin(), std::min_element(g.begin(), g.end()), g.end());
    mesh.faces[i] = g;
  }
  detail::sortFacesByCorners(mesh.faces, n);
  mesh.spatially_ordered = true;
  return input_of;
}

// A copy of `input` in spatial order (putInSpatialOrder), and the map back.
inline SpatialOrder spatialOrder(const MeshArrays &input) {
  SpatialOrder s;
  const int n = int(input.points.size());
  s.mesh.points = input.points;
  s.mesh.faces = input.faces;
  s.mesh.selected.assign(n, 0);
  for (int v = 0; v < n && size_t(v) < input.selected.size(); ++v)
    s.mesh.selected[v] = input.selected[v];
  s.input_of = putInSpatialOrder(s.mesh);
  return s;
}

} // namespace vcg_ext
