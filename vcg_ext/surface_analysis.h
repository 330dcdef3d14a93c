// Stages 1-3 together: normals, principal curvatures and mesh saliency of a mesh's current
// positions. Used once by the inspection filter and once per iteration by the smoothing driver.
#pragma once

#include "curvature.h"
#include "saliency.h"

namespace vcg_ext {

struct SurfaceAnalysis {
  CurvatureField curvature;
  std::vector<double> saliency; // Lee et al. on k2 = min(k1, k2), rescaled to [0,1]
};

// `saliency_scale` is the paper's epsilon as an absolute length (the filter's parameter is a
// fraction of the bounding-box diagonal).
inline void analyseSurface(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                           const Rings &rings, double saliency_scale, SurfaceAnalysis &out) {
  computeCurvature(points, faces, rings, out.curvature);
  // The paper's curvature map: "negative minima of principal curvatures", i.e. k2.
  computeSaliency(points, rings, out.curvature.k2, saliency_scale, out.saliency);
}

} // namespace vcg_ext
