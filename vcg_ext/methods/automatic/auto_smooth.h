// The automatic mode's driver: the feature mode (feature_smooth.h) on meshes with sharp features,
// the organic mode (organic_smooth.h) on meshes without, decided from the mesh alone
// (mode_choice.h). Each mode loses heavily on the other's meshes, so the choice matters more than
// either mode's tuning (docs/studies/mode-choice.md).
//
// The decision reuses the feature mode's first-pass normals after the first guidance period of its
// filter (4 of 10 iterations), so a CAD part costs the feature mode plus one short Taubin run, and
// an organic mesh the organic mode plus the feature mode's set-up, pre-pass and those iterations.
// Same contract as both drivers: the input is never modified, the result does not depend on
// vertex order or thread count, progress can cancel.
#pragma once

#include "vcg_ext/methods/automatic/evidence_windows.h"
#include "vcg_ext/methods/feature/feature_smooth.h"
#include "vcg_ext/methods/automatic/mode_choice.h"
#include "vcg_ext/methods/organic/organic_smooth.h"

namespace vcg_ext {

struct AutoSmoothParams {
  FeatureSmoothParams feature;
  OrganicSmoothParams organic;
  // The plainly smoothed copy that confirms creases: Taubin pairs (0.5 / −0.53) on the input.
  int reference_pairs = 4;
  double crease_deg = 30.0, confirm_deg = 25.0, flat_deg = 1.0;
  // The mesh counts as having sharp features when at least `feature_flat_share` of the edges are
  // flat after the first guidance period of the normal filter (FeatureSmoothParams::
  // check_iterations; planar CAD faces), or at least `feature_confirmed_share` of its creases are
  // confirmed (curved CAD parts such as SharpSphere). Set between the shares of the meshes where
  // each mode wins, on 151 noisy meshes; not held out, and the margins are thin
  // (docs/studies/mode-choice.md).
  double feature_flat_share = 0.235, feature_confirmed_share = 0.785;
  // Heavy noise makes the feature mode's first pass wait heavyNoiseFactor times the filter
  // iterations before the evidence is read, and more iterations flatten organic shapes too: the
  // flat share's threshold grows as that factor to this power. Organic meshes under white noise of
  // one edge length read 0.245-0.28 at factors 2.7-3.1, CAD parts 0.35 and more; any power from
  // 0.16 to 0.34 tells them apart, 0.3 also the Bunny and the armadillo under the heavy set's
  // 4-view noise (0.32-0.33 at factors 3.7-4; docs/studies/mode-choice.md).
  double flat_share_factor_power = 0.3;
  // The confirmed share counts only on a mesh with at least this many creases per √(edges)
  // (creaseDensity, about 0.54 × feature-line length / √area; a box reads 2.8-2.9): the meshes
  // whose confirmed share alone made them CAD parts read 7-10, while the few creases that noise
  // leaves on a finely resolved smooth shape read 0.5 (the 10M-vertex bunny, whose confirmed share
  // of a few thousand creases sat at 0.76, too close to its threshold for its windows to decide;
  // its windows read 0.55 ± 0.24, the creases bunched in a few of them, hence 2 rather than 1).
  // Of the 151 meshes the thresholds were fitted on, the confirmed share of none that reads under
  // 2 decided its choice (docs/studies/mode-choice.md).
  double min_crease_density = 2.0;
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
  double crease_density_error = 0;             // and of the crease density
  double seconds_windows = 0;   // the windows' evidence (also when it was not clear enough)
  double check_factor = 1;      // the heavy-noise factor the first pass's check waited by
  Impulses impulses;            // read, and put back first (impulse_repair.h)
};

namespace detail {

// Whether evidence `e` says the mesh has sharp features (AutoSmoothParams' thresholds), each share
// measured against its threshold plus a margin (negative: minus); `check_factor`: the heavy-noise
// factor the first pass's check waited by (FeaturePassCounts::checkIterations).
inline double flatShareThreshold(const AutoSmoothParams &params, double check_factor) {
  return params.feature_flat_share *
         std::pow(std::max(1.0, check_factor), params.flat_share_factor_power);
}

inline bool hasSharpFeatures(const SharpFeatureEvidence &e, const AutoSmoothParams &params,
                             double flat_margin = 0, double confirmed_margin = 0,
                             double check_factor = 1, double density_margin = 0) {
  return e.flat_share >= flatShareThreshold(params, check_factor) + flat_margin ||
         (e.confirmed_share >= params.feature_confirmed_share + confirmed_margin &&
          e.crease_density >= params.min_crease_density + density_margin);
}

// The choice on windows of the mesh when their evidence is clear (AutoSmoothParams::windows):
// true when it decided (report.windowed, report.evidence, report.chose_feature).
inline bool decideOnWindows(const MeshArrays &mesh, const AutoSmoothParams &params,
                            DriverSetup &setup, AutoSmoothReport &report) {
  const FeaturePassCounts counts = featurePassCounts(mesh, params.feature, setup);
  // A mesh that measures as clean, or a filter asked for no iterations: the usual path says so.
  if (params.windows.max_windows <= 0 || counts.normal_iterations <= 0 ||
      !(setup.stats.mean_edge_length > 0))
    return false;
  const auto start = Clock::now();
  FirstPassCounts first;
  first.prepass_pairs = counts.prepass_pairs;
  first.reference_pairs = params.reference_pairs;
  first.first = params.feature.normals;
  first.first.iterations = counts.checkIterations(params.feature);
  const WindowedEvidence w = windowedEvidence(mesh, setup, first, params.crease_deg,
                                              params.confirm_deg, params.flat_deg, params.windows);
  report.seconds_windows = secondsSince(start);
  if (!w.used) return false;
  const SharpFeatureEvidence &e = w.evidence;
  const double flat_margin = std::max(params.window_margin, params.window_errors * w.flat_error),
               confirmed_margin =
                   std::max(params.window_margin, params.window_errors * w.confirmed_error),
               density_margin = std::max(params.window_margin * params.min_crease_density,
                                         params.window_errors * w.crease_density_error);
  const double f = counts.heavy_factor;
  const bool feature =
      hasSharpFeatures(e, params, flat_margin, confirmed_margin, f, density_margin);
  const bool organic =
      !hasSharpFeatures(e, params, -flat_margin, -confirmed_margin, f, -density_margin);
  if (!feature && !organic) return false;
  report.decided = report.windowed = true;
  report.chose_feature = feature;
  report.check_factor = f;
  report.evidence = e;
  report.window_faces = w.window_faces;
  report.flat_error = w.flat_error;
  report.confirmed_error = w.confirmed_error;
  report.crease_density_error = w.crease_density_error;
  return true;
}

// The face normals of the plainly smoothed copy that confirms creases (AutoSmoothParams::
// reference_pairs Taubin pairs on the input). When the pre-pass ran the same pairs on the same
// input (at full roughness and strength), its positions are that copy, bit for bit.
inline void referenceNormals(const MeshArrays &mesh, const DriverSetup &setup,
                             const std::vector<Vec3> &prepassed, int prepass_pairs,
                             int reference_pairs, std::vector<Vec3> &normals) {
  if (prepass_pairs == reference_pairs) return computeFaceNormals(prepassed, mesh.faces, normals);
  std::vector<Vec3> smoothed = mesh.points;
  taubinSmooth(smoothed, setup.rings, setup.fixed, setup.roles.boundary_neighbours,
               reference_pairs);
  computeFaceNormals(smoothed, mesh.faces, normals);
}

// The choice on the whole mesh, from the feature mode's first-pass normals `filtered` (its
// FilteredNormalsCheck): fills report.evidence, decided and chose_feature; true for the feature
// mode.
inline bool decideOnFirstPass(const MeshArrays &mesh, const AutoSmoothParams &params,
                              const DriverSetup &setup, const std::vector<Vec3> &filtered,
                              const std::vector<Vec3> &prepassed, int prepass_pairs,
                              AutoSmoothReport &report) {
  const auto start = Clock::now();
  std::vector<Vec3> reference;
  referenceNormals(mesh, setup, prepassed, prepass_pairs, params.reference_pairs, reference);
  report.evidence = modelScaleEvidence(filtered, reference, setup.face_rings, mesh.points,
                                       mesh.faces, params.crease_deg, params.confirm_deg,
                                       params.flat_deg);
  report.seconds_reference = secondsSince(start);
  report.decided = true;
  report.check_factor = heavyNoiseFactor(setup.noise, params.feature.heavy);
  report.chose_feature = hasSharpFeatures(report.evidence, params, 0, 0, report.check_factor);
  return report.chose_feature;
}

// The organic mode's parameters in the automatic mode: on the feature mode's set-up, so with its
// selection and boundary mode.
inline OrganicSmoothParams organicParamsOf(const AutoSmoothParams &params) {
  OrganicSmoothParams organic = params.organic;
  organic.selected_only = params.feature.selected_only;
  organic.boundary = params.feature.boundary;
  return organic;
}

// `progress` with the percentages 0-100 mapped onto from-100 (none when `progress` is none).
inline ProgressFn progressFrom(int from, const ProgressFn &progress) {
  if (!progress) return ProgressFn();
  return [from, progress](int percent, const char *stage) {
    return progress(from + percent * (100 - from) / 100, stage);
  };
}

// The mode chosen on windows, run alone.
inline void runChosenMode(const MeshArrays &mesh, const AutoSmoothParams &params,
                          DriverSetup &setup, std::vector<Vec3> &out_points,
                          VertexQuantities &quantities, const ProgressFn &progress,
                          AutoSmoothReport &report) {
  if (report.chose_feature) {
    report.feature = featureSmoothAsGiven(mesh, params.feature, out_points, quantities, progress,
                                          nullptr, &setup);
    report.cancelled = report.feature.cancelled;
  } else {
    report.organic = organicSmoothAsGiven(mesh, organicParamsOf(params), out_points, quantities,
                                          progress, &setup);
    report.cancelled = report.organic.cancelled;
  }
}

// `given_setup`: the set-up when the caller has it already (impulse_repair.h), else made here.
inline AutoSmoothReport autoSmoothAsGiven(const MeshArrays &mesh, const AutoSmoothParams &params,
                                          std::vector<Vec3> &out_points,
                                          VertexQuantities &quantities,
                                          const ProgressFn &progress,
                                          DriverSetup *given_setup = nullptr) {
  AutoSmoothReport report;
  const auto start = Clock::now();
  std::optional<DriverSetup> own_setup;
  if (!given_setup)
    own_setup.emplace(driverSetup(mesh, params.feature.selected_only, params.feature.boundary));
  DriverSetup &setup = given_setup ? *given_setup : *own_setup;
  report.seconds_setup = secondsSince(start);
  if (progress && !progress(1, "Choosing the mode")) return report.cancelled = true, report;
  if (decideOnWindows(mesh, params, setup, report)) {
    runChosenMode(mesh, params, setup, out_points, quantities, progress, report);
    return report;
  }
  // Both drivers report 0-99 %; the feature mode's first pass is the first part of either path.
  report.feature = featureSmoothAsGiven(
      mesh, params.feature, out_points, quantities, progress,
      [&](const std::vector<Vec3> &filtered, const std::vector<Vec3> &prepassed,
          int prepass_pairs, const detail::DriverSetup &given) {
        return decideOnFirstPass(mesh, params, given, filtered, prepassed, prepass_pairs, report);
      },
      &setup);
  if (report.feature.cancelled) return report.cancelled = true, report;
  if (!report.feature.declined) {
    report.chose_feature = true;
    return report;
  }
  // The decision took the feature mode's first pass (about a fifth of its progress range).
  report.organic = organicSmoothAsGiven(mesh, organicParamsOf(params), out_points, quantities,
                                        progressFrom(20, progress), &setup);
  report.cancelled = report.organic.cancelled;
  return report;
}

} // namespace detail

inline AutoSmoothReport autoSmoothMesh(const MeshArrays &mesh, const AutoSmoothParams &params,
                                       std::vector<Vec3> &out_points, VertexQuantities &quantities,
                                       const ProgressFn &progress = nullptr) {
  // The feature mode's settings for the impulses: one reading for both modes.
  return detail::measuredDriverRun(
      mesh, params.feature, out_points, quantities,
      [&](const MeshArrays &m, std::vector<Vec3> &o, VertexQuantities &q,
          detail::DriverSetup &setup) {
        return detail::autoSmoothAsGiven(m, params, o, q, progress, &setup);
      });
}

namespace detail {

// Why the automatic mode chose as it did, for its log line: the two shares (on windows with their
// standard errors and how much of the mesh the windows held), and the flat share's threshold
// when heavy noise raised it (flatShareThreshold).
inline std::string evidencePhrase(const AutoSmoothReport &r, size_t faces,
                                  const AutoSmoothParams &params = {}) {
  const std::string flat_what =
      r.evidence.flat_stride > 1
          ? formatLine("face pairs %.0f edges apart", double(r.evidence.flat_stride))
          : "the edges";
  auto error = [&](double e) { return r.windowed ? formatLine(" ± %.3f", e) : std::string(); };
  const std::string sample =
      r.windowed ? formatLine(", on windows holding %.0f %% of the faces",
                              100.0 * double(r.window_faces) / double(faces))
                 : std::string();
  const double threshold = flatShareThreshold(params, r.check_factor);
  const std::string raised =
      threshold > params.feature_flat_share
          ? formatLine(" (%.3f needed: the check waited x %.2f for heavy noise)", threshold,
                       r.check_factor)
          : std::string();
  // When the confirmed share could have made it a CAD part but the creases were too sparse for
  // it to count (min_crease_density).
  const bool could_count =
      r.evidence.confirmed_share + (r.windowed ? params.window_errors * r.confirmed_error : 0.0) >=
      params.feature_confirmed_share;
  const std::string sparse =
      could_count && r.evidence.crease_density < params.min_crease_density
          ? formatLine(" (too few creases to count: %.2f%s per square root of the edges, %.1f "
                       "needed)",
                       r.evidence.crease_density,
                       r.windowed ? formatLine(" ± %.2f", r.crease_density_error).c_str() : "",
                       params.min_crease_density)
          : std::string();
  return formatLine("%.3f%s of %s flat%s and %.3f%s of the creases confirmed%s after guided "
                    "filtering%s",
                    r.evidence.flat_share, error(r.flat_error).c_str(), flat_what.c_str(),
                    raised.c_str(), r.evidence.confirmed_share, error(r.confirmed_error).c_str(),
                    sparse.c_str(), sample.c_str());
}

// The decision's own time: on windows, the windows' evidence; on the whole mesh, the Taubin copy
// and the evidence, and when the organic mode ran, also the feature mode's first pass the
// decision took (the organic mode's own times do not include it).
inline std::string decisionTimeLine(const AutoSmoothReport &r) {
  if (r.windowed)
    return formatLine("Time of the decision: shared topology %.3f s, evidence on windows %.3f s.",
                      r.seconds_setup, r.seconds_windows);
  if (r.chose_feature)
    return formatLine("Time of the decision: shared topology %.3f s, Taubin copy and evidence "
                      "%.3f s.",
                      r.seconds_setup, r.seconds_reference);
  return formatLine("Time of the decision: shared topology %.3f s, the feature mode's pre-pass and "
                    "first normal filter iterations %.3f s, Taubin copy and evidence %.3f s.",
                    r.seconds_setup, r.feature.seconds_prepass + r.feature.seconds_normals,
                    r.seconds_reference);
}

} // namespace detail

// The automatic method as the filter runs it (methods.h): the log names the mode it chose and why.
inline MethodRun automaticMethod(const MeshArrays &mesh, const MethodParams &p,
                                 std::vector<Vec3> &out_points, VertexQuantities &quantities,
                                 const ProgressFn &progress) {
  AutoSmoothParams params;
  detail::readCommonParams(p, params.feature);
  detail::readCommonParams(p, params.organic);
  AutoSmoothReport r = autoSmoothMesh(mesh, params, out_points, quantities, progress);
  r.feature.impulses = r.organic.impulses = r.impulses; // (for the modes' summaries)
  MethodRun run;
  run.cancelled = r.cancelled;
  if (r.cancelled) return run;
  if (!r.decided) {
    run.method = r.impulses.moved > 0 ? "impulses only" : "none (clean)";
    run.roughness = r.feature.roughness;
    if (r.impulses.moved > 0) detail::measureMovement(quantities, r.feature.mean_edge_length, run);
    run.summary = "Automatic: " +
                  (r.impulses.moved > 0
                       ? detail::cleanAfterImpulsesPhrase(r.impulses, r.feature.noise)
                       : detail::measuredCleanPhrase(r.feature.noise)) +
                  ".";
    run.details = detail::featureDetails(r.feature);
    return run;
  }
  const std::string why = detail::evidencePhrase(r, mesh.faces.size(), params);
  if (r.chose_feature) {
    run = detail::measuredRun(r.feature, "feature-preserving", 3, quantities); // (methods.h)
    run.summary = "Automatic (sharp features: " + why + ") -> " +
                  detail::featureSummary(r.feature, params.feature, run, mesh.points.size());
    run.details = detail::featureDetails(r.feature);
  } else {
    run = detail::measuredRun(r.organic, "organic", 4, quantities);
    run.summary = "Automatic (no sharp features: " + why + ") -> " +
                  detail::organicSummary(r.organic, params.organic, run, mesh.points.size());
    run.details = detail::organicDetails(r.organic);
  }
  run.details.push_back(detail::decisionTimeLine(r));
  return run;
}

} // namespace vcg_ext
