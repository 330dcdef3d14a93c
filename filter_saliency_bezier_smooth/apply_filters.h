// What the two filters do to a mesh, for any vcglib mesh type (CMeshO of either MeshLab API
// generation, or a test mesh): validate, run vcg_ext on a copy of the positions, and write
// positions, quality, attributes and curvature directions back only when everything succeeded.
#pragma once

#include "filter_parameters.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/color.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/complex.h>
#include <vcg_ext/display_scale.h>
#include <vcg_ext/methods.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <typeindex>

namespace saliency_bezier {

struct FilterOutcome {
  bool ok = false;
  std::string error;
  std::vector<std::string> log;
  std::string method;   // the smoothing method that ran (the automatic one names its choice)
  std::string summary;  // the log's first line: what was measured and what was done
  bool colored = false; // the vertex colours were written (the GUI must show them)
};

namespace detail {

inline std::string format(const char *fmt, double a = 0, double b = 0, double c = 0,
                          double d = 0) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, fmt, a, b, c, d);
  return buffer;
}

// `value` in the mesh's scalar type: NaN as 0 and anything beyond the type's range as its largest
// value, counted in `clamped` (found by the fuzzer: a float mesh 3e-30 across has K = 1e59).
template <class Scalar>
Scalar storable(double value, long &clamped) {
  const double limit = double(std::numeric_limits<Scalar>::max());
  if (std::isnan(value)) return ++clamped, Scalar(0);
  if (std::abs(value) > limit) return ++clamped, Scalar(std::copysign(limit, value));
  return Scalar(value);
}

// Stores `values` (compact order) as the per-vertex attribute `name` of the mesh's scalar type,
// replacing an attribute of that name but another type.
template <class MeshType>
void storeAttribute(MeshType &m, const vcg_ext::MeshArrays &arrays, const std::string &name,
                    const std::vector<double> &values, long &clamped) {
  using Scalar = typename MeshType::ScalarType;
  using Allocator = vcg::tri::Allocator<MeshType>;
  // vcglib's lookup compares only the size: an int attribute of this name (another filter's) would
  // come back as a float handle and be written through the wrong type (found by the fuzzer).
  for (const auto &attribute : m.vert_attr)
    if (attribute._name == name && attribute._type != std::type_index(typeid(Scalar))) {
      Allocator::DeletePerVertexAttribute(m, name);
      break;
    }
  auto handle = Allocator::template FindPerVertexAttribute<Scalar>(m, name);
  if (!Allocator::template IsValidHandle<Scalar>(m, handle)) {
    Allocator::DeletePerVertexAttribute(m, name);
    handle = Allocator::template AddPerVertexAttribute<Scalar>(m, name);
  }
  for (size_t c = 0; c < values.size(); ++c)
    handle[arrays.mesh_slot[c]] = storable<Scalar>(values[c], clamped);
}

// Stores `values` (already on their display scale) as vertex quality and, with `color`, colours
// the vertices by it over its full range as MeshLab's Colorize by vertex Quality does at its
// defaults. Returns whether colours were written.
template <class MeshType>
bool storeQuality(MeshType &m, const vcg_ext::MeshArrays &arrays,
                  const std::vector<double> &values, bool color) {
  if (!vcg::tri::HasPerVertexQuality(m)) return false;
  using Scalar = typename MeshType::VertexType::QualityType;
  long clamped = 0; // counted with the attributes
  for (size_t c = 0; c < values.size(); ++c)
    m.vert[arrays.mesh_slot[c]].Q() = storable<Scalar>(values[c], clamped);
  if (!color || !vcg::tri::HasPerVertexColor(m) || values.empty()) return false;
  const auto range = std::minmax_element(values.begin(), values.end());
  vcg::tri::UpdateColor<MeshType>::PerVertexQualityRamp(m, Scalar(*range.first),
                                                         Scalar(*range.second));
  return true;
}

// A quantity on its display scale: saliency up to its 99th percentile, curvatures on a signed
// log scale, the rest (alpha, displacement) as they are.
inline std::vector<double> displayed(const std::string &name, const std::vector<double> &values) {
  if (name == "Saliency") return vcg_ext::percentileClipped(values);
  if (name == "Mean curvature" || name == "Gaussian curvature" || name == "K1" || name == "K2")
    return vcg_ext::signedLogScale(values);
  return values;
}

// The rejection reasons shared by both filters; empty when the mesh can be processed.
template <class MeshType>
std::string rejectMesh(const MeshType &m, const vcg_ext::MeshArrays &arrays) {
  if (m.vn == 0) return "The mesh is empty.";
  return vcg_ext::validateForSmoothing(arrays);
}

inline std::string checkRange(const ParameterValues &p, const std::string &name, double lo,
                              double hi) {
  const double value = p.at(name);
  if (!(value >= lo && value <= hi))
    return "Parameter '" + name + "' = " + format("%g", value) + " is outside [" +
           format("%g", lo) + ", " + format("%g", hi) + "].";
  return {};
}

inline vcg_ext::ProgressFn progressOf(vcg::CallBackPos *cb) {
  if (!cb) return nullptr;
  return [cb](int percent, const char *stage) { return cb(percent, stage); };
}

} // namespace detail

// "Compute Mesh Saliency and Principal Curvatures": stages 1-3, positions untouched.
template <class MeshType>
FilterOutcome applyComputeSaliency(MeshType &m, const ParameterValues &p, vcg::CallBackPos *cb) {
  FilterOutcome out;
  const vcg_ext::MeshArrays arrays = vcg_ext::extractArrays(m);
  out.error = detail::rejectMesh(m, arrays);
  if (out.error.empty()) out.error = detail::checkRange(p, "saliency_scale", 1e-6, 50);
  if (out.error.empty()) out.error = detail::checkRange(p, "quality", 0, 4);
  if (!out.error.empty()) return out;
  const bool color = p.count("color") && p.at("color") != 0;

  const auto start = std::chrono::steady_clock::now();
  const vcg_ext::Rings rings = vcg_ext::computeRings(int(arrays.points.size()), arrays.faces);
  const vcg_ext::EdgeStatistics stats = vcg_ext::edgeStatistics(arrays.points, rings);
  if (cb && !cb(10, "Curvature")) return out.error = "Cancelled.", out;
  vcg_ext::SurfaceAnalysis analysis;
  const double scale = p.at("saliency_scale") / 100.0 * stats.bbox_diagonal;
  vcg_ext::computeCurvature(arrays.points, arrays.faces, rings, analysis.curvature);
  if (cb && !cb(40, "Saliency")) return out.error = "Cancelled.", out;
  vcg_ext::computeMeshSaliency(arrays.points, rings, analysis.curvature, scale, analysis.saliency);
  if (cb && !cb(95, "Storing")) return out.error = "Cancelled.", out;

  const vcg_ext::CurvatureField &c = analysis.curvature;
  const std::vector<double> *quantities[] = {&analysis.saliency, &c.mean, &c.gauss, &c.k1, &c.k2};
  const int quality = int(p.at("quality"));
  out.colored = detail::storeQuality(
      m, arrays,
      detail::displayed(qualityChoices(FilterId::ComputeSaliencyCurvature)[quality],
                        *quantities[quality]),
      color);
  long clamped = 0;
  detail::storeAttribute(m, arrays, "Saliency", analysis.saliency, clamped);
  detail::storeAttribute(m, arrays, "MeanCurvature", c.mean, clamped);
  detail::storeAttribute(m, arrays, "GaussianCurvature", c.gauss, clamped);
  detail::storeAttribute(m, arrays, "K1", c.k1, clamped);
  detail::storeAttribute(m, arrays, "K2", c.k2, clamped);
  if (vcg::tri::HasPerVertexCurvatureDir(m)) {
    using Dir = typename MeshType::VertexType::CurVecType;
    using DirScalar = typename Dir::ScalarType;
    for (size_t i = 0; i < arrays.points.size(); ++i) {
      auto &v = m.vert[arrays.mesh_slot[i]];
      v.PD1() = Dir(DirScalar(c.dir1[i].x()), DirScalar(c.dir1[i].y()), DirScalar(c.dir1[i].z()));
      v.PD2() = Dir(DirScalar(c.dir2[i].x()), DirScalar(c.dir2[i].y()), DirScalar(c.dir2[i].z()));
      long counted_with_the_attributes = 0;
      v.K1() = detail::storable<DirScalar>(c.k1[i], counted_with_the_attributes);
      v.K2() = detail::storable<DirScalar>(c.k2[i], counted_with_the_attributes);
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  long salient = 0, boundary = 0, nonmanifold = 0, isolated = 0;
  double mean_abs_h = 0;
  for (size_t i = 0; i < arrays.points.size(); ++i) {
    salient += analysis.saliency[i] > 0.5;
    boundary += rings.boundary[i];
    nonmanifold += rings.nonmanifold[i];
    isolated += rings.isolated[i];
    mean_abs_h += std::abs(c.mean[i]) / arrays.points.size();
  }
  out.log.push_back(detail::format(
      "Saliency and curvature of %.0f vertices in %.3f s (epsilon = %g of the bbox diagonal).",
      double(arrays.points.size()), seconds, scale / stats.bbox_diagonal));
  out.log.push_back(detail::format("Vertices with saliency > 0.5: %.0f; mean |H| = %g; "
                                   "boundary vertices (curvature from neighbours): %.0f.",
                                   double(salient), mean_abs_h, double(boundary)));
  if (nonmanifold + isolated > 0)
    out.log.push_back(detail::format("Curvature and saliency undefined, set to 0: %.0f "
                                     "non-manifold, %.0f isolated (in no face) vertices.",
                                     double(nonmanifold), double(isolated)));
  if (clamped > 0)
    out.log.push_back(detail::format("%.0f per-vertex values were NaN or beyond the mesh's number "
                                     "range (a tiny mesh or tiny faces): stored as 0 or the largest "
                                     "representable value.",
                                     double(clamped)));
  out.ok = true;
  return out;
}

namespace detail {

// Writes a smoothing run's positions, quality and attributes into the mesh; returns how many
// per-vertex values had to be clamped to the mesh's number range.
template <class MeshType>
long storeSmoothingResult(MeshType &m, const vcg_ext::MeshArrays &arrays,
                          const std::vector<vcg_ext::Vec3> &result,
                          const vcg_ext::VertexQuantities &q, int quality, bool color,
                          bool &colored) {
  vcg_ext::writePositions(m, arrays, result);
  const std::vector<double> *quantities[] = {&q.saliency, &q.mean, &q.gauss, &q.k1,
                                             &q.k2,       &q.alpha, &q.displacement};
  colored = storeQuality(
      m, arrays,
      displayed(qualityChoices(FilterId::SaliencyBezierSmooth)[quality], *quantities[quality]),
      color);
  long clamped = 0;
  storeAttribute(m, arrays, "Saliency", q.saliency, clamped);
  storeAttribute(m, arrays, "MeanCurvature", q.mean, clamped);
  storeAttribute(m, arrays, "GaussianCurvature", q.gauss, clamped);
  storeAttribute(m, arrays, "K1", q.k1, clamped);
  storeAttribute(m, arrays, "K2", q.k2, clamped);
  storeAttribute(m, arrays, "Alpha", q.alpha, clamped);
  storeAttribute(m, arrays, "Displacement", q.displacement, clamped);
  if (vcg::tri::HasPerVertexNormal(m) && vcg::tri::HasPerFaceNormal(m))
    vcg::tri::UpdateNormal<MeshType>::PerVertexNormalizedPerFaceNormalized(m);
  vcg::tri::UpdateBounding<MeshType>::Box(m);
  return clamped;
}

inline std::string clampedLog(long clamped) {
  return format("%.0f per-vertex values were NaN or beyond the mesh's number range (a tiny mesh "
                "or tiny faces): stored as 0 or the largest representable value.",
                double(clamped));
}

} // namespace detail

// The filter's parameters as the methods read them (indexes by the checked enums).
inline vcg_ext::MethodParams methodParamsOf(const ParameterValues &p) {
  vcg_ext::MethodParams s;
  s.iterations = int(p.at("iterations"));
  s.alpha_override = p.at("alpha_override") != 0;
  s.alpha = p.at("alpha");
  const vcg_ext::BoundaryMode boundaries[] = {
      vcg_ext::BoundaryMode::Paper, vcg_ext::BoundaryMode::Fixed,
      vcg_ext::BoundaryMode::AlongBoundary, vcg_ext::BoundaryMode::NoInward};
  s.boundary = boundaries[int(p.at("boundary"))];
  s.preserve_volume = p.at("preserve_volume") != 0;
  s.selected_only = p.at("selected_only") != 0;
  s.saliency_scale = p.at("saliency_scale") / 100.0;
  s.folds = p.at("fold_handling") == 0 ? vcg_ext::FoldHandling::Ignore
                                       : vcg_ext::FoldHandling::Paper;
  s.uniform_variant = p.at("uniform_curvature") == 0 ? vcg_ext::UniformCurvatureVariant::Paper
                                                     : vcg_ext::UniformCurvatureVariant::Neighbour;
  s.newton_iterations = int(p.at("newton_iterations"));
  s.newton_step_limit = p.at("newton_step_limit");
  return s;
}

// Why the smoothing parameters cannot be used (empty: they can).
inline std::string checkSmoothingParameters(const ParameterValues &p) {
  const int methods = int(vcg_ext::methodTable().size());
  for (const auto &check : {detail::checkRange(p, "placement", 0, methods - 1),
                            detail::checkRange(p, "iterations", 0, 1000),
                            detail::checkRange(p, "alpha", 0, 1),
                            detail::checkRange(p, "uniform_curvature", 0, 1),
                            detail::checkRange(p, "boundary", 0, 3),
                            detail::checkRange(p, "fold_handling", 0, 1),
                            detail::checkRange(p, "newton_iterations", 0, 100),
                            detail::checkRange(p, "newton_step_limit", 0, 1000),
                            detail::checkRange(p, "saliency_scale", 1e-6, 50),
                            detail::checkRange(p, "quality", 0, 6)})
    if (!check.empty()) return check;
  // The measured methods take iterations as a strength in thirds: 30 is ten times the measured
  // amount, already far past any use (the paper's methods count plain iterations up to 1000).
  if (int(p.at("placement")) >= 3 && p.at("iterations") > 30)
    return "Parameter 'iterations' = " + detail::format("%g", p.at("iterations")) +
           " is the strength in thirds for this method (3 = as measured) and at most 30.";
  return {};
}

// "Saliency Bezier Smooth": the method the table lists at `placement`; the mesh changes only when
// the run completes.
template <class MeshType>
FilterOutcome applySaliencyBezierSmooth(MeshType &m, const ParameterValues &p,
                                        vcg::CallBackPos *cb) {
  FilterOutcome out;
  vcg_ext::MeshArrays arrays = vcg_ext::extractArrays(m);
  out.error = detail::rejectMesh(m, arrays);
  if (out.error.empty()) out.error = checkSmoothingParameters(p);
  if (!out.error.empty()) return out;
  const vcg_ext::MethodRow &method = vcg_ext::methodTable()[size_t(p.at("placement"))];
  // In the order the method runs in (the mesh slots follow), instead of a second, ordered copy.
  if (method.runs_in_spatial_order) vcg_ext::putInSpatialOrder(arrays);
  const vcg_ext::MethodParams params = methodParamsOf(p);
  if (params.selected_only) {
    bool any = false;
    for (auto s : arrays.selected) any = any || s;
    if (!any)
      return out.error = "'Affect only selected vertices' is on but no vertex is selected.", out;
  }

  std::vector<vcg_ext::Vec3> result;
  vcg_ext::VertexQuantities q;
  const vcg_ext::MethodRun run =
      method.run(arrays, params, result, q, detail::progressOf(cb));
  if (run.cancelled) return out.error = "Cancelled: the mesh is unchanged.", out;
  const bool color = p.count("color") && p.at("color") != 0;
  const long clamped = detail::storeSmoothingResult(m, arrays, result, q, int(p.at("quality")),
                                                    color, out.colored);
  out.method = run.method;
  out.summary = run.summary;
  out.log.push_back(run.summary);
  out.log.insert(out.log.end(), run.details.begin(), run.details.end());
  if (clamped > 0) out.log.push_back(detail::clampedLog(clamped));
  out.ok = true;
  return out;
}

// Default values of a filter's parameters (for tests and tools that call the filters directly).
inline ParameterValues defaultParameters(FilterId id) {
  ParameterValues values;
  for (const ParamSpec &spec : parameterSpecs(id)) values[spec.name] = spec.default_value;
  return values;
}

} // namespace saliency_bezier
