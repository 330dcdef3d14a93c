// The automatic mode's driver: the feature mode (feature_smooth.h) on meshes with sharp features,
// the organic mode (organic_smooth.h) on meshes without, decided from the mesh alone
// (mode_choice.h). Each mode loses heavily on the other's meshes (bench/FEATURE_MODE.md: Fandisk
// with random noise 2.84° feature vs 8.68° organic; armadillo 14.63° vs 10.61°).
//
// The decision reuses the feature mode's first-pass filtered normals, so a CAD part costs the
// feature mode plus one short Taubin run, and an organic mesh the organic mode plus the feature
// mode's pre-pass and first normal filtering. Same contract as both drivers: the input is never
// modified, the result does not depend on vertex order or thread count, progress can cancel.
#pragma once

#include "mode_choice.h"
#include "organic_smooth.h"

namespace vcg_ext {

struct AutoSmoothParams {
  FeatureSmoothParams feature;
  OrganicSmoothParams organic;
  // The plainly smoothed copy that confirms creases: Taubin pairs (0.5 / −0.53) on the input.
  int reference_pairs = 4;
  double crease_deg = 30.0, confirm_deg = 20.0, flat_deg = 1.0;
  // The mesh counts as having sharp features when at least `feature_flat_share` of the filtered
  // normals' edges are flat (planar CAD faces) or at least `feature_confirmed_share` of their
  // creases are confirmed (curved CAD parts such as SharpSphere). Measured on 100 noisy meshes
  // (bench/FEATURE_MODE.md "Automatic mode"): flat share 0.10-0.29 on organic meshes, 0.33-0.96
  // on CAD parts with planar faces; confirmed share up to 0.83 on organic meshes, 0.84-0.87 on
  // SharpSphere.
  double feature_flat_share = 0.30, feature_confirmed_share = 0.835;
};

struct AutoSmoothReport {
  bool cancelled = false;
  bool chose_feature = false;
  SharpFeatureEvidence evidence;
  FeatureSmoothReport feature;   // the feature mode's report (declined when it was not chosen)
  OrganicSmoothReport organic;   // the organic mode's report, when it was chosen
  double seconds_reference = 0;
};

inline AutoSmoothReport autoSmoothMesh(const MeshArrays &mesh, const AutoSmoothParams &params,
                                       std::vector<Vec3> &out_points, VertexQuantities &quantities,
                                       const ProgressFn &progress = nullptr) {
  AutoSmoothReport report;
  // Both drivers report 0-99 %; the feature mode's first pass is the first part of either path.
  report.feature = featureSmoothMesh(
      mesh, params.feature, out_points, quantities, progress,
      [&](const std::vector<Vec3> &filtered, const detail::DriverSetup &setup) {
        const auto start = std::chrono::steady_clock::now();
        std::vector<Vec3> smoothed = mesh.points;
        taubinSmooth(smoothed, setup.rings, setup.fixed, setup.roles.boundary_neighbours,
                     params.reference_pairs);
        FaceGeometry geometry;
        computeFaceGeometry(smoothed, mesh.faces, geometry);
        report.evidence = sharpFeatureEvidence(filtered, geometry.normal, setup.face_rings,
                                               params.crease_deg, params.confirm_deg,
                                               params.flat_deg);
        report.seconds_reference =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        report.chose_feature = report.evidence.flat_share >= params.feature_flat_share ||
                               report.evidence.confirmed_share >= params.feature_confirmed_share;
        return report.chose_feature;
      });
  if (report.feature.cancelled) return report.cancelled = true, report;
  if (!report.feature.declined) {
    report.chose_feature = true;
    return report;
  }
  // The decision took the feature mode's first pass (about a fifth of its progress range).
  const int decided = 20;
  report.organic = organicSmoothMesh(
      mesh, params.organic, out_points, quantities,
      progress ? ProgressFn([&](int percent, const char *stage) {
        return progress(decided + percent * (100 - decided) / 100, stage);
      })
               : ProgressFn());
  report.cancelled = report.organic.cancelled;
  return report;
}

} // namespace vcg_ext
