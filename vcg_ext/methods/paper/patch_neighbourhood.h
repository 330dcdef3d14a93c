// Stage 5, mesh side: the local frame and (u,v) parameters of a vertex's fitting neighbourhood.
//
// Paper 3.2: the points are q_i and its 2-ring; N is the normalised mean of their vertex normals;
// they are projected onto the plane through q_i orthogonal to N and their min-max box is scaled to
// [0,1]^2. Coordinates are kept relative to q_i in the frame (e1, e2, N) so that the 9x9 fit is
// well conditioned whatever the mesh's position and scale, and e1 x e2 = N so that the patch
// normal B_u x B_v agrees with the vertex normal.
#pragma once

#include "vcg_ext/core/rings.h"

#include <Eigen/Geometry>

namespace vcg_ext {

struct LocalFrame {
  Vec3 origin, e1, e2, n;
  double x_min = 0, x_span = 1, y_min = 0, y_span = 1; // min-max box of the projections

  Vec3 toLocal(const Vec3 &p) const {
    const Vec3 d = p - origin;
    return {d.dot(e1), d.dot(e2), d.dot(n)};
  }
  Vec3 toWorld(const Vec3 &local) const {
    return origin + local.x() * e1 + local.y() * e2 + local.z() * n;
  }
  double u(const Vec3 &local) const { return (local.x() - x_min) / x_span; }
  double v(const Vec3 &local) const { return (local.y() - y_min) / y_span; }
};

// Orthonormal e1, e2 with e1 x e2 = n, stable for any unit n.
inline void tangentBasis(const Vec3 &n, Vec3 &e1, Vec3 &e2) {
  const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  e1 = helper.cross(n).normalized();
  e2 = n.cross(e1);
}

// Scratch for one vertex's neighbourhood; sized once per thread, reused for every vertex.
struct NeighbourhoodScratch {
  std::vector<int> vertices; // q_i first, then the neighbours
  std::vector<Vec3> local;   // coordinates in the frame
  std::vector<double> u, v;
  void reserve(int n) {
    vertices.reserve(n);
    local.reserve(n);
    u.reserve(n);
    v.reserve(n);
  }
};

enum class NeighbourhoodSize { TwoRing, OneRing };

// Fills `s` with vertex i and its ring, their local coordinates and (u,v) in [0,1]^2, in a frame
// whose normal is `normal`. Returns false when the projections span no area (a degenerate box).
inline bool projectNeighbourhood(int i, const std::vector<Vec3> &points, const Rings &rings,
                                 NeighbourhoodSize size, const Vec3 &normal, LocalFrame &frame,
                                 NeighbourhoodScratch &s) {
  const int *begin = size == NeighbourhoodSize::TwoRing ? rings.ring2Begin(i) : rings.ring1Begin(i);
  const int *end = size == NeighbourhoodSize::TwoRing ? rings.ring2End(i) : rings.ring1End(i);
  const int count = 1 + int(end - begin);
  // Sized once and written by index (no per-point capacity checks); within the reserved capacity
  // this does not allocate.
  s.vertices.resize(count);
  s.local.resize(count);
  s.u.resize(count);
  s.v.resize(count);
  s.vertices[0] = i;
  std::copy(begin, end, s.vertices.begin() + 1);

  frame.origin = points[i];
  frame.n = normal;
  tangentBasis(normal, frame.e1, frame.e2);
  double x_min = INFINITY, x_max = -INFINITY, y_min = INFINITY, y_max = -INFINITY;
  for (int k = 0; k < count; ++k) {
    const Vec3 l = frame.toLocal(points[s.vertices[k]]);
    s.local[k] = l;
    x_min = std::min(x_min, l.x()), x_max = std::max(x_max, l.x());
    y_min = std::min(y_min, l.y()), y_max = std::max(y_max, l.y());
  }
  frame.x_min = x_min, frame.x_span = x_max - x_min;
  frame.y_min = y_min, frame.y_span = y_max - y_min;
  const double box = std::max(frame.x_span, frame.y_span);
  if (!(frame.x_span > 1e-9 * box) || !(frame.y_span > 1e-9 * box)) return false;
  for (int k = 0; k < count; ++k) {
    s.u[k] = frame.u(s.local[k]);
    s.v[k] = frame.v(s.local[k]);
  }
  return true;
}

// The paper's fold test: some face around the 1-ring projects with flipped orientation, or two
// projections (nearly) coincide. It flags 8-70% of noisy vertices, which is why the driver makes
// acting on it optional (docs/studies/defaults.md).
inline bool neighbourhoodFolds(int i, const std::vector<Vec3> &points,
                               const std::vector<Face> &faces, const Rings &rings,
                               const LocalFrame &frame, const NeighbourhoodScratch &s) {
  auto flipped = [&](int f) {
    const Face &t = faces[f];
    const Vec3 a = points[t[0]], b = points[t[1]], c = points[t[2]];
    return (b - a).cross(c - a).dot(frame.n) <= 0;
  };
  for (const int *f = rings.facesBegin(i); f != rings.facesEnd(i); ++f)
    if (flipped(*f)) return true;
  for (const int *w = rings.ring1Begin(i); w != rings.ring1End(i); ++w)
    for (const int *f = rings.facesBegin(*w); f != rings.facesEnd(*w); ++f)
      if (flipped(*f)) return true;
  const double eps = 1e-9;
  for (size_t a = 0; a < s.u.size(); ++a)
    for (size_t b = a + 1; b < s.u.size(); ++b)
      if (std::abs(s.u[a] - s.u[b]) < eps && std::abs(s.v[a] - s.v[b]) < eps) return true;
  return false;
}

} // namespace vcg_ext
