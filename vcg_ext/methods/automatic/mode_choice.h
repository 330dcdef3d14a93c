// Whether a noisy mesh has sharp features (a CAD part) or is smooth everywhere (an organic
// shape), from the mesh alone: the choice between the feature mode (feature_smooth.h) and the
// organic mode (organic_smooth.h) of the automatic mode (auto_smooth.h).
//
// Guided normal filtering (Zhang et al. 2015) turns a noisy mesh into piecewise-flat pieces
// whether it has sharp edges or not; two things tell the cases apart:
// - planar CAD faces come out exactly flat over large areas, while a curved surface keeps bending
//   a little across almost every edge: the share of edges whose filtered normals differ by less
//   than flat_deg (on fine meshes, of face pairs a few edges apart: flatnessStride);
// - on a curved organic surface the filter invents creases (a staircase of flat faces, which costs
//   the feature mode much of its θ there), and a plainly smoothed copy (Taubin, no range kernel)
//   bends less across invented creases than across real ones: the share of the filtered normals'
//   creases (> crease_deg) across which the smoothed copy still bends by more than confirm_deg.
#pragma once

#include "vcg_ext/methods/feature/normal_filter.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace vcg_ext {

struct SharpFeatureEvidence {
  long edges = 0;            // interior edges between two non-degenerate faces
  long flat_pairs = 0;       // of those, filtered normals within flat_deg
  long crease_pairs = 0;     // of those, filtered normals more than crease_deg apart
  long confirmed_pairs = 0;  // of the creases, smoothed-copy normals more than confirm_deg apart
  double flat_share = 0, confirmed_share = 0;
  int flat_stride = 1;       // edges between the faces the flat share compares (flatnessStride)
  double crease_density = 0; // creases per √(edges) of the whole mesh (creaseDensity)
};

// How many creases a mesh has for its resolution: the creases' share of the edges times
// √(1.5 · faces) (a closed mesh's edge count), i.e. creases per √(edges). A feature line of a given
// length crosses about as many edges as √(edges) grows, so on a CAD part this reads the same at
// any resolution (about 0.54 × the lines' length / √area: a box 2.8-2.9, the meshes whose
// confirmed share alone made them CAD parts 7-10); creases that noise leaves here and there on a
// smooth shape read lower the finer the mesh (0.5 on the 10M-vertex bunny;
// docs/studies/mode-choice.md).
inline double creaseDensity(long crease_pairs, long edges, size_t faces) {
  return edges > 0 ? double(crease_pairs) / double(edges) * std::sqrt(1.5 * double(faces)) : 0.0;
}

// How many edges apart the faces compared for flatness lie: 1 below about 450k faces (every mesh
// the thresholds were fitted on), then growing as the square root of the face count. A curved
// surface bends by about (distance / radius) between two faces, and one edge is a smaller part of
// the model the finer the mesh: compared edge by edge, a subdivided organic mesh reads as planar
// (docs/studies/mode-choice.md). Faces a fixed fraction of the model apart bend alike at any
// resolution; a plane does not bend at all.
inline int flatnessStride(size_t faces, double reference_faces = 2e5) {
  return std::max(1, int(std::lround(std::sqrt(double(faces) / reference_faces))));
}

namespace detail {

// The face `stride` edges from f, leaving through f's edge slot j and then always into the
// neighbour whose centroid is farthest from f's (ties: the lower index), a walk that goes straight
// on; -1 when it cannot go on (a boundary).
inline int faceAlongWalk(int f, int j, int stride, const FaceRings &face_rings,
                         const std::vector<Vec3> &centroids) {
  int previous = f, current = face_rings.edge_neighbours[f][j];
  for (int step = 1; step < stride && current >= 0; ++step) {
    int best = -1;
    double best_distance = -1;
    for (int g : face_rings.edge_neighbours[current]) {
      if (g < 0 || g == previous) continue;
      const double d = (centroids[g] - centroids[f]).squaredNorm();
      if (d > best_distance || (d == best_distance && g < best)) best = g, best_distance = d;
    }
    previous = current, current = best;
  }
  return current;
}

// The walk from f through its edge slot j (faceAlongWalk): −1 when it does not count (a zero
// normal or a boundary on the way), else whether its end face's filtered normal is within
// acos(flat_cos) of f's.
inline int flatWalk(int f, int j, const std::vector<Vec3> &filtered, const FaceRings &face_rings,
                    const std::vector<Vec3> &centroids, int stride, double flat_cos) {
  if (filtered[f].squaredNorm() <= 0.5) return -1;
  const int g = faceAlongWalk(f, j, stride, face_rings, centroids);
  if (g < 0 || filtered[g].squaredNorm() <= 0.5) return -1;
  return filtered[f].dot(filtered[g]) > flat_cos;
}

// The share of walks `stride` edges long (three from every face) whose end faces' filtered
// normals are within acos(flat_cos); integer counts, so any thread count gives the same share.
inline double flatShareAtStride(const std::vector<Vec3> &filtered, const FaceRings &face_rings,
                                const std::vector<Vec3> &centroids, int stride, double flat_cos) {
  const int m = int(filtered.size());
  long walks = 0, flat = 0;
#pragma omp parallel for schedule(static) reduction(+ : walks, flat) if (m >= min_parallel_vertices)
  for (int f = 0; f < m; ++f) {
    for (int j = 0; j < 3; ++j) {
      const int w = flatWalk(f, j, filtered, face_rings, centroids, stride, flat_cos);
      walks += w >= 0;
      flat += w > 0;
    }
  }
  return walks ? double(flat) / double(walks) : 0.0;
}

} // namespace detail

namespace detail {
// What the edge between faces f and g counts for in SharpFeatureEvidence: nothing (a degenerate
// normal), an edge, a flat one, a crease, a confirmed crease (flags kEdge | kFlat | kCrease |
// kConfirmed).
enum : int { kEdge = 1, kFlat = 2, kCrease = 4, kConfirmed = 8 };
inline int edgeEvidence(int f, int g, const std::vector<Vec3> &filtered,
                        const std::vector<Vec3> &smoothed, double crease_cos, double confirm_cos,
                        double flat_cos) {
  const bool valid = filtered[f].squaredNorm() > 0.5 && filtered[g].squaredNorm() > 0.5 &&
                     smoothed[f].squaredNorm() > 0.5 && smoothed[g].squaredNorm() > 0.5;
  if (!valid) return 0;
  const double c = filtered[f].dot(filtered[g]);
  int flags = kEdge | (c > flat_cos ? kFlat : 0);
  if (c < crease_cos)
    flags |= kCrease | (smoothed[f].dot(smoothed[g]) < confirm_cos ? kConfirmed : 0);
  return flags;
}
} // namespace detail

// `filtered`: per-face unit normals after guided filtering; `smoothed`: per-face unit normals of a
// plainly smoothed copy of the mesh. Faces with a zero normal (degenerate) are skipped. Counts each
// interior edge once, so the result does not depend on vertex or face order. Edge by edge; the
// automatic choice reads it through modelScaleEvidence.
inline SharpFeatureEvidence sharpFeatureEvidence(const std::vector<Vec3> &filtered,
                                                 const std::vector<Vec3> &smoothed,
                                                 const FaceRings &face_rings,
                                                 double crease_deg = 30.0,
                                                 double confirm_deg = 20.0,
                                                 double flat_deg = 1.0) {
  SharpFeatureEvidence e;
  const double crease_cos = std::cos(crease_deg * M_PI / 180.0);
  const double confirm_cos = std::cos(confirm_deg * M_PI / 180.0);
  const double flat_cos = std::cos(flat_deg * M_PI / 180.0);
  const int m = int(filtered.size());
  long edges = 0, flat = 0, creases = 0, confirmed = 0; // integer counts: any thread count
#pragma omp parallel for schedule(static) reduction(+ : edges, flat, creases, confirmed) \
    if (m >= min_parallel_vertices)
  for (int f = 0; f < m; ++f) {
    for (int g : face_rings.edge_neighbours[f]) {
      if (g <= f) continue; // each edge once; −1 (boundary) too
      const int flags =
          detail::edgeEvidence(f, g, filtered, smoothed, crease_cos, confirm_cos, flat_cos);
      edges += (flags & detail::kEdge) != 0;
      flat += (flags & detail::kFlat) != 0;
      creases += (flags & detail::kCrease) != 0;
      confirmed += (flags & detail::kConfirmed) != 0;
    }
  }
  e.edges = edges, e.flat_pairs = flat, e.crease_pairs = creases, e.confirmed_pairs = confirmed;
  e.flat_share = e.edges ? double(e.flat_pairs) / double(e.edges) : 0.0;
  e.confirmed_share = e.crease_pairs ? double(e.confirmed_pairs) / double(e.crease_pairs) : 0.0;
  e.crease_density = creaseDensity(e.crease_pairs, e.edges, filtered.size());
  return e;
}

// sharpFeatureEvidence as the automatic choice reads it: on meshes fine enough for a stride above 1
// (flatnessStride) the flat share compares faces that many edges apart instead of neighbours
// (`points`, `faces`: the mesh whose face centroids guide the walks), and says so in flat_stride.
inline SharpFeatureEvidence modelScaleEvidence(const std::vector<Vec3> &filtered,
                                               const std::vector<Vec3> &smoothed,
                                               const FaceRings &face_rings,
                                               const std::vector<Vec3> &points,
                                               const std::vector<Face> &faces, double crease_deg,
                                               double confirm_deg, double flat_deg) {
  SharpFeatureEvidence e =
      sharpFeatureEvidence(filtered, smoothed, face_rings, crease_deg, confirm_deg, flat_deg);
  e.flat_stride = flatnessStride(faces.size());
  if (e.flat_stride > 1) {
    std::vector<Vec3> centroids;
    computeFaceCentroids(points, faces, centroids);
    e.flat_share = detail::flatShareAtStride(filtered, face_rings, centroids, e.flat_stride,
                                             std::cos(flat_deg * M_PI / 180.0));
  }
  return e;
}

} // namespace vcg_ext
