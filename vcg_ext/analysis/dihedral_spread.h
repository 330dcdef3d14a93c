// The dihedral spread: per face, the spread of the signed dihedral angles across its three edges;
// its median over the faces is a roughness figure that needs no reference and tells noise from
// curvature (noise_estimate.h, the feature mode's pass counts, the automatic mode's evidence).
//
// Inputs: positions, triangles, unit face normals and face rings (face_rings.h). Output: degrees.
#pragma once

#include "vcg_ext/core/face_rings.h"
#include "vcg_ext/core/selection.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace vcg_ext {

namespace detail {

// The signed dihedral angles (degrees; positive where the surface turns away from the face's
// normal: convex) across every face's three edges, each computed once: by the lower-numbered of
// its two faces when the other runs the edge the other way (consistently oriented neighbours).
// Seen from either face the angle's arguments are the same numbers (the cross product and the
// edge change sign together), so the higher-numbered face reads the bits it would compute, and
// half the atan2 calls are saved.
struct DihedralAngles {
  std::vector<std::array<double, 3>> angle;       // f's own angle at edge k, where shared[f][k] < 0
  std::vector<std::array<std::int8_t, 3>> shared; // else the corner of f's neighbour to read
  // The angle across f's edge k, whose neighbour is g.
  double at(int f, int k, int g) const {
    const int j = shared[f][k];
    return j >= 0 ? angle[g][j] : angle[f][k];
  }
};

// A face's normal counts when it is a unit normal (a degenerate face has a zero one).
inline bool usableNormal(const std::vector<Vec3> &face_normals, int f) {
  return face_normals[f].squaredNorm() > 0.5;
}

inline void dihedralAngles(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                           const std::vector<Vec3> &face_normals, const FaceRings &face_rings,
                           DihedralAngles &out) {
  const int face_count = int(faces.size());
  auto angle_at = [&](int f, int k, int g) {
    const Vec3 edge = (points[faces[f][(k + 1) % 3]] - points[faces[f][k]]).normalized();
    const Vec3 &a = face_normals[f], &b = face_normals[g];
    return std::atan2(a.cross(b).dot(edge), a.dot(b)) * 180.0 / M_PI;
  };
  // The corner of g whose edge is f's edge k reversed, with f as g's neighbour there (−1: none).
  auto reversed_in = [&](int f, int k, int g) {
    const int a = faces[f][k], b = faces[f][(k + 1) % 3];
    for (int j = 0; j < 3; ++j)
      if (faces[g][j] == b && faces[g][(j + 1) % 3] == a && face_rings.edge_neighbours[g][j] == f)
        return j;
    return -1;
  };
  out.angle.assign(face_count, {});
  out.shared.assign(face_count, {-1, -1, -1});
#pragma omp parallel for schedule(static) if (face_count >= min_parallel_vertices)
  for (int f = 0; f < face_count; ++f) {
    if (!usableNormal(face_normals, f)) continue;
    for (int k = 0; k < 3; ++k) {
      const int g = face_rings.edge_neighbours[f][k];
      if (g < 0 || !usableNormal(face_normals, g)) continue;
      out.shared[f][k] = std::int8_t(g < f ? reversed_in(f, k, g) : -1);
      if (out.shared[f][k] < 0) out.angle[f][k] = angle_at(f, k, g);
    }
  }
}

// Per face, the spread (largest minus smallest) of its three dihedral angles; NaN for a face
// without three usable neighbours or one that `counted` (when given) leaves out.
inline std::vector<double> dihedralSpreads(const std::vector<Vec3> &face_normals,
                                           const FaceRings &face_rings,
                                           const DihedralAngles &angles,
                                           const std::vector<std::uint8_t> *counted) {
  const int face_count = int(face_normals.size());
  std::vector<double> spreads(face_count);
#pragma omp parallel for schedule(static) if (face_count >= min_parallel_vertices)
  for (int f = 0; f < face_count; ++f) {
    double lo = INFINITY, hi = -INFINITY;
    bool complete = usableNormal(face_normals, f);
    for (int k = 0; k < 3 && complete; ++k) {
      const int g = face_rings.edge_neighbours[f][k];
      complete = g >= 0 && usableNormal(face_normals, g);
      if (!complete) break;
      const double a = angles.at(f, k, g);
      lo = std::min(lo, a);
      hi = std::max(hi, a);
    }
    spreads[f] = complete && (!counted || (*counted)[f]) ? hi - lo : NAN;
  }
  return spreads;
}

} // namespace detail

// A noise estimate that needs no reference and tells noise from curvature: per face, the spread
// (largest minus smallest) of the signed dihedral angles across its three edges, in degrees; the
// median over the faces. Curvature bends a face's edges alike (a sphere: all about equal), noise
// bends them at random, convex and concave. Measured: clean meshes 0 (CAD) to 31 (the coarse
// elephant), the public benchmark's noisy meshes 52-81, noise in random directions at 0.25 mean
// edge lengths 88-112.
// Per face in parallel, then gathered in face order, so the median does not depend on the thread
// count; `counted` (optional) names the faces that count.
inline double medianDihedralSpreadDeg(const std::vector<Vec3> &points,
                                      const std::vector<Face> &faces,
                                      const std::vector<Vec3> &face_normals,
                                      const FaceRings &face_rings,
                                      const std::vector<std::uint8_t> *counted = nullptr) {
  std::vector<double> spreads;
  {
    detail::DihedralAngles angles;
    detail::dihedralAngles(points, faces, face_normals, face_rings, angles);
    spreads = detail::dihedralSpreads(face_normals, face_rings, angles, counted);
  }
  detail::eraseNaN(spreads);
  if (spreads.empty()) return 0.0;
  return detail::kthSmallest(spreads, spreads.size() / 2);
}

} // namespace vcg_ext
