// noise_probe: the noise estimate of vcg_ext/analysis/noise_estimate.h for a list of meshes, one JSON line
// per mesh (bench/studies/noise_estimate.py reads them).
//
//   noise_probe <mesh> [<mesh> ...]
#include "tool_mesh.h"

#include <vcg_ext/analysis/noise_amplitude.h>
#include <vcg_ext/analysis/noise_estimate.h>

#include <chrono>

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: noise_probe <mesh> [<mesh> ...]\n");
    return 1;
  }
  int status = 0;
  for (int a = 1; a < argc; ++a) {
    tool_mesh::Mesh mesh;
    if (!tool_mesh::load(mesh, argv[a], "noise_probe")) {
      status = 2;
      continue;
    }
    const vcg_ext::MeshArrays arrays = vcg_ext::extractArrays(mesh);
    const auto start = std::chrono::steady_clock::now();
    const vcg_ext::NoiseEstimate e = vcg_ext::estimateNoise(arrays.points, arrays.faces);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // The amplitude (noise_amplitude.h) on the mesh in spatial order, in the noise frame.
    const auto amplitude_start = std::chrono::steady_clock::now();
    const vcg_ext::SpatialOrder order = vcg_ext::spatialOrder(arrays);
    const vcg_ext::Rings rings = vcg_ext::computeRings(int(order.mesh.points.size()),
                                                       order.mesh.faces);
    const double edge = vcg_ext::edgeStatistics(order.mesh.points, rings).mean_edge_length;
    const vcg_ext::detail::VertexRoles roles = vcg_ext::detail::vertexRoles(order.mesh, rings, edge);
    const vcg_ext::NoiseAmplitude amp = vcg_ext::measureNoiseAmplitude(
        vcg_ext::detail::inNoiseFrame(order.mesh.points, rings,
                                      vcg_ext::detail::noiseFrame(order.mesh.points, rings, edge)),
        order.mesh.faces, rings, roles);
    const double amplitude_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - amplitude_start).count();
    std::printf("{\"mesh\": \"%s\", \"vertices\": %zu, \"noisy\": %s, \"level\": %.5f, "
                "\"spectrum\": [",
                argv[a], arrays.points.size(), e.noisy ? "true" : "false", e.level);
    for (size_t b = 0; b < e.spectrum.size(); ++b)
      std::printf("%s%.5f", b ? ", " : "", e.spectrum[b]);
    std::printf("], \"amplitude\": %.5f, \"correlation_steps\": %d, \"amplitude_fit_error\": %.4f, "
                "\"amplitude_seconds\": %.4f, \"band_energy\": [",
                amp.amplitude, amp.correlation_steps, amp.fit_error, amplitude_seconds);
    for (size_t b = 0; b < amp.band_energy.size(); ++b)
      std::printf("%s%.4e", b ? ", " : "", amp.band_energy[b]);
    std::printf("], \"spread_deg\": %.4f, \"smoothed_spread_deg\": %.4f, \"decay\": %.5f, "
                "\"counted_vertices\": %ld, \"seconds\": %.4f}\n",
                e.spread_deg, e.smoothed_spread_deg, e.decay, e.counted_vertices, seconds);
  }
  return status;
}
