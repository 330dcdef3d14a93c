// The noise estimate (noise_estimate.h) of a large mesh from windows of it.
//
// Inputs: the mesh (in the drivers' spatial order), its Rings, its movable flags and mean edge
// length (DriverSetup's). Output: the estimate with its medians over the cores of windows of the
// mesh (mesh_windows.h), or nothing when the mesh is too small for windows to save time.
//
// Why: on the whole mesh the estimate (a Taubin run of 8 pairs with its white-noise probe, two
// dihedral spreads, ten medians) is a sizeable share of a large mesh's run
// (docs/studies/performance.md). Each value it takes a median of reads a bounded neighbourhood:
// a vertex's band values the 16 Taubin steps of the last band and the normal of the last snapshot
// (17 rings), a face's spread after one pair its neighbours' corners after two steps (3 rings).
// The windows keep the mesh's order and frame (the probe hashes positions in the whole mesh's
// frame), so the cores' values are the whole mesh's bit for bit
// (tests/unit/test_noise_windows.cpp); only the sample differs: medians over at most 64 windows'
// cores instead of the whole mesh (NoiseWindowParams).
#pragma once

#include "vcg_ext/core/mesh_windows.h"
#include "vcg_ext/analysis/noise_estimate.h"

#include <algorithm>
#include <vector>

namespace vcg_ext {

struct NoiseWindowParams {
  int core_rings = 24; // the medians count the vertices and faces within this many rings of a seed
  // As many windows as take about `face_share` of the faces (a window of r rings holds about
  // 6 r² faces), at most `max_windows`. Fewer than `min_windows` (meshes under about 600k
  // vertices): the whole mesh, whose estimate is a small part of the run there, and whose medians
  // a few dozen windows would sample too thinly. A median's error follows the sample's size, not
  // its share of the mesh: 64 windows' cores hold about 110k vertices, and more windows buy little
  // accuracy for their time (docs/studies/noise-estimate.md).
  double face_share = 0.3;
  int min_windows = 32, max_windows = 64;
  double max_face_share = 0.45; // windows that would take more than this: the whole mesh
  int spare_rings = 2;          // beyond the 2·(last band edge) + 1 rings the values read
  // The amplitude (noise_amplitude.h) reads about 40 rings more: it takes its own few windows,
  // their cores a sample of a mean, not of a median (docs/studies/noise-estimate.md).
  int amplitude_windows = 8, amplitude_core_rings = 16;
};

// The rings from a core vertex outward that its values read (see the file comment).
// With the amplitude, also its coarser bands' reach (noise_amplitude.h's coarseBandReach).
inline int noiseWindowMargin(const NoiseEstimateParams &params, const NoiseWindowParams &windows,
                             bool with_amplitude = false) {
  const int pairs = params.band_pairs.empty() ? 1 : std::max(1, params.band_pairs.back());
  const int coarse = with_amplitude ? coarseBandReach(int(params.band_pairs.size()) - 1,
                                                      params.amplitude_bands)
                                    : 0;
  return 2 * pairs + 1 + coarse + windows.spare_rings;
}

namespace detail {

// The estimate over the cores of the windows `distance` and `source` describe (meshWindows).
inline NoiseEstimate measureOnWindows(const MeshArrays &mesh, const std::vector<std::uint8_t> &fixed,
                                      const std::vector<int> &distance,
                                      const std::vector<int> &source, int core_rings, int reach,
                                      const Rings &rings, double edge,
                                      const NoiseEstimateParams &params) {
  const MeshWindows w = meshWindows(mesh, fixed, distance, source, core_rings, reach);
  const Rings window_rings = computeRings(int(w.mesh.points.size()), w.mesh.faces, false);
  const VertexRoles roles = vertexRoles(w.mesh, window_rings, edge);
  const FaceRings face_rings = computeFaceRings(w.mesh.faces, window_rings,
                                                /*with_edge_neighbours=*/true, /*with_lists=*/false);
  return measureNoise(w.mesh.points, w.mesh.faces, window_rings, face_rings, roles,
                      noiseFrame(mesh.points, rings, edge), &w.core_vertex, &w.core, params);
}

// The faces within `core_rings` of a seed (all three corners), as meshWindows counts its cores.
inline std::vector<std::uint8_t> windowCores(const std::vector<Face> &faces,
                                             const std::vector<int> &distance, int core_rings) {
  std::vector<std::uint8_t> core(faces.size());
  auto in = [&](int v) { return distance[v] >= 0 && distance[v] <= core_rings; };
  for (size_t g = 0; g < faces.size(); ++g)
    core[g] = in(faces[g][0]) && in(faces[g][1]) && in(faces[g][2]);
  return core;
}

} // namespace detail

// The amplitude of a large mesh on its own few windows (NoiseWindowParams::amplitude_windows),
// whose margins cover the coarse bands: into `out`, which keeps the spectrum's figures, with the
// amplitude's part of the decision (noise_estimate.h's decideNoisyByAmplitude).
inline void readAmplitudeOnWindows(const MeshArrays &mesh, const Rings &rings,
                                   const std::vector<std::uint8_t> &fixed, double edge,
                                   const NoiseWindowParams &windows,
                                   const NoiseEstimateParams &params, NoiseEstimate &out) {
  const int reach = windows.amplitude_core_rings + noiseWindowMargin(params, windows, true);
  const std::vector<int> seeds = detail::windowSeeds(rings, fixed, windows.amplitude_windows);
  if (seeds.empty()) return;
  std::vector<int> source;
  const std::vector<int> distance = detail::ringDistance(rings, seeds, reach, &source);
  NoiseEstimateParams always = params; // these windows' own decision is not the mesh's
  always.amplitude_when_clean = true;
  if (out.noisy) always.amplitude_noisy = 0; // nothing left to decide: no trimmed reading
  const NoiseEstimate a = detail::measureOnWindows(
      mesh, fixed, distance, source, windows.amplitude_core_rings, reach, rings, edge, always);
  out.amplitude = a.amplitude;
  out.correlation_steps = a.correlation_steps;
  out.correlated_share = a.correlated_share;
  out.trimmed_amplitude = a.trimmed_amplitude;
  detail::decideNoisyByAmplitude(params, out);
}

// True, with `out`, when the windows were used; false (`out` untouched): the caller estimates on
// the whole mesh.
inline bool estimateNoiseOnWindows(const MeshArrays &mesh, const Rings &rings,
                                   const std::vector<std::uint8_t> &fixed, double edge,
                                   NoiseEstimate &out, const NoiseWindowParams &windows = {},
                                   const NoiseEstimateParams &params = {}) {
  const long m = long(mesh.faces.size());
  const int reach = windows.core_rings + noiseWindowMargin(params, windows);
  const long count = std::min<long>(
      windows.max_windows, long(windows.face_share * double(m) / (6.0 * double(reach) * reach)));
  if (count < windows.min_windows || !(edge > 0)) return false;
  const std::vector<int> seeds = detail::windowSeeds(rings, fixed, int(count));
  if (long(seeds.size()) < windows.min_windows) return false;
  std::vector<int> source;
  const std::vector<int> distance = detail::ringDistance(rings, seeds, reach, &source);
  if (double(detail::windowFaceCount(mesh.faces, distance, reach)) >
      windows.max_face_share * double(m))
    return false;

  NoiseEstimateParams spectrum = params;
  spectrum.amplitude = false;
  out = detail::measureOnWindows(mesh, fixed, distance, source, windows.core_rings, reach, rings,
                                 edge, spectrum);
  long core_faces = 0;
  for (std::uint8_t c : detail::windowCores(mesh.faces, distance, windows.core_rings)) core_faces += c;
  out.sampled_share = m > 0 ? double(core_faces) / double(m) : 1.0;
  if (params.amplitude &&
      (out.noisy || params.amplitude_when_clean || detail::amplitudeMayDecide(params, out)))
    readAmplitudeOnWindows(mesh, rings, fixed, edge, windows, params, out);
  return true;
}

} // namespace vcg_ext
