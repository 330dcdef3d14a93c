// Stage 3 helper: truncated-Gaussian weighted means of a per-vertex map on large meshes.
//
// Input: positions, the vertices that take part, a per-vertex map and a list of σ. Output, per σ
// and vertex, G(v) = Σ C(x) g(x−v) / Σ g(x−v), g(d) = exp(−|d|²/2σ²) for |d| < 2σ, as in
// saliency.h, approximated by splat – convolve – slice on sparse lattices (the bilateral grid's
// scheme, Paris & Durand 2006): every vertex spreads C and 1 over the 8 corners of its lattice cell
// with trilinear weights, the node sums are convolved with the truncated Gaussian sampled at
// integer offsets (a table: no exp per pair), and every vertex reads the two sums back with the
// same trilinear weights. The exact sum costs, per vertex, the number of vertices within 2σ, which
// at a fixed relative ε grows with the vertex count; this costs about a hundred lattice nodes per
// occupied node (spacing h = σ/2, cut-off radius 4 nodes) whatever the vertex count.
//
// The σ are taken in chains σ, 2σ, 4σ (saliency's eight σ/ε = 2, 4, 8 | 3, 6, 12 | 5, 10) on nested
// lattices h, 2h, 4h: trilinear hat functions are refinable (the coarse hat is ½, 1, ½ times three
// fine hats per axis), so a chain's vertices are splatted once on its finest lattice and restricted
// to the coarser ones, and the coarse results are interpolated down exactly and sliced once.
//
// The two trilinear steps blur the kernel by a variance of h²/3 per axis, and the cut-off at 2σ
// becomes a step blurred over about ±h; the table's σ² is reduced to compensate (LatticeOptions).
// The remaining difference from the exact sums is measured in tests/unit/test_saliency_lattice.cpp
// and docs/studies/performance.md.
#pragma once

#include "vcg_ext/core/rings.h" // min_parallel_vertices

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace vcg_ext {
namespace detail {

// Open-addressing hash map from 64-bit keys to dense ids 0, 1, 2, … in order of first insertion.
class KeyIndex {
public:
  explicit KeyIndex(size_t expected = 16) { rehash(expected); }

  // The id of `key`, inserted with id size() when absent.
  int insert(std::uint64_t key) {
    size_t s = slot(key);
    while (slot_id_[s] >= 0) {
      if (slot_key_[s] == key) return slot_id_[s];
      s = (s + 1) & mask_;
    }
    const int id = int(keys_.size());
    slot_key_[s] = key;
    slot_id_[s] = id;
    keys_.push_back(key);
    if (2 * keys_.size() > slot_id_.size()) rehash(2 * keys_.size());
    return id;
  }

  int find(std::uint64_t key) const {
    for (size_t s = slot(key); slot_id_[s] >= 0; s = (s + 1) & mask_)
      if (slot_key_[s] == key) return slot_id_[s];
    return -1;
  }

  int size() const { return int(keys_.size()); }
  const std::vector<std::uint64_t> &keys() const { return keys_; }

private:
  size_t slot(std::uint64_t key) const {
    return size_t((key * 0x9E3779B97F4A7C15ull) >> shift_) & mask_;
  }
  void rehash(size_t expected) {
    size_t capacity = 16;
    int bits = 4;
    while (capacity < 2 * expected) capacity <<= 1, ++bits;
    mask_ = capacity - 1;
    shift_ = 64 - bits;
    slot_key_.assign(capacity, 0);
    slot_id_.assign(capacity, -1);
    for (size_t id = 0; id < keys_.size(); ++id) {
      size_t s = slot(keys_[id]);
      while (slot_id_[s] >= 0) s = (s + 1) & mask_;
      slot_key_[s] = keys_[id];
      slot_id_[s] = int(id);
    }
  }

  std::vector<std::uint64_t> slot_key_;
  std::vector<int> slot_id_;
  std::vector<std::uint64_t> keys_;
  size_t mask_ = 0;
  int shift_ = 60;
};

struct WeightedPoint {
  double x, y, z, value;
  Vec3 position() const { return {x, y, z}; }
};

// The occupied nodes of one lattice, sorted by key = (l·ny + j)·nx + i: runs of equal (j, l) are
// the rows along x.
struct SparseLattice {
  double h = 1;
  std::uint64_t nx = 1, ny = 1;
  std::vector<std::uint64_t> key;
  std::vector<int> x;
  std::vector<std::uint64_t> row_key; // key / nx of each row
  std::vector<int> row_start;         // nodes of row r: [row_start[r], row_start[r + 1])

  int size() const { return int(key.size()); }

  // Sorts `keys` (unique) into the lattice; returns each input key's position.
  std::vector<int> assign(const std::vector<std::uint64_t> &keys, bool parallel) {
    const int count = int(keys.size());
    // (key, index) pairs in one array, sorted in parallel: the keys are distinct, so the order is
    // the keys' whatever the sort.
    std::vector<std::pair<std::uint64_t, int>> order(count);
    for (int p = 0; p < count; ++p) order[p] = {keys[p], p};
    if (parallel) parallelSort(order);
    else std::sort(order.begin(), order.end());
    std::vector<int> position(count);
    key.resize(count);
    x.resize(count);
    row_key.clear();
    row_start.clear();
    for (int p = 0; p < count; ++p) {
      position[order[p].second] = p;
      key[p] = order[p].first;
      x[p] = int(key[p] % nx);
      if (p == 0 || key[p] / nx != row_key.back()) {
        row_key.push_back(key[p] / nx);
        row_start.push_back(p);
      }
    }
    row_start.push_back(count);
    return position;
  }
};

struct LatticeOptions {
  int nodes_per_sigma = 2;          // k: each σ's spacing h has k ≤ σ/h < 2k
  // Split the σ into chains σ, 2σ, 4σ, … with σ/h = k exactly (cheapest convolutions, one splat
  // and slice per chain) instead of one nested family for all (one splat and slice in all).
  bool chains_only = true;
  // × h²/3 subtracted from σ² in the kernel table: 1 undoes the two trilinear blurs of an
  // untruncated Gaussian. (2 is closer to the exact sums of a smooth map at σ ≥ 8ε but further
  // from those of a noisy curvature map, the case that matters.)
  double variance_correction = 1.0;
  // Chains on separate threads below this many points (latticeGaussianMeans).
  int chains_in_parallel_below = 500000;
};

// A lattice's rows as dense runs, for the convolution's inner loop: each row's nodes split where
// two neighbours are more than 2R apart (no target is within R of both), each run stored with zeros
// between its nodes and 2R zeros at either end, so that every target within R of a run reads the
// run's window x − ρ … x + ρ (ρ ≤ R) at fixed offsets. The gather's trip counts then depend on the
// kernel's shape only, not on which nodes the data holds: the sparse rows' loops (a few nodes per
// row, their ends found by comparing node positions) were the convolution's cost.
struct DenseRuns {
  struct Run {
    int x_first, x_last; // the run's first and last node
    size_t start;        // entry of x_first − 2R in `values`
  };
  std::vector<int> row_run; // runs of row r: [row_run[r], row_run[r + 1])
  std::vector<Run> runs;
  std::vector<double> values; // (sum, weight) per entry
};

// The runs of `lattice` (rows as in SparseLattice) for a kernel of radius R, holding the nodes'
// (sum, weight) pairs `sum_weight`.
inline DenseRuns denseRuns(const SparseLattice &lattice, const std::vector<double> &sum_weight,
                           int R) {
  DenseRuns d;
  const int rows = int(lattice.row_key.size());
  d.row_run.assign(rows + 1, 0);
  size_t entries = 0;
  auto close_last_run = [&] {
    entries += size_t(d.runs.back().x_last - d.runs.back().x_first) + 4 * R + 1;
  };
  for (int r = 0; r < rows; ++r) {
    d.row_run[r] = int(d.runs.size());
    for (int q = lattice.row_start[r]; q < lattice.row_start[r + 1]; ++q) {
      const bool first = q == lattice.row_start[r];
      if (first || lattice.x[q] - lattice.x[q - 1] > 2 * R) {
        if (!first) close_last_run();
        d.runs.push_back({lattice.x[q], lattice.x[q], entries});
      }
      d.runs.back().x_last = lattice.x[q];
    }
    if (lattice.row_start[r + 1] > lattice.row_start[r]) close_last_run();
  }
  d.row_run[rows] = int(d.runs.size());
  d.values.assign(2 * entries, 0.0);
  for (int r = 0; r < rows; ++r) {
    int run = d.row_run[r];
    for (int q = lattice.row_start[r]; q < lattice.row_start[r + 1]; ++q) {
      while (lattice.x[q] > d.runs[run].x_last) ++run;
      const size_t e = d.runs[run].start + size_t(lattice.x[q] - d.runs[run].x_first + 2 * R);
      d.values[2 * e] = sum_weight[2 * size_t(q)];
      d.values[2 * e + 1] = sum_weight[2 * size_t(q) + 1];
    }
  }
  return d;
}

// One target node's sums over its source rows, for S σ at once (S fixed: the accumulators stay in
// registers). The terms come in the order of the sparse sum (rows, then x), plus exact zeros
// where a row has no node, so the sums are those of the nodes alone.
struct LatticeSourceRow {
  int run, run_end, reach;
  const double *weights; // S weights per dx, at dx = 0
};

template <int S>
inline void gatherNode(int x, int R, const DenseRuns &dense,
                       std::vector<LatticeSourceRow> &sources, double *out) {
  double acc[2 * S] = {};
  for (LatticeSourceRow &src : sources) {
    while (src.run < src.run_end && dense.runs[src.run].x_last < x - R) ++src.run;
    if (src.run == src.run_end || dense.runs[src.run].x_first > x + R) continue;
    const DenseRuns::Run &run = dense.runs[src.run];
    const double *d = &dense.values[2 * (run.start + size_t(x - run.x_first + 2 * R))];
    for (int dx = -src.reach; dx <= src.reach; ++dx) {
      const double *w = src.weights + dx * S;
      const double sum = d[2 * dx], weight = d[2 * dx + 1];
      for (int s = 0; s < S; ++s) {
        acc[2 * s] += w[s] * sum;
        acc[2 * s + 1] += w[s] * weight;
      }
    }
  }
  for (int q = 0; q < 2 * S; ++q) out[q] = acc[q];
}

// The truncated Gaussians of up to 4 σ on one lattice, sampled at integer offsets:
// table[((dz+R)·width + dy+R)·width + dx+R][s]. At exactly the cut-off radius half the weight (a
// node on the sphere is half inside).
struct LatticeKernel {
  int S = 0, R = 0, width = 1;
  std::vector<double> table;
};

inline LatticeKernel latticeKernel(double h, const std::vector<double> &sigmas,
                                   double variance_correction) {
  LatticeKernel k;
  k.S = int(sigmas.size());
  double reach = 0;
  for (double sigma : sigmas) reach = std::max(reach, 2 * sigma / h);
  k.R = int(std::floor(reach + 1e-9));
  k.width = 2 * k.R + 1;
  const int R = k.R, width = k.width, S = k.S;
  k.table.assign(size_t(width) * width * width * S, 0.0);
  for (int s = 0; s < S; ++s) {
    const double cutoff2 = 4 * sigmas[s] * sigmas[s] / (h * h);
    const double sigma2 = std::max(sigmas[s] * sigmas[s] - variance_correction * h * h / 3,
                                   0.25 * sigmas[s] * sigmas[s]);
    for (int dz = -R; dz <= R; ++dz)
      for (int dy = -R; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx) {
          const double d2 = dx * dx + dy * dy + dz * dz;
          const double edge = std::abs(d2 - cutoff2) < 1e-9 * cutoff2 ? 0.5 : d2 < cutoff2 ? 1 : 0;
          k.table[((size_t(dz + R) * width + (dy + R)) * width + (dx + R)) * S + s] =
              edge * std::exp(-d2 * h * h / (2 * sigma2));
        }
  }
  return k;
}

// The convolution of one lattice with a kernel: out[node · 2S + 2s + {0, 1}] (sized by the caller)
// = Σ_q g_s(q − node) · {sum, weight}[q], `dense` holding the (sum, weight) of the nodes as runs
// (denseRuns). Every node gathers from the nodes within the cut-off (deterministic). Call it
// inside a parallel region: it shares the rows among the threads without waiting at the end
// (`nowait`), so the lattices of a chain are convolved in one region.
inline void convolveLatticeRows(const SparseLattice &lattice, const LatticeKernel &kernel,
                                const DenseRuns &dense, std::vector<double> &out) {
  const int R = kernel.R, width = kernel.width, S = kernel.S;
  const int row_count = int(lattice.row_key.size());
  const std::uint64_t ny = lattice.ny;
  std::vector<LatticeSourceRow> sources;
  sources.reserve(size_t(width) * width);
#pragma omp for schedule(dynamic, 16) nowait
  for (int r = 0; r < row_count; ++r) {
    const std::int64_t j = std::int64_t(lattice.row_key[r] % ny),
                       l = std::int64_t(lattice.row_key[r] / ny);
    sources.clear();
    // For each dz the rows (j − R … j + R, l + dz) are one run of the sorted row keys.
    for (int dz = -R; dz <= R; ++dz) {
      if (l + dz < 0) continue;
      const std::uint64_t base = std::uint64_t((l + dz) * std::int64_t(ny));
      const std::uint64_t first = base + std::uint64_t(std::max<std::int64_t>(j - R, 0)),
                          last = base + std::uint64_t(j + R);
      // (`last` may run into the next plane's rows: those end the run.)
      for (auto it = std::lower_bound(lattice.row_key.begin(), lattice.row_key.end(), first);
           it != lattice.row_key.end() && *it <= last && *it - base < ny; ++it) {
        const int dy = int(std::int64_t(*it - base) - j), d2 = dy * dy + dz * dz;
        if (d2 > R * R) continue;
        const int index = int(it - lattice.row_key.begin());
        sources.push_back({dense.row_run[index], dense.row_run[index + 1],
                           int(std::sqrt(double(R * R - d2)) + 1e-9),
                           &kernel.table[((size_t(dz + R) * width + (dy + R)) * width + R) * S]});
      }
    }
    for (int t = lattice.row_start[r]; t < lattice.row_start[r + 1]; ++t) {
      double *o = &out[size_t(t) * 2 * S];
      const int x = lattice.x[t];
      switch (S) {
      case 1: gatherNode<1>(x, R, dense, sources, o); break;
      case 2: gatherNode<2>(x, R, dense, sources, o); break;
      case 3: gatherNode<3>(x, R, dense, sources, o); break;
      default: gatherNode<4>(x, R, dense, sources, o); break;
      }
    }
  }
}

// A chain's nested lattices: spacing base_h · 2^L on level L, one origin (one spare node below
// and two above on every lattice, so that neighbours never wrap around a row). For each level
// above the finest, each finer node's coarse parents (−1: none) and their shared weight: fine node
// 2I + {−1, 0, 1} (per axis) belongs to coarse node I with weight ½, 1, ½.
struct LatticePyramid {
  Vec3 origin = Vec3::Zero();
  std::vector<SparseLattice> lattice;
  std::vector<std::vector<std::array<int, 8>>> parents; // parents[L][node of L − 1]
  std::vector<std::vector<double>> parent_weight;
  int levels() const { return int(lattice.size()); }
};

// The chain's σ on their levels: level[s] with k ≤ σ_s / h_L < 2k (h_L = base_h · 2^L, base_h
// the smallest σ over k); returns the number of levels.
inline int sigmaLevels(const std::vector<double> &sigmas, int k, double &base_h,
                       std::vector<int> &level) {
  const double smallest = *std::min_element(sigmas.begin(), sigmas.end());
  base_h = smallest / k;
  level.resize(sigmas.size());
  int levels = 1;
  for (size_t s = 0; s < sigmas.size(); ++s) {
    level[s] = std::max(0, int(std::floor(std::log2(sigmas[s] / smallest) + 1e-9)));
    levels = std::max(levels, level[s] + 1);
  }
  return levels;
}

// The pyramid's frame around `points`, its lattices still empty.
inline LatticePyramid emptyPyramid(const std::vector<WeightedPoint> &points, double base_h,
                                   int levels) {
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
  for (const WeightedPoint &p : points) lo = lo.cwiseMin(p.position()), hi = hi.cwiseMax(p.position());
  LatticePyramid pyramid;
  pyramid.origin = lo - Vec3::Constant(base_h);
  pyramid.lattice.resize(levels);
  pyramid.parents.resize(levels);
  pyramid.parent_weight.resize(levels);
  for (int L = 0; L < levels; ++L) {
    SparseLattice &lattice = pyramid.lattice[L];
    lattice.h = base_h * std::ldexp(1.0, L);
    lattice.nx = std::uint64_t((hi.x() - pyramid.origin.x()) / lattice.h) + 4;
    lattice.ny = std::uint64_t((hi.y() - pyramid.origin.y()) / lattice.h) + 4;
  }
  return pyramid;
}

// The cells of the finest lattice that hold points, the points grouped by cell (in array order
// within a cell, so that the sums over them do not depend on the thread count), and each cell's
// 8 corners as nodes of the finest lattice (which this fills).
struct PointCells {
  std::vector<int> start;  // points of cell c: point[start[c]] … point[start[c + 1] − 1]
  std::vector<int> point;
  std::vector<std::array<int, 8>> corners;
  int size() const { return int(corners.size()); }
};

inline PointCells bucketIntoCells(const std::vector<WeightedPoint> &points,
                                  LatticePyramid &pyramid, bool parallel) {
  const int m = int(points.size());
  SparseLattice &base = pyramid.lattice[0];
  std::vector<std::uint64_t> vertex_key(m);
  for (int a = 0; a < m; ++a) {
    const Vec3 g = (points[a].position() - pyramid.origin) / base.h;
    vertex_key[a] =
        (std::uint64_t(g.z()) * base.ny + std::uint64_t(g.y())) * base.nx + std::uint64_t(g.x());
  }
  KeyIndex cells(size_t(m) / 8 + 16);
  std::vector<int> cell_of(m);
  for (int a = 0, last = -1; a < m; ++a) {
    last = (a > 0 && vertex_key[a] == vertex_key[a - 1]) ? last : cells.insert(vertex_key[a]);
    cell_of[a] = last;
  }
  std::vector<std::uint64_t>().swap(vertex_key);
  const int cell_count = cells.size();
  PointCells out;
  out.start.assign(cell_count + 1, 0);
  out.point.resize(m);
  for (int a = 0; a < m; ++a) ++out.start[cell_of[a] + 1];
  for (int c = 0; c < cell_count; ++c) out.start[c + 1] += out.start[c];
  {
    std::vector<int> cursor(out.start.begin(), out.start.end() - 1);
    for (int a = 0; a < m; ++a) out.point[cursor[cell_of[a]]++] = a;
  }
  std::vector<int>().swap(cell_of);
  out.corners.resize(cell_count);
  KeyIndex nodes(size_t(cell_count) * 2 + 16);
  for (int c = 0; c < cell_count; ++c)
    for (int corner = 0; corner < 8; ++corner)
      out.corners[c][corner] =
          nodes.insert(cells.keys()[c] + (corner & 1) + ((corner >> 1) & 1) * base.nx +
                       ((corner >> 2) & 1) * base.nx * base.ny);
  const std::vector<int> position = base.assign(nodes.keys(), parallel);
  for (auto &c : out.corners)
    for (int &node : c) node = position[node];
  return out;
}

// The trilinear weights of `p`'s 8 cell corners on the lattice of spacing h from `origin`.
inline void trilinearWeights(const Vec3 &p, const Vec3 &origin, double h, double w[8]) {
  const Vec3 g = (p - origin) / h;
  const double fx = g.x() - std::floor(g.x()), fy = g.y() - std::floor(g.y()),
               fz = g.z() - std::floor(g.z());
  for (int corner = 0; corner < 8; ++corner)
    w[corner] =
        (corner & 1 ? fx : 1 - fx) * (corner & 2 ? fy : 1 - fy) * (corner & 4 ? fz : 1 - fz);
}

// The points' (value, 1) splatted onto the finest lattice: (sum, weight) per node. Each cell's
// share of its 8 corners first (in parallel), then the cells into the nodes (serially).
inline std::vector<double> splatPoints(const std::vector<WeightedPoint> &points,
                                       const PointCells &cells, const LatticePyramid &pyramid,
                                       bool parallel) {
  const int m = int(points.size()), cell_count = cells.size();
  const double h = pyramid.lattice[0].h;
  std::vector<std::array<double, 16>> cell_splat(cell_count);
#pragma omp parallel for schedule(dynamic, 256) if (parallel && m >= min_parallel_vertices)
  for (int c = 0; c < cell_count; ++c) {
    std::array<double, 16> acc{};
    for (int i = cells.start[c]; i < cells.start[c + 1]; ++i) {
      const WeightedPoint &p = points[cells.point[i]];
      double w[8];
      trilinearWeights(p.position(), pyramid.origin, h, w);
      for (int corner = 0; corner < 8; ++corner) {
        acc[2 * corner] += w[corner] * p.value;
        acc[2 * corner + 1] += w[corner];
      }
    }
    cell_splat[c] = acc;
  }
  std::vector<double> splat(2 * size_t(pyramid.lattice[0].size()), 0.0);
  for (int c = 0; c < cell_count; ++c)
    for (int corner = 0; corner < 8; ++corner) {
      splat[2 * size_t(cells.corners[c][corner])] += cell_splat[c][2 * corner];
      splat[2 * size_t(cells.corners[c][corner]) + 1] += cell_splat[c][2 * corner + 1];
    }
  return splat;
}

// Level L's nodes (the coarse parents of level L − 1's), their parents and weights in the pyramid,
// and level L − 1's (sum, weight) pairs `fine_splat` restricted to them.
inline std::vector<double> restrictToLevel(int L, LatticePyramid &pyramid,
                                           const std::vector<double> &fine_splat, bool parallel) {
  const SparseLattice &fine = pyramid.lattice[L - 1];
  SparseLattice &coarse = pyramid.lattice[L];
  const int fine_count = fine.size();
  auto &up = pyramid.parents[L];
  std::vector<double> &weight = pyramid.parent_weight[L];
  up.assign(fine_count, {-1, -1, -1, -1, -1, -1, -1, -1});
  weight.resize(fine_count);
  KeyIndex nodes(size_t(fine_count) / 4 + 16);
  for (int p = 0; p < fine_count; ++p) {
    const std::uint64_t key = fine.key[p];
    const std::uint64_t i = key % fine.nx, j = (key / fine.nx) % fine.ny,
                        l = key / (fine.nx * fine.ny);
    const std::uint64_t ci[2] = {i / 2, (i + 1) / 2}, cj[2] = {j / 2, (j + 1) / 2},
                        cl[2] = {l / 2, (l + 1) / 2};
    const int ni = 1 + int(i & 1), nj = 1 + int(j & 1), nl = 1 + int(l & 1);
    weight[p] = 1.0 / (ni * nj * nl);
    int count = 0;
    for (int c = 0; c < nl; ++c)
      for (int b = 0; b < nj; ++b)
        for (int a = 0; a < ni; ++a)
          up[p][count++] = nodes.insert((cl[c] * coarse.ny + cj[b]) * coarse.nx + ci[a]);
  }
  const std::vector<int> position = coarse.assign(nodes.keys(), parallel);
  std::vector<double> splat(2 * size_t(coarse.size()), 0.0);
  for (int p = 0; p < fine_count; ++p)
    for (int &parent : up[p]) {
      if (parent < 0) break;
      parent = position[parent];
      splat[2 * size_t(parent)] += weight[p] * fine_splat[2 * size_t(p)];
      splat[2 * size_t(parent) + 1] += weight[p] * fine_splat[2 * size_t(p) + 1];
    }
  return splat;
}

// The σ in slot order (level by level, finest first; within a level in `sigmas`' order):
// slot_sigma[slot] is a σ's index, first_slot[L] … first_slot[L + 1] − 1 the slots of level L.
inline void sigmaSlots(const std::vector<int> &level, int levels, std::vector<int> &slot_sigma,
                       std::vector<int> &first_slot) {
  const int S = int(level.size());
  first_slot.assign(levels + 1, 0);
  slot_sigma.clear();
  for (int L = 0; L < levels; ++L) {
    first_slot[L] = int(slot_sigma.size());
    for (int s = 0; s < S; ++s)
      if (level[s] == L) slot_sigma.push_back(s);
  }
  first_slot[levels] = S;
}

// Each level's splat convolved with its own σ (all levels in one parallel region): own[L] holds,
// per node of level L, a (sum, weight) pair per slot of L.
inline std::vector<std::vector<double>>
convolveLevels(const LatticePyramid &pyramid, const std::vector<std::vector<double>> &splat,
               const std::vector<double> &sigmas, const std::vector<int> &slot_sigma,
               const std::vector<int> &first_slot, const LatticeOptions &options, bool parallel) {
  const int levels = pyramid.levels();
  std::vector<std::vector<double>> own(levels);
  std::vector<LatticeKernel> kernels(levels);
  for (int L = 0; L < levels; ++L) {
    std::vector<double> level_sigmas;
    for (int slot = first_slot[L]; slot < first_slot[L + 1]; ++slot)
      level_sigmas.push_back(sigmas[slot_sigma[slot]]);
    if (level_sigmas.empty()) continue;
    kernels[L] = latticeKernel(pyramid.lattice[L].h, level_sigmas, options.variance_correction);
    own[L].assign(size_t(pyramid.lattice[L].size()) * 2 * level_sigmas.size(), 0.0);
  }
  std::vector<DenseRuns> dense(levels);
  for (int L = 0; L < levels; ++L)
    if (kernels[L].S > 0) dense[L] = denseRuns(pyramid.lattice[L], splat[L], kernels[L].R);
#pragma omp parallel if (parallel)
  for (int L = 0; L < levels; ++L)
    if (kernels[L].S > 0) convolveLatticeRows(pyramid.lattice[L], kernels[L], dense[L], own[L]);
  return own;
}

// The levels' convolutions interpolated from coarse to fine: per node of the finest lattice, the
// (sum, weight) pair of every slot. Each level's own pairs, then the coarser levels' trilinearly
// interpolated at its nodes (`own`, the splats and the pyramid's parents are freed on the way).
inline std::vector<double> prolongToFinest(LatticePyramid &pyramid,
                                           std::vector<std::vector<double>> &own,
                                           std::vector<std::vector<double>> &splat,
                                           const std::vector<int> &first_slot) {
  const int levels = pyramid.levels(), S = first_slot[levels];
  std::vector<double> coarser;
  for (int L = levels - 1; L >= 0; --L) {
    const int own_count = first_slot[L + 1] - first_slot[L], below = S - first_slot[L + 1];
    std::vector<double>().swap(splat[L]);
    const int width = 2 * (own_count + below), n = pyramid.lattice[L].size();
    std::vector<double> result(size_t(n) * width, 0.0);
    for (int p = 0; p < n; ++p) {
      double *r = &result[size_t(p) * width];
      for (int q = 0; q < 2 * own_count; ++q) r[q] = own[L][size_t(p) * 2 * own_count + q];
      if (below == 0) continue;
      const double w = pyramid.parent_weight[L + 1][p];
      for (int parent : pyramid.parents[L + 1][p]) {
        if (parent < 0) break;
        const double *c = &coarser[size_t(parent) * 2 * below];
        for (int q = 0; q < 2 * below; ++q) r[2 * own_count + q] += w * c[q];
      }
    }
    coarser.swap(result);
    std::vector<double>().swap(own[L]);
    if (L + 1 < levels) {
      std::vector<std::array<int, 8>>().swap(pyramid.parents[L + 1]);
      std::vector<double>().swap(pyramid.parent_weight[L + 1]);
    }
  }
  return coarser;
}

// Slice: each point's means, trilinear in the (sum, weight) pairs of its cell's corners
// (`finest`: per finest node, a pair per slot); parallel over cells (a cell's points share its
// corners).
inline void sliceAtPoints(const std::vector<WeightedPoint> &points, const PointCells &cells,
                          const LatticePyramid &pyramid, const std::vector<double> &finest,
                          const std::vector<int> &slot_sigma, bool parallel,
                          std::vector<std::vector<double>> &means) {
  const int m = int(points.size()), S = int(slot_sigma.size()), cell_count = cells.size();
  const double h = pyramid.lattice[0].h;
  for (int s = 0; s < S; ++s) means[s].resize(m);
#pragma omp parallel for schedule(dynamic, 256) if (parallel && m >= min_parallel_vertices)
  for (int c = 0; c < cell_count; ++c) {
    for (int i = cells.start[c]; i < cells.start[c + 1]; ++i) {
      const int a = cells.point[i];
      double w[8];
      trilinearWeights(points[a].position(), pyramid.origin, h, w);
      for (int slot = 0; slot < S; ++slot) {
        double sum_at = 0, weight_at = 0;
        for (int corner = 0; corner < 8; ++corner) {
          const double *r = &finest[size_t(cells.corners[c][corner]) * 2 * S + 2 * slot];
          sum_at += w[corner] * r[0];
          weight_at += w[corner] * r[1];
        }
        means[slot_sigma[slot]][a] = weight_at > 0 ? sum_at / weight_at : 0.0;
      }
    }
  }
}

// G at every σ of `sigmas` (a chain σ₀, 2σ₀, 4σ₀, … when options.chains_only) at every point:
// means[s][a] for point a. Points near in space should be near in the array (cache).
// Splat onto the finest lattice, restrict to the coarser ones, convolve each with its σ,
// interpolate back to the finest and slice at the points.
inline void latticeGaussianMeansChain(const std::vector<WeightedPoint> &points,
                                      const std::vector<double> &sigmas,
                                      const LatticeOptions &options,
                                      std::vector<std::vector<double>> &means,
                                      bool parallel = true) {
  const int m = int(points.size());
  if (m == 0 || sigmas.empty()) return;
  double base_h;
  std::vector<int> level;
  const int levels = sigmaLevels(sigmas, std::max(1, options.nodes_per_sigma), base_h, level);
  LatticePyramid pyramid = emptyPyramid(points, base_h, levels);
  const PointCells cells = bucketIntoCells(points, pyramid, parallel);
  std::vector<std::vector<double>> splat(levels);
  splat[0] = splatPoints(points, cells, pyramid, parallel);
  for (int L = 1; L < levels; ++L) splat[L] = restrictToLevel(L, pyramid, splat[L - 1], parallel);
  std::vector<int> slot_sigma, first_slot;
  sigmaSlots(level, levels, slot_sigma, first_slot);
  std::vector<std::vector<double>> own = convolveLevels(
      pyramid, splat, sigmas, slot_sigma, first_slot, options, parallel && m >= min_parallel_vertices);
  const std::vector<double> finest = prolongToFinest(pyramid, own, splat, first_slot);
  sliceAtPoints(points, cells, pyramid, finest, slot_sigma, parallel, means);
}

// The vertices `active` in the order of cells of `cell` (at least; grown until there are at most
// 4 cells per point): row-major cells, input order within a cell. The lattice passes then stream
// through memory instead of jumping over the mesh (much faster on a shuffled mesh).
inline std::vector<int> cellOrder(const std::vector<Vec3> &positions, const std::vector<int> &active,
                                  double cell) {
  const int m = int(active.size());
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
  for (int v : active) lo = lo.cwiseMin(positions[v]), hi = hi.cwiseMax(positions[v]);
  Vec3 counts;
  for (;;) {
    counts = ((hi - lo) / cell).array().floor() + 1.0;
    if (counts.prod() <= 4.0 * m + 4096) break;
    cell *= 1.25;
  }
  const std::uint64_t nx = std::uint64_t(counts.x()), ny = std::uint64_t(counts.y());
  std::vector<std::uint32_t> bucket(m);
  std::vector<int> start(size_t(counts.prod()) + 1, 0);
  for (int a = 0; a < m; ++a) {
    const Vec3 g = (positions[active[a]] - lo) / cell;
    bucket[a] = std::uint32_t((std::uint64_t(g.z()) * ny + std::uint64_t(g.y())) * nx +
                              std::uint64_t(g.x()));
    ++start[bucket[a] + 1];
  }
  for (size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
  std::vector<int> order(m);
  for (int a = 0; a < m; ++a) order[start[bucket[a]]++] = active[a];
  return order;
}

// The σ in chains: from the smallest σ not yet taken (in `sigmas`' order), every σ that is it
// times a power of two. Each chain's indices into `sigmas`.
inline std::vector<std::vector<int>> sigmaChains(const std::vector<double> &sigmas) {
  const int S = int(sigmas.size());
  std::vector<std::vector<int>> chains;
  std::vector<int> done(S, 0);
  for (int first = 0; first < S; ++first) {
    if (done[first]) continue;
    chains.emplace_back();
    for (int s = 0; s < S; ++s) {
      const double ratio = std::log2(sigmas[s] / sigmas[first]);
      if (!done[s] && ratio > -1e-9 && std::abs(ratio - std::round(ratio)) < 1e-9)
        chains.back().push_back(s), done[s] = 1;
    }
  }
  return chains;
}

// G at every σ of `sigmas` for the vertices `active`: means[s][v] (other entries untouched).
inline void latticeGaussianMeans(const std::vector<Vec3> &positions, const std::vector<int> &active,
                                 const std::vector<double> &values,
                                 const std::vector<double> &sigmas, const LatticeOptions &options,
                                 std::vector<std::vector<double>> &means) {
  const int m = int(active.size()), S = int(sigmas.size());
  if (m == 0 || S == 0) return;
  // A compact copy of the points, bucketed by cells of 2σ_min.
  const std::vector<int> order =
      cellOrder(positions, active, 2 * *std::min_element(sigmas.begin(), sigmas.end()));
  std::vector<WeightedPoint> points(m);
  for (int a = 0; a < m; ++a)
    points[a] = {positions[order[a]].x(), positions[order[a]].y(), positions[order[a]].z(),
                 values[order[a]]};

  std::vector<std::vector<double>> sorted_means(S);
  if (!options.chains_only) {
    latticeGaussianMeansChain(points, sigmas, options, sorted_means);
  } else {
    const std::vector<std::vector<int>> chains = sigmaChains(sigmas);
    // With no more threads than chains, each thread takes whole chains (the first, on the finest
    // lattice, is the largest): a chain's serial steps (hashing its nodes, restricting them to the
    // coarser lattices) are a large part of its time, with the other thread waiting. With more
    // threads, the chains run one after another, each on all of them. The means are the same
    // either way (no sum depends on the threads). Only below `chains_in_parallel_below` points:
    // the lattices do not grow with the vertex count, the per-point steps do, so the gain shrinks
    // with size, while the other thread's per-point arrays come from a second malloc arena that
    // the rest of the run does not reuse (docs/studies/performance.md).
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    const bool by_chain = chains.size() > 1 && threads > 1 && threads <= int(chains.size()) &&
                          parallelHeavy(m) && m < options.chains_in_parallel_below;
    AllocationGuard guard;
#pragma omp parallel for schedule(dynamic, 1) if (by_chain)
    for (int c = 0; c < int(chains.size()); ++c)
      guard.run([&] {
        std::vector<double> chain_sigmas;
        for (int s : chains[c]) chain_sigmas.push_back(sigmas[s]);
        std::vector<std::vector<double>> chain_means(chains[c].size());
        latticeGaussianMeansChain(points, chain_sigmas, options, chain_means, !by_chain);
        for (size_t k = 0; k < chains[c].size(); ++k)
          sorted_means[chains[c][k]].swap(chain_means[k]);
      });
    guard.rethrow();
  }
  for (int s = 0; s < S; ++s) {
    means[s].resize(positions.size());
    for (int a = 0; a < m; ++a) means[s][order[a]] = sorted_means[s][a];
    std::vector<double>().swap(sorted_means[s]);
  }
}

} // namespace detail
} // namespace vcg_ext
