// noise_probe: the noise estimate of vcg_ext/analysis/noise_estimate.h for a list of meshes, one JSON line
// per mesh (bench/studies/noise_estimate.py reads them).
//
//   noise_probe [--no-amplitude | --amplitude-always] [--amplitude-noisy T]
//               [--trimmed-quantile Q] <mesh> [<mesh> ...]
#include "tool_mesh.h"

#include <vcg_ext/analysis/noise_estimate.h>

#include <chrono>
#include <cstdlib>
#include <string>

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: noise_probe <mesh> [<mesh> ...]\n");
    return 1;
  }
  int status = 0;
  vcg_ext::NoiseEstimateParams params;
  for (int a = 1; a < argc; ++a) {
    if (std::string(argv[a]) == "--no-amplitude") { // the estimate without the amplitude (timing)
      params.amplitude = false;
      continue;
    }
    if (std::string(argv[a]) == "--trimmed-quantile" && a + 1 < argc) { // trimmed band energies
      params.amplitude_bands.trimmed_quantile = std::atof(argv[++a]);
      continue;
    }
    if (std::string(argv[a]) == "--amplitude-noisy" && a + 1 < argc) { // 0: the pair's test alone
      params.amplitude_noisy = std::atof(argv[++a]);
      continue;
    }
    if (std::string(argv[a]) == "--amplitude-always") { // also where the mesh reads clean
      params.amplitude_when_clean = true;
      continue;
    }
    tool_mesh::Mesh mesh;
    if (!tool_mesh::load(mesh, argv[a], "noise_probe")) {
      status = 2;
      continue;
    }
    const vcg_ext::MeshArrays arrays = vcg_ext::extractArrays(mesh);
    const auto start = std::chrono::steady_clock::now();
    const vcg_ext::NoiseEstimate e = vcg_ext::estimateNoise(arrays.points, arrays.faces, params);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("{\"mesh\": \"%s\", \"vertices\": %zu, \"noisy\": %s, \"level\": %.5f, "
                "\"spectrum\": [",
                argv[a], arrays.points.size(), e.noisy ? "true" : "false", e.level);
    for (size_t b = 0; b < e.spectrum.size(); ++b)
      std::printf("%s%.5f", b ? ", " : "", e.spectrum[b]);
    std::printf("], \"amplitude\": %.5f, \"correlation_steps\": %d, \"correlated_share\": %.4f"
                ", \"trimmed_amplitude\": %.5f, \"noisy_by_amplitude\": %s"
                ", \"spread_deg\": %.4f, \"smoothed_spread_deg\": %.4f, \"decay\": %.5f, "
                "\"counted_vertices\": %ld, \"seconds\": %.4f}\n",
                e.amplitude, e.correlation_steps, e.correlated_share, e.trimmed_amplitude,
                e.noisy_by_amplitude ? "true" : "false", e.spread_deg,
                e.smoothed_spread_deg, e.decay, e.counted_vertices, seconds);
  }
  return status;
}
