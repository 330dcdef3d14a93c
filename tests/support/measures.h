// What the unit tests measure their results with: the mean edge length, θ against a reference
// mesh, the largest move between two sets of positions, and a Bézier patch of known curvature.
#pragma once

#include <vcg_ext/methods/paper/bezier_patch.h>
#include <vcg_ext/core/mesh_arrays.h>
#include <vcg_ext/analysis/mesh_metrics.h>
#include <vcg_ext/core/rings.h>

#include <algorithm>
#include <vector>

namespace test_meshes {

inline double meanEdge(const vcg_ext::MeshArrays &m) {
  return vcg_ext::edgeStatistics(m.points, vcg_ext::computeRings(int(m.points.size()), m.faces))
      .mean_edge_length;
}

// θ and the other normal figures of `result` (positions on the reference's triangles) against
// the reference.
inline vcg_ext::NormalDeviation deviation(const std::vector<vcg_ext::Vec3> &result,
                                          const vcg_ext::MeshArrays &reference) {
  return vcg_ext::normalDeviation(result, reference.points, reference.faces,
                                  vcg_ext::buildEdgeTable(reference.faces));
}

// The largest distance between the same vertex in `a` and `b`.
inline double largestDifference(const std::vector<vcg_ext::Vec3> &a,
                                const std::vector<vcg_ext::Vec3> &b) {
  double largest = 0;
  for (size_t i = 0; i < a.size(); ++i) largest = std::max(largest, (a[i] - b[i]).norm());
  return largest;
}

// Patch of z = a x² + b y² over [-h,h]², x = h(2u−1), y = h(2v−1): x is linear in u (control x
// values −h, 0, h) and (2u−1)² has Bernstein coefficients (1, −1, 1). K and H vary away from the
// apex.
inline vcg_ext::BezierPatch paraboloidPatch(double a, double b, double h) {
  const double e[3] = {1, -1, 1};
  vcg_ext::BezierPatch p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      p.b[3 * i + j] = vcg_ext::Vec3(h * (i - 1), h * (j - 1), h * h * (a * e[i] + b * e[j]));
  return p;
}

} // namespace test_meshes
