// Whether a noisy mesh has sharp features (a CAD part) or is smooth everywhere (an organic
// shape), from the mesh alone: the choice between the feature mode (feature_smooth.h) and the
// organic mode (organic_smooth.h) of the automatic mode (auto_smooth.h).
//
// Guided normal filtering (Zhang et al. 2015) turns a noisy mesh into piecewise-flat pieces
// whether it has sharp edges or not; two things tell the cases apart:
// - planar CAD faces come out exactly flat over large areas, while a curved surface keeps bending
//   a little across almost every edge: the share of edges whose filtered normals differ by less
//   than flat_deg;
// - on a curved organic surface the filter invents creases (the staircase that costs the feature
//   mode 20-70 % of θ there), and a plainly smoothed copy (Taubin, no range kernel) bends less
//   across invented creases than across real ones: the share of the filtered normals' creases
//   (> crease_deg) across which the smoothed copy still bends by more than confirm_deg.
#pragma once

#include "normal_filter.h"

#include <cmath>
#include <vector>

namespace vcg_ext {

struct SharpFeatureEvidence {
  long edges = 0;            // interior edges between two non-degenerate faces
  long flat_pairs = 0;       // of those, filtered normals within flat_deg
  long crease_pairs = 0;     // of those, filtered normals more than crease_deg apart
  long confirmed_pairs = 0;  // of the creases, smoothed-copy normals more than confirm_deg apart
  double flat_share = 0, confirmed_share = 0;
};

// `filtered`: per-face unit normals after guided filtering; `smoothed`: per-face unit normals of a
// plainly smoothed copy of the mesh. Faces with a zero normal (degenerate) are skipped. Counts each
// interior edge once, so the result does not depend on vertex or face order.
inline SharpFeatureEvidence sharpFeatureEvidence(const std::vector<Vec3> &filtered,
                                                 const std::vector<Vec3> &smoothed,
                                                 const FaceRings &face_rings,
                                                 double crease_deg = 30.0,
                                                 double confirm_deg = 20.0,
                                                 double flat_deg = 1.0) {
  SharpFeatureEvidence e;
  const double crease_cos = std::cos(crease_deg * M_PI / 180.0);
  const double confirm_cos = std::cos(confirm_deg * M_PI / 180.0);
  const double flat_cos = std::cos(flat_deg * M_PI / 180.0);
  const int m = int(filtered.size());
  for (int f = 0; f < m; ++f) {
    for (int g : face_rings.edge_neighbours[f]) {
      if (g <= f) continue; // each edge once; −1 (boundary) too
      const bool valid = filtered[f].squaredNorm() > 0.5 && filtered[g].squaredNorm() > 0.5 &&
                         smoothed[f].squaredNorm() > 0.5 && smoothed[g].squaredNorm() > 0.5;
      if (!valid) continue;
      ++e.edges;
      const double c = filtered[f].dot(filtered[g]);
      e.flat_pairs += c > flat_cos;
      if (c >= crease_cos) continue;
      ++e.crease_pairs;
      e.confirmed_pairs += smoothed[f].dot(smoothed[g]) < confirm_cos;
    }
  }
  e.flat_share = e.edges ? double(e.flat_pairs) / double(e.edges) : 0.0;
  e.confirmed_share = e.crease_pairs ? double(e.confirmed_pairs) / double(e.crease_pairs) : 0.0;
  return e;
}

} // namespace vcg_ext
