// add_noise: Gaussian noise of standard deviation k x mean edge length, along the vertex normals or
// in random 3-D directions, with a fixed seed: the benchmark's noisy meshes (the literature's noise
// runs along normals; real scans also have tangential noise, which folds faces).
//
//   add_noise <in> <out.ply> <k> <normal|random> [seed]
#include "tool_mesh.h"

#include <vcg_ext/analysis/curvature.h>
#include <vcg_ext/core/rings.h>

#include <random>

int main(int argc, char **argv) {
  if (argc < 5 || (std::string(argv[4]) != "normal" && std::string(argv[4]) != "random")) {
    std::fprintf(stderr, "usage: add_noise <in> <out.ply> <k> <normal|random> [seed]\n");
    return 1;
  }
  tool_mesh::Mesh mesh;
  if (!tool_mesh::load(mesh, argv[1], "add_noise")) return 2;
  vcg::tri::Allocator<tool_mesh::Mesh>::CompactEveryVector(mesh);
  const double k = std::stod(argv[3]);
  const bool along_normal = std::string(argv[4]) == "normal";
  const unsigned seed = argc > 5 ? unsigned(std::stoul(argv[5])) : 1u;

  const vcg_ext::MeshArrays arrays = vcg_ext::extractArrays(mesh);
  const vcg_ext::Rings rings = vcg_ext::computeRings(int(arrays.points.size()), arrays.faces);
  const double sigma = k * vcg_ext::edgeStatistics(arrays.points, rings).mean_edge_length;
  std::vector<vcg_ext::Vec3> normals;
  vcg_ext::computeVertexNormals(arrays.points, arrays.faces, rings, normals);
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, sigma);
  std::vector<vcg_ext::Vec3> noisy = arrays.points;
  for (size_t i = 0; i < noisy.size(); ++i) {
    if (along_normal) noisy[i] += gauss(rng) * normals[i];
    else noisy[i] += vcg_ext::Vec3(gauss(rng), gauss(rng), gauss(rng));
  }
  vcg_ext::writePositions(mesh, arrays, noisy);
  return tool_mesh::save(mesh, argv[2], "add_noise", false) ? 0 : 2;
}
