// mesh_compare: scores a smoothing result against a reference mesh with the same connectivity.
//
//   mesh_compare <result.ply|off|obj|stl> <reference.ply|off|obj|stl>
//   mesh_compare --volume <mesh>
//
// Prints one JSON object on stdout (metrics: vcg_ext/analysis/mesh_metrics.h; null = not applicable).
// Exit code 2, with the reason on stderr, for unreadable files or meshes that do not share
// connectivity; 1 for bad usage.
#include <vcg_ext/core/mesh_arrays.h>
#include <vcg_ext/analysis/mesh_metrics.h>

#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/import.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

namespace {

class LoadVertex;
class LoadFace;
struct LoadTypes : vcg::UsedTypes<vcg::Use<LoadVertex>::AsVertexType, vcg::Use<LoadFace>::AsFaceType> {};
class LoadVertex : public vcg::Vertex<LoadTypes, vcg::vertex::Coord3d, vcg::vertex::BitFlags> {};
class LoadFace : public vcg::Face<LoadTypes, vcg::face::VertexRef, vcg::face::BitFlags> {};
class LoadMesh : public vcg::tri::TriMesh<std::vector<LoadVertex>, std::vector<LoadFace>> {};

bool load(const char *path, vcg_ext::MeshArrays &out) {
  LoadMesh mesh;
  int mask = 0;
  const int err = vcg::tri::io::Importer<LoadMesh>::Open(mesh, path, mask);
  if (err != 0 && vcg::tri::io::Importer<LoadMesh>::ErrorCritical(err)) {
    std::fprintf(stderr, "mesh_compare: cannot read '%s': %s\n", path,
                 vcg::tri::io::Importer<LoadMesh>::ErrorMsg(err));
    return false;
  }
  out = vcg_ext::extractArrays(mesh);
  if (out.faces.empty()) {
    std::fprintf(stderr, "mesh_compare: '%s' has no triangles\n", path);
    return false;
  }
  return true;
}

// Same triangles in the same order, each possibly starting at a different corner.
bool sameConnectivity(const std::vector<vcg_ext::Face> &a, const std::vector<vcg_ext::Face> &b) {
  for (size_t f = 0; f < a.size(); ++f) {
    bool same = false;
    for (int r = 0; r < 3 && !same; ++r)
      same = a[f][0] == b[f][r] && a[f][1] == b[f][(r + 1) % 3] && a[f][2] == b[f][(r + 2) % 3];
    if (!same) return false;
  }
  return true;
}

std::string number(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", x);
  return buf;
}

int usage() {
  std::fprintf(stderr, "usage: mesh_compare <result.ply|off> <reference.ply|off>\n"
                       "       mesh_compare --volume <mesh.ply|off>\n");
  return 1;
}

} // namespace

int main(int argc, char **argv) {
  if (argc == 3 && std::strcmp(argv[1], "--volume") == 0) {
    vcg_ext::MeshArrays m;
    if (!load(argv[2], m)) return 2;
    const vcg_ext::EdgeTable edges = vcg_ext::buildEdgeTable(m.faces);
    std::printf("{\"volume\": %s, \"closed\": %s, \"vertices\": %zu, \"faces\": %zu}\n",
                number(vcg_ext::signedVolume(m.points, m.faces)).c_str(),
                vcg_ext::isClosed(edges) ? "true" : "false", m.points.size(), m.faces.size());
    return 0;
  }
  if (argc != 3 || argv[1][0] == '-') return usage();

  vcg_ext::MeshArrays result, reference;
  if (!load(argv[1], result) || !load(argv[2], reference)) return 2;
  if (result.points.size() != reference.points.size() ||
      result.faces.size() != reference.faces.size()) {
    std::fprintf(stderr,
                 "mesh_compare: meshes differ in size: result %zu vertices / %zu faces, "
                 "reference %zu vertices / %zu faces\n",
                 result.points.size(), result.faces.size(), reference.points.size(),
                 reference.faces.size());
    return 2;
  }
  if (!sameConnectivity(result.faces, reference.faces)) {
    std::fprintf(stderr, "mesh_compare: meshes have the same size but different triangles; "
                         "face-by-face scores need the same connectivity\n");
    return 2;
  }

  const auto start = std::chrono::steady_clock::now();
  const vcg_ext::MeshComparison c =
      vcg_ext::compareMeshes(result.points, reference.points, reference.faces);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::printf("{\"vertices\": %d, \"faces\": %d, \"theta_deg\": %s, \"theta_sharp_deg\": %s, "
              "\"sharp_faces\": %d, \"ev_1e3\": %s, \"volume_result\": %s, "
              "\"volume_reference\": %s, \"volume_ratio\": %s, \"closed\": %s, "
              "\"flipped_faces\": %d, \"boundary_turning_deg_result\": %s, "
              "\"boundary_turning_deg_reference\": %s, \"boundary_drift_edges\": %s}\n",
              c.vertices, c.faces, number(c.normals.theta_deg).c_str(),
              number(c.normals.theta_sharp_deg).c_str(), c.normals.sharp_faces,
              number(c.ev * 1e3).c_str(), number(c.volume_result).c_str(),
              number(c.volume_reference).c_str(), number(c.volume_ratio).c_str(),
              c.closed ? "true" : "false", c.normals.flipped_faces,
              number(c.boundary_turning_deg_result).c_str(),
              number(c.boundary_turning_deg_reference).c_str(),
              number(c.boundary_drift_edges).c_str());
  std::fprintf(stderr, "mesh_compare: scored in %.2f s\n", seconds);
  return 0;
}
