// Taubin's λ|μ smoothing (normal_filter.h's taubinSmooth) for long runs on large meshes: the same
// steps, bit for bit, over a copy of the 1-ring graph renumbered along a Morton curve
// (spatial_order.h), on several fields at once.
//
// Inputs: positions (only to choose the order), Rings, the vertices that may not move, the boundary
// curve neighbours. Fields are kept in the local order (toLocal / toGlobal convert).
//
// Why: a Taubin step reads every vertex's neighbours, and on a mesh whose vertex order is spatially
// scattered (midpoint subdivision appends new vertices; many exporters do too) nearly every read
// misses the cache. The organic mode's band shrinkage ran 640 such steps (bench/PERFORMANCE.md:
// 14 s of 25 s at 416k vertices; its coarse bands now go through applyChebyshev). Each vertex's neighbours are summed in the order of its ring,
// as taubinSmooth does, so the renumbering changes no bit of the result and the result does not
// depend on the order chosen.
#pragma once

#include "rings.h"
#include "spatial_order.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace vcg_ext {

using Vec3f = Eigen::Vector3f;

class SpatialTaubin {
public:
  // `given_order`: keep the vertices' order (a mesh the drivers already put in spatial order,
  // spatial_order.h), so that local and global indices are the same and nothing is sorted.
  SpatialTaubin(const std::vector<Vec3> &points, const Rings &rings,
                const std::vector<std::uint8_t> &fixed,
                const std::vector<std::array<int, 2>> &curve, bool given_order = false)
      : n_(rings.vertex_count), given_order_(given_order) {
    if (given_order) {
      to_global_.resize(n_);
      for (int v = 0; v < n_; ++v) to_global_[v] = v;
    } else {
      to_global_ = mortonOrder(points);
    }
    to_local_.assign(n_, 0);
    for (int l = 0; l < n_; ++l) to_local_[to_global_[l]] = l;
    offsets_.assign(n_ + 1, 0);
    kind_.assign(n_, Kind::Still);
    for (int l = 0; l < n_; ++l) {
      const int v = to_global_[l];
      int count = 0;
      if (fixed[v] || rings.ring1Size(v) == 0) {
      } else if (rings.boundary[v]) {
        if (curve[v][0] >= 0 && curve[v][1] >= 0) kind_[l] = Kind::Curve, count = 2;
      } else {
        kind_[l] = Kind::Interior, count = rings.ring1Size(v);
      }
      offsets_[l + 1] = offsets_[l] + count;
    }
    neighbours_.resize(offsets_[n_]);
    for (int l = 0; l < n_; ++l) {
      const int v = to_global_[l];
      int *out = neighbours_.data() + offsets_[l];
      if (kind_[l] == Kind::Curve) {
        out[0] = to_local_[curve[v][0]];
        out[1] = to_local_[curve[v][1]];
      } else if (kind_[l] == Kind::Interior) {
        for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w) *out++ = to_local_[*w];
      }
    }
  }

  int local(int v) const { return to_local_[v]; }

  std::vector<Vec3> toLocal(const std::vector<Vec3> &global) const {
    std::vector<Vec3> out(n_);
    for (int l = 0; l < n_; ++l) out[l] = global[to_global_[l]];
    return out;
  }
  std::vector<Vec3> toGlobal(const std::vector<Vec3> &local) const {
    std::vector<Vec3> out(n_);
    for (int l = 0; l < n_; ++l) out[to_global_[l]] = local[l];
    return out;
  }
  // `local` read in the mesh's order: the field itself where the order was kept (no copy), else
  // toGlobal's copy, held in `scratch`.
  const std::vector<Vec3> &inGlobalOrder(const std::vector<Vec3> &local,
                                         std::vector<Vec3> &scratch) const {
    if (given_order_) return local;
    scratch = toGlobal(local);
    return scratch;
  }

  // `pairs` λ|μ pairs on each field (local order). `boundary_still`: boundary vertices stay where
  // they are instead of following their curve.
  void smooth(const std::vector<std::vector<Vec3> *> &fields, int pairs, double lambda, double mu,
              bool boundary_still = false) const {
    smooth(fields, {}, pairs, lambda, mu, boundary_still);
  }

  // The same on double and single precision fields in one sweep (one read of the graph for all):
  // single precision serves fields whose values are only summed into energies (the band
  // shrinkage's probe), at half the memory traffic.
  void smooth(const std::vector<std::vector<Vec3> *> &fields,
              const std::vector<std::vector<Vec3f> *> &float_fields, int pairs, double lambda,
              double mu, bool boundary_still = false) const {
    const int count = int(fields.size()), float_count = int(float_fields.size());
    const bool paired = count == 1 && float_count == 1; // the band shrinkage's case
    // The step's output buffers are kept between calls (a band shrinkage makes dozens of calls).
    reserveBuffers(next_, count);
    reserveBuffers(next_float_, float_count);
    for (int step = 0; step < 2 * pairs; ++step) {
      const double factor = step % 2 == 0 ? lambda : mu;
#pragma omp parallel for schedule(static) if (n_ >= min_parallel_vertices)
      for (int l = 0; l < n_; ++l) {
        const Kind kind = kindOf(l, boundary_still);
        if (paired) {
          Vec3 a;
          Vec3f b;
          averagePair(*fields[0], *float_fields[0], l, kind, a, b);
          next_[0][l] = stepWith(*fields[0], l, kind, factor, a);
          next_float_[0][l] = stepWith(*float_fields[0], l, kind, float(factor), b);
          continue;
        }
        for (int k = 0; k < count; ++k) next_[k][l] = stepAt(*fields[k], l, kind, factor);
        for (int k = 0; k < float_count; ++k)
          next_float_[k][l] = stepAt(*float_fields[k], l, kind, float(factor));
      }
      for (int k = 0; k < count; ++k) fields[k]->swap(next_[k]);
      for (int k = 0; k < float_count; ++k) float_fields[k]->swap(next_float_[k]);
    }
  }

  // outputs[k] = Σ_j c_j T_j(P) inputs[k] (Clenshaw's recurrence), where P is the 1-ring
  // averaging of smooth()'s steps (a step with factor f is (1 − f) I + f P): with the coefficients
  // of taubinChebyshevCoefficients, close to `pairs` smooth() pairs in fewer operator applications
  // (taubin_chebyshev.h). Still vertices (and, with `boundary_still`, the boundary curves) keep
  // their input values exactly. Sums are taken relative to each field's bounding-box centre, so
  // the truncation error scales with the field's extent, not with its distance from the origin.
  // Inputs and outputs are distinct fields in local order; each vertex's arithmetic is fixed, so the
  // result does not depend on the thread count. The float fields (as in smooth) run the same
  // recurrence in single precision.
  void applyChebyshev(const std::vector<const std::vector<Vec3> *> &inputs,
                      const std::vector<std::vector<Vec3> *> &outputs,
                      const std::vector<double> &c, bool boundary_still = false) const {
    applyChebyshev(inputs, outputs, {}, {}, c, boundary_still);
  }

  void applyChebyshev(const std::vector<const std::vector<Vec3> *> &inputs,
                      const std::vector<std::vector<Vec3> *> &outputs,
                      const std::vector<const std::vector<Vec3f> *> &float_inputs,
                      const std::vector<std::vector<Vec3f> *> &float_outputs,
                      const std::vector<double> &c, bool boundary_still = false) const {
    const int count = int(inputs.size()), float_count = int(float_inputs.size());
    const bool paired = count == 1 && float_count == 1; // the band shrinkage's case
    const int degree = int(c.size()) - 1;
    reserveBuffers(next_, count);
    reserveBuffers(next_float_, float_count);
    std::vector<Vec3> centre(count);
    std::vector<Vec3f> float_centre(float_count);
    for (int k = 0; k < count; ++k) centre[k] = clenshawStart(*inputs[k], next_[k], *outputs[k]);
    for (int k = 0; k < float_count; ++k)
      float_centre[k] = clenshawStart(*float_inputs[k], next_float_[k], *float_outputs[k]);
    for (int j = degree; j >= 1; --j) {
      const double cj = c[j];
#pragma omp parallel for schedule(static) if (n_ >= min_parallel_vertices)
      for (int l = 0; l < n_; ++l) {
        const Kind kind = kindOf(l, boundary_still);
        if (paired) {
          Vec3 a;
          Vec3f b;
          averagePair(next_[0], next_float_[0], l, kind, a, b);
          clenshawStepWith(cj, *inputs[0], centre[0], a, *outputs[0], l);
          clenshawStepWith(float(cj), *float_inputs[0], float_centre[0], b, *float_outputs[0], l);
          continue;
        }
        for (int k = 0; k < count; ++k)
          clenshawStep(cj, *inputs[k], centre[k], next_[k], *outputs[k], l, kind);
        for (int k = 0; k < float_count; ++k)
          clenshawStep(float(cj), *float_inputs[k], float_centre[k], next_float_[k],
                       *float_outputs[k], l, kind);
      }
      for (int k = 0; k < count; ++k) next_[k].swap(*outputs[k]);
      for (int k = 0; k < float_count; ++k) next_float_[k].swap(*float_outputs[k]);
    }
    // next_ = b_1, outputs = b_2: the result c_0 x + P b_1 − b_2, in place of b_2.
#pragma omp parallel for schedule(static) if (n_ >= min_parallel_vertices)
    for (int l = 0; l < n_; ++l) {
      const Kind kind = kindOf(l, boundary_still);
      if (paired) {
        Vec3 a;
        Vec3f b;
        averagePair(next_[0], next_float_[0], l, kind, a, b);
        clenshawEndWith(c[0], *inputs[0], centre[0], a, *outputs[0], l, kind);
        clenshawEndWith(float(c[0]), *float_inputs[0], float_centre[0], b, *float_outputs[0], l,
                        kind);
        continue;
      }
      for (int k = 0; k < count; ++k)
        clenshawEnd(c[0], *inputs[k], centre[k], next_[k], *outputs[k], l, kind);
      for (int k = 0; k < float_count; ++k)
        clenshawEnd(float(c[0]), *float_inputs[k], float_centre[k], next_float_[k],
                    *float_outputs[k], l, kind);
    }
  }

  // Frees the step buffers that smooth() and applyChebyshev() keep between calls (they come back
  // on the next call).
  void releaseBuffers() const {
    std::vector<std::vector<Vec3>>().swap(next_);
    std::vector<std::vector<Vec3f>>().swap(next_float_);
  }

private:
  enum class Kind : std::uint8_t { Still, Curve, Interior };

  Kind kindOf(int l, bool boundary_still) const {
    return boundary_still && kind_[l] == Kind::Curve ? Kind::Still : kind_[l];
  }
  // (P b)[l], the 1-ring averaging of a step: the mean of l's neighbours in its ring's order (of
  // its two curve neighbours on a boundary); b[l] where l is still.
  template <class V> V average(const std::vector<V> &b, int l, Kind kind) const {
    using S = typename V::Scalar;
    const int *begin = neighbours_.data() + offsets_[l], *end = neighbours_.data() + offsets_[l + 1];
    if (kind == Kind::Still) return b[l];
    if (kind == Kind::Curve) return S(0.5) * (b[begin[0]] + b[begin[1]]);
    V sum = V::Zero();
    for (const int *w = begin; w != end; ++w) sum += b[*w];
    return sum / S(end - begin);
  }
  // average() of a double and a float field in one pass over l's neighbours: the neighbour list
  // is read once for both (it is a third of a step's memory traffic), each sum as average() takes it.
  void averagePair(const std::vector<Vec3> &a, const std::vector<Vec3f> &b, int l, Kind kind,
                   Vec3 &mean_a, Vec3f &mean_b) const {
    const int *begin = neighbours_.data() + offsets_[l], *end = neighbours_.data() + offsets_[l + 1];
    if (kind == Kind::Still) {
      mean_a = a[l], mean_b = b[l];
    } else if (kind == Kind::Curve) {
      mean_a = 0.5 * (a[begin[0]] + a[begin[1]]);
      mean_b = 0.5f * (b[begin[0]] + b[begin[1]]);
    } else {
      Vec3 sum_a = Vec3::Zero();
#ifdef __SSE2__
      // The float sums in the lanes of one register: lane by lane the same additions and
      // division as Eigen's three scalar ones (the same bits), one division instead of three.
      __m128 sum_b = _mm_setzero_ps();
      for (const int *w = begin; w != end; ++w) {
        sum_a += a[*w];
        const float *q = b[*w].data();
        // (x, y) by one unaligned 64-bit load (of a type that may alias floats), z by a float load.
        const __m128 xy = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i *>(q)));
        sum_b = _mm_add_ps(sum_b, _mm_movelh_ps(xy, _mm_load_ss(q + 2)));
      }
      mean_a = sum_a / double(end - begin);
      alignas(16) float mean[4];
      _mm_store_ps(mean, _mm_div_ps(sum_b, _mm_set1_ps(float(end - begin))));
      mean_b = Vec3f(mean[0], mean[1], mean[2]);
#else
      Vec3f sum_b = Vec3f::Zero();
      for (const int *w = begin; w != end; ++w) sum_a += a[*w], sum_b += b[*w];
      mean_a = sum_a / double(end - begin);
      mean_b = sum_b / float(end - begin);
#endif
    }
  }
  // One smooth() step at l: the arithmetic of taubinSmooth, operation for operation.
  template <class V, class S>
  V stepAt(const std::vector<V> &p, int l, Kind kind, S factor) const {
    return kind == Kind::Still ? p[l] : stepWith(p, l, kind, factor, average(p, l, kind));
  }
  // The same with the average given.
  template <class V, class S>
  V stepWith(const std::vector<V> &p, int l, Kind kind, S factor, const V &mean) const {
    return kind == Kind::Still ? p[l] : V(p[l] + factor * (mean - p[l]));
  }
  // Clenshaw's start: b_{j+1} = b_{j+2} = 0; returns the field's bounding-box centre.
  template <class V>
  V clenshawStart(const std::vector<V> &input, std::vector<V> &scratch, std::vector<V> &out) const {
    using S = typename V::Scalar;
    V lo = V::Constant(S(INFINITY)), hi = V::Constant(S(-INFINITY));
    for (const V &x : input)
      if (x.allFinite()) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    scratch.assign(n_, V::Zero()); // b_{j+1}
    out.assign(n_, V::Zero());     // b_{j+2}, then b_j in place, at last the result
    return lo.allFinite() ? V(S(0.5) * (lo + hi)) : V::Zero();
  }
  // b_j = c_j (x − centre) + 2 P b_{j+1} − b_{j+2}, written over b_{j+2} in `b`.
  template <class V, class S>
  void clenshawStep(S cj, const std::vector<V> &input, const V &centre, const std::vector<V> &next,
                    std::vector<V> &b, int l, Kind kind) const {
    clenshawStepWith(cj, input, centre, average(next, l, kind), b, l);
  }
  // The same with (P b_{j+1})[l] given.
  template <class V, class S>
  void clenshawStepWith(S cj, const std::vector<V> &input, const V &centre, const V &mean,
                        std::vector<V> &b, int l) const {
    b[l] = cj * (input[l] - centre) + S(2) * mean - b[l];
  }
  // The result c_0 x + P b_1 − b_2 (b_1 in `next`, b_2 in `out`), in place of b_2.
  template <class V, class S>
  void clenshawEnd(S c0, const std::vector<V> &input, const V &centre, const std::vector<V> &next,
                   std::vector<V> &out, int l, Kind kind) const {
    clenshawEndWith(c0, input, centre, average(next, l, kind), out, l, kind);
  }
  template <class V, class S>
  void clenshawEndWith(S c0, const std::vector<V> &input, const V &centre, const V &mean,
                       std::vector<V> &out, int l, Kind kind) const {
    const V &x = input[l];
    out[l] = kind == Kind::Still ? x : V(centre + (c0 * (x - centre) + mean - out[l]));
  }
  template <class V>
  void reserveBuffers(std::vector<std::vector<V>> &buffers, int count) const {
    if (int(buffers.size()) < count) buffers.resize(count);
    for (int k = 0; k < count; ++k) buffers[k].resize(n_);
  }

  int n_;
  bool given_order_;
  std::vector<int> to_global_, to_local_, offsets_, neighbours_;
  std::vector<Kind> kind_;
  mutable std::vector<std::vector<Vec3>> next_;
  mutable std::vector<std::vector<Vec3f>> next_float_;
};

} // namespace vcg_ext
