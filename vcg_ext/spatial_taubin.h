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

namespace vcg_ext {

class SpatialTaubin {
public:
  SpatialTaubin(const std::vector<Vec3> &points, const Rings &rings,
                const std::vector<std::uint8_t> &fixed,
                const std::vector<std::array<int, 2>> &curve)
      : n_(rings.vertex_count) {
    to_global_ = mortonOrder(points);
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

  // `pairs` λ|μ pairs on each field (local order). `boundary_still`: boundary vertices stay where
  // they are instead of following their curve.
  void smooth(const std::vector<std::vector<Vec3> *> &fields, int pairs, double lambda, double mu,
              bool boundary_still = false) const {
    const int count = int(fields.size());
    // The step's output buffers are kept between calls (a band shrinkage makes dozens of calls).
    std::vector<std::vector<Vec3>> &next = next_;
    if (int(next.size()) < count) next.resize(count);
    for (int k = 0; k < count; ++k) next[k].resize(n_);
    for (int step = 0; step < 2 * pairs; ++step) {
      const double factor = step % 2 == 0 ? lambda : mu;
#pragma omp parallel for schedule(static) if (n_ >= min_parallel_vertices)
      for (int l = 0; l < n_; ++l) {
        const Kind kind = kindOf(l, boundary_still);
        for (int k = 0; k < count; ++k) {
          const std::vector<Vec3> &p = *fields[k];
          // The arithmetic of taubinSmooth, operation for operation.
          next[k][l] = kind == Kind::Still ? p[l] : Vec3(p[l] + factor * (average(p, l, kind) - p[l]));
        }
      }
      for (int k = 0; k < count; ++k) fields[k]->swap(next[k]);
    }
  }

  // outputs[k] = Σ_j c_j T_j(P) inputs[k] (Clenshaw's recurrence), where P is the 1-ring
  // averaging of smooth()'s steps (a step with factor f is (1 − f) I + f P): with the coefficients
  // of taubinChebyshevCoefficients, close to `pairs` smooth() pairs in fewer operator applications
  // (taubin_chebyshev.h). Still vertices (and, with `boundary_still`, the boundary curves) keep
  // their input values exactly. Sums are taken relative to each field's bounding-box centre, so
  // the truncation error scales with the field's extent, not with its distance from the origin.
  // Inputs and outputs are distinct fields in local order; each vertex's arithmetic is fixed, so the
  // result does not depend on the thread count.
  void applyChebyshev(const std::vector<const std::vector<Vec3> *> &inputs,
                      const std::vector<std::vector<Vec3> *> &outputs,
                      const std::vector<double> &c, bool boundary_still = false) const {
    const int count = int(inputs.size()), degree = int(c.size()) - 1;
    std::vector<std::vector<Vec3>> &scratch = next_;
    if (int(scratch.size()) < count) scratch.resize(count);
    std::vector<Vec3> centre(count);
    for (int k = 0; k < count; ++k) {
      Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
      for (const Vec3 &x : *inputs[k])
        if (x.allFinite()) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
      centre[k] = lo.allFinite() ? Vec3(0.5 * (lo + hi)) : Vec3::Zero();
      scratch[k].assign(n_, Vec3::Zero()); // b_{j+1}
      outputs[k]->assign(n_, Vec3::Zero()); // b_{j+2}, then b_j in place, at last the result
    }
    for (int j = degree; j >= 1; --j) {
      const double cj = c[j];
#pragma omp parallel for schedule(static) if (n_ >= min_parallel_vertices)
      for (int l = 0; l < n_; ++l) {
        const Kind kind = kindOf(l, boundary_still);
        for (int k = 0; k < count; ++k) {
          Vec3 &b = (*outputs[k])[l]; // b_{j+2} in, b_j out
          b = cj * ((*inputs[k])[l] - centre[k]) + 2.0 * average(scratch[k], l, kind) - b;
        }
      }
      for (int k = 0; k < count; ++k) scratch[k].swap(*outputs[k]);
    }
    // scratch = b_1, outputs = b_2: the result c_0 x + P b_1 − b_2, in place of b_2.
#pragma omp parallel for schedule(static) if (n_ >= min_parallel_vertices)
    for (int l = 0; l < n_; ++l) {
      const Kind kind = kindOf(l, boundary_still);
      for (int k = 0; k < count; ++k) {
        const Vec3 &x = (*inputs[k])[l];
        Vec3 &out = (*outputs[k])[l];
        out = kind == Kind::Still
                  ? x
                  : Vec3(centre[k] + (c[0] * (x - centre[k]) + average(scratch[k], l, kind) - out));
      }
    }
  }

private:
  enum class Kind : std::uint8_t { Still, Curve, Interior };

  Kind kindOf(int l, bool boundary_still) const {
    return boundary_still && kind_[l] == Kind::Curve ? Kind::Still : kind_[l];
  }
  // (P b)[l], the 1-ring averaging of a step: the mean of l's neighbours in its ring's order (of
  // its two curve neighbours on a boundary); b[l] where l is still.
  Vec3 average(const std::vector<Vec3> &b, int l, Kind kind) const {
    const int *begin = neighbours_.data() + offsets_[l], *end = neighbours_.data() + offsets_[l + 1];
    if (kind == Kind::Still) return b[l];
    if (kind == Kind::Curve) return 0.5 * (b[begin[0]] + b[begin[1]]);
    Vec3 sum = Vec3::Zero();
    for (const int *w = begin; w != end; ++w) sum += b[*w];
    return sum / int(end - begin);
  }

  int n_;
  std::vector<int> to_global_, to_local_, offsets_, neighbours_;
  std::vector<Kind> kind_;
  mutable std::vector<std::vector<Vec3>> next_;
};

} // namespace vcg_ext
