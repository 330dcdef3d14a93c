// Meshes of analytic surfaces with known curvature, as plain arrays, for the unit tests.
#pragma once

#include <vcg_ext/analysis/curvature.h>
#include <vcg_ext/core/mesh_arrays.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <random>

namespace test_meshes {

using vcg_ext::Face;
using vcg_ext::MeshArrays;
using vcg_ext::Vec3;

inline MeshArrays fromArrays(std::vector<Vec3> points, std::vector<Face> faces) {
  MeshArrays m;
  m.points = std::move(points);
  m.faces = std::move(faces);
  const int n = int(m.points.size());
  m.compact_index.resize(n);
  m.mesh_slot.resize(n);
  for (int i = 0; i < n; ++i) m.compact_index[i] = m.mesh_slot[i] = i;
  m.selected.assign(n, 0);
  return m;
}

// Icosphere of radius r: `subdivisions` = 4 gives 2562 vertices, 5 gives 10242.
inline MeshArrays icosphere(double r, int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Face> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                         {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                         {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                         {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto &q : p) q.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back((p[a] + p[b]).normalized());
      return mid[key] = int(p.size()) - 1;
    };
    std::vector<Face> g;
    for (const Face &q : f) {
      int a = midpoint(q[0], q[1]), b = midpoint(q[1], q[2]), c = midpoint(q[2], q[0]);
      g.push_back({q[0], a, c});
      g.push_back({q[1], b, a});
      g.push_back({q[2], c, b});
      g.push_back({a, b, c});
    }
    f.swap(g);
  }
  for (auto &q : p) q *= r;
  return fromArrays(std::move(p), std::move(f));
}

// Regular triangulated grid over [x0,x1]x[y0,y1] with n x n vertices, z = height(x, y).
inline MeshArrays heightField(int n, double x0, double x1, double y0, double y1,
                              const std::function<double(double, double)> &height) {
  std::vector<Vec3> p;
  std::vector<Face> f;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = x0 + (x1 - x0) * i / (n - 1), y = y0 + (y1 - y0) * j / (n - 1);
      p.emplace_back(x, y, height(x, y));
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      // One diagonal direction everywhere: every interior vertex has valence 6.
      f.push_back({a, b, d});
      f.push_back({a, d, c});
    }
  return fromArrays(std::move(p), std::move(f));
}

// Noise along the clean normals whose values are white noise smoothed by `steps` graph-Laplacian
// steps (x <- (x + 1-ring mean) / 2), renormalised to std `sigma`: correlated over about
// sqrt(steps) rings, like a scanner's.
inline MeshArrays withCorrelatedNoise(const MeshArrays &clean, double sigma, int steps, unsigned seed) {
  const int n = int(clean.points.size());
  const vcg_ext::Rings rings = vcg_ext::computeRings(n, clean.faces);
  std::vector<Vec3> normals;
  vcg_ext::computeVertexNormals(clean.points, clean.faces, rings, normals);
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> z(n), next(n);
  for (double &x : z) x = g(rng);
  for (int s = 0; s < steps; ++s) {
    for (int v = 0; v < n; ++v) {
      double sum = 0;
      for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w) sum += z[*w];
      next[v] = 0.5 * z[v] + 0.5 * sum / std::max(1, rings.ring1Size(v));
    }
    z.swap(next);
  }
  double mean = 0, square = 0;
  for (double x : z) mean += x / n;
  for (double x : z) square += (x - mean) * (x - mean) / n;
  MeshArrays noisy = clean;
  for (int v = 0; v < n; ++v) noisy.points[v] += sigma * (z[v] - mean) / std::sqrt(square) * normals[v];
  return noisy;
}


// Index of the grid vertex nearest to (x, y) in a heightField(n, ...) mesh.
inline int nearestVertex(const MeshArrays &m, double x, double y) {
  int best = 0;
  double bd = INFINITY;
  for (int i = 0; i < int(m.points.size()); ++i) {
    const double d = std::hypot(m.points[i].x() - x, m.points[i].y() - y);
    if (d < bd) bd = d, best = i;
  }
  return best;
}

// Open cylinder of radius r around the z axis, `around` x `along` vertices, height h.
inline MeshArrays cylinder(double r, double h, int around, int along) {
  std::vector<Vec3> p;
  std::vector<Face> f;
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      // Stagger alternate rows by half a step for near-equilateral triangles.
      const double a = 2 * M_PI * (i + 0.5 * (j % 2)) / around;
      p.emplace_back(r * std::cos(a), r * std::sin(a), h * j / (along - 1) - h / 2);
    }
  for (int j = 0; j + 1 < along; ++j)
    for (int i = 0; i < around; ++i) {
      const int i1 = (i + 1) % around;
      const int a = j * around + i, b = j * around + i1, c = (j + 1) * around + i,
                d = (j + 1) * around + i1;
      if (j % 2 == 0) {
        f.push_back({a, b, c});
        f.push_back({b, d, c});
      } else {
        f.push_back({a, d, c});
        f.push_back({a, b, d});
      }
    }
  return fromArrays(std::move(p), std::move(f));
}

// Adds Gaussian noise of standard deviation `sigma` along `direction(i)` (or in 3-D if null).
inline void addNoise(MeshArrays &m, double sigma, unsigned seed,
                     const std::function<Vec3(int)> &direction = nullptr) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, sigma);
  for (int i = 0; i < int(m.points.size()); ++i) {
    if (direction) m.points[i] += g(rng) * direction(i);
    else m.points[i] += Vec3(g(rng), g(rng), g(rng));
  }
}

// A copy with Gaussian noise of standard deviation `sigma` along the clean vertex normals (the
// literature's noise model).
inline MeshArrays withNormalNoise(const MeshArrays &clean, double sigma, unsigned seed) {
  MeshArrays noisy = clean;
  std::vector<Vec3> normals;
  vcg_ext::computeVertexNormals(clean.points, clean.faces,
                                vcg_ext::computeRings(int(clean.points.size()), clean.faces),
                                normals);
  addNoise(noisy, sigma, seed, [&](int i) { return normals[i]; });
  return noisy;
}

// The same mesh with vertices renumbered by `perm` (new index = perm[old]).
inline MeshArrays permuted(const MeshArrays &m, const std::vector<int> &perm) {
  std::vector<Vec3> p(m.points.size());
  for (size_t i = 0; i < p.size(); ++i) p[perm[i]] = m.points[i];
  std::vector<Face> f = m.faces;
  for (auto &q : f)
    for (int &k : q) k = perm[k];
  return fromArrays(std::move(p), std::move(f));
}

// The same mesh with its faces in another order and each face's corners rotated (orientation kept).
inline MeshArrays facesReordered(const MeshArrays &m, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Face> f = m.faces;
  std::shuffle(f.begin(), f.end(), rng);
  for (Face &q : f) std::rotate(q.begin(), q.begin() + rng() % 3, q.end());
  return fromArrays(m.points, std::move(f));
}

inline std::vector<int> shuffledPermutation(int n, unsigned seed) {
  std::vector<int> perm(n);
  for (int i = 0; i < n; ++i) perm[i] = i;
  std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
  return perm;
}

// Closed axis-aligned box [-hx,hx]x[-hy,hy]x[-hz,hz], each side an n x n grid of squares split into
// two triangles, outward (counter-clockwise) orientation; shared edges and corners are one vertex.
inline MeshArrays box(double hx, double hy, double hz, int n) {
  std::vector<Vec3> p;
  std::vector<Face> f;
  std::map<std::array<long, 3>, int> index;
  auto vertex = [&](const Vec3 &q) {
    const std::array<long, 3> key = {std::lround(q.x() * 1e6), std::lround(q.y() * 1e6),
                                     std::lround(q.z() * 1e6)};
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    p.push_back(q);
    return index[key] = int(p.size()) - 1;
  };
  const Vec3 half(hx, hy, hz);
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2) {
      // (u, v, normal) right-handed with the normal pointing outward.
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      std::vector<int> grid((n + 1) * (n + 1));
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          Vec3 q;
          q[axis] = sign * half[axis];
          q[a] = -half[a] + 2 * half[a] * i / n;
          q[b] = -half[b] + 2 * half[b] * j / n;
          grid[j * (n + 1) + i] = vertex(q);
        }
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const int c00 = grid[j * (n + 1) + i], c10 = grid[j * (n + 1) + i + 1];
          const int c01 = grid[(j + 1) * (n + 1) + i], c11 = grid[(j + 1) * (n + 1) + i + 1];
          if (sign > 0) {
            f.push_back({c00, c10, c11});
            f.push_back({c00, c11, c01});
          } else {
            f.push_back({c00, c11, c10});
            f.push_back({c00, c01, c11});
          }
        }
    }
  return fromArrays(std::move(p), std::move(f));
}

} // namespace test_meshes
