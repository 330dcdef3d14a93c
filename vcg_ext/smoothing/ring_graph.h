// The 1-ring averaging graph of Taubin's steps (a step with factor f is (1 − f) I + f P, P the
// mean of a vertex's 1-ring, or of its two curve neighbours on a boundary), renumbered along a
// Morton curve (spatial_order.h) so that a step's neighbour reads hit the cache.
//
// Inputs: positions (only to choose the order), Rings, the vertices that may not move, the boundary
// curve neighbours. Fields on the graph are kept in its local order (toLocal / toGlobal convert).
// Each vertex's neighbours are listed in the order of its ring, so an average sums them in the
// order taubinSmooth does: the renumbering changes no bit of a result.
#pragma once

#include "vcg_ext/core/rings.h"
#include "vcg_ext/core/spatial_order.h"

#include <array>
#include <cstdint>
#include <vector>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace vcg_ext {

using Vec3f = Eigen::Vector3f;

class RingGraph {
public:
  // How a vertex moves in a step: not at all, along its boundary curve, or toward its 1-ring.
  enum class Kind : std::uint8_t { Still, Curve, Interior };

  // `given_order`: keep the vertices' order (a mesh the drivers already put in spatial order,
  // spatial_order.h), so that local and global indices are the same and nothing is sorted.
  RingGraph(const std::vector<Vec3> &points, const Rings &rings,
            const std::vector<std::uint8_t> &fixed, const std::vector<std::array<int, 2>> &curve,
            bool given_order = false)
      : n_(rings.vertex_count), given_order_(given_order) {
    orderVertices(points);
    listNeighbours(rings, fixed, curve);
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

  int size() const { return n_; }

  Kind kindOf(int l, bool boundary_still) const {
    return boundary_still && kind_[l] == Kind::Curve ? Kind::Still : kind_[l];
  }
  // (P b)[l], the 1-ring averaging of a step: the mean of l's neighbours in its ring's order (of
  // its two curve neighbours on a boundary); b[l] where l is still.
  template <class V> V average(const std::vector<V> &b, int l, Kind kind) const {
    using S = typename V::Scalar;
    const int *begin = neighbours_.data() + offsets_[l],
              *end = neighbours_.data() + offsets_[l + 1];
    if (kind == Kind::Still) return b[l];
    if (kind == Kind::Curve) return S(0.5) * (b[begin[0]] + b[begin[1]]);
    V sum = V::Zero();
    for (const int *w = begin; w != end; ++w) sum += b[*w];
    return sum / S(end - begin);
  }
  // average() of a double and a float field in one pass over l's neighbours: the neighbour list
  // is read once for both (it is a third of a step's memory traffic), each sum as average() takes
  // it.
  void averagePair(const std::vector<Vec3> &a, const std::vector<Vec3f> &b, int l, Kind kind,
                   Vec3 &mean_a, Vec3f &mean_b) const {
    const int *begin = neighbours_.data() + offsets_[l],
              *end = neighbours_.data() + offsets_[l + 1];
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

protected:
  int n_;

private:
  void orderVertices(const std::vector<Vec3> &points) {
    if (given_order_) {
      to_global_.resize(n_);
      for (int v = 0; v < n_; ++v) to_global_[v] = v;
    } else {
      to_global_ = mortonOrder(points);
    }
    to_local_.assign(n_, 0);
    for (int l = 0; l < n_; ++l) to_local_[to_global_[l]] = l;
  }
  // Each vertex's kind and its neighbours in local indices (CSR), in its ring's order.
  void listNeighbours(const Rings &rings, const std::vector<std::uint8_t> &fixed,
                      const std::vector<std::array<int, 2>> &curve) {
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
        for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w)
          *out++ = to_local_[*w];
      }
    }
  }

  bool given_order_;
  std::vector<int> to_global_, to_local_, offsets_, neighbours_;
  std::vector<Kind> kind_;
};

} // namespace vcg_ext
