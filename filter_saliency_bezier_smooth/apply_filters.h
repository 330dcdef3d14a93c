// What the two filters do to a mesh, for any vcglib mesh type (CMeshO of either MeshLab API
// generation, or a test mesh): validate, run vcg_ext on a copy of the positions, and write
// positions, quality, attributes and curvature directions back only when everything succeeded.
#pragma once

#include "filter_parameters.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/complex.h>
#include <vcg_ext/feature_smooth.h>
#include <vcg_ext/auto_smooth.h>
#include <vcg_ext/smooth.h>

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

template <class MeshType>
void storeQuality(MeshType &m, const vcg_ext::MeshArrays &arrays,
                  const std::vector<double> &values) {
  if (!vcg::tri::HasPerVertexQuality(m)) return;
  using Scalar = typename MeshType::VertexType::QualityType;
  long clamped = 0; // counted with the attributes
  for (size_t c = 0; c < values.size(); ++c)
    m.vert[arrays.mesh_slot[c]].Q() = storable<Scalar>(values[c], clamped);
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

  const auto start = std::chrono::steady_clock::now();
  const vcg_ext::Rings rings = vcg_ext::computeRings(int(arrays.points.size()), arrays.faces);
  const vcg_ext::EdgeStatistics stats = vcg_ext::edgeStatistics(arrays.points, rings);
  if (cb && !cb(10, "Curvature")) return out.error = "Cancelled.", out;
  vcg_ext::SurfaceAnalysis analysis;
  vcg_ext::computeCurvature(arrays.points, arrays.faces, rings, analysis.curvature);
  if (cb && !cb(40, "Saliency")) return out.error = "Cancelled.", out;
  const double scale = p.at("saliency_scale") / 100.0 * stats.bbox_diagonal;
  vcg_ext::computeSaliency(arrays.points, rings, analysis.curvature.k2, scale, analysis.saliency);
  if (cb && !cb(95, "Storing")) return out.error = "Cancelled.", out;

  const vcg_ext::CurvatureField &c = analysis.curvature;
  const std::vector<double> *quantities[] = {&analysis.saliency, &c.mean, &c.gauss, &c.k1, &c.k2};
  detail::storeQuality(m, arrays, *quantities[int(p.at("quality"))]);
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
                          const vcg_ext::VertexQuantities &q, int quality) {
  vcg_ext::writePositions(m, arrays, result);
  const std::vector<double> *quantities[] = {&q.saliency, &q.mean, &q.gauss, &q.k1,
                                             &q.k2,       &q.alpha, &q.displacement};
  storeQuality(m, arrays, *quantities[quality]);
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

// The lines the feature-preserving and organic drivers' reports share.
template <class DriverReport>
void appendDriverLog(const DriverReport &r, std::vector<std::string> &log) {
  if (r.frozen_vertices > 0)
    log.push_back(format("Skipped (left in place): %.0f non-manifold, isolated or on degenerate "
                         "faces.",
                         double(r.frozen_vertices)));
  if (r.plane_fallbacks + r.rejected_moves > 0)
    log.push_back(format("Patch fits that fell back to the face plane: %.0f; non-finite moves "
                         "kept in place: %.0f.",
                         double(r.plane_fallbacks), double(r.rejected_moves)));
  if (r.closed && r.volume_before != 0)
    log.push_back(format("Volume %g -> %g (ratio %.4f).", r.volume_before, r.volume_after,
                         r.volume_after / r.volume_before));
}

inline std::vector<std::string> featureLog(const vcg_ext::FeatureSmoothReport &r, size_t vertices) {
  std::vector<std::string> log;
  log.push_back(format("Feature-preserving mode, %.0f passes: %.0f of %.0f vertices moved.",
                       r.outer_iterations_done, double(r.vertices_moved), double(vertices)));
  log.push_back(format("Noise estimate (dihedral spread) %.1f deg, roughness %.2f: %.0f Taubin "
                       "pre-pass pairs, %.0f normal filter iterations per pass.",
                       r.dihedral_spread_deg, r.roughness, r.prepass_pairs, r.normal_iterations));
  appendDriverLog(r, log);
  log.push_back(format("Time: topology and pre-pass %.3f s, normal filtering %.3f s, vertex "
                       "updates %.3f s, result quantities %.3f s.",
                       r.seconds_topology + r.seconds_prepass, r.seconds_normals,
                       r.seconds_vertices, r.seconds_quantities));
  return log;
}

inline std::vector<std::string> organicLog(const vcg_ext::OrganicSmoothReport &r, size_t vertices) {
  std::vector<std::string> log;
  log.push_back(format("Organic mode: %.0f of %.0f vertices moved.", double(r.vertices_moved),
                       double(vertices)));
  log.push_back(format("Noise estimate (dihedral spread) %.1f deg, roughness %.2f; noise along "
                       "the normals %.3f mean edge lengths.",
                       r.dihedral_spread_deg, r.roughness,
                       r.mean_edge_length > 0 ? r.bands.noise_sigma / r.mean_edge_length : 0.0));
  std::string gains = format("Shape spectrum slope %.2f, coarse-band shape/noise %.2f, fine-band "
                             "shape/noise %.2f: alpha %.2f; band gains (fine to coarse):",
                             r.bands.shape_slope, r.bands.coarse_snr, r.bands.fine_snr,
                             r.bands.alpha);
  for (double g : r.bands.gains) gains += format(" %.2f", g);
  log.push_back(gains + ".");
  if (r.roughness == 0)
    log.push_back("The mesh measures as clean: left as it is.");
  appendDriverLog(r, log);
  log.push_back(format("Time: topology %.3f s, band shrinkage %.3f s, patch update %.3f s, result "
                       "quantities %.3f s.",
                       r.seconds_topology, r.seconds_bands, r.seconds_patches,
                       r.seconds_quantities));
  return log;
}

inline std::vector<std::string> autoLog(const vcg_ext::AutoSmoothReport &r, size_t vertices) {
  std::vector<std::string> log;
  if (r.decided)
    log.push_back(format("Automatic mode: after guided filtering %.3f of the edges are flat and "
                         "%.3f of the creases are still creases after plain Taubin smoothing: ",
                         r.evidence.flat_share, r.evidence.confirmed_share) +
                  (r.chose_feature ? "sharp features, feature-preserving mode."
                                   : "no sharp features, organic mode."));
  else
    log.push_back("Automatic mode: the mesh measures as clean (see the noise estimate below): "
                  "left as it is.");
  const std::vector<std::string> rest =
      r.chose_feature ? featureLog(r.feature, vertices) : organicLog(r.organic, vertices);
  log.insert(log.end(), rest.begin(), rest.end());
  if (r.chose_feature)
    log.push_back(format("Time of the decision: shared topology %.3f s, Taubin copy and evidence "
                         "%.3f s.",
                         r.seconds_setup, r.seconds_reference));
  else
    log.push_back(format("Time of the decision: shared topology %.3f s, the feature mode's "
                         "pre-pass and first normal filter iterations %.3f s, Taubin copy and "
                         "evidence %.3f s.",
                         r.seconds_setup, r.feature.seconds_prepass + r.feature.seconds_normals,
                         r.seconds_reference));
  return log;
}

} // namespace detail

inline vcg_ext::SmoothParams smoothParamsOf(const ParameterValues &p) {
  vcg_ext::SmoothParams s;
  s.iterations = int(p.at("iterations"));
  const vcg_ext::PlacementMode placements[] = {vcg_ext::PlacementMode::RingBarycentre,
                                               vcg_ext::PlacementMode::PatchPoint,
                                               vcg_ext::PlacementMode::Paper};
  // The feature-preserving and organic choices run their own drivers (feature_smooth.h,
  // organic_smooth.h), not a placement.
  s.placement = placements[std::min(int(p.at("placement")), 2)];
  s.alpha_override = p.at("alpha_override") != 0;
  s.alpha = p.at("alpha");
  s.uniform_variant = p.at("uniform_curvature") == 0 ? vcg_ext::UniformCurvatureVariant::Paper
                                                     : vcg_ext::UniformCurvatureVariant::Neighbour;
  const vcg_ext::BoundaryMode boundaries[] = {
      vcg_ext::BoundaryMode::Paper, vcg_ext::BoundaryMode::Fixed,
      vcg_ext::BoundaryMode::AlongBoundary, vcg_ext::BoundaryMode::NoInward};
  s.boundary = boundaries[int(p.at("boundary"))];
  s.folds = p.at("fold_handling") == 0 ? vcg_ext::FoldHandling::Ignore
                                       : vcg_ext::FoldHandling::Paper;
  s.newton_iterations = int(p.at("newton_iterations"));
  s.newton_step_limit = p.at("newton_step_limit");
  s.saliency_scale = p.at("saliency_scale") / 100.0;
  s.selected_only = p.at("selected_only") != 0;
  s.preserve_volume = p.at("preserve_volume") != 0;
  return s;
}

// "Saliency Bezier Smooth": the smoothing driver; the mesh changes only when the run completes.
template <class MeshType>
FilterOutcome applySaliencyBezierSmooth(MeshType &m, const ParameterValues &p,
                                        vcg::CallBackPos *cb) {
  FilterOutcome out;
  const vcg_ext::MeshArrays arrays = vcg_ext::extractArrays(m);
  out.error = detail::rejectMesh(m, arrays);
  for (const auto &check : {detail::checkRange(p, "iterations", 0, 1000),
                            detail::checkRange(p, "placement", 0, 5),
                            detail::checkRange(p, "alpha", 0, 1),
                            detail::checkRange(p, "uniform_curvature", 0, 1),
                            detail::checkRange(p, "boundary", 0, 3),
                            detail::checkRange(p, "fold_handling", 0, 1),
                            detail::checkRange(p, "newton_iterations", 0, 100),
                            detail::checkRange(p, "newton_step_limit", 0, 1000),
                            detail::checkRange(p, "saliency_scale", 1e-6, 50),
                            detail::checkRange(p, "quality", 0, 6)})
    if (out.error.empty()) out.error = check;
  if (!out.error.empty()) return out;
  const vcg_ext::SmoothParams params = smoothParamsOf(p); // indexes by the checked enums
  if (params.selected_only) {
    bool any = false;
    for (auto s : arrays.selected) any = any || s;
    if (!any)
      return out.error = "'Affect only selected vertices' is on but no vertex is selected.", out;
  }

  std::vector<vcg_ext::Vec3> result;
  vcg_ext::VertexQuantities q;
  // The issue-8 modes end alike: a cancelled run leaves the mesh as it was; a finished one is
  // stored, with its log and a note of values clamped to the mesh's number type.
  auto finish = [&](bool cancelled, const auto &log_of_run) {
    if (cancelled) return out.error = "Cancelled: the mesh is unchanged.", out;
    const long clamped = detail::storeSmoothingResult(m, arrays, result, q, int(p.at("quality")));
    out.log = log_of_run();
    if (clamped > 0) out.log.push_back(detail::clampedLog(clamped));
    out.ok = true;
    return out;
  };
  if (int(p.at("placement")) == 3) {
    vcg_ext::FeatureSmoothParams feature;
    feature.selected_only = params.selected_only;
    feature.preserve_volume = params.preserve_volume;
    feature.saliency_scale = params.saliency_scale;
    const vcg_ext::FeatureSmoothReport r =
        vcg_ext::featureSmoothMesh(arrays, feature, result, q, detail::progressOf(cb));
    return finish(r.cancelled, [&] { return detail::featureLog(r, arrays.points.size()); });
  }
  if (int(p.at("placement")) == 5) {
    vcg_ext::AutoSmoothParams automatic;
    for (bool *flag : {&automatic.feature.selected_only, &automatic.organic.selected_only})
      *flag = params.selected_only;
    automatic.feature.preserve_volume = automatic.organic.preserve_volume = params.preserve_volume;
    automatic.feature.saliency_scale = automatic.organic.saliency_scale = params.saliency_scale;
    const vcg_ext::AutoSmoothReport r =
        vcg_ext::autoSmoothMesh(arrays, automatic, result, q, detail::progressOf(cb));
    return finish(r.cancelled, [&] { return detail::autoLog(r, arrays.points.size()); });
  }
  if (int(p.at("placement")) == 4) {
    vcg_ext::OrganicSmoothParams organic;
    organic.selected_only = params.selected_only;
    organic.preserve_volume = params.preserve_volume;
    organic.saliency_scale = params.saliency_scale;
    const vcg_ext::OrganicSmoothReport r =
        vcg_ext::organicSmoothMesh(arrays, organic, result, q, detail::progressOf(cb));
    return finish(r.cancelled, [&] { return detail::organicLog(r, arrays.points.size()); });
  }
  const vcg_ext::SmoothReport r =
      vcg_ext::smoothMesh(arrays, params, result, q, detail::progressOf(cb));
  if (r.cancelled) return out.error = "Cancelled: the mesh is unchanged.", out;

  const long clamped = detail::storeSmoothingResult(m, arrays, result, q, int(p.at("quality")));

  out.log.push_back(detail::format("%.0f iterations: %.0f of %.0f vertices moved.",
                                   r.iterations_done, double(r.vertices_moved),
                                   double(arrays.points.size())));
  if (r.frozen_vertices > 0)
    out.log.push_back(detail::format("Skipped (left in place): %.0f non-manifold, %.0f isolated "
                                     "(in no face), %.0f on degenerate faces.",
                                     double(r.nonmanifold_vertices), double(r.isolated_vertices),
                                     double(r.degenerate_vertices)));
  out.log.push_back(detail::format("Fold fallbacks %.0f, fold skips %.0f, Newton failures %.0f.",
                                   double(r.fold_fallbacks), double(r.fold_skips),
                                   double(r.newton_failures)));
  if (r.fit_failures + r.rejected_moves > 0)
    out.log.push_back(detail::format("Kept in place (over all iterations): %.0f failed fits, "
                                     "%.0f non-finite results.",
                                     double(r.fit_failures), double(r.rejected_moves)));
  if (r.closed && r.volume_before != 0)
    out.log.push_back(detail::format("Volume %g -> %g (ratio %.4f).", r.volume_before,
                                     r.volume_after, r.volume_after / r.volume_before));
  out.log.push_back(detail::format("Time: topology %.3f s, curvature %.3f s, saliency %.3f s, "
                                   "patch fit + placement %.3f s.",
                                   r.seconds_topology, r.seconds_curvature, r.seconds_saliency,
                                   r.seconds_fit));
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
