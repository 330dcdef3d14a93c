// Untangling folded vertex stars before smoothing.
//
// Inputs: positions (changed in place), triangles, Rings, the vertices that may not move. Output:
// the number of vertex moves made. A vertex's star is folded when one of its faces points against
// the star's own normal, the sum of its faces' area vectors (for an interior vertex that sum is the
// vector area of its ring polygon, so it does not depend on where the vertex itself is): the
// vertex has been pushed through its ring. Such a vertex is moved to its ring's barycentre (one
// step of uniform Laplacian smoothing, Field 1988, on these vertices only), a few rounds, each
// reading the positions of the round before. Crease and corner vertices of a clean mesh are not
// folded (a cube's corner faces lie 55° from its star normal), so they stay where they are.
//
// Why: scanner noise moves vertices along the view ray, which at grazing angles is nearly
// tangential, and folds the mesh where a vertex passes its neighbours (on the 4-view scanner
// cases about a tenth of a coarse mesh's faces turn past 90°: docs/studies/organic-mode.md).
// Smoothing along the normals cannot unfold a star: its faces' normals point the wrong way, so
// they are smoothed the wrong way. MeshLab's HC Laplacian unfolds them with its uniform weights,
// at the price of smoothing everything.
//
// vcglib offers a route on a vcg mesh (tri::Clean::SelectFoldedFaceFromOneRingFaces: faces against
// a plane fitted to their vertices' rings; tri::Smooth::VertexCoordLaplacian on the selection).
// Here: the driver's flat arrays in spatial order (results independent of thread count and vertex
// order), and the star's own vector area, exact and without a plane fit per face.
#pragma once

#include "vcg_ext/core/rings.h"

#include <vector>

namespace vcg_ext {

struct FoldRepairParams {
  // Rounds of moves (folds that survive them are left to the smoothing; 0: none). It helps on
  // scanner noise and hurts on noise in random directions, so the organic mode runs it only on
  // heavy-tailed noise (organic_smooth.h; docs/studies/organic-mode.md).
  int max_rounds = 5;
};

namespace detail {

// Whether vertex v's star is folded: one of its faces' area vectors points against their sum.
inline bool starFolded(int v, const std::vector<Vec3> &points, const std::vector<Face> &faces,
                       const Rings &rings) {
  Vec3 star = Vec3::Zero();
  const int *begin = rings.facesBegin(v), *end = rings.facesEnd(v);
  for (const int *f = begin; f != end; ++f) {
    const Face &t = faces[*f];
    star += (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]);
  }
  for (const int *f = begin; f != end; ++f) {
    const Face &t = faces[*f];
    if ((points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]).dot(star) < 0)
      return true;
  }
  return false;
}

} // namespace detail

// Returns the number of moves (a vertex moved in two rounds counts twice). Boundary, non-manifold
// and `fixed` vertices never move. The same result for any thread count and vertex order (each
// round reads the previous round's positions; a vertex's new position is its ring's mean).
inline long repairFolds(std::vector<Vec3> &points, const std::vector<Face> &faces,
                        const Rings &rings, const std::vector<std::uint8_t> &fixed,
                        const FoldRepairParams &params = FoldRepairParams()) {
  const int n = int(points.size());
  long moves = 0;
  std::vector<int> folded;
  std::vector<Vec3> moved;
  std::vector<std::uint8_t> flag(params.max_rounds > 0 ? n : 0); // every entry written per round
  for (int round = 0; round < params.max_rounds; ++round) {
    folded.clear();
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
    for (int v = 0; v < n; ++v)
      flag[v] = !fixed[v] && !rings.boundary[v] && !rings.nonmanifold[v] &&
                rings.ring1Size(v) > 0 && detail::starFolded(v, points, faces, rings);
    for (int v = 0; v < n; ++v)
      if (flag[v]) folded.push_back(v);
    if (folded.empty()) break;
    moved.resize(folded.size());
    for (size_t k = 0; k < folded.size(); ++k) {
      const int v = folded[k];
      Vec3 sum = Vec3::Zero();
      for (const int *u = rings.ring1Begin(v); u != rings.ring1End(v); ++u) sum += points[*u];
      moved[k] = sum / double(rings.ring1Size(v));
    }
    for (size_t k = 0; k < folded.size(); ++k)
      if (moved[k].allFinite()) points[folded[k]] = moved[k];
    moves += long(folded.size());
  }
  return moves;
}

} // namespace vcg_ext
