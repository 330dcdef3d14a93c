// Flat, compact double-precision copy of a vcglib triangle mesh, and the write-back of new
// positions.
//
// Every stage of vcg_ext works on these plain arrays: it keeps the stages independent of the mesh's
// scalar (MeshLab 2020.09 stores float, 2025.07 double), lets the Jacobi iterations read one array
// and write another, and skips the deleted elements that MeshLab leaves in its containers.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace vcg_ext {

// Below this many vertices the stages run on one thread: a parallel region then costs about what
// its work does, and on a busy machine a region waits for a descheduled thread (a small mesh under
// load ran several times slower on two threads than on one; docs/studies/performance.md). Results
// do not depend on the thread count either way. (A variable so that the unit tests can run their
// small meshes through the parallel paths: tests/unit/test_saliency_lattice.cpp sets it to 0.)
inline int min_parallel_vertices = 20000;

using Vec3 = Eigen::Vector3d;
using Face = std::array<int, 3>;

struct MeshArrays {
  std::vector<Vec3> points;       // live vertices, compact order
  std::vector<Face> faces;        // live faces, compact vertex indices
  std::vector<int> compact_index; // mesh vertex slot -> compact index, -1 where deleted
  std::vector<int> mesh_slot;     // compact index -> mesh vertex slot
  std::vector<std::uint8_t> selected; // per compact vertex: the mesh's selection flag
  // Set by putInSpatialOrder (spatial_order.h): the compact order is already the one the drivers
  // run in, so they use these arrays as they are instead of an ordered copy.
  bool spatially_ordered = false;
};

// Copies the live vertices and faces of `mesh` (any vcglib triangle mesh) into plain arrays.
template <class MeshType>
MeshArrays extractArrays(const MeshType &mesh) {
  MeshArrays a;
  a.compact_index.assign(mesh.vert.size(), -1);
  a.points.reserve(mesh.vn);
  a.mesh_slot.reserve(mesh.vn);
  a.selected.reserve(mesh.vn);
  for (size_t i = 0; i < mesh.vert.size(); ++i) {
    const auto &v = mesh.vert[i];
    if (v.IsD()) continue;
    a.compact_index[i] = int(a.points.size());
    a.mesh_slot.push_back(int(i));
    a.points.emplace_back(double(v.cP()[0]), double(v.cP()[1]), double(v.cP()[2]));
    a.selected.push_back(v.IsS() ? 1 : 0);
  }
  if (mesh.vert.empty()) return a;
  a.faces.reserve(mesh.fn);
  // Faces on a deleted, missing or foreign vertex are skipped, as if deleted.
  for (const auto &f : mesh.face) {
    if (f.IsD()) continue;
    Face idx;
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      const auto *vp = f.cV(k);
      const size_t slot = vp ? size_t(vp - &mesh.vert[0]) : a.compact_index.size();
      idx[k] = slot < a.compact_index.size() ? a.compact_index[slot] : -1;
      ok = ok && idx[k] >= 0;
    }
    if (ok) a.faces.push_back(idx);
  }
  return a;
}

// Writes `points` (compact order, as extracted) back into the mesh's vertex positions.
template <class MeshType>
void writePositions(MeshType &mesh, const MeshArrays &a, const std::vector<Vec3> &points) {
  using Scalar = typename MeshType::ScalarType;
  const long count = long(points.size());
  // Every vertex to its own slot: in parallel (the slots follow the spatial order, so the writes
  // scatter over the mesh's vertex array and wait on memory; docs/studies/performance.md).
#pragma omp parallel for schedule(static) if (count >= min_parallel_vertices)
  for (long c = 0; c < count; ++c) {
    auto &p = mesh.vert[a.mesh_slot[c]].P();
    p[0] = Scalar(points[c].x());
    p[1] = Scalar(points[c].y());
    p[2] = Scalar(points[c].z());
  }
}

} // namespace vcg_ext
