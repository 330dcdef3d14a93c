// The organic mode's driver: for scans of organic shapes with noise in all directions (body and
// object scans, photogrammetry), where Taubin smoothing beats every feature-preserving filter
// and the question is only how much of it (docs/studies/organic-mode.md).
//
// Stages: the noise estimate (noise_estimate.h) decides whether there is anything to do (a clean
// mesh is left exactly as it is); Wiener shrinkage of Taubin's frequency bands (band_shrink.h)
// removes the noise; one update onto bi-quadratic face patches fitted to the result's own normals
// (face_patches.h) takes out what the low-pass left of the curvature bias; closed meshes get their
// input volume back. Same contract as featureSmoothMesh (feature_smooth.h): the input is never
// modified, the result goes to `out_points`, progress can cancel, the result does not depend on
// vertex order or thread count; frozen vertices never move, boundary vertices move along their
// boundary (Taubin) and never inward (the patch update).
#pragma once

#include "vcg_ext/methods/organic/band_shrink.h"
#include "vcg_ext/methods/driver_setup.h"
#include "vcg_ext/methods/impulse_repair.h"
#include "vcg_ext/methods/feature/face_patches.h"
#include "vcg_ext/methods/organic/fold_repair.h"

namespace vcg_ext {

struct OrganicSmoothParams {
  BandShrinkParams bands;
  // Nothing is removed up to a dihedral spread of clean_spread_deg, all from noisy_spread_deg
  // (measuredRoughness in driver_setup.h, roughness r = 0..1). The shrinkage removes the measured
  // noise level times min(1, r / full_noise_roughness): the band gains adapt by themselves, so the
  // gate only has to keep clean meshes as they are; scaling by r itself removed too little
  // (docs/studies/organic-mode.md).
  double clean_spread_deg = 32.0, noisy_spread_deg = 50.0;
  double full_noise_roughness = 0.25;
  // One patch update: a second one changes θ by about nothing on organic meshes for a fifth more
  // time (docs/studies/organic-mode.md).
  int max_patch_updates = 1;
  FacePatchParams patches;
  // false: the patches' α per face from the saliency (faceAlphaFromSaliency), as the paper's rule
  bool alpha_override = true;
  bool selected_only = false;
  BoundaryMode boundary = BoundaryMode::NoInward;
  // The user's strength: scales the noise level the shrinkage removes (strengthen()); above 1 the
  // level is at least (strength − 1) × noise_edges_per_strength mean edge lengths, so that a mesh
  // measured as clean is smoothed too when asked.
  double strength = 1.0;
  double noise_edges_per_strength = 0.1;
  // Above strength 1, one more band per doubling of the strength beyond the coarsest (at most
  // this many octaves of pairs; Iterations' 30, strength 10, takes four: up to 2048 pairs), so
  // that asking for more keeps removing more (addStrengthBands).
  int max_strength_octaves = 4;
  HeavyTailParams tails; // the noise's heavy-tail factor on the measured need (heavyTailFactor)
  // Noise heavier than the public benchmark's (amplitude above heavy.from, noise_estimate.h's
  // heavyNoiseFactor, the feature mode's rule and constants) multiplies the strength: the
  // shrinkage's noise level and the bands beyond 128 pairs (addStrengthBands), as Iterations
  // does. Multiplying only the level removed too little: the base beyond 128 pairs stays whole
  // (heavy set, Bunny 4views_1.0: 20.86° as measured, 15.11° level × factor, 12.85° strength ×
  // factor; docs/studies/scanner-noise.md). The factor is raised to the noise's correlated share
  // (NoiseEstimate::correlated_share) to heavy_share_power: the shrinkage measures white noise
  // itself at any level, and the whole factor over-smoothed heavy white noise (Bunny, armadillo,
  // lion head, camel at 0.6: 3-5 % higher θ). 0: the whole factor.
  HeavyNoiseParams heavy;
  double heavy_share_power = 1.0;
  // Noise that only the amplitude reads (NoiseEstimate::noisy_by_amplitude: correlated over
  // several rings, which one Taubin pair barely changes) multiplies the strength by this: the
  // shrinkage's white probe reads as little of it as the pair does. Held-out meshes under such
  // noise: θ 0.70 of the strength-1 result, none higher; noise_truth.py's: 0.92, one higher
  // (docs/studies/noise-estimate.md). 1: off.
  double unseen_noise_strength = 2.0;
  // The noise's colour (noise_estimate.h's noiseColour) multiplies the white probe's band energies.
  bool coloured_noise = false;
  NoiseColourParams colour;
  bool preserve_volume = true;
  double saliency_scale = 0.003;
  // Folded stars untangled before the band shrinkage (fold_repair.h), only where the noise is
  // heavy-tailed (NoiseEstimate::tail at least fold_min_tail) at a level of at least
  // fold_min_level mean edge lengths: scanner noise, whose view-ray error folds stars at grazing
  // angles. Noise in random directions reads a tail of about 1 on an evenly triangulated mesh and
  // keeps its stars (untangling them cost thin parts there); light noise, whose finest band can be
  // heavy-tailed by its shape detail, is below the level (docs/studies/organic-mode.md).
  FoldRepairParams folds;
  double fold_min_tail = 1.2, fold_min_level = 0.08;
  // Impulses (single vertices far off the surface) are put back first (impulse_repair.h).
  ImpulseParams impulses;
};

struct OrganicSmoothReport {
  bool cancelled = false;
  long vertices_moved = 0;
  long frozen_vertices = 0, boundary_vertices = 0;
  long plane_fallbacks = 0, rejected_moves = 0;
  int patch_updates = 0;
  double patch_step = 0;   // fraction of the way onto the patches per update
  double dihedral_spread_deg = 0, roughness = 0;
  NoiseEstimate noise; // of the input (noise_estimate.h)
  double amount = 0; // the share of the measured noise level removed, with the user's strength
  double tail_factor = 1; // the noise's heavy-tail factor on the measured need (heavyTailFactor)
  double heavy_factor = 1; // the heavy-noise factor on the strength (heavyNoiseFactor)
  double strength = 1;     // the strength the bands ran with: the user's times both factors
  double unseen_factor = 1; // on the strength for noise only the amplitude reads
  long fold_moves = 0; // moves of folded vertices onto their ring's barycentre (fold_repair.h)
  Impulses impulses;   // read, and put back first (impulse_repair.h)
  BandShrinkReport bands;
  double volume_before = 0, volume_after = 0;
  bool closed = false;
  double mean_edge_length = 0, bbox_diagonal = 0;
  double seconds_topology = 0, seconds_bands = 0, seconds_patches = 0, seconds_quantities = 0;
};

namespace detail {

// The bands a strength above 1 adds beyond the coarsest (BandShrinkParams::band_pairs): band j
// (1, 2, ...) spans twice the pairs of the one before (128-256, 256-512, ... after the default
// bands) and takes in its shrinkage as the strength goes from 2^(j-1) to 2^j
// (BandShrinkParams::shrink_share), so the result changes continuously with the strength, and a
// strength of 1 or less runs the bands as they are. Why: the shrinkage keeps the coarsest band's
// base whole, so without them the strength did nothing past about three times the measured
// amount (heavy scanner noise, docs/studies/scanner-noise.md).
inline void addStrengthBands(BandShrinkParams &bands, double strength, int max_octaves) {
  if (!(strength > 1) || bands.band_pairs.size() < 2) return;
  const int existing = int(bands.band_pairs.size()) - 1;
  bands.shrink_share.resize(existing, 1.0);
  const double octaves = std::log2(strength);
  for (int j = 1; j <= max_octaves && octaves > j - 1; ++j) {
    bands.band_pairs.push_back(2 * bands.band_pairs.back());
    bands.shrink_share.push_back(std::clamp(octaves - (j - 1), 0.0, 1.0));
  }
}

// Untangles folds before the band shrinkage (it smooths along the normals, which point the wrong
// way on a fold), under heavy-tailed noise only (OrganicSmoothParams::fold_min_tail,
// fold_min_level). The noise level is read before: untangling removes part of the noise unevenly,
// and a level read after it is far too low (docs/studies/organic-mode.md). Returns the vertex
// moves made.
inline long untangleFoldsForBands(std::vector<Vec3> &points, const std::vector<Face> &faces,
                                  const DriverSetup &setup, const OrganicSmoothParams &params,
                                  BandShrinkParams &bands) {
  FoldRepairParams folds = params.folds;
  if (!(setup.noise.tail >= params.fold_min_tail && setup.noise.level >= params.fold_min_level))
    folds.max_rounds = 0;
  if (folds.max_rounds > 0) {
    std::vector<Vec3> normals;
    computeVertexNormals(points, faces, setup.rings, normals);
    bands.given_noise_sigma = estimateNormalNoiseSigma(points, setup.rings, setup.fixed, normals);
  }
  return repairFolds(points, faces, setup.rings, setup.fixed, folds);
}

// The band shrinkage's parameters for the amount and the strength it ran with (the user's times
// the heavy-noise factor): the noise scaled by the amount, at least a tenth of an edge length per
// strength unit above 1 (asked for more than measured), one band more per doubling of strength
// past the coarsest (addStrengthBands), and the noise's colour when asked.
inline void organicBandParams(const OrganicSmoothParams &params, const NoiseEstimate &noise,
                              double amount, double strength, BandShrinkParams &bands) {
  bands.noise_scale *= amount;
  bands.min_noise_edges = std::max(0.0, strength - 1) * params.noise_edges_per_strength;
  addStrengthBands(bands, strength, params.max_strength_octaves);
  if (params.coloured_noise) bands.noise_colour = noiseColour(noise, bands.band_pairs, params.colour);
  bands.given_order = true; // (inSpatialOrder)
}

// One patch update: each movable vertex `step` of the way onto its face patches, kept off the
// inward direction on the boundary. Returns the number of non-finite moves (those vertices stay).
inline long organicPatchSweep(const std::vector<Vec3> &current, const DriverSetup &setup,
                              const OrganicSmoothParams &params, double step,
                              const FacePatches &patches, const std::vector<Vec3> &vertex_normals,
                              std::vector<Vec3> &next) {
  auto move = [&](int v) {
    return Vec3(current[v] +
                step * (moveOntoFacePatches(v, current[v], setup.rings, patches) - current[v]));
  };
  return sweepVertices(current, setup, params.boundary, vertex_normals, move, next);
}

// What the noise estimate asks of this mode: the report's spread, roughness (measuredRoughness),
// heavy-tail factor, heavy-noise factor, strength and amount (the measured need times the
// strength). The tail factor scales the measured need, the heavy-noise factor and the unseen
// noise's factor the strength, all only where noise was measured: a mesh measured as clean
// (need 0) stays as it is.
inline void organicAmount(const MeshArrays &mesh, DriverSetup &setup,
                          const OrganicSmoothParams &params, OrganicSmoothReport &report) {
  report.dihedral_spread_deg = inputSpreadDeg(mesh, setup);
  report.noise = setup.noise;
  report.roughness = measuredRoughness(setup.noise, report.dihedral_spread_deg,
                                       params.clean_spread_deg, params.noisy_spread_deg);
  report.tail_factor = heavyTailFactor(setup.noise, params.tails);
  const double need =
      std::min(1.0, report.roughness / params.full_noise_roughness) * report.tail_factor;
  // Only measured noise asks for more: a mesh measured as clean keeps the user's strength.
  report.heavy_factor = need > 0 ? heavyNoiseFactor(setup.noise, params.heavy) : 1.0;
  // The band shrinkage's probe is white noise: the factor stands for the correlated part.
  report.heavy_factor = std::pow(
      report.heavy_factor,
      std::pow(std::clamp(setup.noise.correlated_share, 0.0, 1.0), params.heavy_share_power));
  report.unseen_factor = need > 0 && setup.noise.noisy_by_amplitude
                             ? std::max(1.0, params.unseen_noise_strength)
                             : 1.0;
  report.strength = params.strength * report.heavy_factor * report.unseen_factor;
  report.amount = strengthen(need, report.strength);
}

// The patch updates after the band shrinkage. Patches take out curvature bias where the mesh is
// smooth at the scale of a face's neighbourhood and add error where it has detail at that scale:
// each update moves the vertices the fraction of the way onto their patches that the band
// shrinkage found the mesh smooth (report.patch_step), so the result changes continuously with
// that measurement. Then the input volume on a closed mesh. `alpha`: the fits' α, for
// inspection. Returns false when `update_done(update, count)` cancels.
template <class UpdateDone>
bool organicPatchUpdates(const MeshArrays &mesh, DriverSetup &setup,
                         const OrganicSmoothParams &params, std::vector<Vec3> &current,
                         PatchAlpha &alpha, OrganicSmoothReport &report,
                         UpdateDone update_done) {
  const Rings &rings = setup.rings;
  std::vector<Vec3> next(current), vertex_normals, face_normals;
  FacePatches patches;
  report.patch_step = 1.0 - report.bands.detail;
  const int patch_updates = report.patch_step > 0 ? params.max_patch_updates : 0;
  report.patch_updates = patch_updates;
  // The paper's α rule reads the face rings (faceAlphaFromSaliency).
  if (patch_updates > 0 && !params.alpha_override)
    setup.face_rings = computeFaceRings(mesh.faces, rings, /*with_edge_neighbours=*/false);
  for (int update = 0; update < patch_updates; ++update) {
    computeFaceNormals(current, mesh.faces, face_normals);
    const std::vector<double> face_alpha =
        params.alpha_override
            ? std::vector<double>()
            : saliencyFaceAlpha(current, mesh.faces, setup,
                                params.saliency_scale * setup.stats.bbox_diagonal);
    const long fallbacks = fitFacePatches(current, mesh.faces, rings, face_normals,
                                          setup.stats.mean_edge_length, params.patches,
                                          face_alpha, patches);
    alpha.record(rings, face_alpha, params.patches.alpha);
    if (report.boundary_vertices)
      computeBoundaryVertexNormals(current, mesh.faces, rings, vertex_normals);
    const long rejected =
        organicPatchSweep(current, setup, params, report.patch_step, patches, vertex_normals, next);
    current.swap(next);
    report.plane_fallbacks += fallbacks;
    report.rejected_moves += rejected;
    if (!update_done(update, patch_updates)) return false;
  }
  if (params.preserve_volume && report.closed)
    restoreInputVolume(current, setup, mesh.faces, vertex_normals);
  return true;
}

// The driver on `mesh` as given (organicSmoothMesh runs it in spatial order): the amount the
// noise asks for, the band shrinkage, the patch updates, the result's quantities.
inline OrganicSmoothReport organicSmoothAsGiven(const MeshArrays &mesh,
                                                const OrganicSmoothParams &params,
                                                std::vector<Vec3> &out_points,
                                                VertexQuantities &quantities,
                                                const ProgressFn &progress = nullptr,
                                                DriverSetup *given_setup = nullptr) {
  OrganicSmoothReport report;
  auto t = Clock::now();
  // `given_setup`: as in featureSmoothMesh, the topology when the caller has it already.
  std::optional<detail::DriverSetup> own_setup;
  if (!given_setup)
    own_setup.emplace(detail::driverSetup(mesh, params.selected_only, params.boundary));
  detail::DriverSetup &setup = given_setup ? *given_setup : *own_setup;
  const Rings &rings = setup.rings;
  detail::reportSetup(setup, report);
  organicAmount(mesh, setup, params, report);
  report.seconds_topology = secondsSince(t);
  if (progress && !progress(5, "Noise estimate")) return report.cancelled = true, report;

  std::vector<Vec3> current = mesh.points;
  const bool noisy = report.amount > 0 && setup.stats.mean_edge_length > 0;
  detail::PatchAlpha alpha; // the α of the patch update's fits, for inspection
  if (progress && !progress(6, noisy ? "Band shrinkage" : "The mesh measures as clean"))
    return report.cancelled = true, report;
  if (noisy) {
    t = Clock::now();
    BandShrinkParams bands = params.bands;
    report.fold_moves = detail::untangleFoldsForBands(current, mesh.faces, setup, params, bands);
    detail::organicBandParams(params, setup.noise, report.amount, report.strength, bands);
    // The band shrinkage, this mode's peak memory, reads no face rings, nor does the patch update
    // (its fit merges each face's ring when it needs it): ~136 bytes per vertex freed.
    setup.face_rings = FaceRings();
    report.bands = bandShrinkSmooth(current, mesh.faces, rings, setup.fixed,
                                    setup.roles.boundary_neighbours, bands, [&](double fraction) {
                                      return !progress ||
                                             progress(5 + int(75 * fraction), "Band shrinkage");
                                    });
    report.seconds_bands = secondsSince(t);
    if (report.bands.cancelled) return report.cancelled = true, report;

    t = Clock::now();
    if (!organicPatchUpdates(mesh, setup, params, current, alpha, report,
                             [&](int update, int count) {
                               return !progress ||
                                      progress(80 + 10 * (update + 1) / count, "Patch update");
                             }))
      return report.cancelled = true, report;
    report.seconds_patches = secondsSince(t);
  }

  if (progress && !progress(95, "Result quantities")) return report.cancelled = true, report;
  // Only the result and the rings are read from here on (feature_smooth.h: the same).
  setup.face_rings = FaceRings();
  detail::finishDriver(mesh, rings, params.saliency_scale * setup.stats.bbox_diagonal, current,
                       out_points, quantities, report, std::move(alpha));
  return report;
}

} // namespace detail

inline OrganicSmoothReport organicSmoothMesh(const MeshArrays &mesh,
                                             const OrganicSmoothParams &params,
                                             std::vector<Vec3> &out_points,
                                             VertexQuantities &quantities,
                                             const ProgressFn &progress = nullptr) {
  return detail::measuredDriverRun(
      mesh, params, out_points, quantities,
      [&](const MeshArrays &m, std::vector<Vec3> &o, VertexQuantities &q,
          detail::DriverSetup &setup) {
        return detail::organicSmoothAsGiven(m, params, o, q, progress, &setup);
      });
}

namespace detail {

inline std::string organicSummary(const OrganicSmoothReport &r, const OrganicSmoothParams &p,
                                  const MethodRun &run, size_t vertices) {
  if (r.amount <= 0 && r.impulses.moved > 0)
    return "Organic: " + cleanAfterImpulsesPhrase(r.impulses, r.noise) + ".";
  if (r.amount <= 0) return "Organic: " + measuredCleanPhrase(r.noise) + ".";
  return "Organic: " + noisePhrase(r.noise, r.roughness) + impulsePhrase(r.impulses) +
         formatLine("; strength %.2f%s%s%s: ", p.strength,
                    tailPhrase(r.tail_factor, r.amount, r.noise).c_str(),
                    (r.heavy_factor > 1
                         ? formatLine(", the strength x %.2f for heavy noise", r.heavy_factor)
                         : std::string())
                        .c_str(),
                    (r.unseen_factor > 1
                         ? formatLine(", the strength x %.2f for noise only its amplitude reads",
                                      r.unseen_factor)
                         : std::string())
                        .c_str()) +
         (r.fold_moves > 0 ? formatLine("untangled folds (%ld vertex moves), ", r.fold_moves)
                           : std::string()) +
         formatLine("removed %.2f of the noise along the normals (%.3f mean edge lengths); ",
                    r.amount,
                    r.mean_edge_length > 0 ? r.bands.noise_sigma / r.mean_edge_length : 0.0) +
         movedPhrase(run, vertices) + ".";
}

inline std::vector<std::string> organicDetails(const OrganicSmoothReport &r) {
  std::vector<std::string> log;
  if (r.amount > 0) {
    const std::string local =
        r.bands.local_to_pairs > 0
            ? formatLine("; %d-%d pairs: the mean of the vertices' local gains",
                         r.bands.local_from_pairs, r.bands.local_to_pairs)
            : std::string();
    std::string gains = formatLine("Shape spectrum slope %.2f, coarse-band shape/noise %.2f, "
                                   "fine-band shape/noise %.2f: alpha %.2f; band gains (fine to "
                                   "coarse%s):",
                                   r.bands.shape_slope, r.bands.coarse_snr, r.bands.fine_snr,
                                   r.bands.alpha, local.c_str());
    for (double g : r.bands.gains) gains += formatLine(" %.2f", g);
    log.push_back(gains + ".");
  }
  appendFacePatchDriverLog(r, log);
  log.push_back(formatLine("Time: topology %.3f s, band shrinkage %.3f s, patch update %.3f s, "
                           "result quantities %.3f s.",
                           r.seconds_topology, r.seconds_bands, r.seconds_patches,
                           r.seconds_quantities));
  return log;
}

} // namespace detail

// The organic method as the filter runs it (methods.h).
inline MethodRun organicMethod(const MeshArrays &mesh, const MethodParams &p,
                               std::vector<Vec3> &out_points, VertexQuantities &quantities,
                               const ProgressFn &progress) {
  OrganicSmoothParams params;
  detail::readCommonParams(p, params);
  const OrganicSmoothReport r = organicSmoothMesh(mesh, params, out_points, quantities, progress);
  MethodRun run = detail::measuredRun(r, "organic", 4, quantities); // (methods.h)
  if (run.cancelled) return run;
  run.summary = detail::organicSummary(r, params, run, mesh.points.size());
  run.details = detail::organicDetails(r);
  return run;
}

} // namespace vcg_ext
