// noise_probe: the noise estimate of vcg_ext/analysis/noise_estimate.h for a list of meshes, one JSON line
// per mesh (bench/studies/noise_estimate.py reads them).
//
//   noise_probe <mesh> [<mesh> ...]
#include "tool_mesh.h"

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
    std::printf("{\"mesh\": \"%s\", \"vertices\": %zu, \"noisy\": %s, \"level\": %.5f, "
                "\"spectrum\": [",
                argv[a], arrays.points.size(), e.noisy ? "true" : "false", e.level);
    for (size_t b = 0; b < e.spectrum.size(); ++b)
      std::printf("%s%.5f", b ? ", " : "", e.spectrum[b]);
    std::printf("], \"spread_deg\": %.4f, \"smoothed_spread_deg\": %.4f, \"decay\": %.5f, "
                "\"counted_vertices\": %ld, \"seconds\": %.4f}\n",
                e.spread_deg, e.smoothed_spread_deg, e.decay, e.counted_vertices, seconds);
  }
  return status;
}
