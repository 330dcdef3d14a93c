// vcglib meshes for the tests that go through the filters' API-independent core
// (filter_saliency_bezier_smooth/apply_filters.h): MeshLab 2020.09's own CMeshO (float, optional
// components) and the tools' double mesh (the scalar of MeshLab/PyMeshLab 2025.07), filled from the
// plain arrays of analytic_meshes.h, plus a byte-exact snapshot of everything a filter could touch.
#pragma once

#ifndef MESHLAB_SCALAR
#define MESHLAB_SCALAR float
#endif
#include <common/ml_mesh_type.h> // MeshLab 2020.09's CMeshO: vcglib only, no Qt

#include <tools/tool_mesh.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg_ext/core/mesh_arrays.h>

#include <cstddef>
#include <string>
#include <vector>

namespace test_vcg {

// vcglib's TriMesh destructor leaves the per-vertex attributes allocated (its ClearAttributes call
// is commented out); these free them, so LeakSanitizer sees only real leaks.
class FloatMesh : public CMeshO { // MeshLab 2020.09
public:
  ~FloatMesh() { ClearAttributes(); }
};
class DoubleMesh : public tool_mesh::Mesh { // the scalar of MeshLab 2025.07 / PyMeshLab
public:
  ~DoubleMesh() { ClearAttributes(); }
};

// Replaces the contents of `m` by the points and triangles of `a`. (vcglib's TriMesh copy
// constructor copies nothing, so meshes are filled in place, never returned or copied.)
template <class MeshType>
void assign(MeshType &m, const vcg_ext::MeshArrays &a) {
  using Allocator = vcg::tri::Allocator<MeshType>;
  using Scalar = typename MeshType::ScalarType;
  m.Clear();
  if (!a.points.empty()) {
    auto v = Allocator::AddVertices(m, a.points.size());
    for (size_t i = 0; i < a.points.size(); ++i, ++v) {
      const vcg_ext::Vec3 &p = a.points[i];
      v->P() = typename MeshType::CoordType(Scalar(p.x()), Scalar(p.y()), Scalar(p.z()));
      v->Q() = 0;
    }
  }
  // Set by hand: Allocator::AddFace asserts three distinct vertices, MeshLab's importers do not.
  if (!a.faces.empty()) {
    auto f = Allocator::AddFaces(m, a.faces.size());
    for (size_t i = 0; i < a.faces.size(); ++i, ++f)
      for (int k = 0; k < 3; ++k) f->V(k) = &m.vert[size_t(a.faces[i][k])];
  }
  // As MeshLab after loading: vertex and face normals (vcglib leaves zero-length ones alone).
  vcg::tri::UpdateNormal<MeshType>::PerVertexNormalizedPerFaceNormalized(m);
}

// Positions of all vertex slots (deleted ones too) as doubles.
template <class MeshType>
std::vector<vcg_ext::Vec3> positions(const MeshType &m) {
  std::vector<vcg_ext::Vec3> p;
  for (const auto &v : m.vert)
    p.emplace_back(double(v.cP()[0]), double(v.cP()[1]), double(v.cP()[2]));
  return p;
}

template <class MeshType>
bool hasVertexAttribute(const MeshType &m, const std::string &name) {
  for (const auto &a : m.vert_attr)
    if (a._name == name) return true;
  return false;
}

// Per-vertex attribute `name` (of the mesh's scalar type) over all vertex slots; empty if absent.
template <class MeshType>
std::vector<double> attribute(MeshType &m, const std::string &name) {
  using Scalar = typename MeshType::ScalarType;
  using Allocator = vcg::tri::Allocator<MeshType>;
  std::vector<double> values;
  if (!hasVertexAttribute(m, name)) return values;
  auto h = Allocator::template FindPerVertexAttribute<Scalar>(m, name);
  if (!Allocator::template IsValidHandle<Scalar>(m, h)) return values;
  for (size_t i = 0; i < m.vert.size(); ++i) values.push_back(double(h[i]));
  return values;
}

// The bytes of everything the filters may write: every vertex slot's position, normal, quality,
// flags and (when enabled) curvature directions, every face's vertex slots, flags and normal, the
// counters and bounding box, and every per-vertex attribute's name and contents. Equal snapshots
// mean a bit-for-bit unchanged mesh (NaN included).
template <class MeshType>
std::string snapshot(const MeshType &m) {
  std::string s;
  auto put = [&s](const auto value) {
    s.append(reinterpret_cast<const char *>(&value), sizeof value);
  };
  put(m.vn);
  put(m.fn);
  put(m.vert.size());
  put(m.face.size());
  put(m.bbox);
  const bool dirs = vcg::tri::HasPerVertexCurvatureDir(m);
  for (const auto &v : m.vert) {
    put(v.cP());
    put(v.cN());
    put(v.cQ());
    put(v.cFlags());
    if (dirs) {
      put(v.cPD1());
      put(v.cPD2());
      put(v.cK1());
      put(v.cK2());
    }
  }
  for (const auto &f : m.face) {
    for (int k = 0; k < 3; ++k)
      put(f.cV(k) ? std::ptrdiff_t(f.cV(k) - &m.vert[0]) : std::ptrdiff_t(-1));
    put(f.cFlags());
    put(f.cN());
  }
  for (const auto &a : m.vert_attr) {
    s += "|attribute " + a._name + "|";
    for (size_t i = 0; i < m.vert.size(); ++i)
      s.append(static_cast<const char *>(a._handle->At(i)), size_t(a._sizeof));
  }
  return s;
}

} // namespace test_vcg
