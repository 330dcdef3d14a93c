// Windows of a large mesh: patches around seed vertices spread along the spatial order, as one
// mesh, for measurements that read a bounded neighbourhood of each element (evidence_windows.h,
// noise_windows.h).
//
// Inputs: the mesh (plain arrays, in the drivers' spatial order), its Rings, the movable flags.
// Output: MeshWindows, the faces within `reach` rings of a seed in the mesh's order over their
// vertices in the mesh's order (a monotone renumbering: every neighbour sum runs in the same order
// as on the whole mesh), with the elements within `core_rings` of a seed marked. An element whose
// values depend only on the elements within k rings of it gets the whole mesh's values, bit for
// bit, when it is core and reach ≥ core_rings + k (tests/unit/test_evidence_windows.cpp).
#pragma once

#include "vcg_ext/core/rings.h"

#include <cstdint>
#include <vector>

namespace vcg_ext {
namespace detail {

// Ring distance of every vertex from the nearest seed (breadth first from all seeds), up to
// `limit`; farther vertices read limit + 1.
// `source` (optional): per vertex the index in `seeds` of the seed it was reached from first (a
// frontier runs in seed order: the lowest index among equally near seeds), −1 beyond `limit`.
inline std::vector<int> ringDistance(const Rings &rings, const std::vector<int> &seeds, int limit,
                                     std::vector<int> *source = nullptr) {
  std::vector<int> distance(rings.vertex_count, limit + 1), frontier, next;
  if (source) source->assign(rings.vertex_count, -1);
  for (size_t i = 0; i < seeds.size(); ++i)
    if (distance[seeds[i]] > 0) {
      distance[seeds[i]] = 0, frontier.push_back(seeds[i]);
      if (source) (*source)[seeds[i]] = int(i);
    }
  for (int depth = 1; depth <= limit && !frontier.empty(); ++depth) {
    next.clear();
    for (int v : frontier)
      for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w)
        if (distance[*w] > depth) {
          distance[*w] = depth, next.push_back(*w);
          if (source) (*source)[*w] = (*source)[v];
        }
    frontier.swap(next);
  }
  return distance;
}

// One seed per equal run of the vertex order (the spatial order: runs are regions), the run's
// middle vertex or the next one after it that has faces and may move.
inline std::vector<int> windowSeeds(const Rings &rings, const std::vector<std::uint8_t> &fixed,
                                    int windows) {
  const long n = rings.vertex_count;
  std::vector<int> seeds;
  for (long w = 0; w < windows && n > 0; ++w) {
    const long begin = w * n / windows, end = (w + 1) * n / windows;
    for (long v = (begin + end) / 2; v < end; ++v)
      if (!fixed[v] && rings.ring1Size(int(v)) > 0) {
        seeds.push_back(int(v));
        break;
      }
  }
  return seeds;
}

// How many faces windows of `reach` rings would hold (all corners within reach of a seed), from
// the distances of ringDistance: counted before building them, to refuse windows that would take
// most of the mesh.
inline long windowFaceCount(const std::vector<Face> &faces, const std::vector<int> &distance,
                            int reach) {
  const long m = long(faces.size());
  long taken = 0;
#pragma omp parallel for schedule(static) reduction(+ : taken) if (m >= min_parallel_vertices)
  for (long g = 0; g < m; ++g) {
    const Face &f = faces[g];
    taken += distance[f[0]] <= reach && distance[f[1]] <= reach && distance[f[2]] <= reach;
  }
  return taken;
}

} // namespace detail

// The windows as one mesh: the faces whose corners all lie within `reach` rings of a seed, in
// the mesh's order, over their vertices in the mesh's order.
struct MeshWindows {
  MeshArrays mesh;
  std::vector<int> face;            // window face -> mesh face
  std::vector<std::uint8_t> fixed;  // the mesh's movable flags, per window vertex
  std::vector<std::uint8_t> core;   // per window face: its corners within the core rings
  std::vector<std::uint8_t> core_vertex; // per window vertex: within the core rings
  std::vector<int> window;          // per window face: the seed its first corner was reached from
};

// With the ring distances and sources of ringDistance(rings, seeds, reach, &source) given.
inline MeshWindows meshWindows(const MeshArrays &mesh, const std::vector<std::uint8_t> &fixed,
                               const std::vector<int> &distance, const std::vector<int> &source,
                               int core_rings, int reach) {
  MeshWindows w;
  std::vector<int> local(mesh.points.size(), -1);
  for (size_t v = 0; v < mesh.points.size(); ++v)
    if (distance[v] <= reach) {
      local[v] = int(w.mesh.points.size());
      w.mesh.points.push_back(mesh.points[v]);
      w.fixed.push_back(fixed[v]);
      w.core_vertex.push_back(distance[v] <= core_rings);
    }
  for (size_t g = 0; g < mesh.faces.size(); ++g) {
    const Face &f = mesh.faces[g];
    if (local[f[0]] < 0 || local[f[1]] < 0 || local[f[2]] < 0) continue;
    w.face.push_back(int(g));
    w.mesh.faces.push_back({local[f[0]], local[f[1]], local[f[2]]});
    w.core.push_back(distance[f[0]] <= core_rings && distance[f[1]] <= core_rings &&
                     distance[f[2]] <= core_rings);
    w.window.push_back(source[f[0]]);
  }
  return w;
}

inline MeshWindows meshWindows(const MeshArrays &mesh, const Rings &rings,
                               const std::vector<std::uint8_t> &fixed, const std::vector<int> &seeds,
                               int core_rings, int reach) {
  std::vector<int> source;
  const std::vector<int> distance = detail::ringDistance(rings, seeds, reach, &source);
  return meshWindows(mesh, fixed, distance, source, core_rings, reach);
}

} // namespace vcg_ext
