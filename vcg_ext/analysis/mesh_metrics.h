// Scoring of a smoothing result against a reference mesh with the same connectivity.
//
// Inputs: result and reference positions (same vertex order) and their triangles. Outputs: the
// denoising literature's numbers — θ, the mean angle between face normals (Zhang et al. 2015), also
// on the reference's sharp faces; Ev, the area-weighted RMS distance of the result's vertices to
// the reference surface over the reference bbox diagonal (Sun et al. 2007) — plus signed volume,
// folded faces and, on open meshes, boundary turning angle and inward boundary drift. Not part of
// the smoothing itself: tools/mesh_compare, the end-to-end tests and the benchmark use it.
#pragma once

#include "vcg_ext/core/mesh_arrays.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace vcg_ext {

namespace metrics_detail {
constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
} // namespace metrics_detail

// Unnormalised face normal (twice the area vector); zero for a degenerate face.
inline Vec3 faceAreaVector(const std::vector<Vec3> &points, const Face &f) {
  return (points[f[1]] - points[f[0]]).cross(points[f[2]] - points[f[0]]);
}

// Angle between two directions in degrees; atan2 keeps small angles accurate where acos does not.
inline double angleDeg(const Vec3 &a, const Vec3 &b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * metrics_detail::kRadToDeg;
}

// Undirected edges of a triangle list with the faces on each (CSR), built once per comparison.
struct EdgeTable {
  std::vector<std::array<int, 2>> vertices; // (lower, higher) vertex index
  std::vector<int> face_offsets;            // faces on edge e: faces[face_offsets[e] .. [e + 1])
  std::vector<int> faces;
  int size() const { return int(vertices.size()); }
  int faceCount(int e) const { return face_offsets[e + 1] - face_offsets[e]; }
};

inline EdgeTable buildEdgeTable(const std::vector<Face> &faces) {
  // Bucket each face side by its lower vertex (counting sort), then sort the small buckets.
  int vertex_count = 0;
  for (const Face &f : faces) vertex_count = std::max({vertex_count, f[0] + 1, f[1] + 1, f[2] + 1});
  std::vector<int> bucket_offsets(vertex_count + 1, 0);
  for (const Face &f : faces)
    for (int k = 0; k < 3; ++k)
      if (f[k] != f[(k + 1) % 3]) ++bucket_offsets[std::min(f[k], f[(k + 1) % 3]) + 1];
  for (int v = 0; v < vertex_count; ++v) bucket_offsets[v + 1] += bucket_offsets[v];
  std::vector<std::pair<int, int>> higher_and_face(bucket_offsets[vertex_count]);
  std::vector<int> cursor(bucket_offsets.begin(), bucket_offsets.end() - 1);
  for (int f = 0; f < int(faces.size()); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % 3];
      if (a != b) higher_and_face[cursor[std::min(a, b)]++] = {std::max(a, b), f};
    }
  EdgeTable t;
  t.face_offsets.push_back(0);
  for (int v = 0; v < vertex_count; ++v) {
    const auto begin = higher_and_face.begin() + bucket_offsets[v];
    const auto end = higher_and_face.begin() + bucket_offsets[v + 1];
    std::sort(begin, end);
    for (auto i = begin; i != end;) {
      auto j = i;
      while (j != end && j->first == i->first) t.faces.push_back((j++)->second);
      t.vertices.push_back({v, i->first});
      t.face_offsets.push_back(int(t.faces.size()));
      i = j;
    }
  }
  return t;
}

// Closed = every edge has exactly two faces (a watertight, edge-manifold surface).
inline bool isClosed(const EdgeTable &edges) {
  if (edges.size() == 0) return false;
  for (int e = 0; e < edges.size(); ++e)
    if (edges.faceCount(e) != 2) return false;
  return true;
}

inline double meanEdgeLength(const std::vector<Vec3> &points, const EdgeTable &edges) {
  double sum = 0;
  for (const auto &e : edges.vertices) sum += (points[e[1]] - points[e[0]]).norm();
  return edges.size() ? sum / edges.size() : 0.0;
}

inline double boundingBoxDiagonal(const std::vector<Vec3> &points) {
  if (points.empty()) return 0;
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3 &p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (hi - lo).norm();
}

// Faces with an edge whose dihedral angle (angle between the two face normals) exceeds the
// threshold.
inline std::vector<std::uint8_t> sharpFaces(const std::vector<Vec3> &points,
                                            const std::vector<Face> &faces,
                                            const EdgeTable &edges, double threshold_deg = 30.0) {
  std::vector<std::uint8_t> sharp(faces.size(), 0);
  for (int e = 0; e < edges.size(); ++e) {
    const int *begin = edges.faces.data() + edges.face_offsets[e];
    const int *end = edges.faces.data() + edges.face_offsets[e + 1];
    for (const int *f = begin; f != end; ++f)
      for (const int *g = f + 1; g != end; ++g)
        if (angleDeg(faceAreaVector(points, faces[*f]), faceAreaVector(points, faces[*g])) >
            threshold_deg)
          sharp[*f] = sharp[*g] = 1;
  }
  return sharp;
}

struct NormalDeviation {
  double theta_deg = 0;                        // mean over all faces
  double theta_sharp_deg = metrics_detail::kNaN; // mean over the reference's sharp faces (or NaN)
  int sharp_faces = 0;
  int flipped_faces = 0; // result normal > 90° from the reference normal
};

// Face-by-face normal angles of two embeddings of the same triangles.
inline NormalDeviation normalDeviation(const std::vector<Vec3> &result,
                                       const std::vector<Vec3> &reference,
                                       const std::vector<Face> &faces, const EdgeTable &edges,
                                       double sharp_threshold_deg = 30.0) {
  NormalDeviation d;
  const std::vector<std::uint8_t> sharp = sharpFaces(reference, faces, edges, sharp_threshold_deg);
  double sum = 0, sharp_sum = 0;
  for (size_t f = 0; f < faces.size(); ++f) {
    const double a = angleDeg(faceAreaVector(result, faces[f]), faceAreaVector(reference, faces[f]));
    sum += a;
    if (a > 90.0) ++d.flipped_faces;
    if (sharp[f]) sharp_sum += a, ++d.sharp_faces;
  }
  d.theta_deg = faces.empty() ? 0.0 : sum / faces.size();
  if (d.sharp_faces) d.theta_sharp_deg = sharp_sum / d.sharp_faces;
  return d;
}

// Signed volume by the divergence theorem (sum of origin-apex tetrahedra); exact for a closed,
// consistently oriented polyhedron, positive when the faces are counter-clockwise seen from
// outside.
inline double signedVolume(const std::vector<Vec3> &points, const std::vector<Face> &faces) {
  double six_v = 0;
  for (const Face &f : faces) six_v += points[f[0]].dot(points[f[1]].cross(points[f[2]]));
  return six_v / 6.0;
}

// Per-vertex area: one third of the areas of the incident faces (Sun et al.'s Ev weights).
inline std::vector<double> vertexAreas(const std::vector<Vec3> &points,
                                       const std::vector<Face> &faces) {
  std::vector<double> area(points.size(), 0.0);
  for (const Face &f : faces) {
    const double third = faceAreaVector(points, f).norm() / 6.0;
    for (int k = 0; k < 3; ++k) area[f[k]] += third;
  }
  return area;
}

inline Vec3 closestPointOnSegment(const Vec3 &p, const Vec3 &a, const Vec3 &b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

// Exact closest point of triangle abc to p, by Voronoi regions (Ericson, Real-Time Collision
// Detection, 5.1.5); degenerate triangles fall back to their edges.
inline Vec3 closestPointOnTriangle(const Vec3 &p, const Vec3 &a, const Vec3 &b, const Vec3 &c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0 && (d4 - d3) + (d5 - d6) > 0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = va + vb + vc;
  if (!(denom > 0)) {
    Vec3 best = closestPointOnSegment(p, a, b);
    for (const Vec3 &q : {closestPointOnSegment(p, b, c), closestPointOnSegment(p, c, a)})
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    return best;
  }
  return a + (vb / denom) * ab + (vc / denom) * ac;
}

// Uniform grid over a triangle set for exact nearest-surface queries. Each triangle is listed in
// every cell its bounding box touches; a query scans cubic shells of cells around the query's cell,
// skipping cells farther than the best triangle so far, until the next shell cannot be nearer.
// At most 8 cells per triangle, 4 bytes each.
class TriangleGrid {
public:
  TriangleGrid(const std::vector<Vec3> &points, const std::vector<Face> &faces)
      : points_(points), faces_(faces) {
    if (faces_.empty()) return;
    lo_ = hi_ = points_[faces_[0][0]];
    double edge_sum = 0;
    for (const Face &f : faces_)
      for (int k = 0; k < 3; ++k) {
        lo_ = lo_.cwiseMin(points_[f[k]]);
        hi_ = hi_.cwiseMax(points_[f[k]]);
        edge_sum += (points_[f[(k + 1) % 3]] - points_[f[k]]).norm();
      }
    // Cells about one edge long keep a handful of triangles per cell; coarsen until there are at
    // most 8 cells per triangle (bulky meshes, where most cells are empty).
    const Vec3 extent = hi_ - lo_;
    cell_ = edge_sum / (3.0 * faces_.size());
    if (!(cell_ > 0)) cell_ = std::max(extent.maxCoeff(), 1.0);
    const double max_cells = 8.0 * faces_.size() + 64;
    for (;;) {
      double cells = 1;
      for (int a = 0; a < 3; ++a) cells *= std::max(1.0, std::ceil(extent[a] / cell_));
      if (cells <= max_cells) break;
      cell_ *= 1.25;
    }
    for (int a = 0; a < 3; ++a) dims_[a] = std::max(1, int(std::ceil(extent[a] / cell_)));
    const long cell_count = long(dims_[0]) * dims_[1] * dims_[2];
    cell_offsets_.assign(cell_count + 1, 0);
    forEachTriangleCell([&](long cell, int) { ++cell_offsets_[cell + 1]; });
    for (long c = 0; c < cell_count; ++c) cell_offsets_[c + 1] += cell_offsets_[c];
    cell_triangles_.resize(cell_offsets_[cell_count]);
    std::vector<unsigned> cursor(cell_offsets_.begin(), cell_offsets_.end() - 1);
    forEachTriangleCell([&](long cell, int f) { cell_triangles_[cursor[cell]++] = f; });
  }

  // Squared distance from p to the nearest triangle (infinity for an empty set).
  double squaredDistance(const Vec3 &p) const {
    double best = std::numeric_limits<double>::infinity();
    if (faces_.empty() || !p.allFinite()) return best;
    std::array<int, 3> c;
    for (int a = 0; a < 3; ++a) c[a] = cellCoordinate(p[a], a);
    for (int r = 0;; ++r) {
      if (r > 0 && wallSquaredDistance(p, c, r - 1) >= best) break;
      const int i0 = std::max(c[0] - r, 0), i1 = std::min(c[0] + r, dims_[0] - 1);
      const int j0 = std::max(c[1] - r, 0), j1 = std::min(c[1] + r, dims_[1] - 1);
      const int k0 = std::max(c[2] - r, 0), k1 = std::min(c[2] + r, dims_[2] - 1);
      for (int i = i0; i <= i1; ++i)
        for (int j = j0; j <= j1; ++j) {
          const bool on_shell = std::abs(i - c[0]) == r || std::abs(j - c[1]) == r;
          // Inside the shell's i-j cross-section only the two k faces belong to the shell.
          const int step = on_shell ? 1 : std::max(1, 2 * r);
          for (int k = on_shell ? k0 : c[2] - r; k <= (on_shell ? k1 : c[2] + r); k += step) {
            if (k < 0 || k >= dims_[2]) continue;
            if (cellSquaredDistance(p, i, j, k) >= best) continue;
            const long cell = (long(k) * dims_[1] + j) * dims_[0] + i;
            for (unsigned t = cell_offsets_[cell]; t < cell_offsets_[cell + 1]; ++t) {
              const Face &f = faces_[cell_triangles_[t]];
              const Vec3 q =
                  closestPointOnTriangle(p, points_[f[0]], points_[f[1]], points_[f[2]]);
              best = std::min(best, (q - p).squaredNorm());
            }
          }
        }
    }
    return best;
  }

private:
  int cellCoordinate(double x, int axis) const {
    const double u = std::floor((x - lo_[axis]) / cell_);
    return int(std::clamp(u, 0.0, double(dims_[axis] - 1)));
  }

  // Lower bound on the squared distance from p to any cell outside the block of cells within
  // Chebyshev distance r of p's cell c: such a cell lies beyond one of the block's walls that are
  // inside the grid, and inside the grid along the other axes. Infinity once the block covers the
  // grid. Unlike r * cell, this also ends the search early for points far outside the grid.
  double wallSquaredDistance(const Vec3 &p, const std::array<int, 3> &c, int r) const {
    double outside2[3];
    for (int a = 0; a < 3; ++a) {
      const double gap = std::max({lo_[a] - p[a], p[a] - (lo_[a] + dims_[a] * cell_), 0.0});
      outside2[a] = gap * gap;
    }
    const double all_outside2 = outside2[0] + outside2[1] + outside2[2];
    double bound = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      const double others = all_outside2 - outside2[a];
      if (c[a] - r > 0) {
        const double gap = std::max(0.0, p[a] - (lo_[a] + (c[a] - r) * cell_));
        bound = std::min(bound, gap * gap + others);
      }
      if (c[a] + r < dims_[a] - 1) {
        const double gap = std::max(0.0, lo_[a] + (c[a] + r + 1) * cell_ - p[a]);
        bound = std::min(bound, gap * gap + others);
      }
    }
    return bound;
  }

  double cellSquaredDistance(const Vec3 &p, int i, int j, int k) const {
    const int index[3] = {i, j, k};
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
      const double lo = lo_[a] + index[a] * cell_, hi = lo + cell_;
      const double gap = std::max({lo - p[a], p[a] - hi, 0.0});
      d2 += gap * gap;
    }
    return d2;
  }

  template <class Visit> void forEachTriangleCell(Visit visit) const {
    for (int f = 0; f < int(faces_.size()); ++f) {
      Vec3 tlo = points_[faces_[f][0]], thi = tlo;
      for (int k = 1; k < 3; ++k) {
        tlo = tlo.cwiseMin(points_[faces_[f][k]]);
        thi = thi.cwiseMax(points_[faces_[f][k]]);
      }
      std::array<int, 3> a, b;
      for (int ax = 0; ax < 3; ++ax) a[ax] = cellCoordinate(tlo[ax], ax), b[ax] = cellCoordinate(thi[ax], ax);
      for (int k = a[2]; k <= b[2]; ++k)
        for (int j = a[1]; j <= b[1]; ++j)
          for (int i = a[0]; i <= b[0]; ++i) visit((long(k) * dims_[1] + j) * dims_[0] + i, f);
    }
  }

  std::vector<Vec3> points_;
  std::vector<Face> faces_;
  Vec3 lo_ = Vec3::Zero(), hi_ = Vec3::Zero();
  double cell_ = 1;
  std::array<int, 3> dims_ = {1, 1, 1};
  std::vector<unsigned> cell_offsets_; // 32 bits: up to 4e9 cell entries
  std::vector<int> cell_triangles_;
};

// Area-weighted RMS distance of the result's vertices to the reference surface (exact
// point-to-triangle), in absolute units; weights are the result's vertexAreas. Parallel over
// vertices, summed serially so the value does not depend on the thread count.
inline double surfaceDistanceRms(const std::vector<Vec3> &result,
                                 const std::vector<Face> &result_faces,
                                 const std::vector<Vec3> &reference,
                                 const std::vector<Face> &reference_faces) {
  const TriangleGrid grid(reference, reference_faces);
  const std::vector<double> area = vertexAreas(result, result_faces);
  std::vector<double> d2(result.size(), 0.0);
  const long n = long(result.size());
#pragma omp parallel for schedule(dynamic, 1024)
  for (long v = 0; v < n; ++v)
    if (area[v] > 0) d2[v] = grid.squaredDistance(result[v]);
  double weighted = 0, total = 0;
  for (long v = 0; v < n; ++v)
    if (area[v] > 0) weighted += area[v] * d2[v], total += area[v];
  return total > 0 ? std::sqrt(weighted / total) : 0.0;
}

// Ev = surfaceDistanceRms / reference bounding-box diagonal (dimensionless; tables print ×1e3).
inline double evError(const std::vector<Vec3> &result, const std::vector<Face> &result_faces,
                      const std::vector<Vec3> &reference,
                      const std::vector<Face> &reference_faces) {
  const double diag = boundingBoxDiagonal(reference);
  return diag > 0 ? surfaceDistanceRms(result, result_faces, reference, reference_faces) / diag
                  : 0.0;
}

// Closed loops of boundary edges (edges with one face), each oriented as its face and listed as
// consecutive vertices. Chains broken at non-manifold vertices that do not close are dropped.
inline std::vector<std::vector<int>> boundaryLoops(int vertex_count, const std::vector<Face> &faces,
                                                   const EdgeTable &edges) {
  std::vector<std::pair<int, int>> half; // directed boundary edges, sorted by start vertex
  for (int e = 0; e < edges.size(); ++e) {
    if (edges.faceCount(e) != 1) continue;
    const Face &f = faces[edges.faces[edges.face_offsets[e]]];
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3];
      if (std::min(a, b) == edges.vertices[e][0] && std::max(a, b) == edges.vertices[e][1]) {
        half.emplace_back(a, b);
        break;
      }
    }
  }
  std::sort(half.begin(), half.end());
  std::vector<int> first_out(vertex_count + 1, 0);
  for (const auto &h : half) ++first_out[h.first + 1];
  for (int v = 0; v < vertex_count; ++v) first_out[v + 1] += first_out[v];
  std::vector<std::uint8_t> used(half.size(), 0);
  std::vector<std::vector<int>> loops;
  for (size_t start = 0; start < half.size(); ++start) {
    if (used[start]) continue;
    std::vector<int> loop;
    size_t h = start;
    bool closed = false;
    for (;;) {
      used[h] = 1;
      loop.push_back(half[h].first);
      const int next_vertex = half[h].second;
      if (next_vertex == half[start].first) {
        closed = true;
        break;
      }
      size_t next = half.size();
      for (int o = first_out[next_vertex]; o < first_out[next_vertex + 1]; ++o)
        if (!used[o]) {
          next = size_t(o);
          break;
        }
      if (next == half.size()) break;
      h = next;
    }
    if (closed && loop.size() >= 3) loops.push_back(std::move(loop));
  }
  return loops;
}

// Mean absolute turning angle (degrees) between consecutive edges over all boundary loops;
// a regular n-gon gives 360/n. NaN without boundary.
inline double boundaryTurningDeg(const std::vector<Vec3> &points,
                                 const std::vector<std::vector<int>> &loops) {
  double sum = 0;
  long count = 0;
  for (const auto &loop : loops) {
    const size_t n = loop.size();
    for (size_t i = 0; i < n; ++i) {
      const Vec3 &prev = points[loop[(i + n - 1) % n]], &here = points[loop[i]],
                 &next = points[loop[(i + 1) % n]];
      sum += angleDeg(here - prev, next - here);
      ++count;
    }
  }
  return count ? sum / count : metrics_detail::kNaN;
}

// Mean over boundary vertices of (result − reference) projected on the reference's inward boundary
// direction, in units of the reference mean edge length; positive = pulled into the mesh
// (shrinkage). The inward direction of a boundary edge lies in its face's plane, perpendicular to
// the edge, towards the face's third vertex; a vertex uses the normalised sum over its boundary
// edges.
inline double boundaryInwardDrift(const std::vector<Vec3> &result,
                                  const std::vector<Vec3> &reference,
                                  const std::vector<Face> &faces, const EdgeTable &edges) {
  std::vector<Vec3> inward(reference.size(), Vec3::Zero());
  std::vector<std::uint8_t> on_boundary(reference.size(), 0);
  for (int e = 0; e < edges.size(); ++e) {
    if (edges.faceCount(e) != 1) continue;
    const int a = edges.vertices[e][0], b = edges.vertices[e][1];
    const Face &f = faces[edges.faces[edges.face_offsets[e]]];
    const int c = f[0] != a && f[0] != b ? f[0] : f[1] != a && f[1] != b ? f[1] : f[2];
    const Vec3 along = (reference[b] - reference[a]).normalized();
    Vec3 in = reference[c] - reference[a];
    in -= along * along.dot(in);
    if (in.norm() > 0) in.normalize();
    inward[a] += in;
    inward[b] += in;
    on_boundary[a] = on_boundary[b] = 1;
  }
  const double edge = meanEdgeLength(reference, edges);
  double sum = 0;
  long count = 0;
  for (size_t v = 0; v < reference.size(); ++v) {
    if (!on_boundary[v]) continue;
    const double len = inward[v].norm();
    if (len > 0) sum += (result[v] - reference[v]).dot(inward[v] / len);
    ++count;
  }
  return count && edge > 0 ? sum / count / edge : metrics_detail::kNaN;
}

// Everything mesh_compare reports; NaN marks "not applicable".
struct MeshComparison {
  int vertices = 0, faces = 0;
  NormalDeviation normals;
  double ev = 0; // dimensionless (Ev), not ×1e3
  double volume_result = 0, volume_reference = 0, volume_ratio = metrics_detail::kNaN;
  bool closed = false;
  double boundary_turning_deg_result = metrics_detail::kNaN;
  double boundary_turning_deg_reference = metrics_detail::kNaN;
  double boundary_drift_edges = metrics_detail::kNaN;
};

// Scores `result` against `reference`, both embeddings of `faces`.
inline MeshComparison compareMeshes(const std::vector<Vec3> &result,
                                    const std::vector<Vec3> &reference,
                                    const std::vector<Face> &faces) {
  MeshComparison c;
  c.vertices = int(reference.size());
  c.faces = int(faces.size());
  const EdgeTable edges = buildEdgeTable(faces);
  c.normals = normalDeviation(result, reference, faces, edges);
  c.ev = evError(result, faces, reference, faces);
  c.volume_result = signedVolume(result, faces);
  c.volume_reference = signedVolume(reference, faces);
  if (c.volume_reference != 0) c.volume_ratio = c.volume_result / c.volume_reference;
  c.closed = isClosed(edges);
  const auto loops = boundaryLoops(int(reference.size()), faces, edges);
  if (!loops.empty()) {
    c.boundary_turning_deg_result = boundaryTurningDeg(result, loops);
    c.boundary_turning_deg_reference = boundaryTurningDeg(reference, loops);
    c.boundary_drift_edges = boundaryInwardDrift(result, reference, faces, edges);
  }
  return c;
}

} // namespace vcg_ext
