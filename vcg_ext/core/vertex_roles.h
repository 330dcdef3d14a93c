// Which vertices a driver may move, and the boundary curve each boundary vertex moves along.
//
// Inputs: the mesh as plain arrays, its Rings, the mean edge length. Output: VertexRoles: frozen
// vertices (non-manifold, isolated, or on a degenerate face: zero area or a repeated index) and,
// per boundary vertex, its two neighbours along the boundary (−1 where absent).
#pragma once

#include "vcg_ext/core/rings.h"

#include <array>
#include <cstdint>
#include <vector>

namespace vcg_ext {
namespace detail {

struct VertexRoles {
  std::vector<std::uint8_t> frozen;
  std::vector<std::array<int, 2>> boundary_neighbours; // -1 where absent
};

inline VertexRoles vertexRoles(const MeshArrays &mesh, const Rings &rings, double edge) {
  VertexRoles roles;
  const int n = rings.vertex_count;
  roles.frozen.assign(n, 0);
  roles.boundary_neighbours.assign(n, {-1, -1});
  const double min_area = 1e-12 * edge * edge;
  // Degenerate faces in parallel, their corners marked in face order.
  const int m = int(mesh.faces.size());
  std::vector<std::uint8_t> degenerate(m);
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
  for (int g = 0; g < m; ++g) {
    const Face &f = mesh.faces[g];
    const Vec3 &a = mesh.points[f[0]], &b = mesh.points[f[1]], &c = mesh.points[f[2]];
    degenerate[g] = !(0.5 * (b - a).cross(c - a).norm() > min_area) || f[0] == f[1] ||
                    f[1] == f[2] || f[0] == f[2];
  }
  for (int g = 0; g < m; ++g)
    if (degenerate[g]) {
      const Face &f = mesh.faces[g];
      roles.frozen[f[0]] = roles.frozen[f[1]] = roles.frozen[f[2]] = 1;
    }
  // Per vertex: each writes its own entries.
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v) {
    if (rings.nonmanifold[v] || rings.isolated[v]) roles.frozen[v] = 1;
    if (!rings.boundary[v]) continue;
    // A boundary edge (v, w) lies in exactly one of v's faces.
    int found = 0;
    for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v) && found < 2; ++w) {
      int shared = 0;
      for (const int *f = rings.facesBegin(v); f != rings.facesEnd(v); ++f) {
        const Face &t = mesh.faces[*f];
        shared += (t[0] == *w || t[1] == *w || t[2] == *w);
      }
      if (shared == 1) roles.boundary_neighbours[v][found++] = *w;
    }
  }
  return roles;
}

} // namespace detail
} // namespace vcg_ext
