// The automatic choice's evidence (mode_choice.h) on a large mesh from windows of it.
//
// Inputs: the mesh (in the spatial order the drivers run in), its topology and movable vertices
// (DriverSetup), the feature mode's pass counts and the evidence's angles. Output: the evidence
// counted on the cores of `windows` patches of the mesh around seed vertices spread evenly along
// the spatial order, and how much of the mesh the windows took.
//
// Why: the evidence needs the feature mode's pre-pass and first guidance period of its normal
// filter, which the organic mode then throws away (docs/studies/performance.md). Every stage
// reads a bounded neighbourhood: a Taubin step one ring, the guided filter's guidance three face
// rings and each iteration one, a flatness walk `stride` faces. So a face within `core_rings` of a
// seed gets the whole mesh's values when its window reaches `windowMargin` rings further, and a
// window keeps the mesh's element order (a monotone renumbering), so every sum runs in the same
// order: the core's filtered normals are the whole mesh's bit for bit
// (tests/unit/test_evidence_windows.cpp). What is approximate is the sample: the shares over the
// cores instead of over every face (the automatic mode decides on it only when its shares are
// clear of the thresholds).
#pragma once

#include "vcg_ext/methods/driver_setup.h"
#include "vcg_ext/core/mesh_windows.h"
#include "vcg_ext/methods/automatic/mode_choice.h"
#include "vcg_ext/methods/feature/normal_filter.h"
#include "vcg_ext/core/vertex_roles.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace vcg_ext {

struct EvidenceWindowParams {
  int core_rings = 24;  // the evidence is counted on faces within this many rings of a seed
  // As many windows (seed vertices, one per equal run of the spatial order) as take about
  // `face_share` of the mesh's faces, a window of r rings holding about 6 r² faces, within
  // [min_windows, max_windows]: the more windows, the smaller the sample's error (a fixed few
  // dozen held too few creases to decide on; docs/studies/mode-choice.md).
  double face_share = 0.3;
  int min_windows = 8, max_windows = 1000;
  // Windows that would hold more than this share of the mesh's faces save too little: the
  // caller takes the evidence on the whole mesh instead.
  double max_face_share = 0.45;
};

// The feature mode's first pass as the automatic choice reads it (feature_smooth.h,
// auto_smooth.h): `prepass_pairs` Taubin pairs, then the face normals filtered by `first`
// (its first guidance period); `reference`: the face normals after `reference_pairs` plain pairs.
struct FirstPassCounts {
  int prepass_pairs = 0, reference_pairs = 0;
  NormalFilterParams first;
};

struct WindowedEvidence {
  bool used = false; // false: the windows would take too much of the mesh (nothing measured)
  SharpFeatureEvidence evidence;
  // The shares' standard errors as a sample, from their spread over the windows (infinite with
  // fewer than two windows that count).
  double flat_error = INFINITY, confirmed_error = INFINITY, crease_density_error = INFINITY;
  long window_faces = 0, core_faces = 0;
};

namespace detail {

// The rings from each core vertex outward that a window needs for its core to see the whole
// mesh's values: the pre-pass or reference pairs (two steps each), a face's corners, the
// guidance (three face rings) and the iterations (one each), the flatness walks, and two spare.
inline int windowMargin(const FirstPassCounts &counts, int stride) {
  return 2 * std::max(counts.prepass_pairs, counts.reference_pairs) + 1 +
         (3 + std::max(0, counts.first.iterations)) + stride + 2;
}

// The standard error of a pooled share `pooled` = Σ n_k s_k / Σ n_k from the windows' shares s_k
// and counts n_k (a ratio estimator over a sample of windows).
inline double pooledShareError(const std::vector<double> &share, const std::vector<double> &count,
                               double pooled) {
  double total = 0, spread = 0;
  int windows = 0;
  for (size_t k = 0; k < share.size(); ++k) {
    if (!(count[k] > 0)) continue;
    ++windows;
    total += count[k];
    spread += std::pow(count[k] * (share[k] - pooled), 2);
  }
  if (windows < 2) return INFINITY;
  return std::sqrt(spread * windows / (windows - 1.0)) / total;
}

} // namespace detail

// The first pass's filtered and reference face normals of `mesh` (FirstPassCounts); `fixed` and
// `roles` as DriverSetup has them, `edge` the mean edge length the filter's kernel reads.
inline void firstPassNormals(const MeshArrays &mesh, const Rings &rings, const FaceRings &face_rings,
                             const std::vector<std::uint8_t> &fixed,
                             const detail::VertexRoles &roles, const FirstPassCounts &counts,
                             double edge, std::vector<Vec3> &filtered,
                             std::vector<Vec3> &reference) {
  std::vector<Vec3> points = mesh.points;
  taubinSmooth(points, rings, fixed, roles.boundary_neighbours, counts.prepass_pairs);
  computeFaceNormals(points, mesh.faces, filtered);
  filterNormalsInPlace(points, mesh.faces, face_rings, counts.first, edge, filtered);
  if (counts.reference_pairs != counts.prepass_pairs) {
    points = mesh.points;
    taubinSmooth(points, rings, fixed, roles.boundary_neighbours, counts.reference_pairs);
  }
  computeFaceNormals(points, mesh.faces, reference);
}

namespace detail {

// Per window, the evidence counts of its core faces (an edge counts for its lower face's window
// when both faces are core, a flatness walk for the window it starts in): the windows in
// parallel, each in face order, so integer counts that do not depend on the thread count.
enum WindowCount {
  kEdgeCount, kFlatEdgeCount, kCreaseCount, kConfirmedCount, kWalkCount, kFlatWalkCount, kCounts
};
using WindowTallies = std::vector<std::array<long, kCounts>>;

inline WindowTallies windowTallies(const MeshWindows &w, int windows,
                                   const std::vector<Vec3> &filtered,
                                   const std::vector<Vec3> &reference, const FaceRings &face_rings,
                                   const std::vector<Vec3> &centroids, int stride,
                                   double crease_deg, double confirm_deg, double flat_deg) {
  std::vector<std::vector<int>> members(windows);
  for (int f = 0; f < int(w.core.size()); ++f)
    if (w.core[f]) members[w.window[f]].push_back(f);
  const double crease_cos = std::cos(crease_deg * M_PI / 180.0),
               confirm_cos = std::cos(confirm_deg * M_PI / 180.0),
               flat_cos = std::cos(flat_deg * M_PI / 180.0);
  WindowTallies tally(windows);
#pragma omp parallel for schedule(dynamic, 1) if (w.core.size() >= size_t(min_parallel_vertices))
  for (int k = 0; k < windows; ++k) {
    std::array<long, kCounts> t{};
    for (int f : members[k]) {
      for (int g : face_rings.edge_neighbours[f]) {
        if (g <= f || !w.core[g]) continue;
        const int flags = edgeEvidence(f, g, filtered, reference, crease_cos, confirm_cos, flat_cos);
        t[kEdgeCount] += (flags & kEdge) != 0;
        t[kFlatEdgeCount] += (flags & kFlat) != 0;
        t[kCreaseCount] += (flags & kCrease) != 0;
        t[kConfirmedCount] += (flags & kConfirmed) != 0;
      }
      for (int j = 0; j < 3 && stride > 1; ++j) {
        const int walk = flatWalk(f, j, filtered, face_rings, centroids, stride, flat_cos);
        t[kWalkCount] += walk >= 0;
        t[kFlatWalkCount] += walk > 0;
      }
    }
    tally[k] = t;
  }
  return tally;
}

// The pooled evidence (the windows' counts summed: modelScaleEvidence's counts on the cores) and
// the shares' standard errors from their spread over the windows, into `out`.
// `model_faces`: the whole mesh's face count, for the crease density (creaseDensity).
inline void poolWindowTallies(const WindowTallies &tally, int stride, size_t model_faces,
                              WindowedEvidence &out) {
  std::array<long, kCounts> sum{};
  for (const auto &t : tally)
    for (int i = 0; i < kCounts; ++i) sum[i] += t[i];
  const int flat_part = stride > 1 ? kFlatWalkCount : kFlatEdgeCount,
            flat_whole = stride > 1 ? kWalkCount : kEdgeCount;
  auto share = [](long part, long whole) { return whole ? double(part) / double(whole) : 0.0; };
  SharpFeatureEvidence &e = out.evidence;
  e.edges = sum[kEdgeCount], e.flat_pairs = sum[kFlatEdgeCount], e.crease_pairs = sum[kCreaseCount];
  e.confirmed_pairs = sum[kConfirmedCount];
  e.flat_share = share(sum[flat_part], sum[flat_whole]);
  e.confirmed_share = share(sum[kConfirmedCount], sum[kCreaseCount]);
  e.crease_density = creaseDensity(e.crease_pairs, e.edges, model_faces);
  const size_t windows = tally.size();
  std::vector<double> flat(windows), flat_count(windows), confirmed(windows), creases(windows),
      crease_share(windows), edges(windows);
  for (size_t k = 0; k < windows; ++k) {
    flat[k] = share(tally[k][flat_part], tally[k][flat_whole]);
    flat_count[k] = double(tally[k][flat_whole]);
    confirmed[k] = share(tally[k][kConfirmedCount], tally[k][kCreaseCount]);
    creases[k] = double(tally[k][kCreaseCount]);
    crease_share[k] = share(tally[k][kCreaseCount], tally[k][kEdgeCount]);
    edges[k] = double(tally[k][kEdgeCount]);
  }
  out.flat_error = pooledShareError(flat, flat_count, e.flat_share);
  out.confirmed_error = pooledShareError(confirmed, creases, e.confirmed_share);
  // The density is the creases' share of the edges scaled: its error scales alike.
  out.crease_density_error = pooledShareError(crease_share, edges, share(e.crease_pairs, e.edges)) *
                             std::sqrt(1.5 * double(model_faces));
}

} // namespace detail

// The evidence on the windows' cores (see the file comment); `model_faces` of the whole mesh set
// the flatness stride as modelScaleEvidence reads it there.
inline WindowedEvidence windowedEvidence(const MeshArrays &mesh, const detail::DriverSetup &setup,
                                         const FirstPassCounts &counts, double crease_deg,
                                         double confirm_deg, double flat_deg,
                                         const EvidenceWindowParams &params = {}) {
  WindowedEvidence out;
  const int stride = flatnessStride(mesh.faces.size());
  const int reach = params.core_rings + detail::windowMargin(counts, stride);
  const int windows = std::clamp(
      int(params.face_share * double(mesh.faces.size()) / (6.0 * double(reach) * reach)),
      params.min_windows, std::max(params.min_windows, params.max_windows));
  const std::vector<int> seeds = detail::windowSeeds(setup.rings, setup.fixed, windows);
  if (seeds.empty()) return out;
  // How much the windows take, before building them.
  std::vector<int> source;
  const std::vector<int> distance = detail::ringDistance(setup.rings, seeds, reach, &source);
  if (double(detail::windowFaceCount(mesh.faces, distance, reach)) >
      params.max_face_share * double(mesh.faces.size()))
    return out;
  const MeshWindows w =
      meshWindows(mesh, setup.fixed, distance, source, params.core_rings, reach);
  const Rings rings = computeRings(int(w.mesh.points.size()), w.mesh.faces, false);
  const detail::VertexRoles roles =
      detail::vertexRoles(w.mesh, rings, setup.stats.mean_edge_length);
  std::vector<std::uint8_t> fixed(w.fixed);
  for (size_t v = 0; v < fixed.size(); ++v) fixed[v] = fixed[v] || roles.frozen[v];
  const FaceRings face_rings = computeFaceRings(w.mesh.faces, rings);
  std::vector<Vec3> filtered, reference;
  firstPassNormals(w.mesh, rings, face_rings, fixed, roles, counts, setup.stats.mean_edge_length,
                   filtered, reference);
  std::vector<Vec3> centroids;
  if (stride > 1) computeFaceCentroids(w.mesh.points, w.mesh.faces, centroids);
  out.window_faces = long(w.mesh.faces.size());
  for (std::uint8_t c : w.core) out.core_faces += c;
  out.used = true;
  out.evidence.flat_stride = stride;
  detail::poolWindowTallies(
      detail::windowTallies(w, int(seeds.size()), filtered, reference, face_rings, centroids,
                            stride, crease_deg, confirm_deg, flat_deg),
      stride, mesh.faces.size(), out);
  return out;
}

} // namespace vcg_ext
