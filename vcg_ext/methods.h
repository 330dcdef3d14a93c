// The smoothing methods side by side: one row per method, in the order of the filter's Method
// choice (the script value `placement` is the row's index, kept from the first releases so that
// old scripts run unchanged). The plugin asks this table for a method by index and calls its
// driver; a new method is one driver file and one row here.
//
// `reads` lists the filter parameters the method acts on (the dialog's tooltips and the tests
// that change each parameter and check that the result changes are built from it). Every method
// also reads selected_only, preserve_volume, saliency_scale (the Saliency of the result) and the
// quality choice.
#pragma once

#include "vcg_ext/methods/automatic/auto_smooth.h"
#include "vcg_ext/methods/feature/feature_smooth.h"
#include "vcg_ext/methods/organic/organic_smooth.h"
#include "vcg_ext/methods/paper/paper_smooth.h"

#include <array>

namespace vcg_ext {

using MethodDriver = MethodRun (*)(const MeshArrays &mesh, const MethodParams &params,
                                   std::vector<Vec3> &out_points, VertexQuantities &quantities,
                                   const ProgressFn &progress);

struct MethodRow {
  const char *label;    // the dialog's choice
  const char *key;      // short name for scripts and command lines
  const char *summary;  // what it is for, one sentence
  std::vector<const char *> reads; // the filter parameters it acts on, besides the common ones
  MethodDriver run;
  // The driver runs on the mesh in spatial order (spatial_order.h), the same to the bit whatever
  // the input's order: the filter may hand it the arrays already ordered, which saves a copy.
  bool runs_in_spatial_order = false;
};

inline const std::array<MethodRow, 6> &methodTable() {
  static const std::array<MethodRow, 6> table = {{
      {"Ring barycentre", "ring",
       "The paper's patch: each vertex moves to its 2-ring patch above its 1-ring barycentre; a "
       "light Taubin-class smoothing.",
       {"iterations", "alpha_override", "alpha", "boundary", "fold_handling"},
       [](const MeshArrays &m, const MethodParams &p, std::vector<Vec3> &out, VertexQuantities &q,
          const ProgressFn &progress) {
         return paperMethod(PlacementMode::RingBarycentre, m, p, out, q, progress);
       }},
      {"Patch point", "patch",
       "The paper's patch: each vertex moves to its own point on its 2-ring patch.",
       {"iterations", "alpha_override", "alpha", "boundary", "fold_handling"},
       [](const MeshArrays &m, const MethodParams &p, std::vector<Vec3> &out, VertexQuantities &q,
          const ProgressFn &progress) {
         return paperMethod(PlacementMode::PatchPoint, m, p, out, q, progress);
       }},
      {"Paper (Newton)", "newton",
       "The paper as printed: Newton on the patch toward the saliency-weighted uniform principal "
       "curvature (distorts meshes; for comparison).",
       {"iterations", "alpha_override", "alpha", "boundary", "fold_handling", "uniform_curvature",
        "newton_iterations", "newton_step_limit"},
       [](const MeshArrays &m, const MethodParams &p, std::vector<Vec3> &out, VertexQuantities &q,
          const ProgressFn &progress) {
         return paperMethod(PlacementMode::Paper, m, p, out, q, progress);
       }},
      {"Feature-preserving", "feature",
       "Guided normal filtering and face patches: keeps sharp edges and corners (CAD parts, "
       "machined and architectural scans).",
       {"iterations", "alpha_override", "alpha", "boundary"},
       featureMethod, true},
      {"Organic scan", "organic",
       "Taubin's frequency bands, each kept in proportion to its measured shape-to-noise energy: "
       "organic shapes with noise in all directions.",
       {"iterations", "alpha_override", "alpha", "boundary"},
       organicMethod, true},
      {"Automatic", "automatic",
       "Measures whether the mesh has sharp features and runs the feature-preserving or the "
       "organic method.",
       {"iterations", "alpha_override", "alpha", "boundary"},
       automaticMethod, true},
  }};
  return table;
}

// The row of the default method (Automatic).
constexpr int kDefaultMethod = 5;

} // namespace vcg_ext
