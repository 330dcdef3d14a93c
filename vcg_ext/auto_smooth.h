// The automatic mode's driver: the feature mode (feature_smooth.h) on meshes with sharp features,
// the organic mode (organic_smooth.h) on meshes without, decided from the mesh alone
// (mode_choice.h). Each mode loses heavily on the other's meshes (bench/FEATURE_MODE.md: Fandisk
// with random noise 2.84° feature vs 8.68° organic; armadillo 14.63° vs 10.61°).
//
// The decision reuses the feature mode's first-pass normals after the first guidance period of its
// filter (4 of 10 iterations), so a CAD part costs the feature mode plus one short Taubin run, and
// an organic mesh the organic mode plus the feature mode's set-up, pre-pass and those iterations. Same contract as both drivers: the input is never
// modified, the result does not depend on vertex order or thread count, progress can cancel.
#pragma once

#include "evidence_windows.h"
#include "feature_smooth.h"
#include "mode_choice.h"
#include "organic_smooth.h"

namespace vcg_ext {

struct AutoSmoothParams {
  FeatureSmoothParams feature;
  OrganicSmoothParams organic;
  // The plainly smoothed copy that confirms creases: Taubin pairs (0.5 / −0.53) on the input.
  int reference_pairs = 4;
  double crease_deg = 30.0, confirm_deg = 25.0, flat_deg = 1.0;
  // The mesh counts as having sharp features when at least `feature_flat_share` of the edges are
  // flat after the first guidance period of the normal filter (FeatureSmoothParams::
  // check_iterations; planar CAD faces), or at least
  // `feature_confirmed_share` of its creases are confirmed (curved CAD parts such as
  // SharpSphere). Measured on 151 noisy meshes (bench/FEATURE_MODE.md "Automatic mode"): flat
  // share up to 0.205 on meshes where the organic mode wins (the bunny), from 0.262 on CAD parts
  // with planar faces (Block); confirmed share up to 0.78 where the organic mode wins, 0.81-0.84
  // on SharpSphere.
  double feature_flat_share = 0.235, feature_confirmed_share = 0.785;
  // Large meshes: the evidence is first taken on windows of the mesh (evidence_windows.h); when
  // its shares are clear of their thresholds, by at least `window_margin` and `window_errors`
  // standard errors of the sample, the choice is made on it and only the chosen mode runs, else
  // the evidence is taken on the whole mesh as above.
  EvidenceWindowParams windows;
  double window_margin = 0.02, window_errors = 3.0;
};

struct AutoSmoothReport {
  bool cancelled = false;
  bool chose_feature = false;
  bool decided = false; // false: the mesh measured as clean (or had no faces to filter): untouched
  SharpFeatureEvidence evidence;
  FeatureSmoothReport feature;   // the feature mode's report (declined when it was not chosen)
  OrganicSmoothReport organic;   // the organic mode's report, when it was chosen
  double seconds_setup = 0, seconds_reference = 0; // shared topology; the Taubin copy and evidence
  bool windowed = false;        // decided on windows of the mesh (evidence_windows.h)
  long window_faces = 0;        // the faces the windows held
  double flat_error = 0, confirmed_error = 0; // the windows' standard errors of the shares
  double seconds_windows = 0;   // the windows' evidence (also when it was not clear enough)
};

namespace detail {

// The choice on windows of the mesh when their evidence is clear (AutoSmoothParams::windows):
// true when it decided (report.windowed, report.evidence, report.chose_feature).
inline bool decideOnWindows(const MeshArrays &mesh, const AutoSmoothParams &params,
                            DriverSetup &setup, AutoSmoothReport &report) {
  const FeaturePassCounts counts = featurePassCounts(mesh, params.feature, setup);
  // A mesh that measures as clean, or a filter asked for no iterations: the usual path says so.
  if (params.windows.max_windows <= 0 || counts.normal_iterations <= 0 ||
      !(setup.stats.mean_edge_length > 0))
    return false;
  const auto start = std::chrono::steady_clock::now();
  FirstPassCounts first;
  first.prepass_pairs = counts.prepass_pairs;
  first.reference_pairs = params.reference_pairs;
  first.first = params.feature.normals;
  first.first.iterations = counts.checkIterations(params.feature);
  const WindowedEvidence w = windowedEvidence(mesh, setup, first, params.crease_deg,
                                              params.confirm_deg, params.flat_deg, params.windows);
  report.seconds_windows =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!w.used) return false;
  const SharpFeatureEvidence &e = w.evidence;
  const double flat_margin = std::max(params.window_margin, params.window_errors * w.flat_error),
               confirmed_margin =
                   std::max(params.window_margin, params.window_errors * w.confirmed_error);
  const bool feature = e.flat_share >= params.feature_flat_share + flat_margin ||
                       e.confirmed_share >= params.feature_confirmed_share + confirmed_margin;
  const bool organic = e.flat_share < params.feature_flat_share - flat_margin &&
                       e.confirmed_share < params.feature_confirmed_share - confirmed_margin;
  if (!feature && !organic) return false;
  report.decided = report.windowed = true;
  report.chose_feature = feature;
  report.evidence = e;
  report.window_faces = w.window_faces;
  report.flat_error = w.flat_error;
  report.confirmed_error = w.confirmed_error;
  return true;
}

inline AutoSmoothReport autoSmoothAsGiven(const MeshArrays &mesh, const AutoSmoothParams &params,
                                          std::vector<Vec3> &out_points,
                                          VertexQuantities &quantities,
                                          const ProgressFn &progress) {
  AutoSmoothReport report;
  const bool selected_only = params.feature.selected_only;
  const auto start = std::chrono::steady_clock::now();
  detail::DriverSetup setup = detail::driverSetup(mesh, selected_only, params.feature.boundary);
  report.seconds_setup =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  OrganicSmoothParams organic_params = params.organic;
  organic_params.selected_only = selected_only; // one set-up serves both drivers
  organic_params.boundary = params.feature.boundary;
  if (progress && !progress(1, "Choosing the mode")) return report.cancelled = true, report;
  if (decideOnWindows(mesh, params, setup, report)) {
    if (report.chose_feature) {
      report.feature = featureSmoothAsGiven(mesh, params.feature, out_points, quantities, progress,
                                            nullptr, &setup);
      report.cancelled = report.feature.cancelled;
    } else {
      report.organic = organicSmoothAsGiven(mesh, organic_params, out_points, quantities, progress,
                                            &setup);
      report.cancelled = report.organic.cancelled;
    }
    return report;
  }
  // Both drivers report 0-99 %; the feature mode's first pass is the first part of either path.
  report.feature = featureSmoothAsGiven(
      mesh, params.feature, out_points, quantities, progress,
      [&](const std::vector<Vec3> &filtered, const std::vector<Vec3> &prepassed,
          int prepass_pairs, const detail::DriverSetup &) {
        const auto reference_start = std::chrono::steady_clock::now();
        std::vector<Vec3> reference_normals;
        if (prepass_pairs == params.reference_pairs) {
          // The pre-pass ran the same pairs on the same input (at full roughness and strength):
          // its positions are the reference, bit for bit.
          computeFaceNormals(prepassed, mesh.faces, reference_normals);
        } else {
          std::vector<Vec3> smoothed = mesh.points;
          taubinSmooth(smoothed, setup.rings, setup.fixed, setup.roles.boundary_neighbours,
                       params.reference_pairs);
          computeFaceNormals(smoothed, mesh.faces, reference_normals);
        }
        report.evidence = modelScaleEvidence(filtered, reference_normals, setup.face_rings,
                                             mesh.points, mesh.faces, params.crease_deg,
                                             params.confirm_deg, params.flat_deg);
        report.seconds_reference =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - reference_start).count();
        report.decided = true;
        report.chose_feature = report.evidence.flat_share >= params.feature_flat_share ||
                               report.evidence.confirmed_share >= params.feature_confirmed_share;
        return report.chose_feature;
      },
      &setup);
  if (report.feature.cancelled) return report.cancelled = true, report;
  if (!report.feature.declined) {
    report.chose_feature = true;
    return report;
  }
  // The decision took the feature mode's first pass (about a fifth of its progress range).
  const int decided = 20;
  report.organic = organicSmoothAsGiven(
      mesh, organic_params, out_points, quantities,
      progress ? ProgressFn([&](int percent, const char *stage) {
        return progress(decided + percent * (100 - decided) / 100, stage);
      })
               : ProgressFn(),
      &setup);
  report.cancelled = report.organic.cancelled;
  return report;
}

} // namespace detail

inline AutoSmoothReport autoSmoothMesh(const MeshArrays &mesh, const AutoSmoothParams &params,
                                       std::vector<Vec3> &out_points, VertexQuantities &quantities,
                                       const ProgressFn &progress = nullptr) {
  return detail::inSpatialOrder(mesh, out_points, quantities,
                                [&](const MeshArrays &ordered, std::vector<Vec3> &out,
                                    VertexQuantities &q) {
                                  return detail::autoSmoothAsGiven(ordered, params, out, q,
                                                                   progress);
                                });
}

// The automatic method as the filter runs it (methods.h): the log names the mode it chose and why.
inline MethodRun automaticMethod(const MeshArrays &mesh, const MethodParams &p,
                                 std::vector<Vec3> &out_points, VertexQuantities &quantities,
                                 const ProgressFn &progress) {
  AutoSmoothParams params;
  detail::readCommonParams(p, params.feature);
  detail::readCommonParams(p, params.organic);
  const AutoSmoothReport r = autoSmoothMesh(mesh, params, out_points, quantities, progress);
  MethodRun run;
  run.cancelled = r.cancelled;
  if (r.cancelled) return run;
  using detail::formatLine;
  if (!r.decided) {
    run.method = "none (clean)";
    run.roughness = r.feature.roughness;
    run.summary = "Automatic: " + detail::measuredCleanPhrase(r.feature.noise) + ".";
    run.details = detail::featureDetails(r.feature);
    return run;
  }
  const std::string flat_what =
      r.evidence.flat_stride > 1
          ? formatLine("face pairs %.0f edges apart", double(r.evidence.flat_stride))
          : "the edges";
  // On windows: each share with its standard error as a sample, and how much of the mesh it read.
  auto error = [&](double e) { return r.windowed ? formatLine(" ± %.3f", e) : std::string(); };
  const std::string sample =
      r.windowed ? formatLine(", on windows holding %.0f %% of the faces",
                              100.0 * double(r.window_faces) / double(mesh.faces.size()))
                 : std::string();
  const std::string why = formatLine(
      "%.3f%s of %s flat and %.3f%s of the creases confirmed after guided filtering%s",
      r.evidence.flat_share, error(r.flat_error).c_str(), flat_what.c_str(),
      r.evidence.confirmed_share, error(r.confirmed_error).c_str(), sample.c_str());
  // The decision's own time: on windows, or the feature mode's first pass on the whole mesh.
  const std::string decision_time =
      r.windowed ? formatLine("Time of the decision: shared topology %.3f s, evidence on windows "
                              "%.3f s.",
                              r.seconds_setup, r.seconds_windows)
                 : std::string();
  if (r.chose_feature) {
    run.method = "feature-preserving";
    run.method_index = 3; // methods.h
    run.roughness = r.feature.roughness;
    detail::measureMovement(quantities, r.feature.mean_edge_length, run);
    run.summary = "Automatic (sharp features: " + why + ") -> " +
                  detail::featureSummary(r.feature, params.feature, run, mesh.points.size());
    run.details = detail::featureDetails(r.feature);
    run.details.push_back(r.windowed ? decision_time
                                     : formatLine("Time of the decision: shared topology %.3f s, "
                                                  "Taubin copy and evidence %.3f s.",
                                                  r.seconds_setup, r.seconds_reference));
  } else {
    run.method = "organic";
    run.method_index = 4; // methods.h
    run.roughness = r.organic.roughness;
    detail::measureMovement(quantities, r.organic.mean_edge_length, run);
    run.summary = "Automatic (no sharp features: " + why + ") -> " +
                  detail::organicSummary(r.organic, params.organic, run, mesh.points.size());
    run.details = detail::organicDetails(r.organic);
    run.details.push_back(
        r.windowed ? decision_time
                   : formatLine("Time of the decision: shared topology %.3f s, the feature mode's "
                                "pre-pass and first normal filter iterations %.3f s, Taubin copy "
                                "and evidence %.3f s.",
                                r.seconds_setup,
                                r.feature.seconds_prepass + r.feature.seconds_normals,
                                r.seconds_reference));
  }
  return run;
}

} // namespace vcg_ext
