// The paper's method (sections 3.1-3.3; docs/studies/defaults.md) with its three placements: the
// ring barycentre, the patch point and the paper's Newton solve.
//
// Inputs: a mesh as plain arrays (mesh_arrays.h) and SmoothParams. Outputs: the new positions, the
// per-vertex quantities of the last iteration, and a SmoothReport. The input is never modified, so
// a caller can write the result back only when the run succeeded (cancel and failure leave the
// user's mesh as it was). Every iteration reads one position array and writes another (Jacobi), so
// the result does not depend on vertex order or thread count.
#pragma once

#include "vcg_ext/methods/paper/bezier_patch.h"
#include "vcg_ext/methods/driver_setup.h"
#include "vcg_ext/methods/paper/patch_neighbourhood.h"
#include "vcg_ext/methods/paper/placement.h"

#include <functional>
#include <string>

namespace vcg_ext {

enum class PlacementMode {
  Paper,          // Newton on (u,v) toward the uniform principal curvature (paper 3.3)
  PatchPoint,     // the vertex's own patch point B(u_i, v_i)
  RingBarycentre, // the patch point at the parameter of the 1-ring barycentre
};
struct SmoothParams {
  int iterations = 3;
  PlacementMode placement = PlacementMode::RingBarycentre;
  UniformCurvatureVariant uniform_variant = UniformCurvatureVariant::Neighbour;
  bool alpha_override = true; // false: the paper's alpha = Sal_min / Sal_max
  double alpha = 1.0;
  BoundaryMode boundary = BoundaryMode::NoInward;
  FoldHandling folds = FoldHandling::Ignore;
  int newton_iterations = 2;
  double newton_step_limit = 1.0; // safeguard, in mean edge lengths; 0 = off (as printed)
  double saliency_scale = 0.003;  // the paper's epsilon, as a fraction of the bbox diagonal
  bool selected_only = false;
  // Closed meshes: after each iteration, offset the moved vertices along their normals by the one
  // distance that restores the input's volume (Desbrun et al. 1999 rescale instead).
  bool preserve_volume = true;
  // How the saliency's Gaussian means are evaluated: exact sums where the 2σ balls hold few
  // vertices, a lattice approximation where they hold many (saliency.h); lattice_above_vertices =
  // INFINITY gives the exact reference.
  SaliencyOptions saliency;
};

struct SmoothReport {
  int iterations_done = 0;
  bool cancelled = false;
  long vertices_moved = 0;   // vertices whose final position differs from the input
  long frozen_vertices = 0;  // non-manifold, isolated or on a degenerate face: never moved
  long nonmanifold_vertices = 0, isolated_vertices = 0, degenerate_vertices = 0; // its parts
  long fold_fallbacks = 0;   // (over all iterations) neighbourhoods refitted after a fold
  long fold_skips = 0;       // vertices kept because every fallback folded
  long fit_failures = 0;     // degenerate neighbourhoods or failed fits: vertex kept
  long newton_failures = 0;  // paper placement: Newton did not reach the target
  long rejected_moves = 0;   // non-finite results: vertex kept
  double volume_before = 0, volume_after = 0;
  bool closed = false;
  double mean_edge_length = 0, bbox_diagonal = 0;
  double seconds_topology = 0, seconds_curvature = 0, seconds_saliency = 0, seconds_fit = 0;
};

namespace detail {

struct Counters {
  long fold_fallbacks = 0, fold_skips = 0, fit_failures = 0, newton_failures = 0, rejected = 0;
};

// Mean of the unit normals of the neighbourhood's vertices (paper 3.2's "approximate normal N").
inline Vec3 neighbourhoodNormal(int i, const Rings &rings, const std::vector<Vec3> &normals) {
  Vec3 sum = normals[i];
  for (const int *w = rings.ring2Begin(i); w != rings.ring2End(i); ++w) sum += normals[*w];
  const double len = sum.norm();
  return len > 1e-12 ? Vec3(sum / len) : normals[i];
}


// Whether a patch point (local coordinates) lies within the neighbourhood's bounding box grown by
// the box's largest extent. A nearly singular fit (e.g. 9 points that almost interpolate the 9
// control points) can pass the solver's rank test and still put the patch far from its data:
// measured on a noisy unit 9x9 grid, boundary vertices thrown 4.6 units off the plane.
inline bool nearNeighbourhood(const Vec3 &point, const std::vector<Vec3> &local) {
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
  for (const Vec3 &q : local) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  const double reach = (hi - lo).maxCoeff();
  return (point.array() >= lo.array() - reach).all() && (point.array() <= hi.array() + reach).all();
}

} // namespace detail

namespace detail {

// Stages 1-3: vertex i's neighbourhood projected onto the plane of its approximate normal (into
// `frame` and `scratch`). With the paper's fold handling, a folded projection falls back to the
// vertex's own normal, then to its 1-ring. False (counted) when no projection is usable.
inline bool projectNeighbourhoodOf(int i, const MeshArrays &mesh, const Rings &rings,
                                   const std::vector<Vec3> &p, const CurvatureField &c,
                                   FoldHandling folds, LocalFrame &frame,
                                   NeighbourhoodScratch &scratch, Counters &counters) {
  Vec3 normal = neighbourhoodNormal(i, rings, c.normal);
  NeighbourhoodSize size = NeighbourhoodSize::TwoRing;
  bool ok = normal.squaredNorm() > 0.5 &&
            projectNeighbourhood(i, p, rings, size, normal, frame, scratch);
  if (ok && folds == FoldHandling::Paper && neighbourhoodFolds(i, p, mesh.faces, rings, frame, scratch)) {
    ++counters.fold_fallbacks;
    normal = c.normal[i];
    ok = projectNeighbourhood(i, p, rings, size, normal, frame, scratch) &&
         !neighbourhoodFolds(i, p, mesh.faces, rings, frame, scratch);
    if (!ok) {
      size = NeighbourhoodSize::OneRing;
      ok = projectNeighbourhood(i, p, rings, size, normal, frame, scratch) &&
           !neighbourhoodFolds(i, p, mesh.faces, rings, frame, scratch);
    }
    if (!ok) {
      ++counters.fold_skips;
      return false;
    }
  }
  if (!ok) ++counters.fit_failures;
  return ok;
}

// Stage 4: the paper's α from the saliency spread over the fitting neighbourhood's vertices,
// Saliency_min / Saliency_max (1 where nothing there is salient); the user's α with the override.
inline double neighbourhoodAlpha(const std::vector<int> &vertices,
                                 const std::vector<double> &saliency, double max_saliency,
                                 const SmoothParams &params) {
  if (params.alpha_override) return params.alpha;
  double lo = INFINITY, hi = 0;
  for (int w : vertices) {
    lo = std::min(lo, saliency[w]);
    hi = std::max(hi, saliency[w]);
  }
  return hi < 1e-6 * max_saliency || hi <= 0 ? 1.0 : lo / hi;
}

// The ring barycentre's patch parameters (the barycentre projected into the frame, clamped).
inline void ringBarycentreParameters(int i, const Rings &rings, const std::vector<Vec3> &p,
                                     const LocalFrame &frame, double &u, double &v) {
  Vec3 centre = Vec3::Zero();
  for (const int *w = rings.ring1Begin(i); w != rings.ring1End(i); ++w) centre += p[*w];
  const Vec3 local = frame.toLocal(centre / rings.ring1Size(i));
  u = std::clamp(frame.u(local), 0.0, 1.0);
  v = std::clamp(frame.v(local), 0.0, 1.0);
}

// The paper's placement (stages 6-7): Newton from (u, v) towards the patch point whose curvature
// is the uniform principal curvature of vertex i's 1-ring (saliency-weighted). As printed, the
// clamped parameter is used whether or not Newton converged (failures counted).
inline void paperParameters(int i, const Rings &rings, const SurfaceAnalysis &analysis,
                            const BezierPatch &patch, const SmoothParams &params,
                            double mean_edge, double &u, double &v, Counters &counters) {
  const CurvatureField &c = analysis.curvature;
  VertexCurvature self{c.k1[i], c.k2[i], c.dir1[i], c.dir2[i], c.normal[i]};
  constexpr int kMaxRing = 64;
  VertexCurvature ring[kMaxRing];
  double weights[kMaxRing];
  int m = 0;
  for (const int *w = rings.ring1Begin(i); w != rings.ring1End(i) && m < kMaxRing; ++w, ++m) {
    ring[m] = {c.k1[*w], c.k2[*w], c.dir1[*w], c.dir2[*w], c.normal[*w]};
    weights[m] = analysis.saliency[*w];
  }
  double k1u = 0, k2u = 0;
  uniformPrincipalCurvature(self, ring, weights, m, params.uniform_variant, k1u, k2u);
  NewtonOptions options;
  options.iterations = params.newton_iterations;
  options.max_step = params.newton_step_limit * mean_edge;
  // Meyer's H is positive where the surface bends away from its normal (a sphere with outward
  // normals has H = +1/r); the patch formula of paper 3.3 has the opposite sign.
  const NewtonResult r = solveCurvatureTarget(patch, u, v, k1u * k2u, -0.5 * (k1u + k2u), options);
  if (r.status != NewtonStatus::Converged) ++counters.newton_failures;
  u = r.u, v = r.v;
}

} // namespace detail

// One vertex's new position from the current positions `p` (stages 4-7). Returns p[i] unchanged
// where the vertex cannot be placed, counting why.
inline Vec3 placeVertex(int i, const MeshArrays &mesh, const Rings &rings,
                        const std::vector<Vec3> &p, const SurfaceAnalysis &analysis,
                        const SmoothParams &params, double mean_edge, double max_saliency,
                        NeighbourhoodScratch &scratch, double &alpha_out,
                        detail::Counters &counters) {
  LocalFrame frame;
  if (!detail::projectNeighbourhoodOf(i, mesh, rings, p, analysis.curvature, params.folds, frame,
                                      scratch, counters))
    return p[i];
  const double alpha =
      detail::neighbourhoodAlpha(scratch.vertices, analysis.saliency, max_saliency, params);
  alpha_out = alpha;

  BezierPatch patch;
  const int count = int(scratch.vertices.size());
  // A rank-deficient fit (too few points, e.g. a mesh corner's 2-ring or the paper's 1-ring
  // fallback) interpolates its points but extrapolates arbitrarily between them: keep the vertex.
  if (fitBezierPatch(scratch.u.data(), scratch.v.data(), scratch.local.data(), nullptr, count,
                     alpha, patch) != FitStatus::Ok) {
    ++counters.fit_failures;
    return p[i];
  }
  double u = scratch.u[0], v = scratch.v[0]; // q_i is the first point
  if (params.placement == PlacementMode::RingBarycentre)
    detail::ringBarycentreParameters(i, rings, p, frame, u, v);
  else if (params.placement == PlacementMode::Paper)
    detail::paperParameters(i, rings, analysis, patch, params, mean_edge, u, v, counters);
  const Vec3 on_patch = patch.eval(u, v);
  const Vec3 moved = frame.toWorld(on_patch);
  if (!moved.allFinite()) {
    ++counters.rejected;
    return p[i];
  }
  if (!detail::nearNeighbourhood(on_patch, scratch.local)) {
    ++counters.fit_failures;
    return p[i];
  }
  return moved;
}

namespace detail {

// What the report says of the set-up: scale, closedness, and the vertices that may not move and
// why (non-manifold, isolated, otherwise degenerate).
inline void reportPaperSetup(const DriverSetup &setup, SmoothReport &report) {
  const Rings &rings = setup.rings;
  report.mean_edge_length = setup.stats.mean_edge_length;
  report.bbox_diagonal = setup.stats.bbox_diagonal;
  report.closed = setup.closed;
  for (int v = 0; v < rings.vertex_count; ++v) {
    report.frozen_vertices += setup.roles.frozen[v];
    if (rings.nonmanifold[v]) ++report.nonmanifold_vertices;
    else if (rings.isolated[v]) ++report.isolated_vertices;
    else if (setup.roles.frozen[v]) ++report.degenerate_vertices;
  }
  report.volume_before = setup.volume_before;
}

inline void addCounters(const Counters &c, SmoothReport &report) {
  report.fold_fallbacks += c.fold_fallbacks;
  report.fold_skips += c.fold_skips;
  report.fit_failures += c.fit_failures;
  report.newton_failures += c.newton_failures;
  report.rejected_moves += c.rejected;
}

// One Jacobi sweep of placeVertex over the movable vertices (the boundary rule applied), from
// `current` into `next`, the α each placement used into `alpha`; in blocks of 2^16 vertices, after
// each of which `block_done(stop)` may cancel the sweep (returns false). Counts go to `report`.
template <class BlockDone>
bool paperVertexSweep(const MeshArrays &mesh, const DriverSetup &setup,
                      const std::vector<Vec3> &current, const SurfaceAnalysis &analysis,
                      const SmoothParams &params, std::vector<double> &alpha,
                      std::vector<Vec3> &next, SmoothReport &report, BlockDone block_done) {
  const Rings &rings = setup.rings;
  const int n = int(current.size());
  double max_saliency = 0;
  for (double s : analysis.saliency) max_saliency = std::max(max_saliency, s);
  Counters counters;
  const int block = 1 << 16; // progress and cancel between blocks of vertices
  bool finished = true;
  for (int start = 0; start < n && finished; start += block) {
    const int stop = std::min(n, start + block);
    long fold_fallbacks = 0, fold_skips = 0, fit_failures = 0, newton_failures = 0, rejected = 0;
#pragma omp parallel reduction(+ : fold_fallbacks, fold_skips, fit_failures, newton_failures, rejected) \
    if (n >= min_parallel_vertices)
    {
      NeighbourhoodScratch scratch;
      scratch.reserve(64);
      Counters local;
#pragma omp for schedule(dynamic, 512)
      for (int i = start; i < stop; ++i) {
        next[i] = current[i];
        if (setup.fixed[i]) continue;
        Vec3 moved = placeVertex(i, mesh, rings, current, analysis, params,
                                 setup.stats.mean_edge_length, max_saliency, scratch, alpha[i],
                                 local);
        if (rings.boundary[i])
          moved = constrainBoundaryMove(i, moved, current, analysis.curvature.normal, setup.roles,
                                        params.boundary);
        next[i] = moved;
      }
      fold_fallbacks += local.fold_fallbacks;
      fold_skips += local.fold_skips;
      fit_failures += local.fit_failures;
      newton_failures += local.newton_failures;
      rejected += local.rejected;
    }
    counters.fold_fallbacks += fold_fallbacks;
    counters.fold_skips += fold_skips;
    counters.fit_failures += fit_failures;
    counters.newton_failures += newton_failures;
    counters.rejected += rejected;
    finished = block_done(stop);
  }
  if (finished) addCounters(counters, report);
  return finished;
}

// The iteration's analysis of `current`: the curvature (only the vertex normals where nothing
// reads more) and, where needed, the saliency of k2 (the paper's curvature map: "negative minima
// of principal curvatures"). False when the user cancelled.
inline bool analyseIteration(int it, const MeshArrays &mesh, const Rings &rings,
                             const std::vector<Vec3> &current, const SmoothParams &params,
                             bool needs_curvature, bool needs_saliency, double saliency_scale,
                             const PassProgress &progress, SurfaceAnalysis &analysis,
                             SmoothReport &report) {
  auto t = Clock::now();
  if (needs_curvature)
    computeCurvature(current, mesh.faces, rings, analysis.curvature);
  else
    computeVertexNormals(current, mesh.faces, rings, analysis.curvature.normal);
  report.seconds_curvature += secondsSince(t);
  if (!progress(it, 0.1, "Curvature")) return false;
  if (!needs_saliency) return true;
  t = Clock::now();
  computeSaliency(current, rings, analysis.curvature.k2, saliency_scale, analysis.saliency,
                  params.saliency);
  report.seconds_saliency += secondsSince(t);
  return progress(it, 0.3, "Saliency");
}

// The result's quantities, as the other methods describe theirs (Lee et al.'s saliency of the
// mean curvature, surface_analysis.h; the curvatures without directions, which are not stored),
// with the α of the last iteration's placements; its volume.
inline void describePaperResult(const MeshArrays &mesh, const Rings &rings,
                                const std::vector<Vec3> &result, double saliency_scale,
                                const SmoothParams &params, SurfaceAnalysis &analysis,
                                std::vector<double> &alpha, VertexQuantities &quantities,
                                SmoothReport &report) {
  auto t = Clock::now();
  computeCurvature(result, mesh.faces, rings, analysis.curvature, /*with_directions=*/false);
  report.seconds_curvature += secondsSince(t);
  t = Clock::now();
  computeSaliency(result, rings, analysis.curvature.mean, saliency_scale, analysis.saliency,
                  params.saliency);
  report.seconds_saliency += secondsSince(t);
  PatchAlpha used;
  used.per_vertex = std::move(alpha);
  report.vertices_moved += storeResultQuantities(mesh.points, result, rings, std::move(analysis),
                                                 std::move(used), quantities);
  report.volume_after = signedVolume(result, mesh.faces);
}

} // namespace detail

// Smooths `mesh` and writes the result to `out_points`; see the header comment. Each iteration:
// curvature (and the saliency where the placement or the α rule reads it), one placement sweep,
// the volume restored on a closed mesh.
inline SmoothReport smoothMesh(const MeshArrays &mesh, const SmoothParams &params,
                               std::vector<Vec3> &out_points, VertexQuantities &quantities,
                               const ProgressFn &progress = nullptr) {
  SmoothReport report;
  const int n = int(mesh.points.size());
  auto t0 = Clock::now();
  detail::DriverSetup setup =
      detail::driverSetup(mesh, params.selected_only, params.boundary, /*with_face_rings=*/false,
                          /*with_two_rings=*/true);
  Rings &rings = setup.rings;
  report.seconds_topology = secondsSince(t0);
  detail::reportPaperSetup(setup, report);

  std::vector<Vec3> current = mesh.points, next = mesh.points;
  std::vector<double> alpha(n, 1.0);
  std::vector<Vec3> normals_scratch;
  std::vector<std::uint8_t> movable(n, 0);
  for (int i = 0; i < n; ++i) movable[i] = !setup.fixed[i];
  SurfaceAnalysis analysis;
  const double saliency_scale = params.saliency_scale * setup.stats.bbox_diagonal;
  const int iterations = std::max(0, params.iterations);
  // Saliency steers only the paper's placement and its alpha rule; principal curvatures and
  // directions the same and the saliency. The other placements need the vertex normals alone
  // inside the iterations (saliency is the costliest stage) and describe the result once.
  const bool needs_saliency = params.placement == PlacementMode::Paper || !params.alpha_override;
  const bool needs_curvature = needs_saliency || params.placement == PlacementMode::Paper;
  if (!needs_saliency) analysis.saliency.assign(n, 0.0);
  const detail::PassProgress report_progress{progress, iterations, 100.0};

  for (int it = 0; it < iterations; ++it) {
    if (!detail::analyseIteration(it, mesh, rings, current, params, needs_curvature,
                                  needs_saliency, saliency_scale, report_progress, analysis,
                                  report))
      return report.cancelled = true, report;
    const auto t = Clock::now();
    if (!detail::paperVertexSweep(mesh, setup, current, analysis, params, alpha, next, report,
                                  [&](int stop) {
                                    return report_progress(it, 0.3 + 0.7 * stop / n,
                                                           "Fitting patches");
                                  }))
      return report.cancelled = true, report;
    report.seconds_fit += secondsSince(t);
    if (params.preserve_volume && report.closed)
      detail::restoreVolume(next, mesh.faces, rings, movable, report.volume_before,
                            setup.stats.mean_edge_length, normals_scratch);
    current.swap(next);
    report.iterations_done = it + 1;
  }

  // The analysis needs neither the 2-rings nor the iteration buffers; freeing them first keeps
  // them out of the run's peak memory, which the saliency's lattices set.
  std::vector<int>().swap(rings.ring2);
  std::vector<int>().swap(rings.ring2_offsets);
  std::vector<Vec3>().swap(next);
  std::vector<Vec3>().swap(normals_scratch);
  detail::describePaperResult(mesh, rings, current, saliency_scale, params, analysis, alpha,
                              quantities, report);
  out_points.swap(current);
  return report;
}

// The paper's method as the filter runs it (methods.h): `iterations` iterations of `placement`.
inline MethodRun paperMethod(PlacementMode placement, const MeshArrays &mesh,
                             const MethodParams &p, std::vector<Vec3> &out_points,
                             VertexQuantities &quantities, const ProgressFn &progress) {
  SmoothParams s;
  s.iterations = p.iterations;
  s.placement = placement;
  s.uniform_variant = p.uniform_variant;
  s.alpha_override = p.alpha_override;
  s.alpha = p.alpha;
  s.boundary = p.boundary;
  s.folds = p.folds;
  s.newton_iterations = p.newton_iterations;
  s.newton_step_limit = p.newton_step_limit;
  s.saliency_scale = p.saliency_scale;
  s.selected_only = p.selected_only;
  s.preserve_volume = p.preserve_volume;
  const SmoothReport r = smoothMesh(mesh, s, out_points, quantities, progress);
  MethodRun run;
  run.cancelled = r.cancelled;
  if (r.cancelled) return run;
  const char *names[] = {"paper (Newton)", "patch point", "ring barycentre"};
  const int rows[] = {2, 1, 0}; // methods.h
  run.method = names[int(placement)];
  run.method_index = rows[int(placement)];
  detail::measureMovement(quantities, r.mean_edge_length, run);
  run.summary = detail::formatLine("Paper's method, %s placement, %d iterations: ",
                                   run.method.c_str(), r.iterations_done) +
                detail::movedPhrase(run, mesh.points.size()) + ".";
  using detail::formatLine;
  if (r.frozen_vertices > 0)
    run.details.push_back(formatLine("Skipped (left in place): %ld non-manifold, %ld isolated (in "
                                     "no face), %ld on degenerate faces.",
                                     r.nonmanifold_vertices, r.isolated_vertices,
                                     r.degenerate_vertices));
  run.details.push_back(formatLine("Fold fallbacks %ld, fold skips %ld, Newton failures %ld.",
                                   r.fold_fallbacks, r.fold_skips, r.newton_failures));
  if (r.fit_failures + r.rejected_moves > 0)
    run.details.push_back(formatLine("Kept in place (over all iterations): %ld failed fits, %ld "
                                     "non-finite results.",
                                     r.fit_failures, r.rejected_moves));
  if (r.closed && r.volume_before != 0)
    run.details.push_back(detail::volumeLine(r.volume_before, r.volume_after));
  run.details.push_back(formatLine("Time: topology %.3f s, curvature %.3f s, saliency %.3f s, "
                                   "patch fit + placement %.3f s.",
                                   r.seconds_topology, r.seconds_curvature, r.seconds_saliency,
                                   r.seconds_fit));
  return run;
}

} // namespace vcg_ext
