// What the two filters do to a mesh, for any vcglib mesh type (CMeshO of either MeshLab API
// generation, or a test mesh): validate, run vcg_ext on a copy of the positions, and write
// positions, quality, attributes and curvature directions back only when everything succeeded.
#pragma once

#include "filter_parameters.h"
#include "heap_reuse.h"
#include "memory_check.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/color.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/complex.h>
#include <vcg_ext/analysis/display_scale.h>
#include <vcg_ext/methods.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <new>
#include <typeindex>

namespace saliency_bezier {

struct FilterOutcome {
  bool ok = false;
  std::string error;
  std::vector<std::string> log;
  vcg_ext::MethodRun run; // the smoothing method's outcome: which ran, the summary line, figures
  bool colored = false; // the vertex colours were written (the GUI must show them)
};

namespace detail {

using vcg_ext::detail::formatLine;

// `value` in the mesh's scalar type: NaN as 0 and anything beyond the type's range as its largest
// value, counted in `clamped` (found by the fuzzer: a float mesh 3e-30 across has K = 1e59).
template <class Scalar>
Scalar storable(double value, long &clamped) {
  const double limit = double(std::numeric_limits<Scalar>::max());
  if (std::isnan(value)) return ++clamped, Scalar(0);
  if (std::abs(value) > limit) return ++clamped, Scalar(std::copysign(limit, value));
  return Scalar(value);
}

// The per-vertex attributes a filter writes, made (allocated) before anything of the mesh is
// changed: running out of memory here removes the ones it made and leaves the mesh as it was.
template <class MeshType> class AttributeSet {
public:
  using Scalar = typename MeshType::ScalarType;
  using Allocator = vcg::tri::Allocator<MeshType>;
  using Handle = typename MeshType::template PerVertexAttributeHandle<Scalar>;

  AttributeSet(MeshType &m, const std::vector<std::string> &names) : m_(m) {
    try {
      for (const std::string &name : names) handles_.push_back(handleFor(name));
    } catch (const std::bad_alloc &) {
      for (const std::string &name : made_) Allocator::DeletePerVertexAttribute(m_, name);
      throw;
    }
  }
  // Stores `values` (compact order) as attribute `k`.
  void store(size_t k, const vcg_ext::MeshArrays &arrays, const std::vector<double> &values,
             long &clamped) {
    // Every vertex to its own slot, in parallel (scattered writes: see writePositions).
    auto &handle = handles_[k];
    const long count = long(values.size());
    long clamped_here = 0;
#pragma omp parallel for schedule(static) reduction(+ : clamped_here) if (count >= vcg_ext::min_parallel_vertices)
    for (long c = 0; c < count; ++c)
      handle[arrays.mesh_slot[c]] = storable<Scalar>(values[c], clamped_here);
    clamped += clamped_here;
  }

private:
  // The attribute `name` of the mesh's scalar type, replacing one of that name but another type.
  Handle handleFor(const std::string &name) {
    // vcglib's lookup compares only the size: an int attribute of this name (another filter's)
    // would come back as a float handle and be written through the wrong type (found by the
    // fuzzer).
    for (const auto &attribute : m_.vert_attr)
      if (attribute._name == name && attribute._type != std::type_index(typeid(Scalar))) {
        Allocator::DeletePerVertexAttribute(m_, name);
        break;
      }
    auto handle = Allocator::template FindPerVertexAttribute<Scalar>(m_, name);
    if (!Allocator::template IsValidHandle<Scalar>(m_, handle)) {
      Allocator::DeletePerVertexAttribute(m_, name);
      handle = Allocator::template AddPerVertexAttribute<Scalar>(m_, name);
      made_.push_back(name);
    }
    return handle;
  }
  MeshType &m_;
  std::vector<Handle> handles_;
  std::vector<std::string> made_;
};

// Stores `values` (already on their display scale) as vertex quality and, with `color`, colours
// the vertices by it over its full range as MeshLab's Colorize by vertex Quality does at its
// defaults. Returns whether colours were written.
template <class MeshType>
bool storeQuality(MeshType &m, const vcg_ext::MeshArrays &arrays,
                  const std::vector<double> &values, bool color) {
  if (!vcg::tri::HasPerVertexQuality(m)) return false;
  using Scalar = typename MeshType::VertexType::QualityType;
  long clamped = 0; // counted with the attributes
  const long count = long(values.size());
#pragma omp parallel for schedule(static) reduction(+ : clamped) if (count >= vcg_ext::min_parallel_vertices)
  for (long c = 0; c < count; ++c)
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
    return "Parameter '" + name + "' = " + formatLine("%g", value) + " is outside [" +
           formatLine("%g", lo) + ", " + formatLine("%g", hi) + "].";
  return {};
}

inline vcg_ext::ProgressFn progressOf(vcg::CallBackPos *cb) {
  if (!cb) return nullptr;
  return [cb](int percent, const char *stage) { return cb(percent, stage); };
}

} // namespace detail

namespace detail {

// The principal directions and curvatures into vcglib's own per-vertex fields, where the mesh
// has them (MeshLab's "Per vertex curvature directions"); the values' clamping was counted with
// the attributes.
template <class MeshType>
void storeCurvatureDirections(MeshType &m, const vcg_ext::MeshArrays &arrays,
                              const vcg_ext::CurvatureField &c) {
  if (!vcg::tri::HasPerVertexCurvatureDir(m)) return;
  using Dir = typename MeshType::VertexType::CurVecType;
  using DirScalar = typename Dir::ScalarType;
  for (size_t i = 0; i < arrays.points.size(); ++i) {
    auto &v = m.vert[arrays.mesh_slot[i]];
    v.PD1() = Dir(DirScalar(c.dir1[i].x()), DirScalar(c.dir1[i].y()), DirScalar(c.dir1[i].z()));
    v.PD2() = Dir(DirScalar(c.dir2[i].x()), DirScalar(c.dir2[i].y()), DirScalar(c.dir2[i].z()));
    long counted_with_the_attributes = 0;
    v.K1() = storable<DirScalar>(c.k1[i], counted_with_the_attributes);
    v.K2() = storable<DirScalar>(c.k2[i], counted_with_the_attributes);
  }
}

// The log line of the per-vertex values stored clamped to the mesh's number range.
inline std::string clampedLog(long clamped) {
  return formatLine("%.0f per-vertex values were NaN or beyond the mesh's number range (a tiny "
                    "mesh or tiny faces): stored as 0 or the largest representable value.",
                    double(clamped));
}

// The analysis filter's log: what was computed and in what time, how many vertices are salient,
// the vertices whose curvature is borrowed or undefined, the values clamped.
inline std::vector<std::string> analysisLog(const vcg_ext::Rings &rings,
                                            const vcg_ext::SurfaceAnalysis &analysis,
                                            double seconds, double epsilon, long clamped) {
  const size_t n = analysis.saliency.size();
  long salient = 0, boundary = 0, nonmanifold = 0, isolated = 0;
  double mean_abs_h = 0;
  for (size_t i = 0; i < n; ++i) {
    salient += analysis.saliency[i] > 0.5;
    boundary += rings.boundary[i];
    nonmanifold += rings.nonmanifold[i];
    isolated += rings.isolated[i];
    mean_abs_h += std::abs(analysis.curvature.mean[i]) / n;
  }
  std::vector<std::string> log;
  log.push_back(formatLine(
      "Saliency and curvature of %.0f vertices in %.3f s (epsilon = %g of the bbox diagonal).",
      double(n), seconds, epsilon));
  log.push_back(formatLine("Vertices with saliency > 0.5: %.0f; mean |H| = %g; boundary vertices "
                           "(curvature from neighbours): %.0f.",
                           double(salient), mean_abs_h, double(boundary)));
  if (nonmanifold + isolated > 0)
    log.push_back(formatLine("Curvature and saliency undefined, set to 0: %.0f non-manifold, %.0f "
                             "isolated (in no face) vertices.",
                             double(nonmanifold), double(isolated)));
  if (clamped > 0) log.push_back(clampedLog(clamped));
  return log;
}

// "Compute Mesh Saliency and Principal Curvatures" (applyComputeSaliency) without the memory guard.
template <class MeshType>
FilterOutcome computeSaliencyRun(MeshType &m, const ParameterValues &p, vcg::CallBackPos *cb) {
  FilterOutcome out;
  const vcg_ext::MeshArrays arrays = vcg_ext::extractArrays(m);
  out.error = detail::rejectMesh(m, arrays);
  if (out.error.empty()) out.error = detail::checkRange(p, "saliency_scale", 1e-6, 50);
  if (out.error.empty()) out.error = detail::checkRange(p, "quality", 0, 4);
  if (!out.error.empty()) return out;
  const bool color = p.count("color") && p.at("color") != 0;

  const auto start = vcg_ext::Clock::now();
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
  // Everything that allocates comes before the first change to the mesh.
  const std::vector<double> shown = detail::displayed(
      qualityChoices(FilterId::ComputeSaliencyCurvature)[quality], *quantities[quality]);
  detail::AttributeSet<MeshType> attributes(
      m, {"Saliency", "MeanCurvature", "GaussianCurvature", "K1", "K2"});
  out.colored = detail::storeQuality(m, arrays, shown, color);
  long clamped = 0;
  for (size_t k = 0; k < 5; ++k) attributes.store(k, arrays, *quantities[k], clamped);
  storeCurvatureDirections(m, arrays, c);
  out.log = analysisLog(rings, analysis, vcg_ext::secondsSince(start),
                        scale / stats.bbox_diagonal, clamped);
  out.ok = true;
  return out;
}

// Writes a smoothing run's positions, quality and attributes into the mesh; returns how many
// per-vertex values had to be clamped to the mesh's number range.
template <class MeshType>
long storeSmoothingResult(MeshType &m, const vcg_ext::MeshArrays &arrays,
                          const std::vector<vcg_ext::Vec3> &result,
                          const vcg_ext::VertexQuantities &q, int quality, bool color,
                          bool &colored) {
  const std::vector<double> *quantities[] = {&q.saliency, &q.mean, &q.gauss, &q.k1,
                                             &q.k2,       &q.alpha, &q.displacement};
  // Everything that allocates comes before the first change to the mesh.
  const std::vector<double> shown =
      displayed(qualityChoices(FilterId::SaliencyBezierSmooth)[quality], *quantities[quality]);
  AttributeSet<MeshType> attributes(m, {"Saliency", "MeanCurvature", "GaussianCurvature", "K1",
                                        "K2", "Alpha", "Displacement"});
  vcg_ext::writePositions(m, arrays, result);
  colored = storeQuality(m, arrays, shown, color);
  long clamped = 0;
  for (size_t k = 0; k < 7; ++k) attributes.store(k, arrays, *quantities[k], clamped);
  if (vcg::tri::HasPerVertexNormal(m) && vcg::tri::HasPerFaceNormal(m))
    vcg::tri::UpdateNormal<MeshType>::PerVertexNormalizedPerFaceNormalized(m);
  vcg::tri::UpdateBounding<MeshType>::Box(m);
  return clamped;
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
    return "Parameter 'iterations' = " + detail::formatLine("%g", p.at("iterations")) +
           " is the strength in thirds for this method (3 = as measured) and at most 30.";
  return {};
}

namespace detail {

// "Saliency Bezier Smooth" (applySaliencyBezierSmooth) without the memory guard.
template <class MeshType>
FilterOutcome smoothRun(MeshType &m, const ParameterValues &p, vcg::CallBackPos *cb) {
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
  out.run = run;
  out.log.push_back(run.summary);
  out.log.insert(out.log.end(), run.details.begin(), run.details.end());
  if (clamped > 0) out.log.push_back(detail::clampedLog(clamped));
  out.ok = true;
  return out;
}

// Runs `run` (a filter on `m`) unless the memory it needs (`cost`, measured) is not there, and
// turns running out of memory all the same into a refusal: the run's own arrays are freed as the
// exception unwinds, and the mesh changes only after everything that allocates (AttributeSet), so
// it is left as it was. `what`: "smoothing" or "analysing", for the message.
template <class MeshType, class Run>
FilterOutcome withinMemory(const MeshType &m, const MemoryCost &cost, const char *what, Run run) {
  const double needed = cost.bytes(m.vn, m.fn);
  const std::string size = formatLine("%.0f vertices, %.0f faces", double(m.vn), double(m.fn));
  const MemoryRoom room = memoryRoom();
  if (needed > memory_room_scale * room.bytes) {
    FilterOutcome out;
    out.error = std::string("Not enough memory: ") + what + " this mesh (" + size + ") needs about " +
                memoryText(needed) + " more than the mesh itself, and " + room.limit +
                " leaves " + memoryText(room.bytes) + ". The mesh is unchanged.";
    return out;
  }
  try {
    const HeapReuse heap; // large blocks reused within the run (heap_reuse.h)
    return run();
  } catch (const std::bad_alloc &) {
    FilterOutcome out;
    out.error = std::string("Out of memory while ") + what + " this mesh (" + size +
                "): the run needs about " + memoryText(needed) +
                " more than the mesh itself, more than could be allocated" +
                (room.limit.empty() ? std::string() : " (" + room.limit + ")") +
                ". The mesh is unchanged.";
    return out;
  }
}

} // namespace detail

// "Compute Mesh Saliency and Principal Curvatures": stages 1-3, positions untouched.
template <class MeshType>
FilterOutcome applyComputeSaliency(MeshType &m, const ParameterValues &p, vcg::CallBackPos *cb) {
  return detail::withinMemory(m, analysisMemoryCost(), "analysing",
                              [&] { return detail::computeSaliencyRun(m, p, cb); });
}

// "Saliency Bezier Smooth": the method the table lists at `placement`; the mesh changes only when
// the run completes.
template <class MeshType>
FilterOutcome applySaliencyBezierSmooth(MeshType &m, const ParameterValues &p,
                                        vcg::CallBackPos *cb) {
  return detail::withinMemory(m, smoothingMemoryCost(), "smoothing",
                              [&] { return detail::smoothRun(m, p, cb); });
}

// Filter `id` on `m`: the plugins' applyFilter, tools/smooth_mesh and the fuzzer.
template <class MeshType>
FilterOutcome applyFilterById(FilterId id, MeshType &m, const ParameterValues &p,
                              vcg::CallBackPos *cb) {
  return id == FilterId::ComputeSaliencyCurvature ? applyComputeSaliency(m, p, cb)
                                                  : applySaliencyBezierSmooth(m, p, cb);
}

// Default values of a filter's parameters (for tests and tools that call the filters directly).
inline ParameterValues defaultParameters(FilterId id) {
  ParameterValues values;
  for (const ParamSpec &spec : parameterSpecs(id)) values[spec.name] = spec.default_value;
  return values;
}

} // namespace saliency_bezier
