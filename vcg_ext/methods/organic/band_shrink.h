// Organic mode, stage A: Wiener shrinkage of the frequency bands of Taubin's scale space.
//
// Inputs: positions, triangles, Rings, the vertices that may not move, the boundary curve
// neighbours (as for taubinSmooth). Output: smoothed positions and a report (noise estimate, the
// gain of every band). Papers: Taubin 1995 (λ|μ smoothing as a low-pass filter); Wiener shrinkage
// per band as in wavelet denoising (Donoho & Johnstone 1994, with a spectral over-subtraction
// factor α as in Berouti et al. 1979; per vertex on the middle bands as in Mihçak, Kozintsev,
// Ramchandran & Moulin 1999).
//
// Why: with noise in random 3-D directions on organic meshes, Taubin at its best step count beats
// every range-kernel filter we measured, and that best count differs per mesh
// (docs/studies/organic-mode.md). The differences between Taubin results at 0, 1, 2, 4, … 128
// pairs split the mesh into frequency bands; each band is kept in proportion to how much of its
// energy is shape rather than noise. The noise energy of a band is known: the same Taubin steps
// applied to a random field with the noise's variance (a probe). The noise variance is the robust
// spread of the normal component of the 1-ring Laplacian. So the amount of smoothing follows from
// the mesh, not from a step count chosen per case. The middle bands (4-64 pairs) take their gain
// per vertex, from the band's energy around it (locally adaptive Wiener shrinkage,
// BandShrinkParams::local_window_steps): shape gathers in places, noise does not.
//
// θ (face normals) wants more smoothing than the position error does when the mesh is smooth at
// the scale of its edges: α, the over-subtraction, follows the slope of the shape's own spectrum,
// the shape energy of the 64–128 pair band over that of the 8–16 pair band. Unlike a band's
// shape-to-noise ratio, the slope hardly moves with the noise level. Where the fine band still
// holds much shape (a coarse mesh), α stays nearer 1, and so it does at light noise. Where even the
// coarse band holds little shape beyond the noise (a sphere, a cylinder, smooth CAD parts) the
// slope is a ratio of two noisy near-zeros and the mesh is smooth at every band's scale: α takes
// its largest value. The rule's constants were fitted on 81 noisy cases of 18 meshes
// (docs/studies/organic-mode.md, python3 bench/studies/alpha_choice.py).

// The probe's values come from a hash of each vertex's position in the mesh's own frame (bounding
// box corner, mean edge length), and every sum runs in vertex order on one thread, so the result
// depends neither on the vertex order or the thread count nor on the mesh's scale or placement.
#pragma once

#include "vcg_ext/analysis/curvature.h"
#include "vcg_ext/core/position_hash.h"
#include "vcg_ext/core/ramp.h"
#include "vcg_ext/core/selection.h"
#include "vcg_ext/core/trimmed_mean.h"
#include "vcg_ext/smoothing/taubin.h"
#include "vcg_ext/smoothing/spatial_taubin.h"
#include "vcg_ext/smoothing/taubin_chebyshev.h"

#include <cstring>
#include <functional>

namespace vcg_ext {

struct BandShrinkParams {
  // The mesh is in spatial order already (the drivers' meshes: spatial_order.h): the Taubin runs
  // keep its numbering instead of sorting it along a Morton curve again (the same bits either way).
  bool given_order = false;
  // Band edges in Taubin pairs; the last one is the coarse base, kept whole.
  std::vector<int> band_pairs = {0, 1, 2, 4, 8, 16, 32, 64, 128};
  // Taubin's λ|μ. A pair multiplies the frequencies just below its pass band by up to
  // 1 + (λ+μ)²/(4|λμ|): 1.00085 for MeshLab's 0.5 / −0.53, which compounds to ×1.24 over 256
  // pairs (the dino's spikes and legs grew, and faces flipped); 1.0001 for −0.51, ×1.013 over 128
  // pairs (docs/studies/organic-mode.md).
  double lambda = 0.5, mu = -0.51;
  int normal_pairs = 8;           // the band energies are taken along the normals of this snapshot
  // α = 1 + rise · gate · level, within [1, max_alpha]. rise: the larger of
  // alpha_per_slope · (slope − slope_at_alpha_one) and (max_alpha − 1) · smooth, where slope is
  // the shape energy of band `slope_coarse_band` over band `slope_fine_band` and smooth goes from
  // 1 to 0 as that coarse band's shape/noise ratio rises from coarse_snr_smooth to
  // coarse_snr_detailed. gate: 1 at a fine-band shape/noise ratio up to gate_snr_full, 0 from
  // gate_snr_none (linear in between). level: 0 up to a noise estimate of noise_for_any_alpha mean
  // edge lengths, 1 from noise_for_full_alpha, linear in between. Closer to the best α of a grid
  // than any fixed α or a threshold on the fine band alone (docs/studies/organic-mode.md).
  int fine_band = 3;              // band whose shape/noise ratio gates α (4–8 pairs)
  int slope_fine_band = 4, slope_coarse_band = 7; // 8–16 and 64–128 pairs
  double slope_at_alpha_one = 4.0, alpha_per_slope = 0.4, max_alpha = 2.5;
  double gate_snr_full = 0.20, gate_snr_none = 0.35;
  double coarse_snr_smooth = 2.0, coarse_snr_detailed = 4.0;
  double noise_for_full_alpha = 0.25;
  // The floor: the estimate reads 0.05-0.1 mean edge lengths on clean curved meshes too
  // (curvature, see estimateNormalNoiseSigma), so at light noise it is no evidence for
  // over-subtraction; without it, θ on light noise is above Taubin ×10's on more organic meshes
  // (docs/studies/organic-mode.md).
  double noise_for_any_alpha = 0.08;
  double fixed_alpha = 0; // > 0: this α instead (to measure the choice: alpha_choice.py)
  // The patch update's step (organic_smooth.h) grows with α: 0 at α = 1, whole at this α.
  double alpha_whole_patch_step = 3.0;
  double noise_scale = 1.0;       // multiplies the noise estimate (0: nothing is removed)
  // The estimate projects each vertex's umbrella residual on a normal taken from a copy smoothed
  // by this many Taubin pairs: under noise of half an edge length and more the noisy normals tilt
  // with the noise and the projection reads too little of it (bandNoiseSigma). 0: the noisy
  // normals.
  int sigma_normal_pairs = 2;
  // The noise's colour: per band, its energy over a white noise's of the same fine-band level
  // (empty or missing bands: 1, white). Multiplies the probe's band energies.
  std::vector<double> noise_colour;
  // Per band (finest first): the share of its Wiener shrinkage the band takes (missing: 1, all of
  // it; the local bands, whose gains are per vertex, always take all). The organic mode's bands
  // beyond 128 pairs, there only when the user asks for more than the measured amount, take theirs
  // in as the strength grows (organic_smooth.h).
  std::vector<double> shrink_share;
  // The finest bands (up to robust_max_pairs) compare the mesh's and the probe's energies as the
  // means of the values below robust_quantile, not of all: spikes (scan outliers, stray vertices
  // at holes) are noise, yet in plain energies they read as shape and keep the band (the real
  // angel scan, docs/studies/real-scans.md). Gaussian noise reads the same either way. 1: plain
  // energies. Up to 4 pairs (the 2-4 pair band too): scanner noise is heavy-tailed there as well,
  // and the plain band kept it; up to 8 pairs removes shape on light noise
  // (docs/studies/organic-mode.md, docs/studies/scanner-noise.md).
  double robust_quantile = 0.5;
  int robust_max_pairs = 4;
  // The least noise level removed, in mean edge lengths: 0 trusts the estimate; the organic mode
  // raises it when the user asks for more than the estimate (a mesh measured as clean reads ~0).
  double min_noise_edges = 0;
  // > 0: the noise level along the normals (a length) measured by the caller, instead of measuring
  // it on the points given (the organic mode measures it before it untangles folds).
  double given_noise_sigma = 0;
  // Boundary vertices follow their boundary curve for at most this many pairs, then stay: a curve
  // smoothed for hundreds of pairs drifts off the surface, while the faces along a noisy boundary
  // need the smoothing; 32 balances the two (docs/studies/organic-mode.md).
  int boundary_pairs = 32;
  // Bands of many pairs as a Chebyshev series (taubin_chebyshev.h) instead of pair by pair,
  // truncated where the left-out coefficients sum to at most this, their sum at p = 1 moved to
  // c_0 (exact on the shape's smooth part). At 1e-4 the bands of 8-128 pairs take 57 operator
  // applications instead of their 240 steps; vertices stay within 4e-3 mean edge lengths of the
  // pair-by-pair result, θ within 0.002° (docs/studies/performance.md).
  bool chebyshev = true;
  double chebyshev_tolerance = 1e-4;
  // Probes for the fine band (the first is the whole-run probe; the others run only up to the
  // band's upper edge, a few pairs): α hangs on that band's ratio, whose spread shrinks with the
  // number of probe values (with one probe a small mesh's α moved with the rounding of its
  // coordinates). So the count follows the mesh size: enough probes for
  // `fine_band_probe_vertices` probe vertices, at most `max_fine_band_probes`, which keeps their
  // cost below a fifth of the band shrinkage's on small meshes.
  double fine_band_probe_vertices = 250000;
  int max_fine_band_probes = 9;
  // Local gains (Mihçak, Kozintsev, Ramchandran & Moulin 1999, locally adaptive Wiener shrinkage
  // of wavelet coefficients): on bands local_first_band..local_last_band (at most four) each
  // vertex's gain compares the noise energy with the band's energy near the vertex, its squared
  // normal component averaged over the vertex and its 1-ring local_window_steps times, instead
  // of with the band's mean: shape that gathers in some places (a face, a crease) is kept there
  // and the noise elsewhere goes (docs/studies/organic-mode.md). local_window_steps 0: one gain
  // per band.
  int local_window_steps = 16;
  int local_first_band = 3, local_last_band = 6; // 4-8 to 32-64 pairs
};

struct BandShrinkReport {
  double noise_sigma = 0;    // estimated std of the noise along the normals (length units)
  double fine_snr = 0;       // shape-to-noise energy ratio of the fine band
  double shape_slope = 0;    // coarse over fine band shape energy (at most 1e6: no fine shape)
  double coarse_snr = 0;     // shape-to-noise energy ratio of the slope's coarse band
  double noise_edges = 0;    // noise_sigma in mean edge lengths
  double alpha = 0;
  int fine_band_probes = 0;  // probes that measured the fine band's noise
  double detail = 0;         // 0 (smooth at the edge scale) .. 1 (detailed: α = 1, no patch step)
  std::vector<double> gains; // per band, finest first (local bands: the mean of the vertices')
  int local_from_pairs = 0, local_to_pairs = 0; // the local bands' span in Taubin pairs (0: none)
  bool cancelled = false;
};

// The over-subtraction factor α from the shape's spectrum: its slope (coarse over fine band shape
// energy), the coarse and fine bands' shape-to-noise ratios and the noise level in mean edge
// lengths (BandShrinkParams).
inline double alphaFromSpectrum(double shape_slope, double coarse_snr, double fine_snr,
                                double noise_edges, const BandShrinkParams &params) {
  const double gate = std::clamp((params.gate_snr_none - fine_snr) /
                                     (params.gate_snr_none - params.gate_snr_full),
                                 0.0, 1.0);
  const double level =
      rampBetween(noise_edges, params.noise_for_any_alpha, params.noise_for_full_alpha);
  const double smooth = std::clamp((params.coarse_snr_detailed - coarse_snr) /
                                      (params.coarse_snr_detailed - params.coarse_snr_smooth),
                                  0.0, 1.0);
  const double rise =
      std::max(params.alpha_per_slope * std::max(shape_slope - params.slope_at_alpha_one, 0.0),
               (params.max_alpha - 1.0) * smooth);
  const double alpha = 1.0 + rise * gate * level;
  return std::isfinite(alpha) ? std::clamp(alpha, 1.0, std::max(1.0, params.max_alpha)) : 1.0;
}

// The noise's standard deviation along the normals: median |(1-ring centre − p)·n| over the
// interior movable vertices, as a normal std (/0.6745), corrected for the centre's own noise
// (variance σ²/d). Curvature adds to it (a clean coarse mesh reads about 0.1 mean edge lengths),
// which is why the callers gate on a separate clean/noisy test.
inline double estimateNormalNoiseSigma(const std::vector<Vec3> &points, const Rings &rings,
                                       const std::vector<std::uint8_t> &fixed,
                                       const std::vector<Vec3> &normals) {
  std::vector<double> residual;
  double inflation = 0;
  for (int v = 0; v < rings.vertex_count; ++v) {
    const int d = rings.ring1Size(v);
    if (fixed[v] || rings.boundary[v] || d == 0 || normals[v].squaredNorm() == 0) continue;
    Vec3 centre = Vec3::Zero();
    for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w) centre += points[*w];
    const double r = std::abs((centre / d - points[v]).dot(normals[v]));
    if (!std::isfinite(r)) continue;
    residual.push_back(r);
    inflation += 1.0 + 1.0 / d;
  }
  if (residual.empty()) return 0.0;
  inflation /= double(residual.size());
  return detail::kthSmallest(residual, residual.size() / 2) / 0.6745 / std::sqrt(inflation);
}

namespace detail {
// The noise's colour of band b (1: white; BandShrinkParams::noise_colour).
inline double bandColour(const BandShrinkParams &params, int b) {
  return b < int(params.noise_colour.size()) ? params.noise_colour[b] : 1.0;
}
// Wiener shrinkage: the share of `energy` beyond `noise` (1 where there is no energy).
inline double wienerGain(double noise, double energy) {
  return energy > 0 ? std::clamp(1.0 - noise / energy, 0.0, 1.0) : 1.0;
}
// Band b's gain when it takes only its shrink share of the shrinkage (BandShrinkParams::
// shrink_share); a band with all of it keeps the gain's bits.
inline double sharedGain(const BandShrinkParams &params, int b, double gain) {
  const double share = b < int(params.shrink_share.size()) ? params.shrink_share[b] : 1.0;
  return share >= 1.0 ? gain : 1.0 - std::max(share, 0.0) * (1.0 - gain);
}

// The local bands' gains per vertex (local order; other bands empty), and their means into
// `gains` (BandShrinkParams::local_window_steps). The (at most four) bands' energies diffuse in
// one field, one sweep of the rings per step. `noise_energy` holds each band's probe energy
// summed over the `count` counted vertices (per component).
inline std::vector<std::vector<float>>
localBandGains(const SpatialTaubin &taubin, const Rings &rings,
               const std::vector<std::vector<Eigen::Vector3f>> &band,
               const std::vector<Vec3> &normals, const std::vector<std::uint8_t> &counted,
               const std::vector<double> &noise_energy, long count, double alpha,
               const BandShrinkParams &params, std::vector<double> &gains) {
  using Vec4f = Eigen::Vector4f;
  const int bands = int(band.size()), n = int(normals.size());
  std::vector<std::vector<float>> local(bands);
  const int first = std::max(0, params.local_first_band),
            last = std::min({bands - 1, params.local_last_band, first + 3});
  if (params.local_window_steps <= 0 || first > last || count == 0) return local;
  std::vector<Vec4f> energy(n, Vec4f::Zero()), next(n);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v) {
    const int l = taubin.local(v);
    for (int b = first; b <= last; ++b) {
      const double along = band[b][l].cast<double>().dot(normals[v]);
      energy[v][b - first] = float(along * along);
    }
  }
  // The mean over each vertex and its 1-ring, boundary vertices included (their whole ring: a
  // boundary curve alone would keep its drift's energy and hold the noise near holes).
  for (int step = 0; step < params.local_window_steps; ++step) {
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
    for (int v = 0; v < n; ++v) {
      Vec4f sum = energy[v];
      for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w) sum += energy[*w];
      next[v] = sum / float(1 + rings.ring1Size(v));
    }
    energy.swap(next);
  }
  for (int b = first; b <= last; ++b) {
    const double noise = alpha * bandColour(params, b) * noise_energy[b] / double(count);
    local[b].resize(n);
    double sum = 0;
    for (int v = 0; v < n; ++v) {
      const float gain = float(wienerGain(noise, energy[v][b - first]));
      local[b][taubin.local(v)] = gain;
      if (counted[v]) sum += gain;
    }
    gains[b] = sum / double(count);
  }
  return local;
}
} // namespace detail

namespace detail {

// The noise's std along the normals that the gains are measured against: given or estimated
// (estimateNormalNoiseSigma), scaled by noise_scale, at least min_noise_edges mean edge lengths.
// Estimated against the normals of a copy smoothed by sigma_normal_pairs Taubin pairs, not the
// noisy `normals`: under white noise of 0.6-1.0 edge lengths along the normals the noisy normals
// tilt with the noise and the estimate read 0.36 where 0.6 was added (the lion head), the bands
// then kept a third of the noise as shape (θ 24.7° where 9.0° with the smoothed normals;
// docs/studies/organic-mode.md).
inline double bandNoiseSigma(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                             const Rings &rings, const std::vector<std::uint8_t> &fixed,
                             const std::vector<std::array<int, 2>> &curve,
                             const std::vector<Vec3> &normals, const BandShrinkParams &params) {
  double measured = params.given_noise_sigma;
  if (!(measured > 0)) {
    if (params.sigma_normal_pairs > 0) {
      std::vector<Vec3> smoothed = points, smoothed_normals;
      taubinSmooth(smoothed, rings, fixed, curve, params.sigma_normal_pairs);
      computeVertexNormals(smoothed, faces, rings, smoothed_normals);
      measured = estimateNormalNoiseSigma(points, rings, fixed, smoothed_normals);
    } else {
      measured = estimateNormalNoiseSigma(points, rings, fixed, normals);
    }
  }
  double sigma = params.noise_scale * measured;
  if (params.min_noise_edges > 0)
    sigma = std::max(sigma, params.min_noise_edges * edgeStatistics(points, rings).mean_edge_length);
  return sigma;
}

// The noise probe: Gaussian values of std `sigma` hashed from each vertex's position in the
// mesh's own frame, from the lowest corner of the faces' bounding box, in cells of 1/16 mean edge
// length (coarse enough that float rounding of a moved or scaled mesh rarely changes a cell, fine
// enough that two vertices rarely share one). Raw coordinates would give another probe, and
// another result, when the mesh is scaled or moved (or gains an isolated vertex that widens the
// box). Kept in single precision: only its band energies are read (sums of squares in double),
// and the rounding noise of its Taubin steps, ~1e-7 of its values, lies far below the energy of
// even its coarsest band; half of every step's memory traffic.
struct NoiseProbe {
  const std::vector<Vec3> &points;
  const Rings &rings;
  const SpatialTaubin &taubin;
  double sigma = 0, cell = 0;
  Vec3 lowest = Vec3::Constant(INFINITY);

  NoiseProbe(const std::vector<Vec3> &points_, const Rings &rings_, const SpatialTaubin &taubin_,
             double sigma_, double mean_edge)
      : points(points_), rings(rings_), taubin(taubin_), sigma(sigma_), cell(mean_edge / 16.0) {
    for (int v = 0; v < rings.vertex_count; ++v)
      if (rings.ring1Size(v) > 0) lowest = lowest.cwiseMin(points[v]);
  }
  Vec3 key(int v) const {
    return cell > 0 && rings.ring1Size(v) > 0 ? Vec3(((points[v] - lowest) / cell).array().floor())
                                              : Vec3::Zero();
  }
  // The probe of `stream` (independent streams for the same positions), in the taubin's order.
  void make(std::uint64_t stream, std::vector<Vec3f> &probe) const {
    const int n = rings.vertex_count;
    probe.resize(n);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
    for (int v = 0; v < n; ++v)
      probe[taubin.local(v)] = (sigma * positionHashedGaussian(key(v), stream)).cast<float>();
  }
};

// The vertices whose values the band energies sum (movable, with a ring), and each one's slot
// among them: per-vertex terms are written in parallel and summed in vertex order after, which
// gives the serial loops' bits.
struct CountedVertices {
  std::vector<std::uint8_t> counted;
  std::vector<int> slot;
  long count = 0;

  CountedVertices(const Rings &rings, const std::vector<std::uint8_t> &fixed)
      : counted(rings.vertex_count), slot(rings.vertex_count, -1) {
    for (int v = 0; v < rings.vertex_count; ++v) {
      counted[v] = !fixed[v] && rings.ring1Size(v) > 0;
      if (counted[v]) slot[v] = int(count++);
    }
  }
  double sum(const std::vector<double> &term) const {
    double total = 0;
    for (size_t v = 0; v < counted.size(); ++v)
      if (counted[v]) total += term[v];
    return total;
  }
};

// Only the finest bands are trimmed (BandShrinkParams::robust_quantile, robust_max_pairs): the
// others need no per-value copy.
inline bool trimmedBand(const BandShrinkParams &params, int b) {
  return params.robust_quantile < 1.0 && params.band_pairs[b + 1] <= params.robust_max_pairs;
}

// The mesh's scale space as its bands, band[b] = snapshot b − snapshot b+1 in single precision (a
// band is a small difference of positions: its float rounding is ~1e-7 of the band, far below
// anything the gains resolve), and the coarsest snapshot in double (12 instead of 24 bytes per
// vertex and band), in the taubin's order; with the probe's energy per band (its sum over the
// counted vertices, per component, and the trimmed mean where trimmedBand).
struct BandScaleSpace {
  std::vector<std::vector<Eigen::Vector3f>> band;
  std::vector<Vec3> coarse;
  std::vector<double> noise_energy, noise_trimmed;
};

// One band's step of the scale space: `coarse` and `probe` smoothed by `pairs` more Taubin pairs
// (as a Chebyshev series of them where that pays, taubin_chebyshev.h), their values before the
// step left in `previous` and `probe_previous`. Boundary vertices stay from `boundary_still` on.
inline void stepBand(const SpatialTaubin &taubin, const BandShrinkParams &params, int pairs,
                     bool boundary_still, std::vector<Vec3> &coarse, std::vector<Vec3> &previous,
                     std::vector<Vec3f> &probe, std::vector<Vec3f> &probe_previous) {
  const std::vector<double> series =
      params.chebyshev
          ? taubinChebyshevCoefficients(pairs, params.lambda, params.mu, params.chebyshev_tolerance)
          : std::vector<double>();
  if (params.chebyshev && chebyshevPays(series, pairs)) {
    taubin.applyChebyshev({&coarse}, {&previous}, {&probe}, {&probe_previous}, series,
                          boundary_still);
    coarse.swap(previous);
    probe.swap(probe_previous);
  } else {
    previous = coarse;
    probe_previous = probe;
    taubin.smooth({&coarse}, {&probe}, pairs, params.lambda, params.mu, boundary_still);
  }
}

// The probe's energy in band `b` (its step from `probe_previous` to `probe`) into
// space.noise_energy[b], summed over the counted vertices, and where trimmedBand its trimmed mean
// into space.noise_trimmed[b]. Three independent probes in one: the components; a band's noise
// along the normal has their mean variance. `term` (one per vertex) and `values` are work buffers.
inline void probeBandEnergy(const SpatialTaubin &taubin, const CountedVertices &cv,
                            const BandShrinkParams &params, int b,
                            const std::vector<Vec3f> &probe_previous,
                            const std::vector<Vec3f> &probe, std::vector<double> &term,
                            std::vector<double> &values, BandScaleSpace &space) {
  const int n = int(term.size());
  const bool trim = trimmedBand(params, b);
  values.resize(trim ? 3 * size_t(cv.count) : 0);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v)
    if (cv.counted[v]) {
      const int l = taubin.local(v);
      const Vec3 difference = probe_previous[l].cast<double>() - probe[l].cast<double>();
      term[v] = difference.squaredNorm() / 3.0;
      if (trim)
        for (int k = 0; k < 3; ++k)
          values[3 * size_t(cv.slot[v]) + k] = difference[k] * difference[k];
    }
  space.noise_energy[b] = cv.sum(term);
  if (trim) space.noise_trimmed[b] = trimmedMean(values, params.robust_quantile);
}

// Runs the Taubin scale space of `points` and of the probe (stream 0) together, one sweep per
// step, and the vertex normals at BandShrinkParams::normal_pairs into `normals`. False when
// `progress` cancels.
inline bool buildBandScaleSpace(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                                const Rings &rings, const SpatialTaubin &taubin,
                                const NoiseProbe &noise_probe, const CountedVertices &cv,
                                const BandShrinkParams &params, std::vector<Vec3> &normals,
                                BandScaleSpace &space,
                                const std::function<bool(double)> &progress) {
  const std::vector<int> &edges = params.band_pairs;
  const int bands = int(edges.size()) - 1, n = rings.vertex_count;
  space.band.assign(bands, {});
  space.noise_energy.assign(bands, 0.0);
  space.noise_trimmed.assign(bands, 0.0);
  space.coarse = taubin.toLocal(points);
  std::vector<Vec3> previous;
  std::vector<Vec3f> probe, probe_previous;
  noise_probe.make(0, probe);
  std::vector<double> term(n, 0.0), values;
  const auto normal_at = std::find(edges.begin(), edges.end(), params.normal_pairs) - edges.begin();
  auto take_normals = [&] {
    std::vector<Vec3> scratch;
    computeVertexNormals(taubin.inGlobalOrder(space.coarse, scratch), faces, rings, normals);
  };
  taubin.smooth({&space.coarse}, {&probe}, edges[0], params.lambda, params.mu);
  if (normal_at == 0) take_normals();
  for (int b = 0; b < bands; ++b) {
    // Boundary vertices stop following their curve from band `boundary_pairs` on.
    stepBand(taubin, params, edges[b + 1] - edges[b], edges[b] >= params.boundary_pairs,
             space.coarse, previous, probe, probe_previous);
    space.band[b].resize(n);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
    for (int l = 0; l < n; ++l) space.band[b][l] = (previous[l] - space.coarse[l]).cast<float>();
    if (normal_at == b + 1 || (b + 1 == bands && normal_at > bands)) take_normals();
    probeBandEnergy(taubin, cv, params, b, probe_previous, probe, term, values, space);
    if (progress && !progress(0.9 * (b + 1) / bands)) return false;
  }
  return true;
}

// Each band's energy along `normals` (summed over the counted vertices) and, where trimmedBand,
// its trimmed mean.
inline void bandEnergiesAlongNormals(const SpatialTaubin &taubin, const BandScaleSpace &space,
                                     const std::vector<Vec3> &normals, const CountedVertices &cv,
                                     const BandShrinkParams &params, std::vector<double> &energy,
                                     std::vector<double> &energy_trimmed) {
  const int bands = int(space.band.size()), n = int(normals.size());
  energy.assign(bands, 0.0);
  energy_trimmed.assign(bands, 0.0);
  std::vector<double> term(n, 0.0), values;
  for (int b = 0; b < bands; ++b) {
    const bool trim = trimmedBand(params, b);
    values.resize(trim ? size_t(cv.count) : 0);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
    for (int v = 0; v < n; ++v)
      if (cv.counted[v]) {
        const double along = space.band[b][taubin.local(v)].cast<double>().dot(normals[v]);
        term[v] = along * along;
        if (trim) values[cv.slot[v]] = along * along;
      }
    energy[b] = cv.sum(term);
    if (trim) energy_trimmed[b] = trimmedMean(values, params.robust_quantile);
  }
}

// The fine band's probe energy, averaged over enough probes that small meshes read it as steadily
// as large ones (BandShrinkParams::fine_band_probe_vertices): `first_probe` is the scale space's
// own (stream 0), the others run the Taubin steps up to the fine band on the probe alone.
inline double fineBandNoise(const SpatialTaubin &taubin, const NoiseProbe &noise_probe,
                            const CountedVertices &cv, const BandShrinkParams &params, int fine,
                            double first_probe, int &probes) {
  const std::vector<int> &edges = params.band_pairs;
  const double lambda = params.lambda, mu = params.mu;
  probes = std::clamp(int(std::ceil(params.fine_band_probe_vertices / cv.count)), 1,
                      std::max(1, params.max_fine_band_probes));
  double fine_noise = first_probe;
  std::vector<Vec3f> probe, probe_previous;
  for (int extra = 1; extra < probes; ++extra) {
    noise_probe.make(extra, probe);
    taubin.smooth({}, {&probe}, edges[0], lambda, mu);
    for (int b = 0; b < fine; ++b)
      taubin.smooth({}, {&probe}, edges[b + 1] - edges[b], lambda, mu,
                    edges[b] >= params.boundary_pairs);
    probe_previous = probe;
    taubin.smooth({}, {&probe}, edges[fine + 1] - edges[fine], lambda, mu,
                  edges[fine] >= params.boundary_pairs);
    for (int v = 0; v < int(cv.counted.size()); ++v)
      if (cv.counted[v]) {
        const int l = taubin.local(v);
        fine_noise += (probe_previous[l].cast<double>() - probe[l].cast<double>()).squaredNorm() / 3.0;
      }
  }
  return fine_noise / probes;
}

// The shape's spectrum from the bands' energies and noise: the fine band's shape-to-noise ratio,
// the slope (coarse over fine band shape energy), the coarse band's shape-to-noise ratio, and
// from them α (alphaFromSpectrum) and the detail weight.
inline void readSpectrum(const std::vector<double> &energy, const std::vector<double> &noise_energy,
                         int fine, double fine_noise, double mean_edge,
                         const BandShrinkParams &params, BandShrinkReport &report) {
  const int bands = int(energy.size());
  report.fine_snr = fine_noise > 0 ? std::max(energy[fine] - fine_noise, 0.0) / fine_noise : 0.0;
  // The fine band's noise is the probes' mean; every other band has the whole-run probe's.
  auto band_noise = [&](int b) { return b == fine ? fine_noise : noise_energy[b]; };
  const int slope_fine = std::clamp(params.slope_fine_band, 0, bands - 1),
            slope_coarse = std::clamp(params.slope_coarse_band, 0, bands - 1);
  const double fine_shape = std::max(energy[slope_fine] - band_noise(slope_fine), 0.0),
               coarse_shape = std::max(energy[slope_coarse] - band_noise(slope_coarse), 0.0);
  report.shape_slope = fine_shape * 1e6 > coarse_shape ? coarse_shape / fine_shape : 1e6;
  report.coarse_snr =
      band_noise(slope_coarse) > 0 ? coarse_shape / band_noise(slope_coarse) : 1e6;
  report.noise_edges = mean_edge > 0 ? report.noise_sigma / mean_edge : 0.0;
  report.alpha = params.fixed_alpha > 0
                     ? params.fixed_alpha
                     : alphaFromSpectrum(report.shape_slope, report.coarse_snr, report.fine_snr,
                                         report.noise_edges, params);
  report.detail = std::clamp((params.alpha_whole_patch_step - report.alpha) /
                                 (params.alpha_whole_patch_step - 1.0),
                             0.0, 1.0);
}

} // namespace detail

namespace detail {

// The mesh-wide gain per band: the Wiener gain that keeps the band's energy beyond α times its
// noise (the colour's share of it); robust bands count by their energies below the robust
// quantile (trimmedBand), which spikes do not reach.
inline std::vector<double> bandGains(const BandScaleSpace &space, const std::vector<double> &energy,
                                     const std::vector<double> &energy_trimmed, double alpha,
                                     const BandShrinkParams &params) {
  std::vector<double> gains(space.band.size());
  for (int b = 0; b < int(gains.size()); ++b) {
    const bool trimmed = trimmedBand(params, b);
    const double noise = trimmed ? space.noise_trimmed[b] : space.noise_energy[b];
    const double total = trimmed ? energy_trimmed[b] : energy[b];
    gains[b] = sharedGain(params, b, wienerGain(alpha * bandColour(params, b) * noise, total));
  }
  return gains;
}

// The pairs the local gains cover, for the log: from the first band with local gains to the last.
inline void noteLocalBands(const std::vector<std::vector<float>> &local,
                           const std::vector<int> &edges, BandShrinkReport &report) {
  for (int b = 0; b < int(local.size()); ++b)
    if (!local[b].empty()) {
      if (!report.local_to_pairs) report.local_from_pairs = edges[b];
      report.local_to_pairs = edges[b + 1];
    }
}

// The result into `points`: the coarse base plus every band times its gain (the vertex's local
// gain where the band has them); a vertex whose sum is not finite stays where it was.
inline void recombineBands(const SpatialTaubin &taubin, const BandScaleSpace &space,
                           const std::vector<double> &gains,
                           const std::vector<std::vector<float>> &local, std::vector<Vec3> &points) {
  const int n = int(points.size()), bands = int(space.band.size());
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v) {
    const int l = taubin.local(v);
    Vec3 p = space.coarse[l];
    for (int b = 0; b < bands; ++b)
      p += (local[b].empty() ? gains[b] : double(local[b][l])) * space.band[b][l].cast<double>();
    if (p.allFinite()) points[v] = p;
  }
}

} // namespace detail

// Smooths `points` in place (see the file comment). `progress(fraction)` may return false to
// cancel; `points` are then left as they were.
inline BandShrinkReport bandShrinkSmooth(std::vector<Vec3> &points, const std::vector<Face> &faces,
                                         const Rings &rings, const std::vector<std::uint8_t> &fixed,
                                         const std::vector<std::array<int, 2>> &curve,
                                         const BandShrinkParams &params,
                                         const std::function<bool(double)> &progress = nullptr) {
  BandShrinkReport report;
  const int n = rings.vertex_count;
  const int bands = int(params.band_pairs.size()) - 1;
  if (bands < 1 || n == 0) return report;
  std::vector<Vec3> normals;
  computeVertexNormals(points, faces, rings, normals);
  report.noise_sigma = detail::bandNoiseSigma(points, faces, rings, fixed, curve, normals, params);
  const detail::CountedVertices cv(rings, fixed);
  if (!(report.noise_sigma > 0) || cv.count == 0) {
    report.gains.assign(bands, 1.0);
    return report;
  }
  // (`points` stay as they are until the end: the probe's keys are computed where needed.)
  const double mean_edge = edgeStatistics(points, rings).mean_edge_length;
  // The scale space and the probe's, one Taubin run for both, in the renumbered order of
  // `taubin`; every sum runs in vertex order.
  const SpatialTaubin taubin(points, rings, fixed, curve, params.given_order);
  const detail::NoiseProbe noise_probe(points, rings, taubin, report.noise_sigma, mean_edge);
  detail::BandScaleSpace space;
  if (!detail::buildBandScaleSpace(points, faces, rings, taubin, noise_probe, cv, params, normals,
                                   space, progress)) {
    report.cancelled = true;
    return report;
  }
  std::vector<double> energy, energy_trimmed;
  detail::bandEnergiesAlongNormals(taubin, space, normals, cv, params, energy, energy_trimmed);
  const int fine = std::clamp(params.fine_band, 0, bands - 1);
  const double fine_noise = detail::fineBandNoise(taubin, noise_probe, cv, params, fine,
                                                  space.noise_energy[fine], report.fine_band_probes);
  detail::readSpectrum(energy, space.noise_energy, fine, fine_noise, mean_edge, params, report);
  report.gains = detail::bandGains(space, energy, energy_trimmed, report.alpha, params);
  taubin.releaseBuffers(); // no more steps: the local gains' arrays can take their memory
  const std::vector<std::vector<float>> local =
      detail::localBandGains(taubin, rings, space.band, normals, cv.counted, space.noise_energy,
                             cv.count, report.alpha, params, report.gains);
  detail::noteLocalBands(local, params.band_pairs, report);
  detail::recombineBands(taubin, space, report.gains, local, points);
  return report;
}

} // namespace vcg_ext
