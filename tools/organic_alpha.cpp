// organic_alpha: runs the organic mode (vcg_ext/methods/organic/organic_smooth.h) with its over-subtraction α
// chosen from the mesh and with given fixed values, to measure how well the choice does
// (bench/studies/alpha_choice.py).
//
//   organic_alpha <noisy mesh> <output prefix> <alpha>[,<alpha>...]
//
// An alpha of 0 means "chosen from the mesh" (the filter's behaviour). Each run writes
// <prefix>_<alpha>.ply and prints one JSON line on stdout: the α used and what the choice reads
// (shape spectrum slope, fine- and coarse-band shape/noise ratios, noise in mean edge lengths).
#include "tool_mesh.h"

#include <vcg_ext/core/mesh_arrays.h>
#include <vcg_ext/methods/organic/organic_smooth.h>

#include <cstdio>
#include <sstream>
#include <string>

int main(int argc, char **argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: organic_alpha <noisy mesh> <output prefix> <alpha>[,<alpha>...]\n");
    return 1;
  }
  tool_mesh::Mesh mesh;
  if (!tool_mesh::load(mesh, argv[1], "organic_alpha")) return 2;
  const vcg_ext::MeshArrays arrays = vcg_ext::extractArrays(mesh);
  std::stringstream alphas(argv[3]);
  for (std::string text; std::getline(alphas, text, ',');) {
    vcg_ext::OrganicSmoothParams params;
    params.bands.fixed_alpha = std::stod(text);
    std::vector<vcg_ext::Vec3> result;
    vcg_ext::VertexQuantities quantities;
    const vcg_ext::OrganicSmoothReport r =
        vcg_ext::organicSmoothMesh(arrays, params, result, quantities);
    vcg_ext::writePositions(mesh, arrays, result);
    const std::string out = std::string(argv[2]) + "_" + text + ".ply";
    if (!tool_mesh::save(mesh, out, "organic_alpha", false)) return 2;
    std::printf("{\"fixed_alpha\": %s, \"alpha\": %.6g, \"shape_slope\": %.6g, \"fine_snr\": %.6g, "
                "\"coarse_snr\": %.6g, \"noise_edges\": %.6g, \"roughness\": %.6g, \"output\": \"%s\"}\n",
                text.c_str(), r.bands.alpha, r.bands.shape_slope, r.bands.fine_snr, r.bands.coarse_snr,
                r.bands.noise_edges, r.roughness, out.c_str());
  }
  return 0;
}
