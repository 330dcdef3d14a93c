// Feature-preserving mode, stage A: guided or bilateral filtering of the face normals.
//
// Inputs: positions, triangles, face rings (core/face_rings.h). Output, per face in input order:
// the filtered unit normals. Papers: Zheng, Fu, Au, Tai 2011 (bilateral normal filtering); Zhang,
// Deng, Zhang, Bouaziz, Liu 2015 (guided mesh normal filtering, GNF). Lengths are in mean edge
// lengths so the defaults hold for any mesh scale.
//
// The filters gather over each face's "vertex ring" (the faces sharing a vertex with it, itself
// included): each face is written by one thread from the previous iteration's normals (Jacobi), so
// the result does not depend on thread count or face order.
#pragma once

#include "vcg_ext/analysis/dihedral_spread.h"
#include "vcg_ext/core/face_rings.h"
#include "vcg_ext/smoothing/taubin.h"

#include <Eigen/Geometry>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <functional>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace vcg_ext {

// The Gaussian range kernel exp(x), x <= 0. Most pairs of neighbouring faces differ by a few
// degrees (x > −0.5), where a degree-6 Taylor polynomial is within 2e-6 of exp and much cheaper
// than std::exp (docs/studies/feature-mode.md).
inline double rangeKernel(double x) {
  if (x < -0.5) return std::exp(x);
  return 1.0 + x * (1.0 + x * (0.5 + x * (1.0 / 6 + x * (1.0 / 24 + x * (1.0 / 120 + x / 720)))));
}

enum class NormalFilterKind {
  Guided,   // Zhang et al. 2015: range kernel on guidance normals of the most consistent patch
  Bilateral // Zheng et al. 2011: range kernel on the normals themselves
};

struct NormalFilterParams {
  NormalFilterKind kind = NormalFilterKind::Guided;
  double sigma_s = 1.0;  // spatial kernel width, in mean edge lengths (centroid distances)
  double sigma_r = 0.3;  // range kernel width on |n_i − n_j| (unit normals: 0..2)
  int iterations = 15;
  int guidance_every = 1;  // recompute the guidance normals every k-th iteration
  double area_power = 1.0; // weight area^p: 1 as in the papers, 0 on irregular meshes
};

// Called once by the filter after its first `checkpoint_at` iterations with the normals so far
// (unit, one per face); returns the number of iterations the filter runs in all (the guidance
// period goes on where the checkpoint fell, so a checkpoint does not change the normals; a count
// not above `checkpoint_at` stops the filter there).
using NormalFilterCheckpoint = std::function<int(const std::vector<Vec3> &normals)>;

namespace detail {

using Normal3f = Eigen::Vector3f;

// The largest squared distance between two of `count` unit vectors given as coordinate arrays
// padded to a multiple of 4 (the padding repeats a real vector, so it adds no new distance).
// Each i is compared with the j from (i + 1) rounded down to a multiple of 4: the j <= i among
// them are pairs seen from the other side or i itself (distance 0), so the maximum is the same as
// over the pairs i < j, and it is exact whatever the order (no rounding in a maximum).
inline float largestSquaredDistance(const float *xs, const float *ys, const float *zs, int count,
                                    int padded) {
  float largest2 = 0;
#ifdef __SSE2__
  __m128 best = _mm_setzero_ps();
  for (int i = 0; i + 1 < count; ++i) {
    const __m128 xi = _mm_set1_ps(xs[i]), yi = _mm_set1_ps(ys[i]), zi = _mm_set1_ps(zs[i]);
    for (int j = (i + 1) & ~3; j < padded; j += 4) {
      const __m128 dx = _mm_sub_ps(xi, _mm_load_ps(xs + j)), dy = _mm_sub_ps(yi, _mm_load_ps(ys + j)),
                   dz = _mm_sub_ps(zi, _mm_load_ps(zs + j));
      const __m128 d2 =
          _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
      best = _mm_max_ps(best, d2);
    }
  }
  alignas(16) float lanes[4];
  _mm_store_ps(lanes, best);
  for (float l : lanes) largest2 = l > largest2 ? l : largest2;
#else
  for (int i = 0; i + 1 < count; ++i)
    for (int j = (i + 1) & ~3; j < padded; ++j) {
      const float dx = xs[i] - xs[j], dy = ys[i] - ys[j], dz = zs[i] - zs[j];
      const float d2 = (dx * dx + dy * dy) + dz * dz;
      largest2 = d2 > largest2 ? d2 : largest2;
    }
#endif
  return largest2;
}

// Whether `value` is in `values` (length a multiple of 4, 16-byte aligned): four compares at a
// time, no branch on the data (the searches' branches mispredicted on most steps).
inline bool contains(const int *values, int length, int value) {
#ifdef __SSE2__
  const __m128i wanted = _mm_set1_epi32(value);
  __m128i any = _mm_setzero_si128();
  for (int k = 0; k < length; k += 4)
    any = _mm_or_si128(any, _mm_cmpeq_epi32(
                                _mm_load_si128(reinterpret_cast<const __m128i *>(values + k)), wanted));
  return _mm_movemask_epi8(any) != 0;
#else
  bool found = false;
  for (int k = 0; k < length; ++k) found |= values[k] == value;
  return found;
#endif
}

// Per face, the normal jump |n_f − n_g| across each edge to a higher-numbered neighbour g (0 for
// the others), in single precision: patchConsistency's inner edges, once per edge rather than once
// per patch that holds the edge (about six).
using EdgeJumps = std::vector<std::array<float, 3>>;
inline void normalJumps(const FaceRings &face_rings, const std::vector<Normal3f> &normals,
                        EdgeJumps &jumps) {
  const int m = int(normals.size());
  jumps.resize(m);
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
  for (int f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const int g = face_rings.edge_neighbours[f][k];
      float d = 0;
      if (g > f) {
        const float dx = normals[f].x() - normals[g].x(), dy = normals[f].y() - normals[g].y(),
                    dz = normals[f].z() - normals[g].z();
        d = std::sqrt((dx * dx + dy * dy) + dz * dz);
      }
      jumps[f][k] = d;
    }
}

// GNF's patch consistency H = D·R of the vertex ring of `f` (smaller: more consistent): D the
// largest normal difference in the patch, R the largest normal jump across one of its inner edges
// over the sum of those jumps (`jumps`: normalJumps). Also the patch's area-weighted mean normal,
// the guidance it offers. On the filter's single-precision normals; the mean is summed in double.
inline void patchConsistency(int f, const FaceRings &face_rings, const std::vector<Normal3f> &normals,
                             const std::vector<float> &area, const EdgeJumps &jumps,
                             float &consistency, Normal3f &mean_normal) {
  // The patch's normals are gathered first (the pair loop reads each a dozen times), as
  // coordinate arrays for the four-wide pair loop.
  constexpr int kOnStack = 32;
  const int *ring = face_rings.begin(f);
  const int size = face_rings.size(f);
  const int padded = (size + 3) & ~3;
  alignas(16) float on_stack[3][kOnStack];
  alignas(16) int ring_on_stack[kOnStack];
  std::vector<float> on_heap(padded > kOnStack ? 3 * size_t(padded) + 4 : 0);
  std::vector<int> ring_on_heap(padded > kOnStack ? size_t(padded) + 4 : 0);
  float *xs = on_stack[0], *ys = on_stack[1], *zs = on_stack[2];
  int *members = ring_on_stack;
  if (padded > kOnStack) {
    // 16-byte aligned inside the heap blocks.
    float *base = on_heap.data();
    while (reinterpret_cast<std::uintptr_t>(base) % 16 != 0) ++base;
    xs = base, ys = base + padded, zs = base + 2 * padded;
    members = ring_on_heap.data();
    while (reinterpret_cast<std::uintptr_t>(members) % 16 != 0) ++members;
  }
  for (int i = 0; i < size; ++i) members[i] = ring[i];
  for (int i = size; i < padded; ++i) members[i] = -1;
  Vec3 sum = Vec3::Zero();
  for (int i = 0; i < size; ++i) {
    const Normal3f &n = normals[ring[i]];
    xs[i] = n.x(), ys[i] = n.y(), zs[i] = n.z();
    sum += double(area[ring[i]]) * n.cast<double>();
  }
  for (int i = size; i < padded; ++i) xs[i] = xs[size - 1], ys[i] = ys[size - 1], zs[i] = zs[size - 1];
  const float largest2 = largestSquaredDistance(xs, ys, zs, size, padded);
  // Inner edges, each once (from its lower face index), in ring order: an edge that is not inner
  // adds 0, which leaves the sum's bits as they are.
  float largest_jump = 0, jump_sum = 0;
  for (int i = 0; i < size; ++i) {
    const std::array<int, 3> &neighbours = face_rings.edge_neighbours[ring[i]];
    const std::array<float, 3> &jump = jumps[ring[i]];
    for (int k = 0; k < 3; ++k) {
      // (× 1 or 0: exact for the finite jumps of unit or zero normals, and no branch on the data)
      const float d = jump[k] * float(contains(members, padded, neighbours[k]));
      largest_jump = d > largest_jump ? d : largest_jump;
      jump_sum += d;
    }
  }
  consistency = std::sqrt(largest2) * largest_jump / (1e-9f + jump_sum);
  const double len = sum.norm();
  mean_normal = len > 0 ? Normal3f((sum / len).cast<float>()) : normals[f];
}

} // namespace detail

namespace detail {

// The guided filter's guidance: each face takes the area-weighted mean normal of the most
// consistent patch (patchConsistency) that contains it; the lowest face index breaks ties so the
// choice does not depend on the order of the scan.
// `patch_normal`: room for the patches' mean normals (the caller's spare buffer, overwritten). The
// edge jumps are released before the guidance is allocated, so the peak stays that of the
// selection (normals, patch normals, consistencies, guidance).
inline void chooseGuidance(const FaceRings &face_rings, const std::vector<Normal3f> &normals,
                           const std::vector<float> &area, std::vector<Normal3f> &patch_normal,
                           std::vector<Normal3f> &guidance) {
  const int m = int(normals.size());
  std::vector<float> consistency(m);
  patch_normal.resize(m);
  {
    EdgeJumps jumps;
    normalJumps(face_rings, normals, jumps);
    AllocationGuard guard; // (a patch of more than 32 faces takes its arrays from the heap)
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
    for (int f = 0; f < m; ++f)
      guard.run([&] {
        patchConsistency(f, face_rings, normals, area, jumps, consistency[f], patch_normal[f]);
      });
    guard.rethrow();
  }
  guidance.resize(m);
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
  for (int f = 0; f < m; ++f) {
    int best = f;
    for (const int *g = face_rings.begin(f); g != face_rings.end(f); ++g)
      if (consistency[*g] < consistency[best] ||
          (consistency[*g] == consistency[best] && *g < best))
        best = *g;
    guidance[f] = patch_normal[best];
  }
}

// The filter's weight per face-ring entry: spatial Gaussian on the centroids' distance, range
// kernel on the kernel normals' difference, times the area term.
template <class CentroidOf>
void filterWeights(const FaceRings &face_rings, const std::vector<float> &area,
                   CentroidOf centroid_of, const std::vector<Normal3f> &kernel_normals,
                   const NormalFilterParams &params, double mean_edge, std::vector<float> &weight) {
  const int m = int(kernel_normals.size());
  const double spatial = -0.5 / std::pow(params.sigma_s * mean_edge, 2);
  const double range = -0.5 / (params.sigma_r * params.sigma_r);
  weight.resize(face_rings.faces.size());
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
  for (int f = 0; f < m; ++f) {
    const Vec3 own = kernel_normals[f].cast<double>(), own_centroid = centroid_of(f);
    for (int k = face_rings.offsets[f]; k < face_rings.offsets[f + 1]; ++k) {
      const int g = face_rings.faces[k];
      const double ds = (own_centroid - centroid_of(g)).squaredNorm();
      const double face_area = params.area_power == 0.0   ? 1.0
                               : params.area_power == 1.0 ? double(area[g])
                                                          : std::pow(double(area[g]), params.area_power);
      const double dr = (own - kernel_normals[g].cast<double>()).squaredNorm();
      weight[k] = float(face_area * std::exp(spatial * ds) * rangeKernel(range * dr));
    }
  }
}

// One filter iteration: each face's normal becomes the normalised weighted sum of its ring's.
inline void filterIteration(const FaceRings &face_rings, const std::vector<float> &weight,
                            const std::vector<Normal3f> &in, std::vector<Normal3f> &out) {
  const int m = int(in.size());
  out.resize(m);
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
  for (int f = 0; f < m; ++f) {
    Vec3 sum = Vec3::Zero();
    for (int k = face_rings.offsets[f]; k < face_rings.offsets[f + 1]; ++k)
      sum += double(weight[k]) * in[face_rings.faces[k]].cast<double>();
    const double len = sum.norm();
    out[f] = len > 0 && std::isfinite(len) ? Normal3f((sum / len).cast<float>()) : in[f];
  }
}

inline void toDouble(const std::vector<Normal3f> &in, std::vector<Vec3> &out) {
  out.resize(in.size());
  for (size_t f = 0; f < in.size(); ++f) out[f] = in[f].cast<double>();
}

// The normal filter on `normals` in place (see filterNormalsInPlace): `area` per face, and
// `centroid_of(f)` the centroid of face f.
template <class CentroidOf>
void filterNormalsCore(const FaceRings &face_rings, const std::vector<float> &area,
                       CentroidOf centroid_of, const NormalFilterParams &params, double mean_edge,
                       std::vector<Vec3> &normals, int checkpoint_at = 0,
                       const NormalFilterCheckpoint &checkpoint = nullptr) {
  const int m = int(normals.size());
  int iterations = params.iterations;
  if (iterations <= 0 || m == 0) return;
  const bool guided = params.kind == NormalFilterKind::Guided;
  const int every = std::max(1, params.guidance_every);
  std::vector<Normal3f> out(m), next, guidance;
  std::vector<float> weight;
  for (int f = 0; f < m; ++f) out[f] = normals[f].cast<float>();
  std::vector<Vec3>().swap(normals);
  bool pending = checkpoint && checkpoint_at > 0;
  for (int it = 0; it < iterations; ++it) {
    const bool guidance_changed = guided && it % every == 0;
    // The weights change with the kernel normals only: the guided filter's guidance stays for
    // `guidance_every` iterations, and so do its weights (computed once per period). The spatial
    // part (the centroids do not move) is recomputed with them rather than kept: one more exp per
    // entry and period, against another array per face-ring entry held all along.
    if (!guided || guidance_changed) {
      std::vector<float>().swap(weight); // the previous period's
      if (guided) {
        // `next` (the previous iteration's normals, not read again) lends its room to the
        // patches' mean normals, then goes, so the weights do not stack on it.
        chooseGuidance(face_rings, out, area, next, guidance);
        std::vector<Normal3f>().swap(next);
      }
      filterWeights(face_rings, area, centroid_of, guided ? guidance : out, params, mean_edge,
                    weight);
      // The guidance is kept only when the checkpoint falls inside its period, not at its end
      // (the weights are made again from it after the checkpoint).
      if (!(pending && checkpoint_at < it + every)) std::vector<Normal3f>().swap(guidance);
    }
    filterIteration(face_rings, weight, out, next);
    out.swap(next);
    if (pending && it + 1 == checkpoint_at) {
      // The checkpoint sees the normals in double, while the weights (the largest buffer) are
      // released; the filter then goes on in the same guidance period.
      pending = false;
      std::vector<Normal3f>().swap(next);
      std::vector<float>().swap(weight);
      toDouble(out, normals);
      std::vector<Normal3f>().swap(out);
      iterations = checkpoint(normals);
      if (iterations <= it + 1) return; // the normals stay as the checkpoint saw them
      out.resize(m);
      for (int f = 0; f < m; ++f) out[f] = normals[f].cast<float>(); // (exact: they were floats)
      std::vector<Vec3>().swap(normals);
      if (guided && (it + 1) % every != 0) // (inside a period: its weights again)
        filterWeights(face_rings, area, centroid_of, guidance, params, mean_edge, weight);
      std::vector<Normal3f>().swap(guidance);
    }
  }
  std::vector<Normal3f>().swap(next);
  std::vector<float>().swap(weight);
  toDouble(out, normals);
}

} // namespace detail

// Filters face normals in place: `normals` holds the unit normals of the faces of (`points`,
// `faces`) on entry and the filtered ones on return (the positions do not change meanwhile).
// The filter's state is kept in single precision (normals, guidance, consistency, face areas and
// the weights per face-ring entry; sums and weights are computed in double), and the faces'
// centroids are computed where the weights need them: about 80 bytes per face at its peak, most
// of them the weights (4 bytes per face-ring entry). A normal's float rounding (6e-8) is far
// below what the filter resolves. The result is the same for any thread count (every face is
// written by one thread from the previous iteration's values). `normals`' own buffer is released
// while the filter runs. `checkpoint` (optional) sees the normals after `checkpoint_at`
// iterations and may stop the filter there or change its iteration count
// (NormalFilterCheckpoint).
inline void filterNormalsInPlace(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                                 const FaceRings &face_rings, const NormalFilterParams &params,
                                 double mean_edge, std::vector<Vec3> &normals,
                                 int checkpoint_at = 0,
                                 const NormalFilterCheckpoint &checkpoint = nullptr) {
  const int m = int(faces.size());
  std::vector<float> area(m);
#pragma omp parallel for schedule(static) if (m >= min_parallel_vertices)
  for (int f = 0; f < m; ++f) {
    double len;
    detail::unitFaceNormal(points[faces[f][0]], points[faces[f][1]], points[faces[f][2]], len);
    area[f] = float(0.5 * len);
  }
  detail::filterNormalsCore(
      face_rings, area,
      [&](int f) {
        return Vec3((points[faces[f][0]] + points[faces[f][1]] + points[faces[f][2]]) / 3.0);
      },
      params, mean_edge, normals, checkpoint_at, checkpoint);
}

// Filters `geometry.normal` into `out` (unit normals, one per face).
inline void filterNormals(const std::vector<Face> &faces, const FaceRings &face_rings,
                          const FaceGeometry &geometry, const NormalFilterParams &params,
                          double mean_edge, std::vector<Vec3> &out) {
  (void)faces;
  out = geometry.normal;
  const std::vector<float> area(geometry.area.begin(), geometry.area.end());
  detail::filterNormalsCore(
      face_rings, area,
      [&](int f) { return geometry.centroid[f]; }, params, mean_edge, out);
}

} // namespace vcg_ext
