// The vcglib mesh type of the stand-alone tools: double precision, with the components the
// filters write (quality, normals, curvature directions), plus PLY/OFF/OBJ/STL load and save.
#pragma once

#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/export.h>
#include <wrap/io_trimesh/import.h>

#include <cstdio>
#include <string>

namespace tool_mesh {

class Vertex;
class Face;
struct Types : vcg::UsedTypes<vcg::Use<Vertex>::AsVertexType, vcg::Use<Face>::AsFaceType> {};
class Vertex : public vcg::Vertex<Types, vcg::vertex::Coord3d, vcg::vertex::Normal3d,
                                  vcg::vertex::Qualityd, vcg::vertex::CurvatureDird,
                                  vcg::vertex::BitFlags> {};
class Face : public vcg::Face<Types, vcg::face::VertexRef, vcg::face::Normal3d,
                              vcg::face::BitFlags> {};
class Mesh : public vcg::tri::TriMesh<std::vector<Vertex>, std::vector<Face>> {};

// Loads `path`; prints the reason and returns false on failure.
inline bool load(Mesh &mesh, const std::string &path, const char *tool) {
  int mask = 0;
  const int err = vcg::tri::io::Importer<Mesh>::Open(mesh, path.c_str(), mask);
  if (err != 0 && vcg::tri::io::Importer<Mesh>::ErrorCritical(err)) {
    std::fprintf(stderr, "%s: cannot read '%s': %s\n", tool, path.c_str(),
                 vcg::tri::io::Importer<Mesh>::ErrorMsg(err));
    return false;
  }
  return true;
}

inline bool save(Mesh &mesh, const std::string &path, const char *tool, bool with_quality) {
  int mask = with_quality ? vcg::tri::io::Mask::IOM_VERTQUALITY : 0;
  const int err = vcg::tri::io::Exporter<Mesh>::Save(mesh, path.c_str(), mask);
  if (err != 0) {
    std::fprintf(stderr, "%s: cannot write '%s': %s\n", tool, path.c_str(),
                 vcg::tri::io::Exporter<Mesh>::ErrorMsg(err));
    return false;
  }
  return true;
}

} // namespace tool_mesh
