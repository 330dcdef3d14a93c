// Stage 6: uniform principal curvature of a vertex (paper 3.3).
//
// Inputs: the vertex's own principal curvatures, directions and normal, the same for its 1-ring
// neighbours, and the neighbours' saliencies (the weights). Output: k1', k2', the saliency-weighted
// mean of the neighbours' normal curvatures expressed in the vertex's principal frame (x = dir1,
// y = dir2, z = normal). θ1j, θ2j are the angles from x of neighbour j's dir1, dir2 projected into
// the vertex's tangent plane. Two readings (the filter's choice; docs/studies/defaults.md):
//   Paper     k1j = k1_i cos²θ1j + k2_i sin²θ1j,  k2j = k1_i cos²θ2j + k2_i sin²θ2j   (as printed:
//             the vertex's own curvatures; with orthogonal directions k1j + k2j = k1_i + k2_i, so H
//             never changes)
//   Neighbour k1j = k1_j cos²θ1j + k2_j sin²θ1j,  k2j = k1_j sin²θ1j + k2_j cos²θ1j
//             (Euler's formula at q_j along q_i's principal directions)
// Only cos² and sin² of the angles enter, so the signs of the direction vectors do not matter.
#pragma once

#include "vcg_ext/core/mesh_arrays.h"

#include <algorithm>
#include <cmath>

namespace vcg_ext {

enum class UniformCurvatureVariant { Paper, Neighbour };

struct VertexCurvature {
  double k1, k2;
  Vec3 dir1, dir2, normal; // dir1, dir2: principal directions of k1, k2 (need not be unit)
};

namespace detail {
// cos²θ and sin²θ of the angle between x and d projected into the plane (x, y). False when the
// projection vanishes (d parallel to the plane's normal).
inline bool squaredCosSin(const Vec3 &d, const Vec3 &x, const Vec3 &y, double &c2, double &s2) {
  const double dx = d.dot(x), dy = d.dot(y);
  const double len2 = dx * dx + dy * dy;
  if (!(len2 > 1e-24 * d.squaredNorm()) || !std::isfinite(len2)) return false;
  c2 = dx * dx / len2;
  s2 = dy * dy / len2;
  return true;
}
} // namespace detail

// `neighbours[j]` and `saliency[j]`, j < count, describe the 1-ring. Weights are max(saliency, 0),
// all 1 when they sum to less than 1e-12. A neighbour whose directions both project to nothing in
// the tangent plane (degenerate input) is skipped. With no usable neighbour the result is the
// vertex's own (k1, k2). k1' >= k2' is not guaranteed.
inline void uniformPrincipalCurvature(const VertexCurvature &self, const VertexCurvature *neighbours,
                                      const double *saliency, int count, UniformCurvatureVariant variant,
                                      double &k1_uniform, double &k2_uniform) {
  // Orthonormal tangent frame: x along dir1 projected off the normal, y completing it.
  Vec3 z = self.normal;
  if (z.squaredNorm() > 0) z.normalize();
  Vec3 x = self.dir1 - self.dir1.dot(z) * z;
  if (!(x.squaredNorm() > 0)) x = (self.dir2 - self.dir2.dot(z) * z).cross(z);
  x.normalize();
  const Vec3 y = z.cross(x);

  double weight_sum = 0;
  for (int j = 0; j < count; ++j) weight_sum += std::max(saliency[j], 0.0);
  const bool uniform_weights = !(weight_sum >= 1e-12);

  double sum1 = 0, sum2 = 0, used_weight = 0;
  for (int j = 0; j < count; ++j) {
    const VertexCurvature &q = neighbours[j];
    const double wj = uniform_weights ? 1.0 : std::max(saliency[j], 0.0);
    if (wj == 0.0) continue;
    double c1, s1, c2, s2;
    const bool has1 = detail::squaredCosSin(q.dir1, x, y, c1, s1);
    const bool has2 = detail::squaredCosSin(q.dir2, x, y, c2, s2);
    // A direction along the normal: take the other one turned by 90° (they are orthogonal).
    if (!has1 && !has2) continue;
    if (!has1) c1 = s2, s1 = c2;
    if (!has2) c2 = s1, s2 = c1;
    double k1j, k2j;
    if (variant == UniformCurvatureVariant::Paper) {
      k1j = self.k1 * c1 + self.k2 * s1;
      k2j = self.k1 * c2 + self.k2 * s2;
    } else {
      k1j = q.k1 * c1 + q.k2 * s1;
      k2j = q.k1 * s1 + q.k2 * c1;
    }
    sum1 += wj * k1j;
    sum2 += wj * k2j;
    used_weight += wj;
  }
  if (used_weight > 0) {
    k1_uniform = sum1 / used_weight;
    k2_uniform = sum2 / used_weight;
  } else {
    k1_uniform = self.k1;
    k2_uniform = self.k2;
  }
}

} // namespace vcg_ext
