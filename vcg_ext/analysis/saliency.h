// Stage 3: multi-scale mesh saliency (Lee, Varshney, Jacobs 2005, as modified by the paper's 2.2).
//
// Inputs: positions, Rings (for the 1-ring local maxima), a per-vertex scalar map (the driver
// passes k2, the paper's "negative minima of principal curvatures") and ε, an absolute length
// (the paper: 0.3% of the bounding-box diagonal). Output: per-vertex saliency in [0, 1].
//
// G(C, v, σ) = Σ C(x) exp(−|x−v|²/2σ²) / Σ exp(−|x−v|²/2σ²) over the vertices x with |x−v| < 2σ
// (Euclidean); S_i = |G(σ_i) − G(2σ_i)| for σ_i ∈ {2, 3, 4, 5, 6}·ε. Each S_i is divided by its
// maximum M_i, multiplied by (M_i − m̄_i)² with m̄_i the mean of its other local maxima, and the
// sum over the scales is divided by its maximum. Dividing by the maximum (rather than min-max
// rescaling) keeps 0 meaning "not salient", which the ratio α = Sal_min/Sal_max of stage 4 relies
// on.
//
// Neighbours come from a uniform grid on flat arrays rather than vcglib's GridStaticPtr or KdTree:
// those index mesh objects in the mesh's scalar type and fill a result container per query, while
// this stage runs one query per vertex on up to millions of vertices.
#pragma once

#include "vcg_ext/core/rings.h"
#include "vcg_ext/analysis/saliency_lattice.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace vcg_ext {

namespace detail {

// The eight distinct σ/ε the five scales need: σ_i ∈ {2..6}, 2σ_i ∈ {4, 6, 8, 10, 12}.
constexpr int kSaliencySigmaCount = 8;
constexpr int kSaliencySigmas[kSaliencySigmaCount] = {2, 3, 4, 5, 6, 8, 10, 12};
constexpr int kSaliencyScales = 5;
constexpr int kScaleFine[kSaliencyScales] = {0, 1, 2, 3, 4};   // index of σ_i in kSaliencySigmas
constexpr int kScaleCoarse[kSaliencyScales] = {2, 4, 5, 6, 7}; // index of 2σ_i

struct GridPoint {
  double x, y, z, value;
};

// Vertices bucketed into cubic cells, cells in x-fastest order and the vertices of a cell
// contiguous, so a row of cells along x is one contiguous range.
struct UniformPointGrid {
  Vec3 origin = Vec3::Zero();
  double cell = 1;
  int nx = 1, ny = 1, nz = 1;
  std::vector<int> cell_start; // points of cell c: sorted[cell_start[c] .. cell_start[c+1])
  std::vector<GridPoint> sorted;
  std::vector<int> sorted_vertex; // the vertex index of each sorted point

  int clampedCell(double coordinate, double lo, int count) const {
    const int c = int(std::floor((coordinate - lo) / cell));
    return std::min(std::max(c, 0), count - 1);
  }

  void build(const std::vector<Vec3> &points, const std::vector<double> &values,
             const std::vector<int> &active, double cell_size) {
    Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
    for (int v : active) {
      lo = lo.cwiseMin(points[v]);
      hi = hi.cwiseMax(points[v]);
    }
    origin = lo;
    cell = cell_size;
    // Keep the cell array within a few entries per point, whatever ε the user chose.
    const double max_cells = 4.0 * double(active.size()) + 4096;
    const Vec3 extent = hi - lo;
    if (!(cell > 0)) cell = std::max(extent.maxCoeff(), 1.0);
    for (;;) {
      const Vec3 counts = (extent / cell).array().floor() + 1.0;
      if (counts.prod() <= max_cells) {
        nx = int(counts.x()), ny = int(counts.y()), nz = int(counts.z());
        break;
      }
      cell *= 1.25;
    }
    const int cell_count = nx * ny * nz;
    // Inside a cell, points follow a Morton order of 8×8×8 sub-cells: neighbours in memory are
    // neighbours in space, so the σ cut-off tests in the sweep branch predictably. Ties keep
    // vertex order.
    auto sub_cell = [&](double coordinate, double lo_c, int c) {
      const int s = int((coordinate - lo_c - c * cell) * (8 / cell));
      return unsigned(std::min(std::max(s, 0), 7));
    };
    auto spread = [](unsigned b) { return (b & 1u) | ((b & 2u) << 2) | ((b & 4u) << 4); };
    std::vector<std::pair<std::uint64_t, int>> keyed(active.size());
    for (size_t a = 0; a < active.size(); ++a) {
      const Vec3 &p = points[active[a]];
      const int cx = clampedCell(p.x(), lo.x(), nx), cy = clampedCell(p.y(), lo.y(), ny),
                cz = clampedCell(p.z(), lo.z(), nz);
      const unsigned morton = spread(sub_cell(p.x(), lo.x(), cx)) |
                              (spread(sub_cell(p.y(), lo.y(), cy)) << 1) |
                              (spread(sub_cell(p.z(), lo.z(), cz)) << 2);
      const std::uint64_t cell_id = (std::uint64_t(cz) * ny + cy) * nx + cx;
      keyed[a] = {cell_id * 512 + morton, active[a]};
    }
    detail::parallelSort(keyed); // (key, vertex) pairs are distinct: the same order
    cell_start.assign(cell_count + 1, 0);
    sorted.resize(active.size());
    sorted_vertex.resize(active.size());
    for (size_t a = 0; a < keyed.size(); ++a) {
      const int v = keyed[a].second;
      ++cell_start[keyed[a].first / 512 + 1];
      sorted_vertex[a] = v;
      sorted[a] = {points[v].x(), points[v].y(), points[v].z(), values[v]};
    }
    for (int c = 0; c < cell_count; ++c) cell_start[c + 1] += cell_start[c];
  }
};

// Distance from x to the interval [lo, hi], squared.
inline double squaredGap(double x, double lo, double hi) {
  const double g = x < lo ? lo - x : x > hi ? x - hi : 0.0;
  return g * g;
}

// For each σ index s, the index of 2σ_s in kSaliencySigmas (−1: not one of them). exp(−t/(2k)²)⁴ =
// exp(−t/k²): a σ whose double is also summed costs no exp of its own.
constexpr int kSaliencyDoubleSigma[kSaliencySigmaCount] = {2, 4, 5, 6, 7, -1, -1, -1};

// exp(x) for x in [−2, 0], the only range the Gaussian weights take inside their cut-off (d < 2σ:
// −d²/2σ² > −2): exp(x/16)^16, exp(x/16) by its Taylor series to degree 9 (remainder below 3e-16
// of it), then four squarings. Relative error about 1e-14 (tests/unit/test_saliency.cpp checks the
// means against std::exp to 1e-10), and plain arithmetic, so a loop of them vectorises where
// calls to the library's exp (most of the sweep's time) do not.
inline double gaussianWeightExp(double x) {
  const double y = x * (1.0 / 16.0);
  double e = 1.0 / 362880.0;
  e = e * y + 1.0 / 40320.0;
  e = e * y + 1.0 / 5040.0;
  e = e * y + 1.0 / 720.0;
  e = e * y + 1.0 / 120.0;
  e = e * y + 1.0 / 24.0;
  e = e * y + 1.0 / 6.0;
  e = e * y + 0.5;
  e = e * y + 1.0;
  e = e * y + 1.0;
  e *= e, e *= e, e *= e, e *= e;
  return e;
}

// The Gaussian sums of one query at the `count` smallest σ (kSaliencySigmas[0 .. count)).
// Points come in buffered chunks (squared distance, value); every σ's weights and sums then run
// over the chunk in loops the compiler vectorises.
struct GaussianSums {
  static constexpr int kChunk = 128;
  int count;
  double numerator[kSaliencySigmaCount] = {}, denominator[kSaliencySigmaCount] = {};
  double cutoff2[kSaliencySigmaCount], exponent[kSaliencySigmaCount]; // (2σ)², −1/2σ²
  double weight[kSaliencySigmaCount][kChunk];

  GaussianSums(double epsilon, int sigma_count) : count(sigma_count) {
    for (int s = 0; s < count; ++s) {
      const double sigma = kSaliencySigmas[s] * epsilon;
      cutoff2[s] = 4.0 * sigma * sigma;
      exponent[s] = -0.5 / (sigma * sigma);
    }
  }

  // Adds `buffered` points to every σ's sums, from the largest σ down: a σ whose double is also
  // summed takes that weight to the fourth power (exp(−t/(2k)²)⁴ = exp(−t/k²)) instead of an exp.
  void add(const double *d2_in, const double *value_in, int buffered) {
    for (int s = count - 1; s >= 0; --s) {
      const double cut = cutoff2[s], a = exponent[s];
      const int twice = kSaliencyDoubleSigma[s];
      double *w = weight[s];
      if (twice >= 0 && twice < count) {
        const double *w2 = weight[twice];
#pragma omp simd
        for (int i = 0; i < buffered; ++i) {
          const double square = w2[i] * w2[i];
          w[i] = double(d2_in[i] < cut) * (square * square); // (no branch: vectorises)
        }
      } else {
#pragma omp simd
        for (int i = 0; i < buffered; ++i)
          w[i] = double(d2_in[i] < cut) * gaussianWeightExp(a * d2_in[i]);
      }
      double num = 0, den = 0;
#pragma omp simd reduction(+ : num, den)
      for (int i = 0; i < buffered; ++i) {
        num += w[i] * value_in[i];
        den += w[i];
      }
      numerator[s] += num;
      denominator[s] += den;
    }
  }

  // The vertex itself is always inside every cut-off, so no denominator is zero.
  void means(double *out) const {
    for (int s = 0; s < count; ++s)
      out[s] = denominator[s] > 0 ? numerator[s] / denominator[s] : 0.0;
  }
};

// Calls visit(first, end) for each row of grid cells along x that the ball of `radius` around p
// reaches, with the points of the row's cells the ball reaches (one contiguous range), in grid
// order: sums over them do not depend on the thread count.
template <class Visit>
inline void forEachRowInBall(const UniformPointGrid &grid, const Vec3 &p, double radius,
                             Visit &&visit) {
  const double radius2 = radius * radius;
  const int z0 = grid.clampedCell(p.z() - radius, grid.origin.z(), grid.nz);
  const int z1 = grid.clampedCell(p.z() + radius, grid.origin.z(), grid.nz);
  const int y0 = grid.clampedCell(p.y() - radius, grid.origin.y(), grid.ny);
  const int y1 = grid.clampedCell(p.y() + radius, grid.origin.y(), grid.ny);
  for (int iz = z0; iz <= z1; ++iz) {
    const double z_lo = grid.origin.z() + iz * grid.cell;
    const double gap_z = squaredGap(p.z(), z_lo, z_lo + grid.cell);
    if (gap_z >= radius2) continue;
    for (int iy = y0; iy <= y1; ++iy) {
      const double y_lo = grid.origin.y() + iy * grid.cell;
      const double gap_yz = gap_z + squaredGap(p.y(), y_lo, y_lo + grid.cell);
      if (gap_yz >= radius2) continue;
      const double reach_x = std::sqrt(radius2 - gap_yz);
      const int x0 = grid.clampedCell(p.x() - reach_x, grid.origin.x(), grid.nx);
      const int x1 = grid.clampedCell(p.x() + reach_x, grid.origin.x(), grid.nx);
      const int row = (iz * grid.ny + iy) * grid.nx;
      visit(grid.sorted.data() + grid.cell_start[row + x0],
            grid.sorted.data() + grid.cell_start[row + x1 + 1]);
    }
  }
}

// Gaussian-weighted means of the map around p at the `count` smallest σ (kSaliencySigmas[0 ..
// count)) in one sweep over the grid: the points within the largest cut-off are gathered into a
// buffer, summed (GaussianSums) when it is full and at the end.
inline void gaussianMeansSmallestSigmas(const UniformPointGrid &grid, const Vec3 &p, double epsilon,
                                        int count, double *means) {
  GaussianSums sums(epsilon, count);
  const double radius = 2 * kSaliencySigmas[count - 1] * epsilon;
  const double radius2 = radius * radius;
  double d2_in[GaussianSums::kChunk], value_in[GaussianSums::kChunk];
  int k = 0; // points in the buffer
  forEachRowInBall(grid, p, radius, [&](const GridPoint *q, const GridPoint *end) {
    // Without a branch per point: k advances only past those within the cut-off.
    for (; q != end; ++q) {
      const double dx = q->x - p.x(), dy = q->y - p.y(), dz = q->z - p.z();
      const double d2 = dx * dx + dy * dy + dz * dz;
      d2_in[k] = d2;
      value_in[k] = q->value;
      k += d2 < radius2;
      if (k == GaussianSums::kChunk) sums.add(d2_in, value_in, k), k = 0;
    }
  });
  sums.add(d2_in, value_in, k);
  sums.means(means);
}

// Gaussian-weighted means of the map around p at all eight σ in one sweep.
inline void gaussianMeansAllSigmas(const UniformPointGrid &grid, const Vec3 &p, double epsilon,
                                   double means[kSaliencySigmaCount]) {
  gaussianMeansSmallestSigmas(grid, p, epsilon, kSaliencySigmaCount, means);
}

// Non-linear suppression of one scale's S (paper 2.2 after Lee et al.): divided by its maximum and
// multiplied by (1 − mean of its other 1-ring local maxima)², then added to `saliency`. A scale
// with one dominant peak keeps its weight, a scale with many comparable peaks is damped. The peaks
// are found in parallel and summed in vertex order on one thread (the same bits for any thread
// count).
inline void addSuppressedScale(const Rings &rings, const std::vector<int> &active,
                               std::vector<double> &s, double half_spread,
                               std::vector<double> &saliency) {
  const int n = rings.vertex_count, m = int(active.size());
  const double maximum = *std::max_element(s.begin(), s.end());
  if (!(maximum > 1e-12 * half_spread)) return; // rounding only: this scale sees nothing
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v) s[v] /= maximum;
  // Near-ties count as maxima on both sides (so the result does not hinge on rounding); a plateau
  // at zero is not a peak.
  const double tie = 1e-12;
  std::vector<std::uint8_t> peak(m, 0);
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
  for (int a = 0; a < m; ++a) {
    const int v = active[a];
    if (!(s[v] > tie)) continue;
    bool is_peak = true;
    for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v) && is_peak; ++w)
      is_peak = s[v] >= s[*w] - tie;
    peak[a] = is_peak;
  }
  double peak_sum = 0;
  long peak_count = 0;
  for (int a = 0; a < m; ++a)
    if (peak[a]) peak_sum += s[active[a]], ++peak_count;
  // The global maximum (1 after normalising) is always one of the peaks: leave it out.
  const double other_peaks_mean = peak_count > 1 ? (peak_sum - 1.0) / double(peak_count - 1) : 0.0;
  const double weight = (1.0 - other_peaks_mean) * (1.0 - other_peaks_mean);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v) saliency[v] += weight * s[v];
}

} // namespace detail

// How computeSaliency evaluates the Gaussian means.
struct SaliencyOptions {
  // A σ whose 2σ ball is expected to hold more vertices than this (estimated from the mean edge
  // length) takes its means from the lattice (saliency_lattice.h); the smaller σ are summed exactly
  // in one grid sweep. INFINITY: all exact (the reference).
  double lattice_above_vertices = 100;
  int cells_per_radius = 2; // exact sweep: grid cell edge = its largest cut-off radius / this
  detail::LatticeOptions lattice;
};

namespace detail {

// The vertices with faces (isolated ones carry no curvature: they neither contribute nor get a
// saliency).
inline std::vector<int> verticesWithFaces(const Rings &rings) {
  std::vector<int> active;
  active.reserve(rings.vertex_count);
  for (int v = 0; v < rings.vertex_count; ++v)
    if (!rings.isolated[v]) active.push_back(v);
  return active;
}

// The map minus its mid-range on `active` (0 elsewhere) into `centred`; returns its half spread
// (0 or not finite: nothing to see). S is unchanged, but the rounding of the means and their
// differences is then relative to the map's spread instead of its offset, and a constant map
// gives S = 0.
inline double centredMap(const std::vector<double> &map, const std::vector<int> &active,
                         std::vector<double> &centred) {
  double lowest = INFINITY, highest = -INFINITY;
  for (int v : active) {
    lowest = std::min(lowest, map[v]);
    highest = std::max(highest, map[v]);
  }
  const double middle = 0.5 * (lowest + highest), half_spread = 0.5 * (highest - lowest);
  centred.assign(map.size(), 0.0);
  if (!(half_spread > 0) || !std::isfinite(half_spread)) return half_spread;
  for (int v : active) centred[v] = map[v] - middle;
  return half_spread;
}

// How many of the σ (smallest first) are summed exactly: those whose 2σ ball is expected to hold
// at most options.lattice_above_vertices vertices, a vertex of a regular triangulation owning
// (√3/2)·edge² of surface (the mean edge over `active`).
inline int exactSigmaCount(const std::vector<Vec3> &points, const Rings &rings,
                           const std::vector<int> &active, double epsilon,
                           const SaliencyOptions &options) {
  if (!std::isfinite(options.lattice_above_vertices)) return kSaliencySigmaCount;
  double edge_sum = 0;
  long edge_count = 0;
  for (int v : active)
    for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w)
      if (*w > v) edge_sum += (points[*w] - points[v]).norm(), ++edge_count;
  const double edge = edge_count ? edge_sum / edge_count : 0.0;
  const double area_per_vertex = 0.5 * std::sqrt(3.0) * edge * edge;
  int exact_count = 0;
  while (exact_count < kSaliencySigmaCount) {
    const double radius = 2 * kSaliencySigmas[exact_count] * epsilon;
    if (!(M_PI * radius * radius <= options.lattice_above_vertices * area_per_vertex)) break;
    ++exact_count;
  }
  return exact_count;
}

// G at the first `exact_count` σ, summed exactly in one sweep of a grid of the active points:
// means[s][v] (the others untouched).
inline void exactGaussianMeans(const std::vector<Vec3> &points, const std::vector<int> &active,
                               const std::vector<double> &centred, double epsilon, int exact_count,
                               const SaliencyOptions &options,
                               std::vector<std::vector<double>> &means) {
  const int n = int(points.size());
  UniformPointGrid grid;
  const double radius = 2 * kSaliencySigmas[exact_count - 1] * epsilon;
  grid.build(points, centred, active, radius / std::max(options.cells_per_radius, 1));
  for (int s = 0; s < exact_count; ++s) means[s].assign(n, 0.0);
  // Queries in grid order, so consecutive queries share their neighbours in cache.
#pragma omp parallel for schedule(dynamic, 256) if (parallelHeavy(n))
  for (int a = 0; a < int(active.size()); ++a) {
    const int v = grid.sorted_vertex[a];
    double m[kSaliencySigmaCount];
    gaussianMeansSmallestSigmas(grid, points[v], epsilon, exact_count, m);
    for (int s = 0; s < exact_count; ++s) means[s][v] = m[s];
  }
}

// The saliency from the means at all σ: per scale |G(σ_fine) − G(σ_coarse)|, suppressed and summed
// (addSuppressedScale; each fine mean freed after its scale), divided by its maximum.
inline void sumSuppressedScales(const Rings &rings, const std::vector<int> &active,
                                std::vector<std::vector<double>> &means, double half_spread,
                                std::vector<double> &saliency) {
  const int n = rings.vertex_count;
  std::vector<double> scale_saliency(n, 0.0);
  for (int i = 0; i < kSaliencyScales; ++i) {
    const std::vector<double> &fine = means[kScaleFine[i]], &coarse = means[kScaleCoarse[i]];
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
    for (int a = 0; a < int(active.size()); ++a)
      scale_saliency[active[a]] = std::abs(fine[active[a]] - coarse[active[a]]);
    addSuppressedScale(rings, active, scale_saliency, half_spread, saliency);
    std::vector<double>().swap(means[kScaleFine[i]]); // not needed again
  }
  const double maximum = *std::max_element(saliency.begin(), saliency.end());
  if (maximum > 0) {
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
    for (int v = 0; v < n; ++v) saliency[v] /= maximum;
  }
}

inline void computeSaliencyImpl(const std::vector<Vec3> &points, const Rings &rings,
                                const std::vector<double> &curvature_map, double epsilon,
                                std::vector<double> &saliency, const SaliencyOptions &options) {
  const int n = rings.vertex_count;
  saliency.assign(n, 0.0);
  if (n == 0 || !(epsilon > 0) || !std::isfinite(epsilon)) return;
  const std::vector<int> active = verticesWithFaces(rings);
  if (active.empty()) return;
  std::vector<double> centred;
  const double half_spread = centredMap(curvature_map, active, centred);
  if (!(half_spread > 0) || !std::isfinite(half_spread)) return;

  // means[s][v]: G at σ_s, exactly where the 2σ balls hold few vertices, else on the lattice.
  const int exact_count = exactSigmaCount(points, rings, active, epsilon, options);
  std::vector<std::vector<double>> means(kSaliencySigmaCount);
  if (exact_count > 0)
    exactGaussianMeans(points, active, centred, epsilon, exact_count, options, means);
  if (exact_count < kSaliencySigmaCount) {
    std::vector<double> sigmas;
    for (int s = exact_count; s < kSaliencySigmaCount; ++s)
      sigmas.push_back(kSaliencySigmas[s] * epsilon);
    std::vector<std::vector<double>> lattice_means(sigmas.size());
    latticeGaussianMeans(points, active, centred, sigmas, options.lattice, lattice_means);
    for (int s = exact_count; s < kSaliencySigmaCount; ++s)
      means[s].swap(lattice_means[s - exact_count]);
  }
  sumSuppressedScales(rings, active, means, half_spread, saliency);
}

// computeSaliency, all σ exact, with the grid's cell edge as a fraction of the largest cut-off
// radius (24ε).
inline void computeSaliencyWithCells(const std::vector<Vec3> &points, const Rings &rings,
                                     const std::vector<double> &curvature_map, double epsilon,
                                     std::vector<double> &saliency, int cells_per_radius) {
  SaliencyOptions options;
  options.lattice_above_vertices = INFINITY;
  options.cells_per_radius = cells_per_radius;
  computeSaliencyImpl(points, rings, curvature_map, epsilon, saliency, options);
}


} // namespace detail

// Lee et al. 2005 multi-scale saliency (as modified by the paper) of `curvature_map` (the driver
// passes k2); σ_i = {2, 3, 4, 5, 6}·ε with ε an absolute length; output in [0, 1]. The σ whose 2σ
// ball holds few vertices are summed exactly on a grid of cells 2σ/2 (other cell sizes are no
// faster); the others on the lattice (see SaliencyOptions and docs/studies/performance.md for
// its error).
inline void computeSaliency(const std::vector<Vec3> &points, const Rings &rings,
                            const std::vector<double> &curvature_map, double epsilon,
                            std::vector<double> &saliency, const SaliencyOptions &options = {}) {
  detail::computeSaliencyImpl(points, rings, curvature_map, epsilon, saliency, options);
}

} // namespace vcg_ext
