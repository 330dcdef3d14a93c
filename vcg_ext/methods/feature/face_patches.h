// Feature-preserving mode, stage B: one bi-quadratic height patch per face, and the vertex update
// that moves each vertex onto the patches of its faces.
//
// Inputs: current positions, triangles, FaceRings and face geometry (face_rings.h), the filtered
// face normals. Output: per face a FacePatch; per vertex its new position. The patch of face f is a
// height field z(x, y) = Σ c_ab x^a y^b (a, b ≤ 2, the space of a bi-quadratic Bézier patch) over
// the plane through f's centroid perpendicular to f's filtered normal, in mean-edge-length units.
// It is fitted by weighted least squares to the centroids of f's vertex ring (weight: area × a
// range kernel on the filtered normals, so faces across a crease do not count), with the filtered
// normals as slope constraints and a tiny thin-plate term that keeps the fit well posed. The vertex
// update is Sun, Rosin, Martin, Langbein 2007's (each face's plane pulls the vertex along its
// normal) with the patches in place of the planes. Written as a scalar height fit rather than with
// bezier_patch.h: slope constraints need derivative rows, which the 3-D control-point fit does not
// take.
#pragma once

#include "vcg_ext/methods/feature/normal_filter.h"
#include "vcg_ext/core/small_ldlt.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace vcg_ext {

using HeightCoefficients = Eigen::Matrix<double, 9, 1>;

struct FacePatch {
  Vec3 origin = Vec3::Zero(), normal = Vec3::UnitZ();
  double unit = 1;                                      // length of one local unit (mean edge)
  HeightCoefficients c = HeightCoefficients::Zero();    // zero: the plane (Sun's update)
  bool curved = false;                                  // c was fitted (else the plane)

  // The patch's tangent frame (x along e1, y along e2): derived from the normal rather than
  // stored (a patch per face on millions of faces). Any frame serves, the fit being rotation
  // invariant; this one takes the axis least aligned with the normal.
  static void tangentFrame(const Vec3 &n, Vec3 &e1, Vec3 &e2) {
    const Vec3 axis = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : std::abs(n.y()) < 0.6 ? Vec3::UnitY()
                                                                                     : Vec3::UnitZ();
    e1 = (axis - n * n.dot(axis)).normalized();
    e2 = n.cross(e1);
  }

  // The height basis x^a y^b, index 3a + b, and its x and y derivatives.
  static HeightCoefficients basis(double x, double y) {
    HeightCoefficients b;
    basisInto(x, y, b.data());
    return b;
  }
  // The same into 9 plain values (the patch fit's rows, fitFacePatchAt).
  static void basisInto(double x, double y, double *b) {
    const double px[3] = {1, x, x * x}, py[3] = {1, y, y * y};
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) b[3 * a + k] = px[a] * py[k];
  }
  static void basisGradient(double x, double y, HeightCoefficients &bx, HeightCoefficients &by) {
    const double px[3] = {1, x, x * x}, py[3] = {1, y, y * y};
    const double dx[3] = {0, 1, 2 * x}, dy[3] = {0, 1, 2 * y};
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) {
        bx[3 * a + k] = dx[a] * py[k];
        by[3 * a + k] = px[a] * dy[k];
      }
  }

  // Where the patch is, measured along the normal from `p`'s foot point: p moved onto the patch.
  Vec3 projectAlongNormal(const Vec3 &p) const {
    return project(origin, normal, unit, c, curved, p);
  }
  static Vec3 project(const Vec3 &origin, const Vec3 &normal, double unit,
                      const HeightCoefficients &c, bool curved, const Vec3 &p) {
    const Vec3 d = (p - origin) / unit;
    const double z = d.dot(normal);
    double height = 0.0;
    if (curved) {
      Vec3 e1, e2;
      tangentFrame(normal, e1, e2);
      height = basis(d.dot(e1), d.dot(e2)).dot(c);
    }
    return p + normal * ((height - z) * unit);
  }
};

struct FacePatchParams {
  double sigma = 0.2;        // range kernel width on |n_f − n_j| of the filtered normals
  double slope_weight = 1.0; // weight of a slope row relative to its centroid's position row
  double thin_plate = 1e-5;  // thin-plate energy over [−1,1]², relative to the total weight
  // The paper's α: the data's weight against the smoothness term (α² against (1 − α)², as in its
  // Bézier fit). Below 1 the thin-plate weight grows by ((1 − α)/α)², so the patches bend less
  // and the vertex updates smooth more; 1 is the plain fit.
  double alpha = 1.0;
};

namespace detail {

// ∫∫ over [−1,1]² of z_xx² + 2 z_xy² + z_yy² as a quadratic form in the height coefficients,
// integrated exactly by 3-point Gauss–Legendre quadrature (the integrands have degree ≤ 4 per
// axis).
inline const Eigen::Matrix<double, 9, 9> &thinPlateMatrix() {
  static const Eigen::Matrix<double, 9, 9> T = [] {
    Eigen::Matrix<double, 9, 9> t = Eigen::Matrix<double, 9, 9>::Zero();
    const double g[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double x = g[i], y = g[j];
        const double px[3] = {1, x, x * x}, py[3] = {1, y, y * y};
        const double dx[3] = {0, 1, 2 * x}, dy[3] = {0, 1, 2 * y};
        const double ddx[3] = {0, 0, 2}, ddy[3] = {0, 0, 2};
        HeightCoefficients xx, xy, yy;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            xx[3 * a + b] = ddx[a] * py[b];
            xy[3 * a + b] = dx[a] * dy[b];
            yy[3 * a + b] = px[a] * ddy[b];
          }
        t += w[i] * w[j] * (xx * xx.transpose() + 2 * xy * xy.transpose() + yy * yy.transpose());
      }
    return t;
  }();
  return T;
}

// M += w a aᵀ on the lower triangle only (what LDLT<·, Lower> reads); column-major, so the inner
// loop runs down a column. `a` holds 9 values.
inline void addLowerOuter(Eigen::Matrix<double, 9, 9> &M, double w, const double *a) {
  double *m = M.data();
  for (int j = 0; j < 9; ++j) {
    const double s = w * a[j];
    double *column = m + 9 * j;
    for (int i = j; i < 9; ++i) column[i] += s * a[i];
  }
}

// addLowerOuter three times (w0 a0 a0ᵀ, then w1 a1 a1ᵀ, then w2 a2 a2ᵀ) in one sweep of M: each
// entry takes the same three products in the same order, so the same bits, a third of the traffic.
inline void addLowerOuter3(Eigen::Matrix<double, 9, 9> &M, double w0, const double *a0, double w1,
                           const double *a1, double w2, const double *a2) {
  double *m = M.data();
  for (int j = 0; j < 9; ++j) {
    const double s0 = w0 * a0[j], s1 = w1 * a1[j], s2 = w2 * a2[j];
    double *column = m + 9 * j;
    for (int i = j; i < 9; ++i) {
      double c = column[i] + s0 * a0[i];
      c += s1 * a1[i];
      column[i] = c + s2 * a2[i];
    }
  }
}

} // namespace detail

namespace detail {

// fitFacePatch with the face's centroid given, its ring as the range [ring, ring_end) and the
// faces' areas in `area` (fitFacePatchAt compiles this body twice, see there).
[[gnu::always_inline]] inline bool
fitFacePatchBody(int f, const Vec3 &centroid, const std::vector<Vec3> &points,
                 const std::vector<Face> &faces, const int *ring, const int *ring_end,
                 const double *area, const std::vector<Vec3> &filtered, double mean_area,
                 double mean_edge, const FacePatchParams &params, FacePatch &out) {
  const Vec3 &n = filtered[f];
  out.origin = centroid;
  out.unit = mean_edge;
  out.c.setZero();
  out.curved = false;
  out.normal = n; // a zero normal makes the patch a no-op in the vertex update
  if (!(n.squaredNorm() > 0.5)) return false;
  Vec3 e1, e2;
  FacePatch::tangentFrame(n, e1, e2);

  Eigen::Matrix<double, 9, 9> M = Eigen::Matrix<double, 9, 9>::Zero();
  HeightCoefficients rhs = HeightCoefficients::Zero();
  const double range = -0.5 / (params.sigma * params.sigma);
  // Multiplications by reciprocals where the fit divided, which is faster (the coefficients are
  // kept in single precision: the result hardly ever changes; docs/studies/performance.md).
  const double inverse_edge = 1.0 / mean_edge;
  double total = 0;
  for (const int *g = ring; g != ring_end; ++g) {
    const Vec3 &m = filtered[*g];
    const double w = area[*g] / mean_area * rangeKernel(range * (n - m).squaredNorm());
    if (!(w > 1e-12)) continue;
    // Face g's data are its centroid height and its normal, i.e. its plane. The patch is asked to
    // reproduce that plane where it interpolates g's corners (the mean of the patch at the corners,
    // the gradient of the linear interpolant), not at the centroid: a centroid lies below a convex
    // surface by about h²κ/6, and fitting centroids would sink the mesh a little every pass.
    // The rows are plain arrays, written and read element by element: as Eigen 9-vectors (scalar
    // stores, read in pairs) every pair stalled on store forwarding, in the fit's hottest
    // instructions. The arithmetic per element is Eigen's, so the bits are the same.
    double x[3], y[3], z[3], corner[3][9];
    for (int k = 0; k < 3; ++k) {
      const Vec3 d = (points[faces[*g][k]] - out.origin) * inverse_edge;
      x[k] = d.dot(e1), y[k] = d.dot(e2), z[k] = d.dot(n);
      FacePatch::basisInto(x[k], y[k], corner[k]);
    }
    double b[9];
    for (int i = 0; i < 9; ++i) b[i] = (corner[0][i] + corner[1][i] + corner[2][i]) / 3.0;
    const double height = w * (z[0] + z[1] + z[2]) / 3.0;
    for (int i = 0; i < 9; ++i) rhs[i] += height * b[i];
    total += w;
    const double along = m.dot(n);
    const double ax = x[1] - x[0], ay = y[1] - y[0], bx = x[2] - x[0], by = y[2] - y[0];
    const double det = ax * by - ay * bx; // twice the projected area, in edge² units
    const double true_area = 2.0 * area[*g] / (mean_edge * mean_edge);
    // Slopes only where g's projection is a fair, unfolded triangle and m is not steep.
    if (along > 0.5 && params.slope_weight > 0 && det > 0.3 * true_area) {
      // The interpolant's gradient: J g = (h1 − h0, h2 − h0), J = [ax ay; bx by].
      double gx[9], gy[9];
      const double inverse_det = 1.0 / det;
      for (int i = 0; i < 9; ++i) {
        const double d1 = corner[1][i] - corner[0][i], d2 = corner[2][i] - corner[0][i];
        gx[i] = (by * d1 - ay * d2) * inverse_det;
        gy[i] = (-bx * d1 + ax * d2) * inverse_det;
      }
      // The height field whose normal is m has gradient −(m·e1, m·e2)/(m·n).
      const double ws = w * params.slope_weight;
      detail::addLowerOuter3(M, w, b, ws, gx, ws, gy);
      const double sx = ws * (-m.dot(e1) / along), sy = ws * (-m.dot(e2) / along);
      for (int i = 0; i < 9; ++i) rhs[i] += sx * gx[i] + sy * gy[i];
    } else {
      detail::addLowerOuter(M, w, b);
    }
  }
  if (!(total > 0)) return false;
  double smoothness = params.thin_plate;
  if (params.alpha < 1) {
    const double alpha = std::max(params.alpha, 1e-3); // α = 0 would ask for a plane: nearly that
    smoothness += (1 - alpha) * (1 - alpha) / (alpha * alpha);
  }
  M += smoothness * total * detail::thinPlateMatrix();
  // Unpivoted LDLᵀ (small_ldlt.h); where its pivots are not clearly positive, Eigen's pivoted
  // LDLT decides, with the test the fit has always used (its pivots above 1e-12 of the largest).
  double L[9][9];
  for (int j = 0; j < 9; ++j)
    for (int i = j; i < 9; ++i) L[i][j] = M(i, j);
  HeightCoefficients c;
  if (detail::ldlt9(L, 1e-10)) {
    detail::ldlt9Solve<1>(L, rhs.data(), c.data());
  } else {
    Eigen::LDLT<Eigen::Matrix<double, 9, 9>, Eigen::Lower> ldlt(M);
    const auto D = ldlt.vectorD();
    if (ldlt.info() != Eigen::Success || !(D.minCoeff() > 1e-12 * D.maxCoeff())) return false;
    c = ldlt.solve(rhs);
  }
  if (!c.allFinite()) return false;
  out.c = c;
  out.curved = true;
  return true;
}

// The fit's body as built for every x86-64 processor, and again with AVX2's instructions (VEX
// encoding: three-operand forms, no register copies before each sum), chosen once by the
// processor. AVX2 without FMA: the compiler may not fuse a product and a sum nor reorder sums, so
// both give the same bits (FacePatches.BothBuildsOfTheFitGiveTheSameBits); the second is about
// a tenth faster (docs/studies/performance.md).
inline bool fitFacePatchPortable(int f, const Vec3 &centroid, const std::vector<Vec3> &points,
                                 const std::vector<Face> &faces, const int *ring,
                                 const int *ring_end, const double *area,
                                 const std::vector<Vec3> &filtered, double mean_area,
                                 double mean_edge, const FacePatchParams &params, FacePatch &out) {
  return fitFacePatchBody(f, centroid, points, faces, ring, ring_end, area, filtered, mean_area,
                          mean_edge, params, out);
}
#if defined(__GNUC__) && defined(__x86_64__)
#define VCG_EXT_FIT_WITH_AVX2 1
__attribute__((target("avx2"))) inline bool
fitFacePatchAvx2(int f, const Vec3 &centroid, const std::vector<Vec3> &points,
                 const std::vector<Face> &faces, const int *ring, const int *ring_end,
                 const double *area, const std::vector<Vec3> &filtered, double mean_area,
                 double mean_edge, const FacePatchParams &params, FacePatch &out) {
  return fitFacePatchBody(f, centroid, points, faces, ring, ring_end, area, filtered, mean_area,
                          mean_edge, params, out);
}
#endif

inline bool fitFacePatchAt(int f, const Vec3 &centroid, const std::vector<Vec3> &points,
                           const std::vector<Face> &faces, const int *ring, const int *ring_end,
                           const double *area, const std::vector<Vec3> &filtered, double mean_area,
                           double mean_edge, const FacePatchParams &params, FacePatch &out) {
#ifdef VCG_EXT_FIT_WITH_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2)
    return fitFacePatchAvx2(f, centroid, points, faces, ring, ring_end, area, filtered, mean_area,
                            mean_edge, params, out);
#endif
  return fitFacePatchPortable(f, centroid, points, faces, ring, ring_end, area, filtered,
                              mean_area, mean_edge, params, out);
}

// A face's centroid, as computeFaceGeometry computes it.
inline Vec3 faceCentroid(const std::vector<Vec3> &points, const Face &t) {
  return (points[t[0]] + points[t[1]] + points[t[2]]) / 3.0;
}

} // namespace detail

// Fits face f's patch. Returns false (leaving `out` the plane through f's centroid with its
// filtered normal, i.e. Sun's update) when the face has no usable normal or the solve fails.
inline bool fitFacePatch(int f, const std::vector<Vec3> &points, const std::vector<Face> &faces,
                         const FaceRings &face_rings, const FaceGeometry &geometry,
                         const std::vector<Vec3> &filtered, double mean_area, double mean_edge,
                         const FacePatchParams &params, FacePatch &out) {
  return detail::fitFacePatchAt(
      f, geometry.centroid[f], points, faces, face_rings.begin(f), face_rings.end(f),
      geometry.area.data(), filtered, mean_area, mean_edge, params, out);
}

// Every face's patch, compactly: per face the height coefficients in single precision and whether
// they were fitted (37 bytes instead of a FacePatch's 136; a coefficient's rounding moves a vertex
// by ~1e-7 mean edge lengths). The rest of a FacePatch is read back from the arrays the fit was
// given (origin: the face's centroid; normal: the normal it was fitted with), which must stay as
// they were while the patches are used.
struct FacePatches {
  std::vector<Eigen::Matrix<float, 9, 1>> c;
  std::vector<std::uint8_t> curved;
  const std::vector<Vec3> *points = nullptr, *normals = nullptr;
  const std::vector<Face> *faces = nullptr;
  double unit = 1;

  size_t size() const { return c.size(); }
  FacePatch patch(int f) const {
    FacePatch p;
    p.origin = detail::faceCentroid(*points, (*faces)[f]);
    p.normal = (*normals)[f];
    p.unit = unit;
    p.c = c[f].cast<double>();
    p.curved = curved[f] != 0;
    return p;
  }
  Vec3 projectAlongNormal(int f, const Vec3 &p) const {
    return FacePatch::project(detail::faceCentroid(*points, (*faces)[f]), (*normals)[f], unit,
                              c[f].cast<double>(), curved[f] != 0, p);
  }
};

namespace detail {

// fitFacePatches with face f's ring from `ring_of(f, scratch)`, a pair of pointers (into the
// FaceRings, or into `scratch` when the ring is merged on the fly).
template <class RingOf>
long fitFacePatchesWith(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                        RingOf ring_of, const std::vector<Vec3> &normals, double mean_edge,
                        const FacePatchParams &params, const std::vector<double> &face_alpha,
                        FacePatches &patches) {
  const int face_count = int(faces.size());
  patches.c.resize(face_count);
  patches.curved.resize(face_count);
  patches.points = &points;
  patches.normals = &normals;
  patches.faces = &faces;
  patches.unit = mean_edge;
  std::vector<double> area(face_count);
#pragma omp parallel for schedule(static) if (face_count >= min_parallel_vertices)
  for (int f = 0; f < face_count; ++f) {
    double len;
    detail::unitFaceNormal(points[faces[f][0]], points[faces[f][1]], points[faces[f][2]], len);
    area[f] = 0.5 * len;
  }
  double mean_area = 0;
  for (double a : area) mean_area += a / face_count;
  long fallbacks = 0;
#pragma omp parallel reduction(+ : fallbacks) if (parallelHeavy(face_count))
  {
    std::vector<int> scratch;
#pragma omp for schedule(static)
    for (int f = 0; f < face_count; ++f) {
      FacePatchParams own = params;
      if (!face_alpha.empty()) own.alpha = face_alpha[f];
      FacePatch fitted;
      const std::pair<const int *, const int *> ring = ring_of(f, scratch);
      fallbacks += !detail::fitFacePatchAt(f, detail::faceCentroid(points, faces[f]), points,
                                           faces, ring.first, ring.second, area.data(),
                                           normals, mean_area,
                                           mean_edge, own, fitted);
      patches.c[f] = fitted.c.cast<float>();
      patches.curved[f] = fitted.curved;
    }
  }
  return fallbacks;
}

} // namespace detail

// Fits every face's patch from `normals` (filtered or the faces' own); `face_alpha`, when not
// empty, replaces params.alpha per face. Returns how many fits fell back to the face's plane.
// The faces' areas and centroids are computed here as computeFaceGeometry does (same values).
inline long fitFacePatches(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                           const FaceRings &face_rings, const std::vector<Vec3> &normals,
                           double mean_edge, const FacePatchParams &params,
                           const std::vector<double> &face_alpha, FacePatches &patches) {
  return detail::fitFacePatchesWith(
      points, faces,
      [&](int f, std::vector<int> &) { return std::make_pair(face_rings.begin(f), face_rings.end(f)); },
      normals, mean_edge, params, face_alpha, patches);
}

// The same without FaceRings: each face's ring merged from its corners' face lists when its patch
// is fitted (the same faces in the same order as computeFaceRings lists them, so the same
// patches), which saves building and holding the rings (13 faces per face) for a single fit.
inline long fitFacePatches(const std::vector<Vec3> &points, const std::vector<Face> &faces,
                           const Rings &rings, const std::vector<Vec3> &normals, double mean_edge,
                           const FacePatchParams &params, const std::vector<double> &face_alpha,
                           FacePatches &patches) {
  return detail::fitFacePatchesWith(
      points, faces,
      [&](int f, std::vector<int> &scratch) {
        scratch.clear();
        const Face &t = faces[f];
        detail::mergeSortedUnique(rings.facesBegin(t[0]), rings.facesEnd(t[0]),
                                  rings.facesBegin(t[1]), rings.facesEnd(t[1]),
                                  rings.facesBegin(t[2]), rings.facesEnd(t[2]), scratch);
        return std::make_pair<const int *, const int *>(scratch.data(),
                                                         scratch.data() + scratch.size());
      },
      normals, mean_edge, params, face_alpha, patches);
}

// The paper's α rule moved to face patches: per face, the smallest over the largest saliency of
// the vertices its fit reads (the corners of its ring's faces); 1 where nothing there is salient.
inline std::vector<double> faceAlphaFromSaliency(const std::vector<Face> &faces,
                                                 const FaceRings &face_rings,
                                                 const std::vector<double> &saliency) {
  const int face_count = int(faces.size());
  std::vector<double> alpha(face_count, 1.0);
#pragma omp parallel for schedule(static) if (face_count >= min_parallel_vertices)
  for (int f = 0; f < face_count; ++f) {
    double lo = INFINITY, hi = 0;
    for (const int *g = face_rings.begin(f); g != face_rings.end(f); ++g)
      for (int v : faces[*g]) lo = std::min(lo, saliency[v]), hi = std::max(hi, saliency[v]);
    if (hi > 0 && std::isfinite(lo)) alpha[f] = lo / hi;
  }
  return alpha;
}

namespace detail {
inline Vec3 projectOnto(const std::vector<FacePatch> &patches, int f, const Vec3 &p) {
  return patches[f].projectAlongNormal(p);
}
inline Vec3 projectOnto(const FacePatches &patches, int f, const Vec3 &p) {
  return patches.projectAlongNormal(f, p);
}
} // namespace detail

// Sun et al.'s vertex update with patches: the mean, over the vertex's faces, of the vertex moved
// along each face's normal onto that face's patch (FacePatches or a vector of FacePatch).
template <class Patches>
Vec3 moveOntoFacePatches(int v, const Vec3 &p, const Rings &rings, const Patches &patches) {
  Vec3 sum = Vec3::Zero();
  int count = 0;
  for (const int *f = rings.facesBegin(v); f != rings.facesEnd(v); ++f) {
    sum += detail::projectOnto(patches, *f, p) - p;
    ++count;
  }
  return count ? Vec3(p + sum / count) : p;
}

// The same update with every patch flat (Sun et al. 2007 as published): the planes through the
// face centroids with the filtered normals. The arithmetic of projectAlongNormal at zero height,
// without building a FacePatch per face (most of the feature mode's vertex updates use planes).
inline Vec3 moveOntoFacePlanes(int v, const Vec3 &p, const Rings &rings,
                               const std::vector<Vec3> &centroid, const std::vector<Vec3> &normal,
                               double unit) {
  Vec3 sum = Vec3::Zero();
  int count = 0;
  for (const int *f = rings.facesBegin(v); f != rings.facesEnd(v); ++f) {
    const Vec3 d = (p - centroid[*f]) / unit;
    const double z = d.dot(normal[*f]);
    sum += (p + normal[*f] * ((0.0 - z) * unit)) - p;
    ++count;
  }
  return count ? Vec3(p + sum / count) : p;
}

} // namespace vcg_ext
