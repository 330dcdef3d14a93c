// Taubin's λ|μ smoothing (smoothing/taubin.h's taubinSmooth) for long runs on large meshes: the
// same steps, bit for bit, on the cache-friendly graph of ring_graph.h, on several fields at once,
// and many pairs at once as a Chebyshev series (taubin_chebyshev.h).
//
// Inputs: positions (only to choose the order), Rings, the vertices that may not move, the boundary
// curve neighbours. Fields are kept in the graph's local order (toLocal / toGlobal convert).
//
// Why: a Taubin step reads every vertex's neighbours, and on a mesh whose vertex order is spatially
// scattered (midpoint subdivision appends new vertices; many exporters do too) nearly every read
// misses the cache; the organic mode's band shrinkage runs hundreds of such steps
// (docs/studies/performance.md).
#pragma once

#include "vcg_ext/smoothing/ring_graph.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace vcg_ext {

namespace detail {
// Clenshaw's recurrence for Σ c_j T_j(P) x, one vertex at a time (SpatialTaubin::applyChebyshev).
// Clenshaw's start: b_{j+1} = b_{j+2} = 0; returns the field's bounding-box centre.
template <class V>
V clenshawStart(const std::vector<V> &input, std::vector<V> &scratch, std::vector<V> &out) {
  using S = typename V::Scalar;
  V lo = V::Constant(S(INFINITY)), hi = V::Constant(S(-INFINITY));
  for (const V &x : input)
    if (x.allFinite()) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  scratch.assign(input.size(), V::Zero()); // b_{j+1}
  out.assign(input.size(), V::Zero());     // b_{j+2}, then b_j in place, at last the result
  return lo.allFinite() ? V(S(0.5) * (lo + hi)) : V::Zero();
}
// b_j = c_j (x − centre) + 2 P b_{j+1} − b_{j+2}, written over b_{j+2} in `b`; mean = (P
// b_{j+1})[l].
template <class V, class S>
void clenshawStepWith(S cj, const std::vector<V> &input, const V &centre, const V &mean,
                      std::vector<V> &b, int l) {
  b[l] = cj * (input[l] - centre) + S(2) * mean - b[l];
}
// The result c_0 x + P b_1 − b_2 (mean = (P b_1)[l], b_2 in `out`), in place of b_2.
template <class V, class S>
void clenshawEndWith(S c0, const std::vector<V> &input, const V &centre, const V &mean,
                     std::vector<V> &out, int l, RingGraph::Kind kind) {
  const V &x = input[l];
  out[l] = kind == RingGraph::Kind::Still ? x : V(centre + (c0 * (x - centre) + mean - out[l]));
}
} // namespace detail

class SpatialTaubin : public RingGraph {
public:
  using RingGraph::RingGraph;

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
  // Inputs and outputs are distinct fields in local order; each vertex's arithmetic is fixed, so
  // the result does not depend on the thread count. The float fields (as in smooth) run the same
  // recurrence in single precision.
  void applyChebyshev(const std::vector<const std::vector<Vec3> *> &inputs,
                      const std::vector<std::vector<Vec3> *> &outputs, const std::vector<double> &c,
                      bool boundary_still = false) const {
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
    for (int k = 0; k < count; ++k)
      centre[k] = detail::clenshawStart(*inputs[k], next_[k], *outputs[k]);
    for (int k = 0; k < float_count; ++k)
      float_centre[k] = detail::clenshawStart(*float_inputs[k], next_float_[k], *float_outputs[k]);
    for (int j = degree; j >= 1; --j) {
      const double cj = c[j];
#pragma omp parallel for schedule(static) if (n_ >= min_parallel_vertices)
      for (int l = 0; l < n_; ++l) {
        const Kind kind = kindOf(l, boundary_still);
        if (paired) {
          Vec3 a;
          Vec3f b;
          averagePair(next_[0], next_float_[0], l, kind, a, b);
          detail::clenshawStepWith(cj, *inputs[0], centre[0], a, *outputs[0], l);
          detail::clenshawStepWith(float(cj), *float_inputs[0], float_centre[0], b,
                                   *float_outputs[0], l);
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
        detail::clenshawEndWith(c[0], *inputs[0], centre[0], a, *outputs[0], l, kind);
        detail::clenshawEndWith(float(c[0]), *float_inputs[0], float_centre[0], b,
                                *float_outputs[0], l, kind);
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
  // One smooth() step at l: the arithmetic of taubinSmooth, operation for operation.
  template <class V, class S> V stepAt(const std::vector<V> &p, int l, Kind kind, S factor) const {
    return kind == Kind::Still ? p[l] : stepWith(p, l, kind, factor, average(p, l, kind));
  }
  // The same with the average given.
  template <class V, class S>
  V stepWith(const std::vector<V> &p, int l, Kind kind, S factor, const V &mean) const {
    return kind == Kind::Still ? p[l] : V(p[l] + factor * (mean - p[l]));
  }
  // b_j = c_j (x − centre) + 2 P b_{j+1} − b_{j+2}, written over b_{j+2} in `b`.
  template <class V, class S>
  void clenshawStep(S cj, const std::vector<V> &input, const V &centre, const std::vector<V> &next,
                    std::vector<V> &b, int l, Kind kind) const {
    detail::clenshawStepWith(cj, input, centre, average(next, l, kind), b, l);
  }
  // The result c_0 x + P b_1 − b_2 (b_1 in `next`, b_2 in `out`), in place of b_2.
  template <class V, class S>
  void clenshawEnd(S c0, const std::vector<V> &input, const V &centre, const std::vector<V> &next,
                   std::vector<V> &out, int l, Kind kind) const {
    detail::clenshawEndWith(c0, input, centre, average(next, l, kind), out, l, kind);
  }
  template <class V> void reserveBuffers(std::vector<std::vector<V>> &buffers, int count) const {
    if (int(buffers.size()) < count) buffers.resize(count);
    for (int k = 0; k < count; ++k) buffers[k].resize(n_);
  }

  mutable std::vector<std::vector<Vec3>> next_;
  mutable std::vector<std::vector<Vec3f>> next_float_;
};

} // namespace vcg_ext
