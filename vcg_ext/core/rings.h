// Stage 0: mesh topology computed once per run, in compressed (CSR) arrays.
//
// Inputs: vertex count and triangles (compact indices). Outputs: per-vertex incident faces, 1-ring
// and 2-ring vertex lists (sorted, without the vertex itself), boundary / non-manifold / isolated
// flags. Positions are not needed; edge statistics are a separate function because positions
// change every iteration while the rings do not.
#pragma once

#include "vcg_ext/core/mesh_arrays.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <new>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace vcg_ext {

struct Rings {
  int vertex_count = 0;
  std::vector<int> face_offsets, faces; // faces around vertex v: faces[face_offsets[v] .. +1)
  std::vector<int> ring1_offsets, ring1;
  std::vector<int> ring2_offsets, ring2; // 2-ring includes the 1-ring; see computeRings
  std::vector<std::uint8_t> boundary;    // on an edge used by exactly one face
  std::vector<std::uint8_t> nonmanifold; // on an edge of > 2 faces, or its faces form > 1 fan
  std::vector<std::uint8_t> isolated;    // referenced by no face
  long boundary_edges = 0, nonmanifold_edges = 0; // both zero: the surface encloses a volume

  int ring1Size(int v) const { return ring1_offsets[v + 1] - ring1_offsets[v]; }
  int ring2Size(int v) const { return ring2_offsets[v + 1] - ring2_offsets[v]; }
  const int *ring1Begin(int v) const { return ring1.data() + ring1_offsets[v]; }
  const int *ring1End(int v) const { return ring1.data() + ring1_offsets[v + 1]; }
  const int *ring2Begin(int v) const { return ring2.data() + ring2_offsets[v]; }
  const int *ring2End(int v) const { return ring2.data() + ring2_offsets[v + 1]; }
  const int *facesBegin(int v) const { return faces.data() + face_offsets[v]; }
  const int *facesEnd(int v) const { return faces.data() + face_offsets[v + 1]; }
};

// (min_parallel_vertices: mesh_arrays.h)

// The stages whose work per element is a microsecond or more (the patch fits and the vertices'
// moves onto the patches, the saliency's exact sums and lattice chains, the curvature fits) run
// in parallel from this many elements: a few regions per run, each long enough that a wait for a
// descheduled thread stays small against it (on a busy machine every stage in parallel made a
// small mesh several times slower; docs/studies/performance.md). Never above
// min_parallel_vertices (the tests set that to 0).
inline int min_parallel_heavy = 5000;
inline bool parallelHeavy(long count) {
  return count >= std::min(min_parallel_vertices, min_parallel_heavy);
}

namespace detail {

// An allocation that fails inside an OpenMP region cannot leave it as an exception (the runtime
// calls std::terminate: the process aborts). Regions that allocate run their bodies through
// `run`, which notes the failure, and call rethrow() after the region, where std::bad_alloc can
// reach the filter (which refuses the run and leaves the mesh as it was).
class AllocationGuard {
public:
  template <class Body> void run(Body &&body) noexcept {
    if (failed_.load(std::memory_order_relaxed)) return;
    try {
      body();
    } catch (const std::bad_alloc &) {
      failed_.store(true, std::memory_order_relaxed);
    }
  }
  void rethrow() const {
    if (failed_.load()) throw std::bad_alloc();
  }

private:
  std::atomic<bool> failed_{false};
};

// Per-vertex lists built in parallel: vertices are cut into fixed blocks (independent of the thread
// count), each block appends its vertices' lists to its own buffer via `fill(v, out)`, and the
// buffers are joined in vertex order into a CSR.
constexpr int kCsrBlock = 4096;

template <class Fill>
void buildCsrInBlocks(int n, std::vector<int> &offsets, std::vector<int> &values, Fill fill) {
  const int block = kCsrBlock, blocks = (n + block - 1) / block;
  std::vector<std::vector<int>> buffer(blocks);
  offsets.assign(n + 1, 0);
  AllocationGuard guard;
#pragma omp parallel for schedule(dynamic, 1) if (n >= min_parallel_vertices)
  for (int b = 0; b < blocks; ++b)
    guard.run([&] {
      std::vector<int> &out = buffer[b];
      for (int v = b * block; v < std::min(n, (b + 1) * block); ++v) {
        const size_t before = out.size();
        fill(v, out);
        offsets[v + 1] = int(out.size() - before);
      }
    });
  guard.rethrow();
  for (int v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
  values.resize(offsets[n]);
  for (int b = 0; b < blocks; ++b)
    std::copy(buffer[b].begin(), buffer[b].end(), values.begin() + offsets[b * block]);
}

// Sorts `values` ascending, in parallel where OpenMP is on: blocks sorted by std::sort, then merged
// pairwise, the merges writing into a buffer allocated before any parallel region (std::sort and
// std::merge allocate nothing). libstdc++'s parallel mode allocated inside its threads, where a
// failed allocation cannot reach the caller: under an address-space limit the process aborted
// instead of the filter refusing (MemoryCheck.AllocationFailureAnywhereInARunIsARefusal...). For
// values that are all distinct or equal only when identical, the result is std::sort's, whatever
// the number of blocks.
template <class T> void parallelSort(std::vector<T> &values) {
  // Already sorted (the second Morton order of a mesh the driver put in that order): a check
  // instead of a sort, the same sequence (equal elements are equal values).
  if (std::is_sorted(values.begin(), values.end())) return;
  const size_t n = values.size();
  int blocks = 1;
#ifdef _OPENMP
  if (n >= size_t(std::max(min_parallel_vertices, 2)))
    while (blocks < omp_get_max_threads() && blocks < 64) blocks *= 2;
#endif
  if (blocks == 1) {
    std::sort(values.begin(), values.end());
    return;
  }
  std::vector<T> buffer(n);
  auto bound = [&](int b) { return ptrdiff_t(n * size_t(b) / size_t(blocks)); };
#pragma omp parallel for schedule(static, 1)
  for (int b = 0; b < blocks; ++b)
    std::sort(values.begin() + bound(b), values.begin() + bound(b + 1));
  std::vector<T> *from = &values, *to = &buffer;
  for (int width = 1; width < blocks; width *= 2) {
#pragma omp parallel for schedule(static, 1)
    for (int b = 0; b < blocks; b += 2 * width) {
      const auto lo = bound(b), mid = bound(std::min(b + width, blocks)),
                 hi = bound(std::min(b + 2 * width, blocks));
      std::merge(from->begin() + lo, from->begin() + mid, from->begin() + mid, from->begin() + hi,
                 to->begin() + lo);
    }
    std::swap(from, to);
  }
  if (from != &values) values.swap(*from);
}

} // namespace detail

namespace detail {

// Faces around each vertex, in face order (a face naming a vertex twice is listed twice).
inline void facesAroundVertices(int n, const std::vector<Face> &faces, Rings &r) {
  r.face_offsets.assign(n + 1, 0);
  for (const Face &f : faces)
    for (int k = 0; k < 3; ++k) ++r.face_offsets[f[k] + 1];
  for (int v = 0; v < n; ++v) r.face_offsets[v + 1] += r.face_offsets[v];
  r.faces.resize(r.face_offsets[n]);
  std::vector<int> cursor(r.face_offsets.begin(), r.face_offsets.end() - 1);
  for (int f = 0; f < int(faces.size()); ++f)
    for (int k = 0; k < 3; ++k) r.faces[cursor[faces[f][k]]++] = f;
}

// The other ends of the half-edges (f[k], f[k+1]) of v's faces that touch v, sorted: each
// neighbour as often as it has faces with v across their shared edge.
inline void edgeEndsAround(int v, const Rings &r, const std::vector<Face> &faces,
                           std::vector<int> &ends) {
  ends.clear();
  for (const int *f = r.facesBegin(v); f != r.facesEnd(v); ++f) {
    if (f != r.facesBegin(v) && *f == f[-1]) continue; // the same face again
    const Face &t = faces[*f];
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a == b) continue;
      if (a == v) ends.push_back(b);
      else if (b == v) ends.push_back(a);
    }
  }
  std::sort(ends.begin(), ends.end());
}

// Whether v's faces (at least one) form one fan: its link (the edges opposite to it) is one path
// or one cycle. Counts the link's connected components by repeatedly absorbing faces that share a
// neighbour with the growing fan; a second component is a "bow-tie".
inline bool facesFormOneFan(int v, const Rings &r, const std::vector<Face> &faces) {
  thread_local std::vector<int> fan_faces, members;
  fan_faces.assign(r.facesBegin(v), r.facesEnd(v));
  members.clear();
  auto others = [&](int f, int k) {
    const Face &t = faces[f];
    return t[0] == v ? (k ? t[2] : t[1]) : t[1] == v ? (k ? t[0] : t[2]) : (k ? t[1] : t[0]);
  };
  members.push_back(others(fan_faces.back(), 0));
  members.push_back(others(fan_faces.back(), 1));
  fan_faces.pop_back();
  for (bool grew = true; grew && !fan_faces.empty();) {
    grew = false;
    for (size_t k = 0; k < fan_faces.size();) {
      const int a = others(fan_faces[k], 0), b = others(fan_faces[k], 1);
      const bool touches = std::find(members.begin(), members.end(), a) != members.end() ||
                           std::find(members.begin(), members.end(), b) != members.end();
      if (touches) {
        members.push_back(a);
        members.push_back(b);
        fan_faces[k] = fan_faces.back();
        fan_faces.pop_back();
        grew = true;
      } else {
        ++k;
      }
    }
  }
  return fan_faces.empty();
}

// v's 2-ring: the union of its neighbours' (sorted) 1-rings and its own, without v. A
// non-manifold neighbour is included but not expanded: its 1-ring reaches into other sheets (a
// fin, a second fan), which would bend the patch fitted to this one (measured: a fin of height
// 0.3 on a unit grid lifted its neighbours by 0.07). Merging sorted lists costs less than sorting
// their concatenation.
inline void mergedTwoRing(int v, const Rings &r, std::vector<int> &out) {
  thread_local std::vector<int> ring, merged;
  ring.assign(r.ring1Begin(v), r.ring1End(v));
  for (const int *a = r.ring1Begin(v); a != r.ring1End(v); ++a) {
    if (r.nonmanifold[*a]) continue;
    merged.resize(ring.size() + r.ring1Size(*a));
    merged.erase(std::set_union(ring.begin(), ring.end(), r.ring1Begin(*a), r.ring1End(*a),
                                merged.begin()),
                 merged.end());
    ring.swap(merged);
  }
  for (int w : ring)
    if (w != v) out.push_back(w);
}

} // namespace detail

// Builds the rings of a triangle mesh with `vertex_count` vertices. Every list is gathered per
// vertex from its own faces (no global sort of the edges), in parallel, in vertex order.
// `with_two_rings` false leaves the 2-rings empty: only the paper's patches read them, and they
// are the largest lists (about 18 entries per vertex, 76 bytes per vertex with the offsets).
inline Rings computeRings(int vertex_count, const std::vector<Face> &faces,
                          bool with_two_rings = true) {
  Rings r;
  r.vertex_count = vertex_count;
  const int n = vertex_count;
  detail::facesAroundVertices(n, faces, r);
  r.boundary.assign(n, 0);
  r.nonmanifold.assign(n, 0);
  r.isolated.assign(n, 0);
  // 1-ring and each edge's face count: an edge used by one face is a boundary edge, by more than
  // two a non-manifold one; each edge is counted once overall, from its smaller end. Then the fan
  // test (isolated and bow-tie vertices). Per block of buildCsrInBlocks (one thread each): edge
  // counts without a shared counter.
  const int blocks = n / detail::kCsrBlock + 1;
  std::vector<long> block_boundary_edges(blocks, 0), block_nonmanifold_edges(blocks, 0);
  detail::buildCsrInBlocks(n, r.ring1_offsets, r.ring1, [&](int v, std::vector<int> &out) {
    thread_local std::vector<int> ends;
    detail::edgeEndsAround(v, r, faces, ends);
    for (size_t i = 0; i < ends.size();) {
      size_t j = i;
      while (j < ends.size() && ends[j] == ends[i]) ++j;
      const int count = int(j - i), w = ends[i];
      if (count == 1) r.boundary[v] = 1, block_boundary_edges[v / detail::kCsrBlock] += v < w;
      if (count > 2) r.nonmanifold[v] = 1, block_nonmanifold_edges[v / detail::kCsrBlock] += v < w;
      out.push_back(w);
      i = j;
    }
    if (r.facesBegin(v) == r.facesEnd(v)) r.isolated[v] = 1;
    else if (!detail::facesFormOneFan(v, r, faces)) r.nonmanifold[v] = 1;
  });
  for (long c : block_boundary_edges) r.boundary_edges += c;
  for (long c : block_nonmanifold_edges) r.nonmanifold_edges += c;
  if (with_two_rings)
    detail::buildCsrInBlocks(n, r.ring2_offsets, r.ring2,
                             [&](int v, std::vector<int> &out) { detail::mergedTwoRing(v, r, out); });
  return r;
}

struct EdgeStatistics {
  double mean_edge_length = 0;
  double bbox_diagonal = 0;
};

inline EdgeStatistics edgeStatistics(const std::vector<Vec3> &points, const Rings &r) {
  EdgeStatistics s;
  double sum = 0;
  long count = 0;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (int v = 0; v < r.vertex_count; ++v) {
    lo = lo.cwiseMin(points[v]);
    hi = hi.cwiseMax(points[v]);
    for (const int *a = r.ring1Begin(v); a != r.ring1End(v); ++a)
      if (*a > v) {
        sum += (points[*a] - points[v]).norm();
        ++count;
      }
  }
  s.mean_edge_length = count ? sum / count : 0;
  s.bbox_diagonal = r.vertex_count ? (hi - lo).norm() : 0;
  return s;
}

} // namespace vcg_ext
