// The feature-preserving mode's driver: a short Taubin pre-pass, guided normal filtering, and
// vertices moved onto the planes and then the bi-quadratic patches of their faces
// (normal_filter.h, face_patches.h; docs/studies/feature-mode.md).
//
// Same contract as smoothMesh (paper_smooth.h): the input is never modified, the result goes to
// `out_points`, a report says what happened, progress can cancel, every pass reads one position
// array and writes another (Jacobi), so the result does not depend on vertex order or thread count.
// Non-manifold, isolated and degenerate-face vertices never move; boundary vertices move along
// their boundary and the surface normal, never inward (driver_setup.h's
// BoundaryMode::NoInward). All lengths are in mean edge lengths: no parameter depends on the
// mesh's scale.
//
// Per outer pass: filter the face normals (guided), then `vertex_iterations` Sun-style updates; in
// the last pass the last `patch_iterations` of them go onto face patches instead of face planes.
// Near folded faces (normal far from the filtered one) an update also relaxes the vertex toward
// its 1-ring barycentre within its "feature tangent space" (the directions orthogonal to all its
// faces' filtered normals: the tangent plane on smooth parts, the crease line on a crease, nothing
// at a corner): noise with a tangential part folds faces, and moves along the filtered normals
// alone cannot unfold them. The Taubin pre-pass runs in proportion to the measured noise.
#pragma once

#include "vcg_ext/methods/driver_setup.h"
#include "vcg_ext/methods/impulse_repair.h"
#include "vcg_ext/methods/feature/face_patches.h"
#include "vcg_ext/methods/automatic/mode_choice.h"

#include <Eigen/Eigenvalues>

#include <optional>

namespace vcg_ext {

// Measured on the public benchmark (docs/studies/feature-mode.md): a narrower spatial kernel and
// range than GNF's defaults, and no area weights (area weights let large faces dictate the
// normals of small neighbours, which bends the curved parts of irregular meshes such as
// SharpSphere).
inline NormalFilterParams featureNormalFilterDefaults() {
  NormalFilterParams p;
  p.kind = NormalFilterKind::Guided;
  p.sigma_s = 1.0;
  p.sigma_r = 0.25;
  p.iterations = 10;
  p.guidance_every = 4;
  p.area_power = 0.0;
  return p;
}

struct FeatureSmoothParams {
  int prepass_pairs = 4;      // Taubin λ|μ pairs (0.5 / −0.53) before the normals are filtered
  // The pre-pass, normal filter and vertex iteration counts are scaled by the measured roughness:
  // nothing up to a dihedral spread of clean_spread_deg, in full from noisy_spread_deg.
  double clean_spread_deg = 32.0, noisy_spread_deg = 50.0;
  // The roughness reads the largest level of the noise estimate's first `correlated_bands` bands
  // (its white-equivalent spectrum: 0-1, 1-2, 2-4 pairs) rather than its finest band alone:
  // scanner noise, correlated over a few rings, reads up to 1.5 times higher there, white noise
  // about the same (docs/studies/feature-mode.md, docs/studies/scanner-noise.md). The 4-8 pair
  // band reads more still, but on small CAD meshes it reads the creases too. 1: the finest band
  // only.
  int correlated_bands = 3;
  NormalFilterParams normals = featureNormalFilterDefaults();
  // The first pass's evidence (the automatic choice, planar_extra) is taken after this many normal
  // filter iterations, the first guidance period, where their thresholds were fitted
  // (docs/studies/feature-mode.md, docs/studies/scanner-noise.md).
  int check_iterations = 4;
  int outer_iterations = 2;   // filter normals, then move vertices; repeated
  int vertex_iterations = 6;  // vertex updates per outer pass
  int patch_iterations = 1;   // how many of the last pass's (the last ones) use face patches
  // Meshes of planar faces take up to (1 + planar_extra) times the normal filter iterations and
  // vertex updates, by the share of edges flat after the first guidance period: none up to
  // planar_share_from, all from planar_share_full. Planar faces gain from more, curved ones lose
  // (docs/studies/feature-mode.md).
  double planar_extra = 1.0, planar_share_from = 0.3, planar_share_full = 0.45;
  // Correlated noise leaves more edges bent after the first guidance period than white noise of
  // the same amplitude (a bump a few rings wide outlasts the first averaging), so planar faces
  // read a lower share: both thresholds lower by up to planar_correlated_shift, as far as the
  // noise is into the correlated range (correlatedNoiseRamp; docs/studies/feature-mode.md).
  double planar_correlated_shift = 0.15;
  double planar_normal_share = 1.0, planar_vertex_share = 1.0; // of the extra, to each
  double tangential = 0.5;    // step of the tangential relaxation toward the 1-ring barycentre
  int relax_rings = 1;        // relax vertices within this many rings of a folded face; −1: all
  double fold_cos = 0.5;      // a face is folded when its normal is this far from its filtered one
  FacePatchParams patches;
  // false: the patches' α per face from the saliency (faceAlphaFromSaliency), as the paper's rule
  bool alpha_override = true;
  bool selected_only = false;
  BoundaryMode boundary = BoundaryMode::NoInward;
  // The user's strength: scales the pass counts the noise estimate asks for (strengthen()); the
  // need it scales includes the noise's heavy-tail factor (noise_estimate.h's heavyTailFactor).
  double strength = 1.0;
  HeavyTailParams tails;
  // Heavy noise (an amplitude beyond the public benchmark's) multiplies the need too
  // (noise_estimate.h's heavyNoiseFactor).
  HeavyNoiseParams heavy;
  // Correlated noise multiplies it too (noise_estimate.h's correlatedNoiseFactor).
  CorrelatedNoiseParams correlated;
  // Impulses (single vertices far off the surface) are put back first (impulse_repair.h).
  ImpulseParams impulses;
  // Closed meshes: two rounds of an offset along the vertex normals at the end restore the
  // input's volume (the pre-pass and the patch updates lose 0.85 % on a coarse organic mesh: the
  // cow; restoreInputVolume).
  bool preserve_volume = true;
  double saliency_scale = 0.003; // the saliency of the result (and of the α rule) in bbox diagonals
};

struct FeatureSmoothReport {
  bool cancelled = false;
  bool declined = false;        // the first-pass check said no: nothing was changed
  int outer_iterations_done = 0;
  long vertices_moved = 0;
  long frozen_vertices = 0;     // non-manifold, isolated or on a degenerate face: never moved
  long boundary_vertices = 0;   // moved along the boundary and the normal only
  long plane_fallbacks = 0;     // (over all passes) patch fits that fell back to the face's plane
  long rejected_moves = 0;      // non-finite positions: vertex kept
  double dihedral_spread_deg = 0; // of the input: the noise estimate
  NoiseEstimate noise;            // of the input (noise_estimate.h)
  double roughness = 0;           // 0 (clean) .. 1 (noisy), from the noise estimate
  double amount = 0;              // the roughness with the user's strength: what scales the passes
  double tail_factor = 1;         // the noise's heavy-tail factor on the need (heavyTailFactor)
  double heavy_factor = 1;        // the heavy-noise factor on the need (heavyNoiseFactor)
  double correlated_factor = 1;   // on the filter iterations and updates (correlatedNoiseFactor)
  Impulses impulses;              // read, and put back first (impulse_repair.h)
  int prepass_pairs = 0;          // Taubin pairs actually run
  int vertex_iterations = 0;      // vertex updates actually run per pass
  double flat_share = 0;          // edges flat after the first guidance period (planar_extra)
  int normal_iterations = 0;      // normal filter iterations actually run per pass
  double volume_before = 0, volume_after = 0;
  bool closed = false;
  double mean_edge_length = 0, bbox_diagonal = 0;
  double seconds_topology = 0, seconds_prepass = 0, seconds_normals = 0, seconds_vertices = 0,
         seconds_quantities = 0;
};

namespace detail {

// The projector onto the directions orthogonal to the vertex's filtered face normals, in which the
// surface around it does not bend away: its tangent plane, a crease line, or nothing at a corner.
inline Eigen::Matrix3d featureTangentProjector(int v, const Rings &rings,
                                               const std::vector<Vec3> &filtered) {
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const int *f = rings.facesBegin(v); f != rings.facesEnd(v); ++f)
    C.noalias() += filtered[*f] * filtered[*f].transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(C);
  const double largest = eigen.eigenvalues()[2];
  if (!(largest > 0) || !eigen.eigenvectors().allFinite()) return Eigen::Matrix3d::Zero();
  Eigen::Matrix3d P = Eigen::Matrix3d::Identity();
  // A direction carrying a tenth of the largest normal "mass" counts as a normal direction: one
  // for a smooth vertex, two on a crease, three at a corner.
  for (int k = 0; k < 3; ++k)
    if (eigen.eigenvalues()[k] > 0.1 * largest) {
      const Vec3 e = eigen.eigenvectors().col(k);
      P.noalias() -= e * e.transpose();
    }
  return P;
}

// A symmetric 3×3 matrix (the tangent projectors) in its six distinct entries, single precision:
// 24 instead of 72 bytes per vertex (the rounding changes a relaxation step by ~1e-7 of itself).
using SymmetricMatrix3 = std::array<float, 6>;
inline SymmetricMatrix3 packSymmetric(const Eigen::Matrix3d &P) {
  return {float(P(0, 0)), float(P(1, 0)), float(P(2, 0)), float(P(1, 1)), float(P(2, 1)),
          float(P(2, 2))};
}
inline Eigen::Matrix3d unpackSymmetric(const SymmetricMatrix3 &s) {
  Eigen::Matrix3d P;
  P << s[0], s[1], s[2], s[1], s[3], s[4], s[2], s[4], s[5];
  return P;
}

} // namespace detail

// `given_setup` (optional): the topology and roles of `mesh` with the same selected_only, when the
// caller has them already (the automatic mode shares them between both drivers). A driver that
// finishes releases the set-up's face rings (the result quantities do not need them).
// `first_pass_check` (optional) sees the first pass's face normals after the first guidance
// period of the normal filter (4 iterations), before any vertex moves, with the positions they
// were filtered on (the input after `prepass_pairs` Taubin pairs); false stops the driver
// (report.declined, out_points untouched). The automatic mode decides with it (auto_smooth.h)
// without paying for the filtering twice.
using FilteredNormalsCheck = std::function<bool(
    const std::vector<Vec3> &filtered_normals, const std::vector<Vec3> &prepassed_positions,
    int prepass_pairs, const detail::DriverSetup &setup)>;

// The feature mode's pass counts on a mesh: its measured roughness (measuredRoughness) times the
// noise's heavy-tail factor, with the user's strength, scales the pre-pass, the normal filter and
// the vertex updates.
struct FeaturePassCounts {
  double spread_deg = 0, roughness = 0, amount = 0, tail_factor = 1, heavy_factor = 1,
         correlated_factor = 1, correlated_ramp = 0;
  int prepass_pairs = 0, normal_iterations = 0, vertex_iterations = 0;
  // The normal filter iterations before the first pass's check
  // (FeatureSmoothParams::check_iterations).
  // Heavy noise takes as many more of them as its factor (heavyNoiseFactor): after the first
  // guidance period noise of an edge length leaves a box's faces as rough as an organic shape's.
  int checkIterations(const FeatureSmoothParams &params) const {
    const int check = int(std::lround(std::max(1, params.check_iterations) * heavy_factor));
    return std::min(normal_iterations, std::max(1, check));
  }
};

namespace detail {

inline FeaturePassCounts featurePassCounts(const MeshArrays &mesh, const FeatureSmoothParams &params,
                                           DriverSetup &setup) {
  FeaturePassCounts c;
  c.spread_deg = inputSpreadDeg(mesh, setup);
  c.roughness = measuredRoughness(setup.noise, c.spread_deg, params.clean_spread_deg,
                                  params.noisy_spread_deg, params.correlated_bands);
  c.roughness = std::max(c.roughness, amplitudeNeed(setup.noise, params.heavy));
  // The factor scales the measured need, not the user's strength: a mesh measured as clean
  // (need 0) stays as it is.
  c.tail_factor = heavyTailFactor(setup.noise, params.tails);
  c.heavy_factor = heavyNoiseFactor(setup.noise, params.heavy);
  c.amount = strengthen(c.roughness * c.tail_factor * c.heavy_factor, params.strength);
  auto scaled = [&](int count) { return int(std::lround(c.amount * std::max(0, count))); };
  c.prepass_pairs = scaled(params.prepass_pairs);
  // Correlated noise takes more filter iterations and vertex updates, not a longer pre-pass: the
  // pre-pass's Taubin pairs shape the evidence the automatic choice reads (auto_smooth.h).
  c.correlated_factor = correlatedNoiseFactor(setup.noise, params.correlated);
  c.correlated_ramp = correlatedNoiseRamp(setup.noise, params.correlated);
  auto filtered = [&](int count) {
    return int(std::lround(c.amount * c.correlated_factor * std::max(0, count)));
  };
  c.normal_iterations = filtered(params.normals.iterations);
  c.vertex_iterations = filtered(params.vertex_iterations);
  return c;
}

} // namespace detail

namespace detail {

// Meshes of planar faces take more normal filter iterations and vertex updates, by the share of
// edges flat after the first guidance period, read against a ramp that starts lower under
// correlated noise (`correlated_ramp`: correlatedNoiseRamp; FeatureSmoothParams::planar_extra).
inline void addPlanarExtra(double flat_share, double correlated_ramp,
                           const FeatureSmoothParams &params, int &normal_iterations,
                           int &vertex_iterations) {
  const double shift = params.planar_correlated_shift * correlated_ramp;
  const double extra =
      params.planar_extra * rampBetween(flat_share, params.planar_share_from - shift,
                                        params.planar_share_full - shift);
  normal_iterations = int(std::lround(normal_iterations * (1 + extra * params.planar_normal_share)));
  vertex_iterations = int(std::lround(vertex_iterations * (1 + extra * params.planar_vertex_share)));
}

// Each movable vertex's tangent projector from the filtered normals of its faces
// (featureTangentProjector); zero on the boundary and for fixed vertices.
inline void featureTangentProjectors(const Rings &rings, const std::vector<std::uint8_t> &fixed,
                                     const std::vector<Vec3> &filtered,
                                     std::vector<SymmetricMatrix3> &projector) {
  const int n = int(fixed.size());
  projector.resize(n);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v)
    projector[v] = packSymmetric(rings.boundary[v] || fixed[v]
                                     ? Eigen::Matrix3d::Zero()
                                     : featureTangentProjector(v, rings, filtered));
}

// Which vertices the tangential relaxation moves: those on or within `relax_rings` rings of a
// folded face (one whose normal is farther than `fold_cos` from its filtered normal), so that a
// clean or unfolded mesh keeps its triangulation. `folded` and `scratch` are work buffers.
inline void markVerticesNearFolds(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                                  const std::vector<Vec3> &filtered, const Rings &rings,
                                  double fold_cos, int relax_rings,
                                  std::vector<std::uint8_t> &folded,
                                  std::vector<std::uint8_t> &relax,
                                  std::vector<std::uint8_t> &scratch) {
  const int n = int(points.size()), face_count = int(faces.size());
  folded.resize(face_count);
#pragma omp parallel for schedule(static) if (face_count >= min_parallel_vertices)
  for (int f = 0; f < face_count; ++f) {
    double len;
    folded[f] = unitFaceNormal(points[faces[f][0]], points[faces[f][1]], points[faces[f][2]], len)
                    .dot(filtered[f]) < fold_cos;
  }
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v) {
    std::uint8_t near = 0;
    for (const int *f = rings.facesBegin(v); f != rings.facesEnd(v) && !near; ++f) near = folded[*f];
    relax[v] = near;
  }
  for (int ring = 0; ring < relax_rings; ++ring) {
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
    for (int v = 0; v < n; ++v) {
      std::uint8_t near = relax[v];
      for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v) && !near; ++w) near = relax[*w];
      scratch[v] = near;
    }
    relax.swap(scratch);
  }
}

// What one vertex update reads besides the positions: the filtered normals and either the face
// patches or the face centroids, the tangential relaxation's projectors and marks, and the
// boundary's vertex normals.
struct FeatureMoveInputs {
  const std::vector<Vec3> &filtered;
  const FacePatches *patches; // null: onto the filtered face planes through `centroid`
  const std::vector<Vec3> &centroid;
  const std::vector<SymmetricMatrix3> &tangent_projector;
  const std::vector<std::uint8_t> &relax;
  const std::vector<Vec3> &vertex_normals;
};

// One Jacobi sweep of the vertex update: each movable vertex onto its faces' patches (or filtered
// planes), plus the tangential relaxation where marked, kept off the inward direction on the
// boundary. Returns the number of non-finite moves (those vertices stay).
inline long featureVertexSweep(const std::vector<Vec3> &current, const DriverSetup &setup,
                               const FeatureSmoothParams &params, double edge,
                               const FeatureMoveInputs &in, std::vector<Vec3> &next) {
  const Rings &rings = setup.rings;
  auto move = [&](int v) {
    Vec3 moved = in.patches ? moveOntoFacePatches(v, current[v], rings, *in.patches)
                            : moveOntoFacePlanes(v, current[v], rings, in.centroid, in.filtered,
                                                 edge);
    if (params.tangential > 0 && in.relax[v]) {
      Vec3 centre = Vec3::Zero();
      for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w) centre += current[*w];
      const Vec3 step = centre / rings.ring1Size(v) - current[v];
      // On the boundary, sweepVertices keeps what may stay of the step.
      moved += params.tangential *
               (rings.boundary[v] ? step : Vec3(unpackSymmetric(in.tangent_projector[v]) * step));
    }
    return moved;
  };
  return sweepVertices(current, setup, params.boundary, in.vertex_normals, move, next);
}

// The passes' buffers. Each lives only while its stage runs, so that the normal filter's peak
// (its weights) and the patch fits' do not add up with each other's.
struct FeaturePassBuffers {
  std::vector<Vec3> filtered, next, vertex_normals, centroid;
  FacePatches patches;
  std::vector<SymmetricMatrix3> tangent_projector;
  std::vector<std::uint8_t> relax, relax_scratch, folded;
  PatchAlpha alpha; // the α of the patch update's fits, for inspection
  explicit FeaturePassBuffers(int n) : relax(n, 1), relax_scratch(n, 1) {}
  // What the vertex updates alone read, before the next pass's filter.
  void releaseVertexStage() {
    std::vector<SymmetricMatrix3>().swap(tangent_projector);
    std::vector<Vec3>().swap(next);
    std::vector<Vec3>().swap(centroid);
    std::vector<Vec3>().swap(vertex_normals);
  }
  // Everything but the α for inspection, before the result quantities.
  void releaseAll() {
    releaseVertexStage();
    std::vector<Vec3>().swap(filtered);
    patches = FacePatches();
  }
};

// A pass's normal filter: the current face normals filtered into `b.filtered`. On the first pass
// (`check` set) the filter stops at a checkpoint after counts.checkIterations (before any vertex
// moves) for the automatic mode's check, which may decline (returns false), and for the planar
// extra, which may raise the filter's and the vertex updates' counts; the filter then goes on
// from there in the same guidance period.
inline bool filterPassNormals(bool check, const MeshArrays &mesh, DriverSetup &setup,
                              const FeatureSmoothParams &params, const FeaturePassCounts &counts,
                              const FilteredNormalsCheck &first_pass_check,
                              const std::vector<Vec3> &current, NormalFilterParams &normal_filter,
                              int &vertex_iterations, FeaturePassBuffers &b,
                              FeatureSmoothReport &report) {
  computeFaceNormals(current, mesh.faces, b.filtered); // (the filter works in place)
  const bool scale_by_flatness = params.planar_extra > 0;
  const int check_iterations =
      check && (first_pass_check || scale_by_flatness) ? counts.checkIterations(params) : 0;
  bool declined = false;
  auto checkpoint = [&](const std::vector<Vec3> &normals) {
    if (first_pass_check && !first_pass_check(normals, current, report.prepass_pairs, setup)) {
      declined = true;
      return 0;
    }
    if (scale_by_flatness) {
      // Edge by edge, as the planar extra's thresholds were fitted (docs/studies/feature-mode.md);
      // on a fine curved mesh this reads high, but the automatic choice sends those to the organic
      // mode.
      report.flat_share = sharpFeatureEvidence(normals, normals, setup.face_rings).flat_share;
      addPlanarExtra(report.flat_share, counts.correlated_ramp, params, normal_filter.iterations,
                     vertex_iterations);
      report.normal_iterations = normal_filter.iterations;
      report.vertex_iterations = vertex_iterations;
    }
    return normal_filter.iterations;
  };
  filterNormalsInPlace(current, mesh.faces, setup.face_rings, normal_filter,
                       setup.stats.mean_edge_length, b.filtered, check_iterations, checkpoint);
  return !declined;
}

// One vertex update (featureVertexSweep) of `current`: onto the filtered face planes, or with
// `use_patches` onto face patches fitted to the current positions (α by the override or by the
// paper's saliency rule), with the boundary normals and the fold marks it needs.
inline void featureVertexUpdate(bool use_patches, const MeshArrays &mesh, const DriverSetup &setup,
                                const FeatureSmoothParams &params, std::vector<Vec3> &current,
                                FeaturePassBuffers &b, FeatureSmoothReport &report) {
  const Rings &rings = setup.rings;
  const double edge = setup.stats.mean_edge_length;
  if (use_patches) {
    std::vector<Vec3>().swap(b.centroid);
    const std::vector<double> face_alpha =
        params.alpha_override ? std::vector<double>()
                              : saliencyFaceAlpha(current, mesh.faces, setup,
                                                  params.saliency_scale * setup.stats.bbox_diagonal);
    report.plane_fallbacks += fitFacePatches(current, mesh.faces, setup.face_rings, b.filtered,
                                             edge, params.patches, face_alpha, b.patches);
    b.alpha.record(rings, face_alpha, params.patches.alpha);
  } else {
    computeFaceCentroids(current, mesh.faces, b.centroid);
  }
  // Boundary moves keep off the inward direction, which needs the surface normal there.
  if (report.boundary_vertices)
    computeBoundaryVertexNormals(current, mesh.faces, rings, b.vertex_normals);
  if (params.tangential > 0 && params.relax_rings >= 0)
    markVerticesNearFolds(current, mesh.faces, b.filtered, rings, params.fold_cos,
                          params.relax_rings, b.folded, b.relax, b.relax_scratch);
  const FeatureMoveInputs inputs{b.filtered,          use_patches ? &b.patches : nullptr,
                                 b.centroid,          b.tangent_projector,
                                 b.relax,             b.vertex_normals};
  report.rejected_moves += featureVertexSweep(current, setup, params, edge, inputs, b.next);
  current.swap(b.next);
}

// What the noise estimate asked for, into the report (the log says what was done).
inline void reportPassCounts(const FeaturePassCounts &counts, const DriverSetup &setup,
                             FeatureSmoothReport &report) {
  report.dihedral_spread_deg = counts.spread_deg;
  report.noise = setup.noise;
  report.roughness = counts.roughness;
  report.amount = counts.amount;
  report.tail_factor = counts.tail_factor;
  report.heavy_factor = counts.heavy_factor;
  report.correlated_factor = counts.correlated_factor;
  report.prepass_pairs = counts.prepass_pairs;
  report.normal_iterations = counts.normal_iterations;
  report.vertex_iterations = counts.vertex_iterations;
}

enum class PassEnd { Done, Declined, Cancelled };

// One outer pass on `current`: the face normals filtered (the first pass's `check` may decline
// the mode: the automatic choice), then the vertex updates, the last pass's last ones onto face
// patches. `normal_filter` and `vertex_iterations` may grow at the first pass (planar extra).
inline PassEnd featurePass(int pass, const MeshArrays &mesh, DriverSetup &setup,
                           const FeatureSmoothParams &params, const FeaturePassCounts &counts,
                           const FilteredNormalsCheck &check, const PassProgress &progress,
                           NormalFilterParams &normal_filter, int &vertex_iterations,
                           std::vector<Vec3> &current, FeaturePassBuffers &b,
                           FeatureSmoothReport &report) {
  const bool last = pass == progress.passes - 1;
  auto t = Clock::now();
  b.releaseVertexStage();
  if (!filterPassNormals(pass == 0, mesh, setup, params, counts, check, current, normal_filter,
                         vertex_iterations, b, report)) {
    report.seconds_normals += secondsSince(t);
    return PassEnd::Declined;
  }
  b.next.resize(current.size());
  if (params.tangential > 0)
    featureTangentProjectors(setup.rings, setup.fixed, b.filtered, b.tangent_projector);
  // After the last filtering nothing reads the faces' edge neighbours.
  if (last) std::vector<std::array<int, 3>>().swap(setup.face_rings.edge_neighbours);
  report.seconds_normals += secondsSince(t);
  if (!progress(pass, 0.4, "Filtering normals")) return PassEnd::Cancelled;

  t = Clock::now();
  for (int it = 0; it < vertex_iterations; ++it) {
    // Patches refine the last pass only: earlier passes gain little from them for their cost (a
    // fit per face is most of a pass's time; docs/studies/feature-mode.md).
    const bool use_patches = last && it >= vertex_iterations - params.patch_iterations;
    featureVertexUpdate(use_patches, mesh, setup, params, current, b, report);
    if (!progress(pass, 0.4 + 0.6 * (it + 1) / vertex_iterations, "Moving vertices"))
      return PassEnd::Cancelled;
  }
  report.seconds_vertices += secondsSince(t);
  report.outer_iterations_done = pass + 1;
  return PassEnd::Done;
}

// The driver on `mesh` as given (featureSmoothMesh runs it in spatial order).
inline FeatureSmoothReport featureSmoothAsGiven(const MeshArrays &mesh,
                                                const FeatureSmoothParams &params,
                                                std::vector<Vec3> &out_points,
                                                VertexQuantities &quantities,
                                                const ProgressFn &progress = nullptr,
                                                const FilteredNormalsCheck &first_pass_check = nullptr,
                                                DriverSetup *given_setup = nullptr) {
  FeatureSmoothReport report;
  auto t = Clock::now();
  std::optional<DriverSetup> own_setup;
  if (!given_setup) own_setup.emplace(driverSetup(mesh, params.selected_only, params.boundary));
  DriverSetup &setup = given_setup ? *given_setup : *own_setup;
  ensureFaceRings(mesh, setup);
  reportSetup(setup, report);
  report.seconds_topology = secondsSince(t);
  const double edge = setup.stats.mean_edge_length;
  // 0-90 % over the passes: the result quantities take the rest.
  const PassProgress report_progress{progress, std::max(0, params.outer_iterations), 90.0};

  std::vector<Vec3> current = mesh.points;
  t = Clock::now();
  // How much smoothing the mesh needs: the noise estimate's roughness (measuredRoughness: none
  // where it reads clean, light noise and real scans' noise included) scales every pass count.
  // The pre-pass rounds creases that the rest only partly restores, and even one filter
  // iteration followed by the vertex updates flattens a coarse organic mesh (clean armadillo:
  // 11°), hence the clean/noisy decision first (docs/studies/noise-estimate.md).
  const FeaturePassCounts counts = featurePassCounts(mesh, params, setup);
  reportPassCounts(counts, setup, report);
  NormalFilterParams normal_filter = params.normals;
  normal_filter.iterations = counts.normal_iterations;
  int vertex_iterations = counts.vertex_iterations;
  if (edge > 0)
    taubinSmooth(current, setup.rings, setup.fixed, setup.roles.boundary_neighbours,
                 report.prepass_pairs);
  report.seconds_prepass = secondsSince(t);
  if (!report_progress(0, 0.05, "Taubin pre-pass")) return report.cancelled = true, report;

  FeaturePassBuffers b(int(mesh.points.size()));
  for (int pass = 0; pass < report_progress.passes && edge > 0; ++pass) {
    const PassEnd end = featurePass(pass, mesh, setup, params, counts, first_pass_check,
                                    report_progress, normal_filter, vertex_iterations, current, b,
                                    report);
    if (end == PassEnd::Declined) return report.declined = true, report;
    if (end == PassEnd::Cancelled) return report.cancelled = true, report;
  }

  if (params.preserve_volume && report.closed && vertex_iterations > 0 && edge > 0)
    restoreInputVolume(current, setup, mesh.faces, b.vertex_normals);

  // Only the result and the rings are read from here on: the result quantities' peak (saliency)
  // should not stack on the iterations' buffers.
  b.releaseAll();
  setup.face_rings = FaceRings();
  finishDriver(mesh, setup.rings, params.saliency_scale * setup.stats.bbox_diagonal, current,
               out_points, quantities, report, std::move(b.alpha));
  return report;
}

} // namespace detail

inline FeatureSmoothReport featureSmoothMesh(const MeshArrays &mesh,
                                             const FeatureSmoothParams &params,
                                             std::vector<Vec3> &out_points,
                                             VertexQuantities &quantities,
                                             const ProgressFn &progress = nullptr) {
  return detail::measuredDriverRun(
      mesh, params, out_points, quantities,
      [&](const MeshArrays &m, std::vector<Vec3> &o, VertexQuantities &q,
          detail::DriverSetup &setup) {
        return detail::featureSmoothAsGiven(m, params, o, q, progress, nullptr, &setup);
      });
}

namespace detail {

inline std::string featureSummary(const FeatureSmoothReport &r, const FeatureSmoothParams &p,
                                  const MethodRun &run, size_t vertices) {
  if (r.amount <= 0 && r.impulses.moved > 0)
    return "Feature-preserving: " + cleanAfterImpulsesPhrase(r.impulses, r.noise) + ".";
  if (r.amount <= 0) return "Feature-preserving: " + measuredCleanPhrase(r.noise) + ".";
  return "Feature-preserving: " + noisePhrase(r.noise, r.roughness) + impulsePhrase(r.impulses) +
         formatLine("; strength %.2f%s: %d pre-pass pairs, %d normal filter iterations and %d "
                    "vertex updates per pass, %d passes; ",
                    p.strength,
                    (tailPhrase(r.tail_factor, r.amount, r.noise) +
                     heavyPhrase(r.heavy_factor, r.amount) +
                     correlatedPhrase(r.correlated_factor, r.amount, r.noise))
                        .c_str(),
                    r.prepass_pairs, r.normal_iterations, r.vertex_iterations,
                    r.outer_iterations_done) +
         movedPhrase(run, vertices) + ".";
}

inline std::vector<std::string> featureDetails(const FeatureSmoothReport &r) {
  std::vector<std::string> log;
  appendFacePatchDriverLog(r, log);
  log.push_back(formatLine("Time: topology and pre-pass %.3f s, normal filtering %.3f s, vertex "
                           "updates %.3f s, result quantities %.3f s.",
                           r.seconds_topology + r.seconds_prepass, r.seconds_normals,
                           r.seconds_vertices, r.seconds_quantities));
  return log;
}

} // namespace detail

// The feature-preserving method as the filter runs it (methods.h).
inline MethodRun featureMethod(const MeshArrays &mesh, const MethodParams &p,
                               std::vector<Vec3> &out_points, VertexQuantities &quantities,
                               const ProgressFn &progress) {
  FeatureSmoothParams params;
  detail::readCommonParams(p, params);
  const FeatureSmoothReport r = featureSmoothMesh(mesh, params, out_points, quantities, progress);
  MethodRun run = detail::measuredRun(r, "feature-preserving", 3, quantities); // (methods.h)
  if (run.cancelled) return run;
  run.summary = detail::featureSummary(r, params, run, mesh.points.size());
  run.details = detail::featureDetails(r);
  return run;
}

} // namespace vcg_ext
