// Stages 1–2: vertex normals, Meyer curvatures and principal directions.
//
// Inputs: positions, triangles and their Rings (stage 0). Outputs, per vertex in compact order:
// area-weighted unit normal (paper 3.1), Meyer mixed Voronoi area, mean curvature H, Gaussian
// curvature K, principal curvatures k1 >= k2 (Meyer, Desbrun, Schröder, Barr 2003, as the paper's
// 3.1 asks) and principal directions from a Taubin (1995) style tangent-plane tensor fit, which the
// paper needs in 3.3 but never defines.
//
// Sign convention: outward normals of a counter-clockwise oriented closed mesh; a sphere of radius
// r has k1 = k2 = H = +1/r.
//
// Written on the flat arrays instead of wrapping vcg::tri::UpdateCurvature: that works on the
// mesh's (float, in MeshLab 2020.09) scalar and scatter-adds over faces, which is neither double
// precision nor independent of thread count and vertex order; here each vertex gathers from its own
// incident faces.
#pragma once

#include "vcg_ext/core/rings.h"

#include <Eigen/Geometry> // cross products
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace vcg_ext {

struct CurvatureField {       // per vertex, compact order
  std::vector<Vec3> normal;   // area-weighted, unit (zero vector for isolated vertices)
  std::vector<double> area;   // Meyer mixed Voronoi area
  std::vector<double> mean;   // H, signed (convex sphere with outward normals: H = +1/r)
  std::vector<double> gauss;  // K
  std::vector<double> k1, k2; // k1 >= k2
  std::vector<Vec3> dir1, dir2; // unit principal directions in the tangent plane (dir1 for k1)
};

namespace detail {
// Vertex v's face-area-weighted normal: the sum of its faces' cross products (whose lengths are
// twice their areas), in the order of its face list, normalised; zero where they have no area.
inline Vec3 vertexNormalAt(int v, const std::vector<Vec3> &points, const std::vector<Face> &faces,
                           const Rings &rings) {
  Vec3 sum = Vec3::Zero();
  for (const int *f = rings.facesBegin(v); f != rings.facesEnd(v); ++f) {
    const Face &t = faces[*f];
    sum += (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]);
  }
  const double length = sum.norm();
  return (length > 0 && std::isfinite(length)) ? Vec3(sum / length) : Vec3::Zero();
}
} // namespace detail

// Face-area-weighted vertex normals (paper 3.1). Zero where the incident faces have no area.
// Each vertex crosses its own faces' edges (every face three times) rather than gathering them
// from a per-face array: the same bits, no 24 bytes per face to allocate (fresh pages at the
// band shrinkage's peak), and faster on large meshes, where the gather waited on memory
// (docs/studies/performance.md).
inline void computeVertexNormals(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                                 const Rings &rings, std::vector<Vec3> &normals) {
  const int n = rings.vertex_count;
  normals.resize(n);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v) normals[v] = detail::vertexNormalAt(v, points, faces, rings);
}

// computeVertexNormals at the boundary vertices only (the same values); the other entries are left
// as they are. What the boundary moves of the drivers need, without a pass over every vertex's
// faces per vertex update.
inline void computeBoundaryVertexNormals(const std::vector<Vec3> &points,
                                         const std::vector<Face> &faces, const Rings &rings,
                                         std::vector<Vec3> &normals) {
  const int n = rings.vertex_count;
  normals.resize(n);
#pragma omp parallel for schedule(static) if (n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v)
    if (rings.boundary[v]) normals[v] = detail::vertexNormalAt(v, points, faces, rings);
}

namespace detail {

// A triangle counts as degenerate when its area is negligible against its longest edge.
inline bool isDegenerateTriangle(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
  const double longest2 =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  const double twice_area = (b - a).cross(c - a).norm();
  return !(longest2 > 0) || !(twice_area > 1e-12 * longest2) || !std::isfinite(twice_area);
}

// A fixed orthonormal tangent frame that depends only on the normal (so on nothing order-related).
inline void tangentFrame(const Vec3 &normal, Vec3 &t1, Vec3 &t2) {
  const Vec3 a = std::abs(normal.x()) < 0.6 ? Vec3::UnitX()
                 : std::abs(normal.y()) < 0.6 ? Vec3::UnitY()
                                              : Vec3::UnitZ();
  t1 = a.cross(normal).normalized();
  t2 = normal.cross(t1);
}

// Directions of a symmetric tangent tensor [a b; b c] given in the frame (t1, t2): dir1 is the
// eigenvector of the larger eigenvalue; (dir1, dir2, normal) is right-handed.
inline void tensorDirections(double a, double b, double c, const Vec3 &t1, const Vec3 &t2,
                             const Vec3 &normal, Vec3 &dir1, Vec3 &dir2) {
  const double phi = 0.5 * std::atan2(2 * b, a - c);
  dir1 = std::cos(phi) * t1 + std::sin(phi) * t2;
  dir2 = normal.cross(dir1);
}

// The least-squares tensor (a, b, d) from its 3×3 normal equations. Well conditioned (the usual
// fan of ≥ 3 edge directions): LDLᵀ. Otherwise rank-revealing: a fan with fewer than three edge
// directions yields the minimum-norm tensor (SVD with relative threshold 1e-10). The LDLᵀ path is
// taken only where all singular values are far above that threshold, so both give the same tensor.
inline Eigen::Vector3d solveTensorFit(const Eigen::Matrix3d &M, const Eigen::Vector3d &rhs) {
  const double d0 = M(0, 0);
  if (d0 > 0) {
    const double l10 = M(1, 0) / d0, l20 = M(2, 0) / d0;
    const double d1 = M(1, 1) - l10 * M(1, 0);
    if (d1 > 0) {
      const double l21 = (M(2, 1) - l20 * M(1, 0)) / d1;
      const double d2 = M(2, 2) - l20 * M(2, 0) - l21 * l21 * d1;
      const double largest = std::max({d0, d1, d2});
      if (std::min(d1, d2) > 1e-6 * largest && std::isfinite(largest)) {
        const double y0 = rhs[0], y1 = rhs[1] - l10 * y0, y2 = rhs[2] - l20 * y0 - l21 * y1;
        const double z2 = y2 / d2, z1 = y1 / d1 - l21 * z2, z0 = y0 / d0 - l10 * z1 - l20 * z2;
        return {z0, z1, z2};
      }
    }
  }
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  svd.setThreshold(1e-10);
  return svd.solve(rhs);
}

} // namespace detail

namespace detail {

// What one vertex's fan of faces adds up to: Meyer's mixed area, the angle sum, the cotangent
// Laplacian Σ (cot α + cot β)(q_j − q_i) (pointing inward on a sphere), and the normal equations of
// the least-squares tensor fit κ(c, s) = a c² + 2 b c s + d s² to the edges' normal curvatures
// (upper triangle; each edge weighted by the area of the face it is seen from, twice for interior
// edges).
struct FanSums {
  double mixed_area = 0, angle_sum = 0;
  Vec3 laplacian = Vec3::Zero();
  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
};

// The tensor fit's row for an edge from the vertex (its normal curvature along the edge), weighted
// by `face_area`. The edge's direction in the tangent plane is (c, s) = (x, y)/|(x, y)|; the row
// (c², 2cs, s²) needs no square root. An edge along the normal adds nothing.
inline void addEdgeCurvature(const Vec3 &edge, double length2, double face_area, const Vec3 &normal,
                             const Vec3 &t1, const Vec3 &t2, FanSums &sums) {
  const double along_normal = edge.dot(normal);
  const double x = edge.dot(t1), y = edge.dot(t2), tangent2 = x * x + y * y;
  if (!(tangent2 > 1e-24 * length2)) return;
  // The neighbour lies below the tangent plane on a sphere: curvature positive.
  const double kappa = -2 * along_normal / length2;
  const Eigen::Vector3d row = Eigen::Vector3d(x * x, 2 * x * y, y * y) / tangent2;
  const Eigen::Vector3d weighted = face_area * row;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) sums.normal_matrix(i, j) += weighted[i] * row[j];
  sums.rhs += kappa * weighted;
}

// Adds the corner of face `t` at vertex v (position p) to v's sums; false for a degenerate face
// (the vertex then gets zeros).
inline bool addFanCorner(int v, const Face &t, const std::vector<Vec3> &points, const Vec3 &normal,
                         const Vec3 &t1, const Vec3 &t2, bool with_directions, FanSums &sums) {
  const Vec3 &p = points[v];
  const int corner = t[0] == v ? 0 : t[1] == v ? 1 : 2;
  const Vec3 &q = points[t[(corner + 1) % 3]], &r = points[t[(corner + 2) % 3]];
  const Vec3 pq = q - p, pr = r - p, qr = r - q;
  const double pq2 = pq.squaredNorm(), pr2 = pr.squaredNorm();
  const double twice_area = pq.cross(pr).norm();
  // As detail::isDegenerateTriangle, on the values needed below anyway.
  const double longest2 = std::max({pq2, pr2, qr.squaredNorm()});
  if (!(longest2 > 0) || !(twice_area > 1e-12 * longest2) || !std::isfinite(twice_area))
    return false;
  const double dot_p = pq.dot(pr), dot_q = -pq.dot(qr), dot_r = pr.dot(qr);
  const double cot_q = dot_q / twice_area, cot_r = dot_r / twice_area;
  sums.laplacian += cot_r * pq + cot_q * pr;
  sums.angle_sum += std::atan2(twice_area, dot_p);
  // Meyer's mixed area: Voronoi region unless the triangle is obtuse.
  if (dot_p >= 0 && dot_q >= 0 && dot_r >= 0)
    sums.mixed_area += (pr2 * cot_q + pq2 * cot_r) / 8;
  else
    sums.mixed_area += dot_p < 0 ? twice_area / 4 : twice_area / 8;
  if (with_directions) {
    addEdgeCurvature(pq, pq2, 0.5 * twice_area, normal, t1, t2, sums);
    addEdgeCurvature(pr, pr2, 0.5 * twice_area, normal, t1, t2, sums);
  }
  return true;
}

// An interior vertex's Meyer H, K, k1, k2 from its sums, and with them its principal directions
// (the tensor fit's eigenvectors in the tangent frame t1, t2).
inline void storeInteriorCurvature(int v, FanSums &sums, const Vec3 &t1, const Vec3 &t2,
                                   bool with_directions, CurvatureField &out) {
  const Vec3 &normal = out.normal[v];
  const double H = -sums.laplacian.dot(normal) / (4 * sums.mixed_area);
  const double K = (2 * M_PI - sums.angle_sum) / sums.mixed_area;
  const double root = std::sqrt(std::max(H * H - K, 0.0));
  out.mean[v] = H;
  out.gauss[v] = K;
  out.k1[v] = H + root;
  out.k2[v] = H - root;
  if (!with_directions) return;
  Eigen::Matrix3d &M = sums.normal_matrix;
  M(1, 0) = M(0, 1); // (the fan filled the upper triangle)
  M(2, 0) = M(0, 2);
  M(2, 1) = M(1, 2);
  const Eigen::Vector3d tensor = solveTensorFit(M, sums.rhs);
  tensorDirections(tensor[0], tensor[1], tensor[2], t1, t2, normal, out.dir1[v], out.dir2[v]);
}

// A boundary vertex, where the angle deficit is undefined: H, K, k1, k2 are the averages of its
// interior 1-ring neighbours' values (0 if none), and the directions the eigenvectors of their
// averaged anisotropic tensors (k1 − k2) d1 d1ᵀ projected into its tangent plane (its frame from
// the first pass in dir1, dir2).
inline void borrowBoundaryCurvature(int v, const Rings &rings,
                                    const std::vector<std::uint8_t> &interior_valid,
                                    bool with_directions, CurvatureField &out) {
  double H = 0, K = 0, k1 = 0, k2 = 0;
  Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
  int count = 0;
  for (const int *w = rings.ring1Begin(v); w != rings.ring1End(v); ++w) {
    if (!interior_valid[*w]) continue;
    H += out.mean[*w];
    K += out.gauss[*w];
    k1 += out.k1[*w];
    k2 += out.k2[*w];
    if (with_directions)
      tensor += (out.k1[*w] - out.k2[*w]) * out.dir1[*w] * out.dir1[*w].transpose();
    ++count;
  }
  if (count == 0) return;
  out.mean[v] = H / count;
  out.gauss[v] = K / count;
  out.k1[v] = k1 / count;
  out.k2[v] = k2 / count;
  if (!with_directions) return;
  const Vec3 t1 = out.dir1[v], t2 = out.dir2[v];
  tensorDirections(t1.dot(tensor * t1), t1.dot(tensor * t2), t2.dot(tensor * t2), t1, t2,
                   out.normal[v], out.dir1[v], out.dir2[v]);
}

} // namespace detail

// Meyer et al. 2003 H, K, k1, k2 plus a per-vertex curvature tensor fit for the directions.
// Non-manifold, isolated and degenerate-face vertices get zeros (directions: a tangent frame when
// the normal exists, zero otherwise). Boundary vertices borrow from their interior neighbours
// (detail::borrowBoundaryCurvature). `with_directions` false leaves dir1 and dir2 empty and skips
// the tensor fit (H, K, k1, k2 are the same to the bit): what describes a smoothing result needs
// no directions (48 bytes per vertex).
inline void computeCurvature(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                             const Rings &rings, CurvatureField &out, bool with_directions = true) {
  const int n = rings.vertex_count;
  computeVertexNormals(points, faces, rings, out.normal);
  out.area.assign(n, 0.0);
  out.mean.assign(n, 0.0);
  out.gauss.assign(n, 0.0);
  out.k1.assign(n, 0.0);
  out.k2.assign(n, 0.0);
  out.dir1.assign(with_directions ? n : 0, Vec3::Zero());
  out.dir2.assign(with_directions ? n : 0, Vec3::Zero());
  // Vertices whose Meyer values are defined: the ones boundary vertices borrow from.
  std::vector<std::uint8_t> interior_valid(n, 0);
  std::vector<std::uint8_t> degenerate(n, 0);

#pragma omp parallel for schedule(dynamic, 2048) if (parallelHeavy(n))
  for (int v = 0; v < n; ++v) {
    const Vec3 &normal = out.normal[v];
    Vec3 t1 = Vec3::Zero(), t2 = Vec3::Zero();
    if (normal.squaredNorm() > 0) {
      detail::tangentFrame(normal, t1, t2);
      if (with_directions) out.dir1[v] = t1, out.dir2[v] = t2;
    }
    if (rings.isolated[v] || rings.nonmanifold[v] || normal.squaredNorm() == 0) continue;
    detail::FanSums sums;
    bool has_degenerate_face = false;
    for (const int *f = rings.facesBegin(v); f != rings.facesEnd(v) && !has_degenerate_face; ++f)
      has_degenerate_face =
          !detail::addFanCorner(v, faces[*f], points, normal, t1, t2, with_directions, sums);
    if (has_degenerate_face || !(sums.mixed_area > 0)) {
      degenerate[v] = 1;
      continue;
    }
    out.area[v] = sums.mixed_area;
    if (rings.boundary[v]) continue;
    detail::storeInteriorCurvature(v, sums, t1, t2, with_directions, out);
    interior_valid[v] = 1;
  }

  const bool any_boundary =
      std::find(rings.boundary.begin(), rings.boundary.end(), 1) != rings.boundary.end();
#pragma omp parallel for schedule(dynamic, 2048) if (any_boundary && n >= min_parallel_vertices)
  for (int v = 0; v < n; ++v)
    if (rings.boundary[v] && !rings.nonmanifold[v] && !degenerate[v] && out.area[v] != 0)
      detail::borrowBoundaryCurvature(v, rings, interior_valid, with_directions, out);
}

} // namespace vcg_ext
