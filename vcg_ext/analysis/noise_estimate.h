// Whether a mesh is noisy, and how much noise it carries, from the mesh alone.
//
// Inputs: positions and triangles (plain arrays, mesh_arrays.h). Output: a NoiseEstimate: the
// decision (noisy / clean), the noise level in mean edge lengths and the figures it came from.
// Papers: Taubin 1995 (λ|μ smoothing as a low-pass filter); the dihedral spread of
// dihedral_spread.h; the white-noise probe of band_shrink.h.
//
// Why not the dihedral spread alone: it reads the roughness of the surface at the scale of one
// edge, and a coarse clean mesh is as rough there as a fine scan with noise. What tells them
// apart is what one Taubin pair does to it: noise lives at the highest frequencies, which a pair
// damps, while shape — however coarse the mesh — lies below Taubin's pass band and stays. So the
// decision is on the spread's decay: spread after one pair over spread before, with a floor on
// the spread it removed (degrees) so that nearly flat meshes, whose decay is a ratio of two small
// numbers, do not decide on it (docs/studies/noise-estimate.md). A spread above
// `noisy_spread_deg` (the feature mode's "fully noisy" threshold) is noisy whatever its decay.
// Heavy noise correlated over several rings barely decays under one pair: where the pair reads
// clean, the noise amplitude (noise_amplitude.h) read on trimmed band energies decides too
// (decideNoisyByAmplitude; a clean mesh's creases are left out by the trimming, its fine relief
// is not, hence a threshold above the relief of the clean meshes measured).
//
// The level: the median normal displacement that the first Taubin pair takes out, over the same
// median of a white-noise probe run through the same pair (so it reads σ for white noise of std σ
// along the normals, whatever the mesh's valences and boundaries). The same ratio per Taubin band
// (pairs 0–1, 1–2, 2–4, 4–8) gives a white-equivalent spectrum: flat for white noise, rising for
// noise correlated over several rings (and for shape). Medians make both robust to a few outliers
// and to creases; boundary, non-manifold and isolated vertices are left out.
//
// Scale: every length is in mean edge lengths (positions are shifted to the bounding box corner and
// divided by the mean edge length first). Order: the probe's values hash each vertex's position
// (position_hash.h), every quantity is per vertex or per face, then a median: the result does not
// depend on the thread count, nor on the vertex order up to the rounding of the neighbour sums
// (the probe runs in single precision: its figures agree to float rounding).
#pragma once

#include "vcg_ext/core/ramp.h"
#include "vcg_ext/analysis/curvature.h"
#include "vcg_ext/analysis/dihedral_spread.h"
#include "vcg_ext/analysis/noise_amplitude.h"
#include "vcg_ext/core/position_hash.h"
#include "vcg_ext/core/vertex_roles.h"
#include "vcg_ext/smoothing/spatial_taubin.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace vcg_ext {

struct NoiseEstimateParams {
  double lambda = 0.5, mu = -0.53;  // one Taubin pair, as MeshLab's Taubin filter
  // Decision: noisy when one pair leaves at most `max_decay` of the spread and removes at least
  // `min_drop_deg` of it, or when the spread reaches `noisy_spread_deg`. Fitted on half of the
  // meshes of docs/studies/noise-estimate.md, checked on the other half: no clean mesh of the
  // promise reads noisy. Light noise on coarse meshes reads clean, where Taubin ×10 makes θ worse
  // anyway.
  double max_decay = 0.85;
  double min_drop_deg = 3.0;
  double noisy_spread_deg = 50.0;
  // Band edges in Taubin pairs of the white-equivalent spectrum. They start 0, 1: the first band
  // is the decision's pair, run once for both (other edges give the decision without a spectrum).
  std::vector<int> band_pairs = {0, 1, 2, 4, 8};
  // The amplitude (noise_amplitude.h) of a mesh that reads noisy: its finer bands from this
  // estimate's snapshots (band_pairs must be its first bands), the coarser ones after them.
  bool amplitude = true;
  // Also on a mesh that reads clean (studies only: noise correlated over four rings and more
  // reads clean by the pair's test; bench/studies/noise_truth.py --amplitude-always).
  bool amplitude_when_clean = false;
  NoiseAmplitudeParams amplitude_bands;
  // A mesh the pair's test reads clean reads noisy when its trimmed amplitude
  // (NoiseAmplitude::trimmed_amplitude) reaches `amplitude_noisy` and at least
  // `amplitude_noisy_share` of its amplitude: heavy noise correlated over four rings and more,
  // which one pair barely changes. Noise's band displacements are Gaussian, so both readings agree
  // on it; a CAD part's creases read far less trimmed (clean anchor ×16 faces 0.26 of 0.56,
  // turbine 0.00 of 0.57). Fine relief reads like noise: the clean ChineseDragon (10k vertices)
  // 0.42 of 0.44, the highest of the 95 pair-clean meshes read (the next, anchor, 0.26): 0.5; noise
  // correlated over four rings reads from about 0.2 at level 0.2 (docs/studies/noise-estimate.md).
  // 0: the pair's test alone (the amplitude is then read on noisy meshes only).
  double amplitude_noisy = 0.5;
  double amplitude_noisy_share = 0.7;
  // ... on meshes whose dihedral spread reaches this: such noise tilts the normals (the cases it
  // reads noisy: 16.7° and more), and smooth clean meshes skip the amplitude's time (a clean
  // 2.2M-vertex Bunny: 0.8 s of 5.7 s).
  double amplitude_noisy_min_spread_deg = 8.0;
};

struct NoiseEstimate {
  bool noisy = false;
  double level = 0;              // white-equivalent noise std along the normals, mean edge lengths
  std::vector<double> spectrum;  // the same per band of `band_pairs` (level = spectrum[0])
  // The largest of the spectrum's levels: noise correlated over several rings has more of its
  // amplitude in the coarser bands than its finest-band level says (white noise: about `level`).
  double correlated_level = 0;
  double spread_deg = 0;         // median dihedral spread of the input (dihedral_spread.h)
  double smoothed_spread_deg = 0; // the same after one Taubin pair
  double decay = 1;              // smoothed_spread_deg / spread_deg (1 when the spread is 0)
  double mean_edge_length = 0;
  long counted_vertices = 0;     // interior, manifold vertices the medians ran over
  // The finest band's root mean square over its median's normal std (median / 0.6745): 1 for
  // Gaussian noise, above it for heavy-tailed noise (heavyTailFactor).
  double tail = 1;
  // The share of the mesh's faces the spread's medians counted: 1, or the windows' cores on a
  // large mesh (noise_windows.h).
  double sampled_share = 1;
  // The noise's amplitude along the normals in the bands up to 128 pairs (noise_amplitude.h),
  // white and correlated, in the clean mesh's edge lengths; the drivers fill it in on noisy meshes.
  double amplitude = 0;
  int correlation_steps = 0;   // the correlated part's steps (0: white only)
  double correlated_share = 0; // the correlated part's share of the amplitude's energy
  // The amplitude on trimmed band energies (noise_amplitude.h), read where the pair's test says
  // clean (NoiseEstimateParams::amplitude_noisy); 0 elsewhere.
  double trimmed_amplitude = 0;
  bool noisy_by_amplitude = false; // noisy by NoiseEstimateParams::amplitude_noisy, not the pair
};

namespace detail {

inline double medianOf(std::vector<double> &values) {
  if (values.empty()) return 0.0;
  return kthSmallest(values, values.size() / 2);
}

// Median dihedral spread of `points` (a FaceRings built once, shared by the calls) over the
// faces `counted` marks (null: all).
inline double spreadOf(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                       const FaceRings &face_rings,
                       const std::vector<std::uint8_t> *counted = nullptr) {
  std::vector<Vec3> normals;
  computeFaceNormals(points, faces, normals);
  return medianDihedralSpreadDeg(points, faces, normals, face_rings, counted);
}

// The frame every length of the estimate is in: positions from the lowest corner of the faces'
// vertices, in mean edge lengths (the probe's hash reads positions in it).
struct NoiseFrame {
  Vec3 lowest = Vec3::Zero();
  double edge = 0;
};

inline NoiseFrame noiseFrame(const std::vector<Vec3> &points, const Rings &rings, double edge) {
  NoiseFrame frame;
  frame.edge = edge;
  Vec3 lowest = Vec3::Constant(INFINITY);
  for (int v = 0; v < rings.vertex_count; ++v)
    if (rings.ring1Size(v) > 0) lowest = lowest.cwiseMin(points[v]);
  frame.lowest = lowest;
  return frame;
}

// The mesh's positions in `frame` (from its lowest corner, in mean edge lengths); vertices
// without faces at the origin.
inline std::vector<Vec3> inNoiseFrame(const std::vector<Vec3> &points, const Rings &rings,
                                      const NoiseFrame &frame) {
  std::vector<Vec3> out(points.size());
  for (int v = 0; v < int(points.size()); ++v)
    out[v] = rings.ring1Size(v) > 0 ? Vec3((points[v] - frame.lowest) / frame.edge) : Vec3::Zero();
  return out;
}

// The estimate's white-noise probe: a hashed Gaussian of unit std per component, constant on cells
// of 1/16 edge of the frame's positions (so it follows the position, not the vertex's index).
inline std::vector<Vec3f> hashedProbe(const std::vector<Vec3> &framed) {
  const int n = int(framed.size());
  std::vector<Vec3f> probe(n);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v)
    probe[v] = positionHashedGaussian(Vec3((framed[v] * 16.0).array().floor()), 0x4e6f697365ull)
                   .cast<float>();
  return probe;
}

// The vertices the medians can count: interior, not frozen, with faces, and marked by
// `counted_vertices` when given (the mesh's own medians also leave out the rare vertex whose
// normal or displacement is not usable, which is read only after its last snapshot).
inline std::vector<std::uint8_t> probedVertices(const Rings &rings, const VertexRoles &roles,
                                                const std::vector<std::uint8_t> *counted_vertices) {
  const int n = rings.vertex_count;
  std::vector<std::uint8_t> interior(n);
  for (int v = 0; v < n; ++v)
    interior[v] = !roles.frozen[v] && !rings.boundary[v] && rings.ring1Size(v) > 0 &&
                  (!counted_vertices || (*counted_vertices)[v]);
  return interior;
}

// The probe's median band value |before − after| per component over the `interior` vertices.
inline double probeBandMedian(const std::vector<Vec3f> &before, const std::vector<Vec3f> &after,
                              const std::vector<std::uint8_t> &interior) {
  const int n = int(interior.size());
  std::vector<double> noise(3 * size_t(n), NAN);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v) {
    if (!interior[v]) continue;
    for (int k = 0; k < 3; ++k)
      noise[3 * size_t(v) + k] = std::abs(double(before[v][k]) - double(after[v][k]));
  }
  eraseNaN(noise);
  return medianOf(noise);
}

// The clean/noisy decision from the spread before (out.spread_deg) and after one Taubin pair.
inline void decideNoisy(double smoothed_spread_deg, const NoiseEstimateParams &params,
                        NoiseEstimate &out) {
  out.smoothed_spread_deg = smoothed_spread_deg;
  // A spread of a few hundredths of a degree is a flat mesh: its ratio says nothing.
  out.decay = out.spread_deg > 0.01 ? out.smoothed_spread_deg / out.spread_deg : 1.0;
  out.noisy = out.spread_deg >= params.noisy_spread_deg ||
              (out.decay <= params.max_decay &&
               out.spread_deg - out.smoothed_spread_deg >= params.min_drop_deg);
}

// The spectrum: per band b, the median |displacement| along the last snapshot's normals between
// snapshots b and b + 1 (`snapshot[0]` the framed mesh itself) over the probe's median band
// value; also the finest band's tail and the level. Frees each snapshot after its last read.
inline void spectrumAlongNormals(std::vector<std::vector<Vec3>> &snapshot,
                                 const std::vector<Face> &faces, const Rings &rings,
                                 const std::vector<std::uint8_t> &interior,
                                 const std::vector<double> &probe_median, NoiseEstimate &out,
                                 std::vector<Vec3> &normals, std::vector<double> *energies = nullptr,
                                 std::vector<double> *trimmed = nullptr, double quantile = 1.0) {
  const int n = rings.vertex_count, bands = int(snapshot.size()) - 1;
  computeVertexNormals(snapshot[bands], faces, rings, normals);
  std::vector<std::uint8_t> counted(n);
  for (int v = 0; v < n; ++v) counted[v] = interior[v] && normals[v].squaredNorm() != 0;
  std::vector<double> along; // a non-finite displacement is left out
  out.spectrum.assign(bands, 0.0);
  for (int b = 0; b < bands; ++b) {
    const std::vector<Vec3> &current = snapshot[b], &next = snapshot[b + 1];
    along.assign(n, NAN);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
    for (int v = 0; v < n; ++v) {
      if (!counted[v]) continue;
      const double d = (current[v] - next[v]).dot(normals[v]);
      if (std::isfinite(d)) along[v] = std::abs(d);
    }
    eraseNaN(along);
    if (energies) { // the amplitude's mean square along the normals (noise_amplitude.h)
      double sum = 0;
      for (double a : along) sum += a * a;
      energies->push_back(along.empty() ? 0.0 : sum / double(along.size()));
    }
    if (trimmed) { // and its trimmed energy
      std::vector<double> squares(along.size());
      for (size_t i = 0; i < along.size(); ++i) squares[i] = along[i] * along[i];
      trimmed->push_back(trimmedEnergy(squares, quantile));
    }
    double squares = 0; // in vertex order, before the median reorders the values
    if (b == 0)
      for (double a : along) squares += a * a;
    if (b == 0) out.counted_vertices = long(along.size());
    const double along_median = medianOf(along);
    if (b == 0 && along_median > 0)
      out.tail = std::sqrt(squares / double(along.size())) / (along_median / 0.6745);
    out.spectrum[b] = probe_median[b] > 0 ? along_median / probe_median[b] : 0.0;
    if (b > 0) std::vector<Vec3>().swap(snapshot[b]); // read for the last time
  }
  out.level = out.spectrum[0];
  out.correlated_level = *std::max_element(out.spectrum.begin(), out.spectrum.end());
}

// The amplitude (noise_amplitude.h) from the finer bands' energies and the coarser ones after
// `last` (the snapshot `bands` pairs in) up to band `read_bands` (amplitudeBandCount), over the
// same vertices and normals as the spectrum; with `trimmed` (the finer bands' trimmed energies),
// its trimmed reading likewise.
inline void readAmplitude(const std::vector<Vec3> &last, int bands, int read_bands,
                          const SpatialTaubin &taubin,
                          const std::vector<Vec3> &normals, const std::vector<std::uint8_t> &interior,
                          const NoiseEstimateParams &params, std::vector<double> energies,
                          std::vector<double> *trimmed, NoiseEstimate &out) {
  std::vector<std::uint8_t> counted(interior.size());
  for (size_t v = 0; v < counted.size(); ++v)
    counted[v] = interior[v] && normals[v].squaredNorm() != 0;
  const std::vector<double> coarse =
      coarseBandEnergies(last, bands, taubin, normals, counted, params.amplitude_bands,
                         read_bands, trimmed);
  energies.insert(energies.end(), coarse.begin(), coarse.end());
  NoiseAmplitude a = fitNoiseAmplitude(energies, params.amplitude_bands);
  if (trimmed) a = withTrimmedAmplitude(a, *trimmed, params.amplitude_bands);
  out.amplitude = a.amplitude;
  out.correlation_steps = a.correlation_steps;
  out.correlated_share = a.correlated_share;
  out.trimmed_amplitude = a.trimmed_amplitude;
}

// Whether the amplitude may make a mesh the pair's test reads clean noisy
// (NoiseEstimateParams::amplitude_noisy, amplitude_noisy_min_spread_deg).
inline bool amplitudeMayDecide(const NoiseEstimateParams &params, const NoiseEstimate &out) {
  return params.amplitude_noisy > 0 && out.spread_deg >= params.amplitude_noisy_min_spread_deg;
}

// The amplitude's part of the decision (NoiseEstimateParams::amplitude_noisy) on an estimate whose
// amplitude was read; then a mesh that still reads clean keeps no amplitude unless
// `amplitude_when_clean` asks for it.
inline void decideNoisyByAmplitude(const NoiseEstimateParams &params, NoiseEstimate &out) {
  if (!out.noisy && amplitudeMayDecide(params, out) &&
      out.trimmed_amplitude >= params.amplitude_noisy &&
      out.trimmed_amplitude >= params.amplitude_noisy_share * out.amplitude) {
    out.noisy = true;
    out.noisy_by_amplitude = true;
  }
  if (!out.noisy && !params.amplitude_when_clean) {
    out.amplitude = out.trimmed_amplitude = out.correlated_share = 0;
    out.correlation_steps = 0;
  }
}

// The estimate of the file comment in `frame`, its medians over the vertices and faces that
// `counted_vertices` / `counted_faces` mark (null: all): a part of a larger mesh (noise_windows.h)
// reads, on the elements it counts, the larger mesh's values when its margins are wide enough.
inline NoiseEstimate measureNoise(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                                  const Rings &rings, const FaceRings &face_rings,
                                  const detail::VertexRoles &roles, const NoiseFrame &frame,
                                  const std::vector<std::uint8_t> *counted_vertices,
                                  const std::vector<std::uint8_t> *counted_faces,
                                  const NoiseEstimateParams &params) {
  NoiseEstimate out;
  const int n = int(points.size());
  if (n == 0 || faces.empty()) return out;
  // The input's spread on its own coordinates (angles do not scale): the drivers reuse it
  // (driver_setup.h), so it is measured before anything can stop the estimate.
  out.spread_deg = spreadOf(points, faces, face_rings, counted_faces);
  out.mean_edge_length = frame.edge;
  if (!(frame.edge > 0) || !std::isfinite(frame.edge)) return out;
  const int bands = int(params.band_pairs.size()) - 1;
  // The first band is the decision's pair (the level is what that pair takes out).
  const bool spectrum = bands >= 1 && params.band_pairs[0] == 0 && params.band_pairs[1] == 1;

  // One Taubin run for the mesh and its white-noise probe, as band_shrink.h does: one sweep over
  // the rings per step for both, the mesh in double (the same bits as taubinSmooth), the probe in
  // single precision (only the medians of its band values are read: half its memory traffic).
  // The drivers' meshes are in spatial order already. Each snapshot continues the one before
  // (the decision's pair the first) and is kept until the last one's normals are known.
  std::vector<std::vector<Vec3>> snapshot(spectrum ? bands + 1 : 2);
  snapshot[0] = inNoiseFrame(points, rings, frame);
  const SpatialTaubin taubin(snapshot[0], rings, roles.frozen, roles.boundary_neighbours,
                             /*given_order=*/true);
  std::vector<Vec3f> probe = spectrum ? hashedProbe(snapshot[0]) : std::vector<Vec3f>();
  const std::vector<std::uint8_t> interior = probedVertices(rings, roles, counted_vertices);
  std::vector<double> probe_median(std::max(bands, 0), 0.0);
  std::vector<Vec3f> probe_before;
  for (int b = 0; b < (spectrum ? bands : 1); ++b) {
    const int pairs = spectrum ? params.band_pairs[b + 1] - params.band_pairs[b] : 1;
    snapshot[b + 1] = snapshot[b];
    if (spectrum) {
      probe_before = probe;
      taubin.smooth({&snapshot[b + 1]}, {&probe}, pairs, params.lambda, params.mu);
      probe_median[b] = probeBandMedian(probe_before, probe, interior);
    } else {
      taubin.smooth({&snapshot[b + 1]}, pairs, params.lambda, params.mu);
    }
    if (b == 0) decideNoisy(spreadOf(snapshot[1], faces, face_rings, counted_faces), params, out);
  }
  if (!spectrum) return out;
  std::vector<Vec3f>().swap(probe);
  std::vector<Vec3f>().swap(probe_before);
  std::vector<Vec3> normals;
  std::vector<double> energies;
  const int read_bands = amplitudeBandCount(rings.vertex_count, params.amplitude_bands);
  const bool amplitude = params.amplitude &&
                         (out.noisy || params.amplitude_when_clean ||
                          amplitudeMayDecide(params, out)) &&
                         read_bands > bands &&
                         params.amplitude_bands.band_pairs.size() > params.band_pairs.size() &&
                         std::equal(params.band_pairs.begin(), params.band_pairs.end(),
                                    params.amplitude_bands.band_pairs.begin());
  // The trimmed reading only decides (decideNoisyByAmplitude): read where the pair's test says
  // clean, or for a study (amplitude_when_clean); never with the amplitude's decision off.
  std::vector<double> trimmed_energies;
  std::vector<double> *trimmed =
      amplitude && params.amplitude_noisy > 0 && (!out.noisy || params.amplitude_when_clean)
          ? &trimmed_energies
          : nullptr;
  spectrumAlongNormals(snapshot, faces, rings, interior, probe_median, out, normals,
                       amplitude ? &energies : nullptr, trimmed,
                       params.amplitude_bands.trimmed_quantile);
  if (amplitude) {
    readAmplitude(snapshot[bands], bands, read_bands, taubin, normals, interior, params, energies,
                  trimmed, out);
    decideNoisyByAmplitude(params, out);
  }
  return out;
}

} // namespace detail

// Measures `points` / `faces` with their topology (the drivers' DriverSetup has it): see the file
// comment. Empty or degenerate input: clean, level 0.
inline NoiseEstimate estimateNoise(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                                   const Rings &rings, const FaceRings &face_rings,
                                   const detail::VertexRoles &roles,
                                   const NoiseEstimateParams &params = {}) {
  return detail::measureNoise(points, faces, rings, face_rings, roles,
                              detail::noiseFrame(points, rings,
                                                 edgeStatistics(points, rings).mean_edge_length),
                              nullptr, nullptr, params);
}

// The same, building the topology itself.
inline NoiseEstimate estimateNoise(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                                   const NoiseEstimateParams &params = {}) {
  const int n = int(points.size());
  if (n == 0 || faces.empty()) return {};
  for (const Face &f : faces)
    for (int k = 0; k < 3; ++k)
      if (f[k] < 0 || f[k] >= n) return {};
  const Rings rings = computeRings(n, faces);
  MeshArrays mesh;
  mesh.points = points;
  mesh.faces = faces;
  const detail::VertexRoles roles =
      detail::vertexRoles(mesh, rings, edgeStatistics(points, rings).mean_edge_length);
  return estimateNoise(points, faces, rings, computeFaceRings(faces, rings), roles, params);
}

} // namespace vcg_ext

namespace vcg_ext {

// How much more than the median-based level heavy-tailed noise needs (heavyTailFactor). Power 1
// replaces the median-based std by the rms-based one; neither it nor the ramp was fitted, the
// held-out sets chose between their neighbours (docs/studies/noise-estimate.md).
struct HeavyTailParams {
  double power = 1.0;      // the factor is tail^power (0: off)
  double max_factor = 2.0;
  // It ramps in from level_from to level_full mean edge lengths: below about 0.08 the finest band
  // of a clean curved mesh reads that much (band_shrink.h's noise_for_any_alpha), and shape
  // detail, which gathers in a few places, makes that band heavy-tailed by itself.
  double level_from = 0.08, level_full = 0.12;
};

// The factor on the amount of smoothing for noise whose finest band is heavy-tailed: its root
// mean square over its median-based std (NoiseEstimate::tail), raised to `power`, where the level
// is high enough for the band to be noise. Scanner noise is a mixture: its std grows with depth
// and incidence, a few outliers; the median reads its quiet majority and the Wiener gains then keep
// the rest (docs/studies/scanner-noise.md). Gaussian noise reads a tail of about 1 on an
// evenly triangulated mesh; triangles of very different sizes make it a mixture in edge units
// too (up to about 1.3 on CAD meshes).
inline double heavyTailFactor(const NoiseEstimate &noise, const HeavyTailParams &params = {}) {
  if (!(params.power > 0) || !(noise.tail > 1) || !std::isfinite(noise.tail)) return 1.0;
  const double ramp = rampBetween(noise.level, params.level_from, params.level_full);
  const double full = std::min(std::pow(noise.tail, params.power), params.max_factor);
  return 1.0 + ramp * (full - 1.0);
}

// How much more smoothing heavy noise asks for than the measured need of 1 gives
// (heavyNoiseFactor).
struct HeavyNoiseParams {
  double from = 0.35;    // amplitude (mean edge lengths) up to which the need of 1 suffices
  double power = 3.0;    // beyond it the factor is (amplitude / from)^power
  double max_factor = 4.0;
  // The feature mode's need reads the amplitude times this beside the finest bands' level
  // (amplitudeNeed; 0: not).
  double need_weight = 1.0;
  // It does so in full once the amplitude is need_ratio_full times the finest bands' level, not
  // below need_ratio_from times it (linear between). White noise reads 1.0-1.7, a red spectrum
  // 2.5-3.9 (heavy set), so this keeps the need for noise beyond the finest band. Light noise on a
  // CAD part reads about 2 by the part's own shape (Fandisk under white noise of 0.05: amplitude
  // 0.14, level 0.07), as does a subdivided Bunny under 2-view scanner noise of 0.2 (1.73): there
  // the amplitude's extra passes raised theta and took 15 % more time
  // (docs/studies/scanner-noise.md).
  double need_ratio_from = 1.8, need_ratio_full = 2.4;
};

// The need (0-1, as measuredRoughness's level term: saturating at a tenth of an edge length) that
// the amplitude asks for on a mesh that reads noisy: noise whose energy lies in coarser bands
// (a depth camera's redder spectrum) leaves the finest band at 0.04-0.07 while its amplitude is
// 0.14 and more, so the finest band alone asked for half the passes (heavy set, red cases; white
// noise reads about the same in both). 0 where the amplitude was not read.
inline double amplitudeNeed(const NoiseEstimate &noise, const HeavyNoiseParams &params = {}) {
  if (!noise.noisy || !(params.need_weight > 0) || !(noise.amplitude > 0) ||
      !std::isfinite(noise.amplitude))
    return 0.0;
  // (a level of 0, not read: the need as without the ramp)
  const double ratio = noise.level > 0 ? noise.amplitude / noise.level : INFINITY;
  const double ramp = rampBetween(ratio, params.need_ratio_from, params.need_ratio_full);
  return ramp * std::min(1.0, params.need_weight * noise.amplitude / 0.1);
}

// The factor on the amount of smoothing for noise heavier than the public benchmark's: the need
// (measuredRoughness) saturates at 1 from a tenth of an edge length, while noise of half an edge
// length and more, the level of a raw depth scan, asks the feature mode for several times its
// passes and the organic mode for several times its strength (docs/studies/noise-estimate.md).
// 1 where the amplitude was not read.
inline double heavyNoiseFactor(const NoiseEstimate &noise, const HeavyNoiseParams &params = {}) {
  if (!(params.from > 0) || !(noise.amplitude > params.from) || !std::isfinite(noise.amplitude))
    return 1.0;
  return std::min(std::pow(noise.amplitude / params.from, params.power),
                  std::max(1.0, params.max_factor));
}

// Noise correlated over several rings asks the feature mode for more passes than white noise of
// the same amplitude: a normal filter iteration averages neighbouring normals, which removes white
// noise at once but a correlated bump only as the averaging spreads over its width (heavy set and
// scanner set: CAD parts under correlated noise gain from more passes, white noise of the same
// amplitude loses; docs/studies/scanner-noise.md). The factor grows from 1 to 1 + extra as the
// amplitude's correlated share goes from share_from to share_full (white noise reads 0-0.26 on the
// public meshes and heavy white noise, correlated noise 0.5-0.8). It ramps in over amplitudes of
// 0.1-0.15 mean edge lengths, past where the need saturates (amplitudeNeed): lighter noise is
// removed by the measured passes, and a subdivided 139k-vertex Bunny under light scanner noise
// (amplitude 0.097) would pay 12 % more time for nothing (docs/studies/scanner-noise.md).
struct CorrelatedNoiseParams {
  double extra = 0.5; // 0: off
  double share_from = 0.3, share_full = 0.55;
  double amplitude_from = 0.1, amplitude_full = 0.15; // both 0: no amplitude ramp
  // The share's fit splits the amplitude between white and correlated templates and can give a
  // red spectrum's energy to white noise (cylinder red_0.6: share 0.28); an amplitude far beyond
  // the finest band's level says the same thing directly, so the larger of the two ramps counts:
  // the share's, and the amplitude over the level from ratio_from to ratio_full (both 0, or a
  // level of 0, not read: the share's only). It starts where amplitudeNeed's ramp is full: white
  // noise with impulses reads up to about 2 (docs/studies/scanner-noise.md).
  double ratio_from = 2.4, ratio_full = 3.2;
};

// How far a noise is into the correlated range (CorrelatedNoiseParams' ramps, 0 to 1): 0
// where the amplitude was not read or the mesh reads clean. The feature mode reads it twice
// (correlatedNoiseFactor; its planar extra's ramp, feature_smooth.h).
inline double correlatedNoiseRamp(const NoiseEstimate &noise,
                                  const CorrelatedNoiseParams &params = {}) {
  if (!noise.noisy || !(noise.amplitude > 0) || !std::isfinite(noise.correlated_share)) return 0.0;
  double correlated = rampBetween(noise.correlated_share, params.share_from, params.share_full);
  if (params.ratio_full > 0 && noise.level > 0)
    correlated = std::max(correlated, rampBetween(noise.amplitude / noise.level,
                                                  params.ratio_from, params.ratio_full));
  return correlated * rampBetween(noise.amplitude, params.amplitude_from, params.amplitude_full);
}

// The factor on the feature mode's need for correlated noise (CorrelatedNoiseParams): 1 where the
// amplitude was not read or the mesh reads clean.
inline double correlatedNoiseFactor(const NoiseEstimate &noise,
                                    const CorrelatedNoiseParams &params = {}) {
  if (!(params.extra > 0)) return 1.0;
  return 1.0 + params.extra * correlatedNoiseRamp(noise, params);
}

// How a noise's colour is extrapolated beyond the estimate's bands (noiseColour). Off by default
// (OrganicSmoothParams::coloured_noise): the shape's own spectrum rises as much as a correlated
// noise's, so every gate that helped scanner noise hurt white or light noise
// (docs/studies/noise-estimate.md).
struct NoiseColourParams {
  double max_octave_rise = 1.35; // the largest amplitude rise per octave of pairs extrapolated
  double max_rise = 4.0;         // the largest amplitude over the finest band's
  double weight = 1.0;           // 0: white (every band 1); 1: as measured and extrapolated
  // The weight ramps from 0 to `weight` as the level rises from level_white to level_coloured
  // (mean edge lengths): at low levels the rise of the fine bands is mostly the shape's. Equal
  // ends (the defaults): no ramp.
  double level_white = 0.0, level_coloured = 0.0;
  // And from 0 to 1 as the rise of the spectrum (its last band over its first) goes from
  // rise_white to rise_coloured: white noise measures a rise of about 1. Equal ends: no ramp.
  double rise_white = 0.0, rise_coloured = 0.0;
};

// The noise's colour per band of `band_pairs` (edges in Taubin pairs, as BandShrinkParams's):
// its energy over that of white noise with the same finest-band level, from the estimate's
// white-equivalent spectrum (noise correlated over several rings puts more of its energy into the
// coarser bands than white noise does). Bands the estimate measured take its ratios; coarser ones
// continue the rise of its last octave, at most `max_octave_rise` per octave, at most the whole
// measured rise, and at most `max_rise` in all. The shape's own spectrum rises too, so this
// over-reads the colour of meshes with much fine detail (coarse meshes): the weight and caps
// bound it.
inline std::vector<double> noiseColour(const NoiseEstimate &noise, const std::vector<int> &band_pairs,
                                       const NoiseColourParams &params = {}) {
  const int bands = int(band_pairs.size()) - 1;
  std::vector<double> colour(std::max(0, bands), 1.0);
  const std::vector<double> &s = noise.spectrum;
  double weight = params.weight;
  if (params.level_coloured > params.level_white)
    weight *= std::clamp((noise.level - params.level_white) /
                             (params.level_coloured - params.level_white), 0.0, 1.0);
  if (s.size() < 2 || !(s[0] > 0) || weight <= 0) return colour;
  if (params.rise_coloured > params.rise_white)
    weight *= std::clamp((s.back() / s[0] - params.rise_white) /
                             (params.rise_coloured - params.rise_white), 0.0, 1.0);
  // The last octave's rise, at most the whole spectrum's (a wobble of a flat one is not a rise).
  const double octave = std::clamp(s.back() / s[s.size() - 2], 1.0,
                                   std::max(1.0, std::min(params.max_octave_rise, s.back() / s[0])));
  for (int b = 0; b < bands; ++b) {
    double rise;
    if (b < int(s.size())) rise = s[b] / s[0];
    else rise = s.back() / s[0] * std::pow(octave, b - int(s.size()) + 1);
    rise = std::clamp(rise, 1.0, params.max_rise);
    colour[b] = std::pow(rise, 2.0 * weight);
  }
  return colour;
}

} // namespace vcg_ext
