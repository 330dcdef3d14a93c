// What every smoothing method shares: the result's per-vertex quantities, progress and cancel,
// the input check, and the per-run set-up (topology, which vertices may move, boundary
// constraints, the input's volume, the spatial order the drivers run in), so that the method
// drivers (paper_smooth.h, feature_smooth.h, organic_smooth.h, auto_smooth.h) stand side by side
// on it instead of including each other.
//
// Also the common parameters and the outcome every method returns to the table (methods.h): the
// filter's dialog reads into MethodParams, and a MethodRun says which method ran, what it measured
// and what it did, in lines a user reads.
#pragma once

#include "vcg_ext/methods/feature/face_patches.h"
#include "vcg_ext/analysis/mesh_metrics.h"
#include "vcg_ext/analysis/noise_estimate.h"
#include "vcg_ext/analysis/noise_windows.h"
#include "vcg_ext/methods/feature/normal_filter.h"
#include "vcg_ext/core/spatial_order.h"
#include "vcg_ext/analysis/surface_analysis.h"
#include "vcg_ext/core/timing.h"
#include "vcg_ext/methods/paper/uniform_curvature.h"

#include <array>
#include <cstdarg>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>

namespace vcg_ext {

enum class BoundaryMode {
  Paper,         // as interior vertices
  Fixed,         // never moved
  AlongBoundary, // only along the boundary curve's tangent
  NoInward,      // along the tangent and the surface normal, never toward the interior
};
enum class FoldHandling {
  Ignore, // fit anyway: least squares does not need a one-to-one projection
  Paper,  // retry with the vertex's own normal, then with the 1-ring; else keep the vertex
};

// Per vertex, for inspection: the result's saliency and curvatures, the α its last patch fit used
// (the paper's rule or the user's; 1 where none ran) and its displacement from the input.
struct VertexQuantities {
  std::vector<double> saliency, k1, k2, mean, gauss, alpha, displacement;
};

// The filter's parameters as the methods read them (methods.h lists which method reads which).
struct MethodParams {
  // The paper's placements: the number of iterations. The other methods measure how much smoothing
  // the mesh needs; for them `iterations` is that amount in thirds (strength()): 3 = as measured,
  // 6 = twice as much, 1 = a third, 0 = nothing. Old scripts' 3 keeps its meaning either way.
  int iterations = 3;
  bool alpha_override = true; // false: the paper's α = Sal_min / Sal_max over each fit's data
  double alpha = 1.0;         // the patch fits' data weight against their smoothness term (paper α)
  BoundaryMode boundary = BoundaryMode::NoInward;
  bool preserve_volume = true;
  bool selected_only = false;
  double saliency_scale = 0.003; // the paper's ε as a fraction of the bbox diagonal
  // The paper's placements only.
  FoldHandling folds = FoldHandling::Ignore;
  UniformCurvatureVariant uniform_variant = UniformCurvatureVariant::Neighbour; // Newton only
  int newton_iterations = 2;                                                    // Newton only
  double newton_step_limit = 1.0; // Newton only, in mean edge lengths; 0 = no limit
  double strength() const { return std::max(0, iterations) / 3.0; }
};

// What a method did, for the filter's log: which method ran (the automatic one names its choice),
// one line a user reads (what was measured, what was done), and the details.
struct MethodRun {
  bool cancelled = false;
  std::string method;
  int method_index = -1;  // its row in methods.h; -1: none ran (the mesh measured as clean)
  std::string summary;
  std::vector<std::string> details;
  long vertices_moved = 0;
  double mean_displacement_edges = 0; // over all vertices, in mean edge lengths
  double roughness = 0;               // the noise estimate, 0 (clean) .. 1 (noisy); paper: 0
};

// Called between stages and between blocks of vertices with a percentage; returning false cancels.
using ProgressFn = std::function<bool(int percent, const char *stage)>;

// The scales the computations in double can carry: normals and fits take products of up to four
// lengths (squared norms of cross products), which overflow beyond ~1e77 and vanish below ~1e-77;
// the limits keep a wide margin.
constexpr double kMaxCoordinate = 1e30, kMinExtent = 1e-30;

// Why a mesh cannot be smoothed (empty string: it can).
inline std::string validateForSmoothing(const MeshArrays &mesh) {
  if (mesh.points.empty()) return "the mesh has no vertices";
  if (mesh.faces.empty()) return "the mesh has no faces (a point cloud): the filter needs triangles";
  for (const Vec3 &p : mesh.points)
    if (!p.allFinite()) return "the mesh has NaN or infinite vertex coordinates; remove them first";
  Vec3 lo = mesh.points[0], hi = lo;
  for (const Vec3 &p : mesh.points) {
    if (p.cwiseAbs().maxCoeff() > kMaxCoordinate)
      return "the mesh has vertex coordinates beyond 1e30, where the computations in double would "
             "overflow; scale the mesh down first";
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  if (!((hi - lo).norm() >= kMinExtent))
    return "the mesh is smaller than 1e-30 across (or all its vertices coincide), where the "
           "computations in double would underflow; scale the mesh up first";
  return {};
}

namespace detail {

// printf into a std::string (the methods' log lines).
inline std::string formatLine(const char *format, ...) {
  char buffer[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buffer, sizeof buffer, format, args);
  va_end(args);
  return buffer;
}

// How far the result moved from the input (MethodRun's vertices_moved, mean_displacement_edges).
inline void measureMovement(const VertexQuantities &q, double mean_edge, MethodRun &run) {
  double sum = 0;
  run.vertices_moved = 0;
  for (double d : q.displacement) run.vertices_moved += d > 0, sum += d;
  run.mean_displacement_edges = q.displacement.empty() || !(mean_edge > 0)
                                    ? 0.0 : sum / double(q.displacement.size()) / mean_edge;
}

// The MethodRun of a driver's run (a report with cancelled, roughness and mean_edge_length): the
// method's name and index in methods.h' table, the roughness and how far the result moved, or
// only `cancelled`; the caller adds the log lines.
template <class Report>
MethodRun measuredRun(const Report &r, const char *method, int method_index,
                      const VertexQuantities &q) {
  MethodRun run;
  run.cancelled = r.cancelled;
  if (r.cancelled) return run;
  run.method = method;
  run.method_index = method_index;
  run.roughness = r.roughness;
  measureMovement(q, r.mean_edge_length, run);
  return run;
}

// A driver's progress over its passes: pass p at fraction f of it reports span·(p + f) / passes
// percent, at most 99 (the rest is the result's); false when the user cancelled.
struct PassProgress {
  const ProgressFn &progress;
  int passes;
  double span;
  bool operator()(int pass, double fraction, const char *stage) const {
    if (!progress) return true;
    const int percent = int(span * (pass + fraction) / std::max(1, passes));
    return progress(std::min(percent, 99), stage);
  }
};

// "6475 of 6475 vertices moved, by 0.21 mean edge lengths on average": what a user checks first.
inline std::string movedPhrase(const MethodRun &run, size_t vertices) {
  return formatLine("%ld of %zu vertices moved, by %.3g mean edge lengths on average",
                    run.vertices_moved, vertices, run.mean_displacement_edges);
}

// The log line of the vertices a driver could not move.
inline std::string skippedLine(long frozen) {
  return formatLine("Skipped (left in place): %ld non-manifold, isolated or on degenerate faces.",
                    frozen);
}

// The log line of a closed mesh's volume change.
inline std::string volumeLine(double before, double after) {
  return formatLine("Volume %g -> %g (ratio %.4f).", before, after, after / before);
}

// The feature-preserving and organic drivers' common log lines.
template <class Report>
void appendFacePatchDriverLog(const Report &r, std::vector<std::string> &log) {
  if (r.frozen_vertices > 0) log.push_back(skippedLine(r.frozen_vertices));
  if (r.plane_fallbacks + r.rejected_moves > 0)
    log.push_back(formatLine("Patch fits that fell back to the face plane: %ld; non-finite moves "
                             "kept in place: %ld.",
                             r.plane_fallbacks, r.rejected_moves));
  if (r.closed && r.volume_before != 0) log.push_back(volumeLine(r.volume_before, r.volume_after));
}

// The common parameters as the face-patch drivers read them.
template <class DriverParams>
void readCommonParams(const MethodParams &p, DriverParams &d) {
  d.strength = p.strength();
  d.patches.alpha = p.alpha;
  d.alpha_override = p.alpha_override;
  d.boundary = p.boundary;
  d.preserve_volume = p.preserve_volume;
  d.selected_only = p.selected_only;
  d.saliency_scale = p.saliency_scale;
}

// Where the estimate's medians ran: nothing for the whole mesh, else the windows' share of it.
inline std::string sampledPhrase(const NoiseEstimate &noise) {
  return noise.sampled_share < 1
             ? formatLine(" (on windows: %.0f %% of the faces)", 100.0 * noise.sampled_share)
             : std::string();
}

// What a user reads when a driver finds nothing to do.
inline std::string measuredCleanPhrase(const NoiseEstimate &noise) {
  return formatLine("the mesh measures as clean%s (dihedral spread %.1f deg, %.2f of it left "
                    "after one Taubin pair; noise leaves at most %.2f): left as it is; set "
                    "Iterations above 3 to smooth it anyway",
                    sampledPhrase(noise).c_str(), noise.spread_deg, noise.decay,
                    NoiseEstimateParams().max_decay);
}

// The amplitude in the summary lines (noise_amplitude.h), when it was read; and why a mesh that
// one Taubin pair barely changes reads noisy (NoiseEstimateParams::amplitude_noisy).
inline std::string amplitudePhrase(const NoiseEstimate &noise) {
  if (!(noise.amplitude > 0)) return std::string();
  const std::string by_amplitude =
      noise.noisy_by_amplitude
          ? formatLine("noisy by its amplitude (%.3f on trimmed bands: noise correlated over "
                       "several rings, which one pair barely changes), ",
                       noise.trimmed_amplitude)
          : std::string();
  return (noise.correlation_steps > 0 && noise.correlated_share > 0.005
              ? formatLine("amplitude %.3f (%.0f %% of it correlated over about %d rings), ",
                           noise.amplitude, 100.0 * noise.correlated_share,
                           std::max(1, int(std::lround(std::sqrt(noise.correlation_steps)))))
              : formatLine("amplitude %.3f (white), ", noise.amplitude)) +
         by_amplitude;
}

// After the strength in the summary lines: the heavy-noise factor when it acts on a noisy mesh
// (heavyNoiseFactor).
inline std::string heavyPhrase(double factor, double amount) {
  return factor > 1 && amount > 0
             ? formatLine(", the measured amount x %.2f for heavy noise", factor)
             : std::string();
}

// The feature mode's extra filter iterations for correlated noise (correlatedNoiseFactor).
inline std::string correlatedPhrase(double factor, double amount, const NoiseEstimate &noise) {
  return factor > 1 && amount > 0
             ? formatLine(", the filter iterations and vertex updates x %.2f for noise %.0f %% "
                          "correlated",
                          factor, 100.0 * noise.correlated_share)
             : std::string();
}

// The noise estimate in the summary lines.
inline std::string noisePhrase(const NoiseEstimate &noise, double roughness) {
  return formatLine("noise estimate%s: dihedral spread %.1f deg (%.2f of it left after one Taubin "
                    "pair), level %.3f mean edge lengths (%.3f in the coarser bands), %s"
                    "roughness %.2f",
                    sampledPhrase(noise).c_str(), noise.spread_deg, noise.decay, noise.level,
                    noise.correlated_level, amplitudePhrase(noise).c_str(), roughness);
}

// After the strength in the summary lines: the heavy-tail factor when it acts on a noisy mesh
// (heavyTailFactor).
inline std::string tailPhrase(double factor, double amount, const NoiseEstimate &noise) {
  return factor > 1 && amount > 0
             ? formatLine(", the measured amount x %.2f for the noise's heavy tails (%.2f of a "
                          "Gaussian's rms)", factor, noise.tail)
             : std::string();
}


// Applies the boundary mode to a boundary vertex's proposed position.
inline Vec3 constrainBoundaryMove(int i, const Vec3 &moved, const std::vector<Vec3> &current,
                                  const std::vector<Vec3> &normals, const VertexRoles &roles,
                                  BoundaryMode mode) {
  if (mode == BoundaryMode::Paper) return moved;
  const auto &bn = roles.boundary_neighbours[i];
  if (mode == BoundaryMode::Fixed || bn[0] < 0 || bn[1] < 0) return current[i];
  const Vec3 in = current[i] - current[bn[0]], out = current[bn[1]] - current[i];
  // A boundary corner (turning more than 45 degrees) is a feature: it stays.
  if (in.dot(out) < std::cos(M_PI / 4) * in.norm() * out.norm()) return current[i];
  const Vec3 tangent = (current[bn[1]] - current[bn[0]]).normalized();
  const Vec3 step = moved - current[i];
  Vec3 result;
  if (mode == BoundaryMode::AlongBoundary) {
    result = current[i] + tangent * tangent.dot(step);
  } else {
    const Vec3 inward = normals[i].cross(tangent).normalized();
    result = moved - inward * inward.dot(step);
  }
  return result.allFinite() ? result : current[i];
}

// The distance d such that moving every vertex flagged in `moved` by d along its normal changes the
// enclosed volume by `missing` (to first order: each vertex sweeps a third of its faces' area).
inline double volumeRestoringOffset(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                                    const std::vector<std::uint8_t> &moved, double missing) {
  double swept = 0;
  for (const Face &f : faces) {
    const double third = (points[f[1]] - points[f[0]]).cross(points[f[2]] - points[f[0]]).norm() / 6;
    for (int k = 0; k < 3; ++k) swept += moved[f[k]] ? third : 0.0;
  }
  return swept > 0 ? missing / swept : 0.0;
}

// Offsets the vertices flagged in `moved` along their normals so that the enclosed volume becomes
// `target` (first order). Returns false, leaving `points` as they are, when the offset would exceed
// `max_offset`: that means a (nearly) collapsed surface, not a lost sliver of volume (found by the
// fuzzer: a flattened octahedron asked for 1e15 edge lengths).
inline bool restoreVolume(std::vector<Vec3> &points, const std::vector<Face> &faces,
                          const Rings &rings, const std::vector<std::uint8_t> &moved,
                          double target, double max_offset, std::vector<Vec3> &normals) {
  computeVertexNormals(points, faces, rings, normals);
  const double offset =
      volumeRestoringOffset(points, faces, moved, target - signedVolume(points, faces));
  if (!(std::abs(offset) <= max_offset)) return false;
  for (size_t i = 0; i < points.size(); ++i)
    if (moved[i]) points[i] += offset * normals[i];
  return true;
}

// The α a driver's patch fits used, for the "Alpha" attribute: per vertex under the paper's
// saliency rule (vertexAlphaOfPatches), else one value (the user's override; 1 where no patch
// update ran), spread over the vertices with faces only when the result is described, so that it
// does not add to the run's peak.
struct PatchAlpha {
  std::vector<double> per_vertex;
  double uniform = 1.0;
  void record(const Rings &rings, const std::vector<double> &face_alpha, double alpha);
};

// The result's quantities from its analysis (curvatures, saliency) and the patches' α, and its
// displacement from the input. Returns how many vertices moved.
inline long storeResultQuantities(const std::vector<Vec3> &input, const std::vector<Vec3> &result,
                                  const Rings &rings, SurfaceAnalysis &&analysis,
                                  PatchAlpha &&alpha, VertexQuantities &quantities) {
  const int n = int(result.size());
  quantities.saliency = std::move(analysis.saliency);
  quantities.k1 = std::move(analysis.curvature.k1);
  quantities.k2 = std::move(analysis.curvature.k2);
  quantities.mean = std::move(analysis.curvature.mean);
  quantities.gauss = std::move(analysis.curvature.gauss);
  if (alpha.per_vertex.size() == size_t(n)) {
    quantities.alpha = std::move(alpha.per_vertex);
  } else {
    quantities.alpha.assign(n, 1.0);
    for (int v = 0; v < n; ++v)
      if (rings.facesBegin(v) != rings.facesEnd(v)) quantities.alpha[v] = alpha.uniform;
  }
  quantities.displacement.assign(n, 0.0);
  long moved = 0;
  for (int i = 0; i < n; ++i) {
    quantities.displacement[i] = (result[i] - input[i]).norm();
    moved += quantities.displacement[i] > 0;
  }
  return moved;
}

// Describes a result with the same per-vertex quantities as the other modes (curvatures and
// saliency of the result, displacement from the input, the α its patch fits used). Returns how
// many vertices moved.
inline long describeResult(const std::vector<Vec3> &input, const std::vector<Vec3> &result,
                           const std::vector<Face> &faces, const Rings &rings,
                           double saliency_scale, VertexQuantities &quantities,
                           PatchAlpha &&alpha = {}) {
  SurfaceAnalysis analysis;
  analyseSurface(result, faces, rings, saliency_scale, analysis, /*with_directions=*/false);
  return storeResultQuantities(input, result, rings, std::move(analysis), std::move(alpha),
                               quantities);
}

// What the drivers set up once per run: topology, which vertices may move (not frozen, selected
// when only the selection is smoothed, not on the boundary when the boundary is fixed), and the
// input's enclosed volume. The face rings and the noise estimate only for the measured methods
// (the drivers that filter face normals), the 2-rings only for the paper's patches.
struct DriverSetup {
  Rings rings;
  EdgeStatistics stats;
  VertexRoles roles;
  FaceRings face_rings;
  std::vector<std::uint8_t> fixed;
  long frozen_vertices = 0, boundary_vertices = 0; // boundary: the movable ones
  bool closed = false;
  double volume_before = 0;
  NoiseEstimate noise; // the measured methods' noise estimate (noise_estimate.h)
  double input_spread_deg = NAN; // the input's median dihedral spread, once read (inputSpreadDeg)
};

// One Jacobi sweep of a face-patch driver's vertex update: each movable vertex (not fixed, with a
// ring) to `move(v)`, kept off the inward direction on the boundary (constrainBoundaryMove, which
// reads `vertex_normals` there); a non-finite move leaves the vertex where it is. Returns how many
// did. `move` reads `current` only, so the sweep is the same for any thread count.
template <class Move>
long sweepVertices(const std::vector<Vec3> &current, const DriverSetup &setup, BoundaryMode boundary,
                   const std::vector<Vec3> &vertex_normals, Move move, std::vector<Vec3> &next) {
  const Rings &rings = setup.rings;
  const int n = int(current.size());
  long rejected = 0;
#pragma omp parallel for schedule(static) reduction(+ : rejected) if (parallelHeavy(n))
  for (int v = 0; v < n; ++v) {
    next[v] = current[v];
    if (setup.fixed[v] || rings.ring1Size(v) == 0) continue;
    Vec3 moved = move(v);
    if (rings.boundary[v])
      moved = constrainBoundaryMove(v, moved, current, vertex_normals, setup.roles, boundary);
    if (moved.allFinite()) next[v] = moved;
    else ++rejected;
  }
  return rejected;
}

// What a driver's report says of its set-up: scale, closedness, the vertices it may not move
// and the input's volume (FeatureSmoothReport, OrganicSmoothReport).
template <class Report> void reportSetup(const DriverSetup &setup, Report &report) {
  report.mean_edge_length = setup.stats.mean_edge_length;
  report.bbox_diagonal = setup.stats.bbox_diagonal;
  report.closed = setup.closed;
  report.frozen_vertices = setup.frozen_vertices;
  report.boundary_vertices = setup.boundary_vertices;
  report.volume_before = setup.volume_before;
}

// A driver's last step: the result's quantities for inspection (describeResult, timed, with the
// α its patch fits used), its volume, and the result handed to the caller (`result` is left
// empty).
template <class Report>
void finishDriver(const MeshArrays &mesh, const Rings &rings, double saliency_scale,
                  std::vector<Vec3> &result, std::vector<Vec3> &out_points,
                  VertexQuantities &quantities, Report &report, PatchAlpha &&alpha = {}) {
  const auto start = Clock::now();
  report.vertices_moved = describeResult(mesh.points, result, mesh.faces, rings, saliency_scale,
                                         quantities, std::move(alpha));
  report.seconds_quantities = secondsSince(start);
  report.volume_after = signedVolume(result, mesh.faces);
  out_points.swap(result);
  std::vector<Vec3>().swap(result);
}

// The input's median dihedral spread (dihedral_spread.h), measured once per set-up (by the noise
// estimate, or here on first use): the automatic mode runs both drivers on one set-up, and both
// read it (a second of 2M vertices).
inline double inputSpreadDeg(const MeshArrays &mesh, DriverSetup &setup) {
  if (std::isnan(setup.input_spread_deg)) {
    setup.input_spread_deg = detail::spreadOf(mesh.points, mesh.faces, setup.face_rings);
  }
  return setup.input_spread_deg;
}

// `rings`: the mesh's rings without 2-rings when the caller has them already (moved in).
inline DriverSetup driverSetup(const MeshArrays &mesh, bool selected_only,
                               BoundaryMode boundary = BoundaryMode::NoInward,
                               bool with_face_rings = true, bool with_two_rings = false,
                               Rings *rings = nullptr) {
  DriverSetup s;
  const int n = int(mesh.points.size());
  s.rings = rings && !with_two_rings ? std::move(*rings) : computeRings(n, mesh.faces, with_two_rings);
  s.stats = edgeStatistics(mesh.points, s.rings);
  s.roles = vertexRoles(mesh, s.rings, s.stats.mean_edge_length);
  s.closed = s.rings.boundary_edges == 0 && s.rings.nonmanifold_edges == 0;
  s.fixed.assign(n, 0);
  for (int v = 0; v < n; ++v) {
    s.fixed[v] = s.roles.frozen[v] || (selected_only && !mesh.selected[v]) ||
                 (boundary == BoundaryMode::Fixed && s.rings.boundary[v]);
    s.frozen_vertices += s.roles.frozen[v];
    s.boundary_vertices += s.rings.boundary[v] && !s.fixed[v];
  }
  s.volume_before = signedVolume(mesh.points, mesh.faces);
  if (with_face_rings) {
    // Large meshes: on windows of the mesh (noise_windows.h); the input spread is then the
    // windows' too, and the face rings wait for the feature mode (ensureFaceRings: the organic
    // mode and the windowed mode choice never read them; docs/studies/performance.md).
    // Otherwise edge neighbours only: the noise estimate reads nothing else.
    if (!estimateNoiseOnWindows(mesh, s.rings, s.roles.frozen, s.stats.mean_edge_length,
                                s.noise)) {
      s.face_rings = computeFaceRings(mesh.faces, s.rings, /*with_edge_neighbours=*/true,
                                      /*with_lists=*/false);
      s.noise = estimateNoise(mesh.points, mesh.faces, s.rings, s.face_rings, s.roles);
    }
    s.input_spread_deg = s.noise.spread_deg; // (0 without faces, as inputSpreadDeg reads it)
  }
  return s;
}

// The face rings with edge neighbours and ring lists, as a whole-mesh normal filter reads them:
// the lists added to the set-up's edge neighbours, or both built where the set-up has none yet.
inline void ensureFaceRings(const MeshArrays &mesh, DriverSetup &s) {
  if (s.face_rings.edge_neighbours.empty() && !mesh.faces.empty())
    s.face_rings = computeFaceRings(mesh.faces, s.rings);
  else
    addFaceRingLists(s.face_rings, mesh.faces, s.rings);
}

// The noise estimate as a roughness 0 (clean) .. 1 (noisy): linear in the median dihedral spread
// between the two thresholds.
inline double roughnessOf(double spread_deg, double clean_spread_deg, double noisy_spread_deg) {
  return rampBetween(spread_deg, clean_spread_deg, noisy_spread_deg);
}

// The measured methods' need for smoothing, 0 (clean) .. 1 (noisy): 0 where the noise estimate
// reads clean (noise_estimate.h: the dihedral spread barely decays under one Taubin pair); else
// the larger of the dihedral spread's roughness (roughnessOf) and the noise level over a tenth of
// an edge length; `correlated_bands` > 1: the largest level of the estimate's first that many
// bands (its spectrum), which reads noise correlated over a few rings. The spread alone took real
// scans for clean, as rough per edge as coarse clean meshes; its decay tells them apart
// (docs/studies/noise-estimate.md).
inline double measuredRoughness(const NoiseEstimate &noise, double spread_deg,
                                double clean_spread_deg, double noisy_spread_deg,
                                int correlated_bands = 1) {
  if (!noise.noisy) return 0.0;
  double level = noise.level;
  for (int b = 1; b < std::min<int>(correlated_bands, int(noise.spectrum.size())); ++b)
    level = std::max(level, noise.spectrum[b]);
  return std::max(roughnessOf(spread_deg, clean_spread_deg, noisy_spread_deg),
                  std::min(1.0, level / 0.1));
}

// How much a driver smooths: the measured need (0 = clean .. 1 = noisy) times the user's
// strength; above strength 1 each further unit adds the full amount, so that a mesh measured as
// clean is smoothed too when the user asks for more (strength 2 on a clean mesh: what a noisy
// mesh gets at 1). Continuous in both, and the need itself at strength 1.
inline double strengthen(double need, double strength) {
  strength = std::max(0.0, strength);
  return strength <= 1 ? need * strength : need + (strength - 1);
}

// The patches' α per face by the paper's saliency rule (faceAlphaFromSaliency) on the current
// positions: what the drivers' face-patch fits use when the user turns the α override off.
inline std::vector<double> saliencyFaceAlpha(const std::vector<Vec3> &points,
                                             const std::vector<Face> &faces,
                                             const DriverSetup &setup, double saliency_scale) {
  SurfaceAnalysis analysis;
  analyseSurface(points, faces, setup.rings, saliency_scale, analysis, /*with_directions=*/false);
  return faceAlphaFromSaliency(faces, setup.face_rings, analysis.saliency);
}

// Per vertex, the α the patch fits of its faces used under the paper's saliency rule, for
// inspection (the "Alpha" attribute): the mean of `face_alpha` (saliencyFaceAlpha) over the
// vertex's faces, 1 for a vertex without faces. A vertex's last update moved it onto these faces'
// patches. (Under the user's override every patch has the one α: PatchAlpha::uniform.)
inline std::vector<double> vertexAlphaOfPatches(const Rings &rings,
                                                const std::vector<double> &face_alpha) {
  const int n = rings.vertex_count;
  std::vector<double> out(n, 1.0);
  for (int v = 0; v < n; ++v) {
    const int *begin = rings.facesBegin(v), *end = rings.facesEnd(v);
    if (begin == end) continue;
    double sum = 0;
    int count = 0;
    for (const int *f = begin; f != end; ++f)
      if (f == begin || *f != f[-1]) sum += face_alpha[*f], ++count; // (a face listed twice: once)
    out[v] = sum / count;
  }
  return out;
}

inline void PatchAlpha::record(const Rings &rings, const std::vector<double> &face_alpha,
                              double alpha) {
  if (face_alpha.empty()) uniform = alpha;
  else per_vertex = vertexAlphaOfPatches(rings, face_alpha);
}

// Gives a closed mesh its input volume back by offsets along the vertex normals of the movable
// vertices. The offset is first-order in the lost volume; a second round takes out what curvature
// leaves (coarse sphere: 1.2 % lost, 6e-4 after one round).
inline void restoreInputVolume(std::vector<Vec3> &points, const DriverSetup &setup,
                               const std::vector<Face> &faces, std::vector<Vec3> &normals) {
  std::vector<std::uint8_t> movable(setup.fixed.size());
  for (size_t v = 0; v < movable.size(); ++v) movable[v] = !setup.fixed[v];
  for (int round = 0; round < 2; ++round)
    if (!restoreVolume(points, faces, setup.rings, movable, setup.volume_before,
                       setup.stats.mean_edge_length, normals))
      break;
}

// Runs `drive(ordered_mesh, out, quantities)` on the mesh in spatial order (spatial_order.h) and
// puts the result back in the input's order; `out_points` and `quantities` are left as they were
// when the driver leaves its own untouched (cancelled, declined). A mesh already put in spatial
// order (the filter does that, MeshArrays::spatially_ordered) is used as it is, without a copy.
template <class Drive>
auto inSpatialOrder(const MeshArrays &mesh, std::vector<Vec3> &out_points,
                    VertexQuantities &quantities, Drive drive) {
  if (mesh.spatially_ordered) return drive(mesh, out_points, quantities);
  const SpatialOrder order = spatialOrder(mesh);
  std::vector<Vec3> out;
  VertexQuantities q;
  auto report = drive(order.mesh, out, q);
  if (out.size() == mesh.points.size()) {
    order.toInputOrder(out);
    for (std::vector<double> *values :
         {&q.saliency, &q.k1, &q.k2, &q.mean, &q.gauss, &q.alpha, &q.displacement})
      order.toInputOrder(*values);
    out_points.swap(out);
    quantities = std::move(q);
  }
  return report;
}

} // namespace detail

} // namespace vcg_ext
