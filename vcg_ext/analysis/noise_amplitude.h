// The noise's amplitude along the normals, white or correlated over several rings, from the mesh
// alone.
//
// Inputs: positions in the noise frame (noise_estimate.h's NoiseFrame: mean edge lengths), Rings,
// the vertices that may not move and those the statistics count. Output: a NoiseAmplitude: the
// noise's root mean square along the normals in mean edge lengths, the correlation it was read
// with, and the band energies it came from.
//
// How: the mesh is split into the octave bands of Taubin's scale space (0-1, 1-2, 2-4, ..., 64-128
// λ|μ pairs); each band's energy is the mean square of its displacement along the vertex normals.
// Noise correlated over s rings (white noise smoothed s times by x <- (x + mean of the 1-ring) / 2,
// the scanner model's correlation) has a known share of its energy in each band, the same on every
// mesh of near-regular valence (measured once on a regular torus: noiseTemplates); the shape adds
// energy that grows from band to band. The energies are fitted as σ² times a template plus a
// geometric shape term and a constant floor (non-negative least squares, weighted by each band's
// energy), for each s of `correlation_steps` and each growth of `shape_growth`; the best fit gives
// σ and s. Why: the finest-band level of noise_estimate.h reads white noise well but a fifth of
// noise correlated over a few rings, whose energy lies in the bands beyond 8 pairs
// (docs/studies/noise-estimate.md). The shape term keeps a mesh's coarse shape from reading as
// strongly correlated noise; what it cannot tell apart (noise correlated over ten rings or more
// at levels below the shape's own energy there) it gives to the shape, so the amplitude errs low
// there, not high.
//
// Scale, order, threads: every length is in mean edge lengths; band energies are sums over the
// counted vertices in vertex order after per-vertex terms computed in parallel, so the result does
// not depend on the thread count; Taubin's steps read each ring in its order (spatial_taubin.h).
#pragma once

#include "vcg_ext/analysis/curvature.h"
#include "vcg_ext/core/position_hash.h"
#include "vcg_ext/core/trimmed_mean.h"
#include "vcg_ext/core/vertex_roles.h"
#include "vcg_ext/smoothing/spatial_taubin.h"
#include "vcg_ext/smoothing/taubin_chebyshev.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace vcg_ext {

struct NoiseAmplitudeParams {
  double lambda = 0.5, mu = -0.53;                    // Taubin's pair, as the noise estimate's
  std::vector<int> band_pairs = {0, 1, 2, 4, 8, 16, 32, 64, 128};
  std::vector<int> correlation_steps = {1, 2, 4, 6, 10};
  std::vector<double> shape_growth = {2.5, 3.0}; // the shape term's growth per band
  double chebyshev_tolerance = 1e-3;                  // the coarse bands as series (taubin_chebyshev.h)
  int normal_pairs = 8; // the band displacements are read along the normals of this snapshot
  // A mesh reads the bands whose coarser edge has at least `vertices_per_pair` vertices per pair:
  // coarser bands (a kernel of about eleven rings at 128 pairs) reach across the whole shape,
  // whose energy there then reads as noise correlated over several rings (coarse held-out meshes
  // of 1-3k vertices read 0.7-0.9 under noise of 0.3 with every band; docs/studies/
  // noise-estimate.md). All eight bands from 8192 vertices, seven from 4096 (up to 64 pairs);
  // none below: with six bands, coarse CAD and organic meshes of 2-3k vertices read their shape
  // as noise of 0.6 (held-out rotor_small under scanner noise of 0.3).
  int vertices_per_pair = 64;
  int min_bands = 7;
  // The trimmed reading (NoiseAmplitude::trimmed_amplitude) fits band energies taken as the mean
  // of the squared displacements below this quantile over a unit Gaussian's (gaussianTrimmedSquare).
  // Noise's band displacements are Gaussian at every vertex whatever its correlation; a CAD
  // part's concentrate on its creases, which the trimming leaves out (clean turbine 0.00 of 0.57,
  // spool ×16 faces 0.16 of 0.59); fine relief spread over the surface stays (the clean
  // ChineseDragon 0.42 of 0.44; docs/studies/noise-estimate.md).
  double trimmed_quantile = 0.75;
};

// The trimmed band energy of per-vertex squared displacements (NoiseAmplitudeParams::
// trimmed_quantile): their trimmed mean over a unit Gaussian's. Reorders `squares`.
inline double trimmedEnergy(std::vector<double> &squares, double quantile) {
  return squares.empty() ? 0.0 : trimmedMean(squares, quantile) / gaussianTrimmedSquare(quantile);
}

// How many of p.band_pairs' bands a mesh of `vertices` vertices reads (NoiseAmplitudeParams::
// vertices_per_pair): 0 when fewer than p.min_bands.
inline int amplitudeBandCount(long vertices, const NoiseAmplitudeParams &p = {}) {
  int bands = 0;
  while (bands + 1 < int(p.band_pairs.size()) &&
         long(p.band_pairs[bands + 1]) * p.vertices_per_pair <= vertices)
    ++bands;
  return bands >= p.min_bands ? bands : 0;
}

struct NoiseAmplitude {
  double amplitude = 0;          // rms along the normals, mean edge lengths
  int correlation_steps = 0;     // the fitted s of the correlated part (0: white only)
  double correlated_share = 0;   // the correlated part's share of the noise's energy
  double shape_energy = 0;       // the shape term's energy in the coarsest band
  double fit_error = 0;          // rms relative error of the fit over the bands
  std::vector<double> band_energy; // per band, mean square along the normals (edge lengths²)
  // The same fit on the trimmed band energies (NoiseAmplitudeParams::trimmed_quantile): near the
  // amplitude for noise, far below it for a shape's creases and relief (withTrimmedAmplitude).
  double trimmed_amplitude = 0;
};

namespace detail {

// Band b's displacement along the normals, squared and averaged over the counted vertices: the
// terms in parallel, their sum in vertex order; with `trimmed`, also their trimmed energy
// (trimmedEnergy) appended to it. Fields in the taubin's local order.
template <class V>
double bandEnergy(const std::vector<V> &finer, const std::vector<V> &coarser,
                  const std::vector<Vec3> &normals, const std::vector<std::uint8_t> &counted,
                  const SpatialTaubin &taubin, std::vector<double> *trimmed = nullptr,
                  double quantile = 1.0) {
  const int n = int(counted.size());
  std::vector<double> term(n, 0.0);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v) {
    if (!counted[v]) continue;
    const int l = taubin.local(v);
    const double d = (finer[l] - coarser[l]).template cast<double>().dot(normals[v]);
    term[v] = std::isfinite(d) ? d * d : 0.0;
  }
  double sum = 0;
  long count = 0;
  std::vector<double> squares;
  if (trimmed) squares.reserve(size_t(n));
  for (int v = 0; v < n; ++v)
    if (counted[v]) {
      sum += term[v], ++count;
      if (trimmed) squares.push_back(term[v]);
    }
  if (trimmed) trimmed->push_back(trimmedEnergy(squares, quantile));
  return count > 0 ? sum / double(count) : 0.0;
}

// The next snapshot, `pairs` Taubin pairs smoother than `field`: as a Chebyshev series where that
// pays (taubin_chebyshev.h), else step by step.
inline void smoothBy(const SpatialTaubin &taubin, int pairs, const NoiseAmplitudeParams &p,
                     std::vector<Vec3> &field, std::vector<Vec3> &scratch) {
  const std::vector<double> series =
      taubinChebyshevCoefficients(pairs, p.lambda, p.mu, p.chebyshev_tolerance);
  if (chebyshevPays(series, pairs)) {
    taubin.applyChebyshev({&field}, {&scratch}, series);
    field.swap(scratch);
  } else {
    taubin.smooth({&field}, pairs, p.lambda, p.mu);
  }
}

} // namespace detail

// The band energies of `points` (in the noise frame, the taubin's local order) along `normals`
// (global order), over the `counted` vertices: one per band of params.band_pairs.
inline std::vector<double> bandEnergiesAlongNormals(std::vector<Vec3> field,
                                                    const SpatialTaubin &taubin,
                                                    const std::vector<Vec3> &normals,
                                                    const std::vector<std::uint8_t> &counted,
                                                    const NoiseAmplitudeParams &p,
                                                    std::vector<double> *trimmed = nullptr) {
  const int bands = int(p.band_pairs.size()) - 1;
  std::vector<double> energy(std::max(bands, 0), 0.0);
  std::vector<Vec3> previous, scratch;
  for (int b = 0; b < bands; ++b) {
    previous = field;
    detail::smoothBy(taubin, p.band_pairs[b + 1] - p.band_pairs[b], p, field, scratch);
    energy[b] = detail::bandEnergy(previous, field, normals, counted, taubin, trimmed,
                                   p.trimmed_quantile);
  }
  taubin.releaseBuffers();
  return energy;
}

// The energies of the bands from band_pairs[first] on, continuing from `snapshot` (the mesh
// smoothed by band_pairs[first] pairs, local order), in single precision: a band is a small
// difference of smooth fields, far above float rounding, and the coarse bands' series are most of
// the amplitude's time (half their memory traffic). The noise estimate calls it after its own
// bands (noise_estimate.h), whose snapshots give the finer ones.
inline std::vector<double> coarseBandEnergies(const std::vector<Vec3> &snapshot, int first,
                                              const SpatialTaubin &taubin,
                                              const std::vector<Vec3> &normals,
                                              const std::vector<std::uint8_t> &counted,
                                              const NoiseAmplitudeParams &p, int last = -1,
                                              std::vector<double> *trimmed = nullptr) {
  std::vector<double> energy;
  std::vector<Vec3f> field(snapshot.size()), previous, scratch;
  for (size_t l = 0; l < snapshot.size(); ++l) field[l] = snapshot[l].cast<float>();
  if (last < 0) last = int(p.band_pairs.size()) - 1;
  for (int b = first; b < last; ++b) {
    const int pairs = p.band_pairs[b + 1] - p.band_pairs[b];
    previous = field;
    const std::vector<double> series =
        taubinChebyshevCoefficients(pairs, p.lambda, p.mu, p.chebyshev_tolerance);
    if (chebyshevPays(series, pairs)) {
      taubin.applyChebyshev({}, {}, {&previous}, {&scratch}, series);
      field.swap(scratch);
    } else {
      taubin.smooth({}, {&field}, pairs, p.lambda, p.mu);
    }
    energy.push_back(detail::bandEnergy(previous, field, normals, counted, taubin, trimmed,
                                        p.trimmed_quantile));
  }
  taubin.releaseBuffers();
  return energy;
}

// The rings the coarse bands from band_pairs[first] on read beyond a vertex (their series'
// degrees, or two per pair where the steps run one by one): a window's margin (noise_windows.h).
inline int coarseBandReach(int first, const NoiseAmplitudeParams &p) {
  int reach = 0;
  for (int b = first; b + 1 < int(p.band_pairs.size()); ++b) {
    const int pairs = p.band_pairs[b + 1] - p.band_pairs[b];
    const std::vector<double> series =
        taubinChebyshevCoefficients(pairs, p.lambda, p.mu, p.chebyshev_tolerance);
    reach += chebyshevPays(series, pairs) ? int(series.size()) - 1 : 2 * pairs;
  }
  return reach;
}

// The share of a unit-variance noise's energy in each Taubin band of NoiseAmplitudeParams'
// default band_pairs (0-1, ..., 64-128 pairs), for noise smoothed s times by x <- (x + mean of the
// 1-ring) / 2: measured on a regular 128 x 128 torus, the mean of six probes (standard errors
// below 2 %); the same within 5-10 % on the benchmark's meshes, whatever their valences
// (tests/unit/test_noise_amplitude.cpp measures them again on a torus; docs/studies/noise-estimate.md).
// Also measured there: each template's edge decorrelation.
struct NoiseTemplate {
  int steps;
  std::array<double, 8> energy;
  // Half the mean square difference across an edge of the unit-variance noise (1 - the
  // neighbours' correlation): how much the noise lengthens the mesh's edges (cleanEdgeUnits).
  double edge_decorrelation;
};
inline const std::array<NoiseTemplate, 6> &noiseTemplates() {
  static const std::array<NoiseTemplate, 6> table = {{
      {0, {1.0779e-01, 3.6908e-02, 3.8521e-02, 2.2994e-02, 1.2889e-02, 8.0663e-03, 5.1789e-03,
           3.3838e-03}, 1.0006},
      {1, {4.6167e-02, 1.8520e-02, 2.4999e-02, 2.3393e-02, 1.9622e-02, 1.5659e-02, 1.1766e-02,
           8.5755e-03}, 0.6686},
      {2, {1.4815e-02, 7.2175e-03, 1.2708e-02, 1.7043e-02, 1.9168e-02, 1.8665e-02, 1.6131e-02,
           1.3024e-02}, 0.4244},
      {4, {1.8044e-03, 1.2375e-03, 3.1717e-03, 6.5713e-03, 1.0829e-02, 1.4305e-02, 1.5681e-02,
           1.5262e-02}, 0.2267},
      {6, {4.0307e-04, 3.2635e-04, 9.9542e-04, 2.5627e-03, 5.3259e-03, 8.7732e-03, 1.1676e-02,
           1.3436e-02}, 0.1551},
      {10, {5.0920e-05, 4.6220e-05, 1.6165e-04, 5.0923e-04, 1.3729e-03, 3.0334e-03, 5.4402e-03,
            8.4109e-03}, 0.0957},
  }};
  return table;
}

// The band that holds most of a template's energy.
inline int peakBand(const NoiseTemplate &t) {
  return int(std::max_element(t.energy.begin(), t.energy.end()) - t.energy.begin());
}

namespace detail {

// min |A c - e|² over c >= 0 for a few columns (at most 5), by trying every set of free columns
// (at most 31 least-squares solves): exact, deterministic, and small.
inline Eigen::VectorXd nonNegativeFit(const Eigen::MatrixXd &A, const Eigen::VectorXd &e,
                                      double &residual) {
  const int columns = int(A.cols());
  Eigen::VectorXd best = Eigen::VectorXd::Zero(columns);
  residual = e.squaredNorm();
  for (int mask = 1; mask < (1 << columns); ++mask) {
    std::vector<int> cols;
    for (int j = 0; j < columns; ++j)
      if (mask & (1 << j)) cols.push_back(j);
    Eigen::MatrixXd sub(A.rows(), int(cols.size()));
    for (int j = 0; j < int(cols.size()); ++j) sub.col(j) = A.col(cols[j]);
    const Eigen::VectorXd x = sub.colPivHouseholderQr().solve(e);
    if ((x.array() < 0).any() || !x.allFinite()) continue;
    const double r = (sub * x - e).squaredNorm();
    if (r < residual) {
      residual = r;
      best.setZero();
      for (int j = 0; j < int(cols.size()); ++j) best[cols[j]] = x[j];
    }
  }
  return best;
}

} // namespace detail

// An amplitude read in the noisy mesh's mean edge lengths, in those of the mesh without the noise:
// noise along the normals lengthens the edges, by 2 a² (1 - ρ) of their squared length for an
// amplitude a and a correlation ρ between neighbours (white noise of one mean edge length reads
// 0.58 of it in its own mesh's units). The levels of the benchmark's noise are in clean units.
inline double cleanEdgeUnits(double read, double edge_decorrelation) {
  const double denominator = 1.0 - 2.0 * read * read * edge_decorrelation;
  // Beyond the pole (a' >= 0.7 white) the reading cannot come from noise along the normals alone.
  return denominator > 0.25 ? read / std::sqrt(denominator) : 2.0 * read;
}

// The fit of the file comment on band energies of the default bands (all eight, or fewer on a
// small mesh: amplitudeBandCount): energy_b ≈ σ_w² π_0,b + σ_c² π_s,b +
// A g^(b - last) + F (white and correlated noise, shape, a floor), each band weighted by
// 1 / energy_b (relative errors), for the best (s, g); the amplitude is the two noises' rms in
// clean edge units. Real depth noise mixes a white part (quantisation, outliers) with its
// correlated part: one template alone took the mixture for white noise of the finest band's level.
inline NoiseAmplitude fitNoiseAmplitude(const std::vector<double> &energy,
                                        const NoiseAmplitudeParams &p = {}) {
  NoiseAmplitude out;
  out.band_energy = energy;
  const int bands = int(energy.size());
  if (bands < 5 || bands > 8) return out;
  const NoiseTemplate &white = noiseTemplates()[0];
  double best = INFINITY;
  for (const NoiseTemplate &t : noiseTemplates()) {
    if (std::find(p.correlation_steps.begin(), p.correlation_steps.end(), t.steps) ==
        p.correlation_steps.end())
      continue;
    // With fewer bands (a small mesh) a correlation whose energy peaks in the last bands read or
    // beyond them cannot be told from the shape's rise: coarse organic meshes of 3-4k vertices
    // read their shape as noise correlated over 10 rings, 0.65-0.75 under white noise of 0.3.
    if (bands < 8 && peakBand(t) > bands - 2) continue;
    for (double g : p.shape_growth) {
      Eigen::MatrixXd A(bands, 4);
      Eigen::VectorXd e(bands);
      for (int b = 0; b < bands; ++b) {
        const double w = energy[b] > 0 ? 1.0 / energy[b] : 0.0;
        A(b, 0) = w * white.energy[b];
        A(b, 1) = t.steps > 0 ? w * t.energy[b] : 0.0;
        A(b, 2) = w * std::pow(g, b - bands + 1);
        A(b, 3) = w;
        e[b] = w * energy[b];
      }
      double residual = 0;
      const Eigen::VectorXd c = detail::nonNegativeFit(A, e, residual);
      if (residual < best) {
        best = residual;
        const double total = c[0] + c[1];
        const double decorrelation =
            total > 0 ? (c[0] * white.edge_decorrelation + c[1] * t.edge_decorrelation) / total : 1;
        out.amplitude = cleanEdgeUnits(std::sqrt(total), decorrelation);
        out.correlation_steps = c[1] > 0 ? t.steps : 0;
        out.correlated_share = total > 0 ? c[1] / total : 0.0;
        out.shape_energy = c[2];
        out.fit_error = std::sqrt(residual / bands);
      }
    }
  }
  return out;
}

// `a` with its trimmed reading: the amplitude fitted on the trimmed band energies.
inline NoiseAmplitude withTrimmedAmplitude(NoiseAmplitude a, const std::vector<double> &trimmed,
                                           const NoiseAmplitudeParams &p = {}) {
  a.trimmed_amplitude = fitNoiseAmplitude(trimmed, p).amplitude;
  return a;
}

// The amplitude of `points` (the noise frame: mean edge lengths) with its topology: band energies
// along the normals of the `normal_pairs` snapshot over the movable interior vertices (and, when
// given, only those `counted` marks), then fitNoiseAmplitude. Empty input: amplitude 0.
inline NoiseAmplitude measureNoiseAmplitude(const std::vector<Vec3> &points,
                                            const std::vector<Face> &faces, const Rings &rings,
                                            const detail::VertexRoles &roles,
                                            const std::vector<std::uint8_t> *counted = nullptr,
                                            const NoiseAmplitudeParams &p = {}) {
  const int n = int(points.size());
  const int bands = amplitudeBandCount(n, p);
  if (n == 0 || faces.empty() || bands == 0) return {};
  const SpatialTaubin taubin(points, rings, roles.frozen, roles.boundary_neighbours,
                             /*given_order=*/true);
  std::vector<Vec3> snapshot = points, scratch;
  detail::smoothBy(taubin, p.normal_pairs, p, snapshot, scratch);
  std::vector<Vec3> normals;
  computeVertexNormals(snapshot, faces, rings, normals);
  std::vector<std::uint8_t> use(n, 0);
  for (int v = 0; v < n; ++v)
    use[v] = !roles.frozen[v] && !rings.boundary[v] && rings.ring1Size(v) > 0 &&
             (!counted || (*counted)[v]);
  NoiseAmplitudeParams read = p;
  read.band_pairs.resize(bands + 1);
  std::vector<double> trimmed;
  return withTrimmedAmplitude(
      fitNoiseAmplitude(bandEnergiesAlongNormals(points, taubin, normals, use, read, &trimmed), p),
      trimmed, p);
}


} // namespace vcg_ext
