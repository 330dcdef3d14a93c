// Stages 1-3 together: normals, principal curvatures and mesh saliency of a mesh's current
// positions, as the filters store them for inspection.
#pragma once

#include "vcg_ext/analysis/curvature.h"
#include "vcg_ext/analysis/saliency.h"

namespace vcg_ext {

struct SurfaceAnalysis {
  CurvatureField curvature;
  std::vector<double> saliency; // Lee et al. on the mean curvature, rescaled to [0,1]
};

// Mesh saliency as Lee, Varshney, Jacobs 2005 define it, on the mean curvature: what the filters
// store and show. (The paper's Newton placement and α rule weight with saliency of the minimum
// principal curvature k2, its own choice, inside paper_smooth.h.) Measured on the clean Fandisk:
// on k2 its convex creases do not show at all (k2 is about 0 across a convex crease); on the mean
// curvature every crease and corner does.
inline void computeMeshSaliency(const std::vector<Vec3> &points, const Rings &rings,
                                const CurvatureField &curvature, double saliency_scale,
                                std::vector<double> &saliency) {
  computeSaliency(points, rings, curvature.mean, saliency_scale, saliency);
}

// `saliency_scale` is the paper's epsilon as an absolute length (the filter's parameter is a
// fraction of the bounding-box diagonal).
// `with_directions` as in computeCurvature.
inline void analyseSurface(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                           const Rings &rings, double saliency_scale, SurfaceAnalysis &out,
                           bool with_directions = true) {
  computeCurvature(points, faces, rings, out.curvature, with_directions);
  computeMeshSaliency(points, rings, out.curvature, saliency_scale, out.saliency);
}

} // namespace vcg_ext
