// The measured methods' first step: impulses (analysis/impulses.h) put back before the method
// reads the mesh, so that the noise estimate, the mode choice and the smoothing see the noise
// around them rather than the spikes, and the result is described against the user's input.
#pragma once

#include "vcg_ext/analysis/impulses.h"
#include "vcg_ext/methods/driver_setup.h"

namespace vcg_ext {
namespace detail {

// The vertices an impulse may not be read at: frozen (vertexRoles), on the boundary (a one-sided
// ring), or outside the selection when only the selection is smoothed.
inline std::vector<std::uint8_t> impulseFixed(const MeshArrays &mesh, const Rings &rings,
                                              double edge, bool selected_only) {
  const VertexRoles roles = vertexRoles(mesh, rings, edge);
  std::vector<std::uint8_t> fixed(mesh.points.size());
  for (size_t v = 0; v < fixed.size(); ++v)
    fixed[v] = roles.frozen[v] || rings.boundary[v] || (selected_only && !mesh.selected[v]);
  return fixed;
}

// Runs `drive(mesh, out, quantities, setup)` (a measured driver, as given, on the set-up made
// here; its report has `impulses`) on `mesh` with its impulses put back when there are enough of
// them (enoughImpulses) and the user's strength is above 0. The rings are computed once, for the
// reading and the set-up. The result's quantities then measure the displacement from `mesh`
// itself; where the driver leaves the repaired mesh as it is (it measures clean), the result is
// the repaired mesh, described like any other.
template <class Drive>
auto withImpulsesRepaired(const MeshArrays &mesh, const ImpulseParams &params, double strength,
                          bool selected_only, BoundaryMode boundary, double saliency_scale,
                          std::vector<Vec3> &out_points, VertexQuantities &quantities,
                          Drive drive) {
  Rings rings = computeRings(int(mesh.points.size()), mesh.faces, false);
  Impulses impulses;
  MeshArrays repaired;
  if (strength > 0 && !mesh.faces.empty() && params.rounds > 0) {
    const double edge = edgeStatistics(mesh.points, rings).mean_edge_length;
    const std::vector<std::uint8_t> fixed = impulseFixed(mesh, rings, edge, selected_only);
    impulses = findImpulses(mesh.points, mesh.faces, rings, fixed, edge, params);
    if (enoughImpulses(impulses, params)) {
      repaired.points = mesh.points;
      impulses.moved = putBackImpulses(repaired.points, mesh.faces, rings, fixed, edge, params);
    }
  }
  if (impulses.moved == 0) {
    DriverSetup setup = driverSetup(mesh, selected_only, boundary, true, false, &rings);
    auto report = drive(mesh, out_points, quantities, setup);
    report.impulses = impulses;
    return report;
  }
  repaired.faces = mesh.faces;
  repaired.selected = mesh.selected;
  repaired.spatially_ordered = mesh.spatially_ordered;
  DriverSetup setup = driverSetup(repaired, selected_only, boundary, true, false, &rings);
  auto report = drive(repaired, out_points, quantities, setup);
  report.impulses = impulses;
  if (report.cancelled) return report;
  if (out_points.size() != mesh.points.size()) {
    out_points = repaired.points;
    describeResult(mesh.points, out_points, mesh.faces, setup.rings,
                   saliency_scale * setup.stats.bbox_diagonal, quantities);
  } else {
    for (size_t v = 0; v < out_points.size(); ++v)
      quantities.displacement[v] = (out_points[v] - mesh.points[v]).norm();
  }
  return report;
}

// A measured driver as the filter runs it: on the mesh in spatial order (inSpatialOrder), its
// impulses put back first (withImpulsesRepaired), with the settings of `p` (FeatureSmoothParams
// or OrganicSmoothParams: impulses, strength, selected_only, boundary, saliency_scale).
// `drive(mesh, out, quantities, setup)` is the driver as given.
template <class Params, class Drive>
auto measuredDriverRun(const MeshArrays &mesh, const Params &p, std::vector<Vec3> &out_points,
                       VertexQuantities &quantities, Drive drive) {
  return inSpatialOrder(mesh, out_points, quantities,
                        [&](const MeshArrays &ordered, std::vector<Vec3> &out,
                            VertexQuantities &q) {
                          return withImpulsesRepaired(ordered, p.impulses, p.strength,
                                                      p.selected_only, p.boundary,
                                                      p.saliency_scale, out, q, drive);
                        });
}

// After the noise estimate in the summary lines: the impulses read, and whether they were put
// back.
inline std::string impulsePhrase(const Impulses &impulses) {
  if (impulses.found == 0) return std::string();
  return formatLine(", impulses on %.2f %% of the vertices (median %.2f mean edge lengths%s)",
                    100.0 * impulses.share, impulses.median_size,
                    impulses.moved > 0 ? ", put back first" : ", too few to act on");
}

// A method's summary when the mesh, its impulses put back, measures as clean.
inline std::string cleanAfterImpulsesPhrase(const Impulses &impulses, const NoiseEstimate &noise) {
  return formatLine("%ld impulses put back (%.2f %% of the vertices, median %.2f mean edge "
                    "lengths); then the mesh measures as clean%s (dihedral spread %.1f deg): "
                    "nothing more done; set Iterations above 3 to smooth it anyway",
                    impulses.moved, 100.0 * impulses.share, impulses.median_size,
                    sampledPhrase(noise).c_str(), noise.spread_deg);
}

} // namespace detail
} // namespace vcg_ext
