// The fuzz target's body, shared by the libFuzzer binary (fuzz_filters.cpp) and the unit test that
// replays the committed corpus and every past finding (tests/unit/test_bad_input.cpp).
//
// The input bytes decode into a small vcglib mesh, MeshLab 2020.09's float CMeshO or a double mesh:
// a grid, an octahedron, a few components or pure random triangles; positions perturbed or replaced
// by NaN, Inf, huge, tiny, denormal and negative-zero values and scaled/offset to 1e-7..1e7;
// faces with repeated indices, duplicates and non-manifold fans; some vertices and faces deleted
// without compaction, random selection, stale attributes of the filters' names but another type,
// random filter parameters (sometimes an invalid one) and sometimes a cancel at the k-th progress
// call. Either filter then runs through the API-independent core (apply_filters.h), and:
//   - on success every live position, the quality and every attribute the filters write are
//     finite, and deleted vertices, faces and the counters are untouched;
//   - on refusal or cancel the mesh is bit for bit what it was;
//   - an invalid parameter and a cancel that was reached are refused.
// A violated check prints what broke and aborts (libFuzzer saves the input).
#pragma once

#include <support/vcg_meshes.h>

#include <filter_saliency_bezier_smooth/apply_filters.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace sbs_fuzz {

using vcg_ext::Face;
using vcg_ext::MeshArrays;
using vcg_ext::Vec3;

// Reads the input front to back; past the end every read is 0.
class ByteReader {
public:
  ByteReader(const uint8_t *data, size_t size) : data_(data), size_(size) {}
  uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  // An integer in [lo, hi].
  int range(int lo, int hi) {
    const unsigned span = unsigned(hi - lo) + 1;
    const unsigned raw = unsigned(byte()) | unsigned(byte()) << 8;
    return lo + int(raw % span);
  }
  bool chance(int one_in) { return byte() % one_in == 0; }
  double unit() { return range(0, 65535) / 65535.0; }

private:
  const uint8_t *data_;
  size_t size_, pos_ = 0;
};

inline double specialValue(ByteReader &in) {
  static const double values[] = {std::numeric_limits<double>::quiet_NaN(),
                                  std::numeric_limits<double>::infinity(),
                                  -std::numeric_limits<double>::infinity(),
                                  1e30, -1e30, 1.5e30, 1e31, 3.4e38, 1e300,
                                  1e-300, 5e-324, -0.0, 1e-7, 1e7, 1e15, 0.5};
  return values[in.byte() % (sizeof values / sizeof values[0])];
}

inline void perturb(MeshArrays &m, ByteReader &in) {
  // Jitter on a 1/64 lattice keeps exact coincidences (degenerate faces) reachable.
  for (Vec3 &p : m.points)
    if (in.chance(2)) p += Vec3(in.range(-8, 8), in.range(-8, 8), in.range(-8, 8)) / 64.0;
  const int replaced = in.chance(3) ? in.range(0, 3) : 0;
  for (int k = 0; k < replaced && !m.points.empty(); ++k)
    m.points[in.range(0, int(m.points.size()) - 1)][in.range(0, 2)] = specialValue(in);
  const int extra_faces = in.range(0, 6), n = int(m.points.size());
  for (int k = 0; k < extra_faces && n > 0; ++k)
    m.faces.push_back({in.range(0, n - 1), in.range(0, n - 1), in.range(0, n - 1)});
}

inline MeshArrays grid(int k) {
  MeshArrays m;
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) m.points.emplace_back(i * 0.25, j * 0.25, 0.0);
  for (int j = 0; j + 1 < k; ++j)
    for (int i = 0; i + 1 < k; ++i) {
      const int a = j * k + i;
      m.faces.push_back({a, a + 1, a + k + 1});
      m.faces.push_back({a, a + k + 1, a + k});
    }
  return m;
}

inline MeshArrays octahedron() {
  MeshArrays m;
  m.points = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0),
              Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  m.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
             {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return m;
}

inline void append(MeshArrays &to, const MeshArrays &part, const Vec3 &shift) {
  const int base = int(to.points.size());
  for (const Vec3 &p : part.points) to.points.push_back(p + shift);
  for (const Face &f : part.faces) to.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
}

inline MeshArrays decodeMesh(ByteReader &in) {
  MeshArrays m;
  switch (in.byte() % 4) {
  case 0: { // pure random
    const int n = in.range(0, 24);
    for (int i = 0; i < n; ++i)
      m.points.emplace_back(in.range(-8, 8) / 4.0, in.range(-8, 8) / 4.0, in.range(-8, 8) / 4.0);
    const int faces = n > 0 ? in.range(0, 40) : 0;
    for (int k = 0; k < faces; ++k)
      m.faces.push_back({in.range(0, n - 1), in.range(0, n - 1), in.range(0, n - 1)});
    break;
  }
  case 1:
    m = grid(in.range(2, 6));
    break;
  case 2:
    m = octahedron();
    break;
  default: {
    const int parts = in.range(1, 4);
    for (int k = 0; k < parts; ++k)
      append(m, in.chance(2) ? octahedron() : grid(in.range(2, 3)),
             Vec3(in.range(-4, 4), in.range(-4, 4), in.range(-4, 4)));
  }
  }
  perturb(m, in);
  static const double scales[] = {1, 1, 1, 1, 1e-7, 1e7, 1e-20, 1e20, 3e-30, 3e29};
  static const double offsets[] = {0, 0, 0, 1e3, -1e7, 1e7};
  const double scale = scales[in.byte() % 10], offset = offsets[in.byte() % 6];
  for (Vec3 &p : m.points) p = p * scale + Vec3::Constant(offset);
  m.selected.assign(m.points.size(), 0);
  return m;
}

// Filter parameters inside each one's range, from the specs (so new parameters are covered).
inline saliency_bezier::ParameterValues decodeParameters(saliency_bezier::FilterId id,
                                                         ByteReader &in, bool &invalid) {
  using namespace saliency_bezier;
  ParameterValues p = defaultParameters(id);
  for (const ParamSpec &spec : parameterSpecs(id)) {
    if (in.chance(2)) continue; // keep the default
    double &value = p[spec.name];
    switch (spec.kind) {
    case ParamKind::Bool: value = in.byte() & 1; break;
    case ParamKind::Enum: value = in.range(0, int(spec.choices.size()) - 1); break;
    case ParamKind::Int: value = in.range(0, spec.name == "iterations" ? 3 : 4); break;
    case ParamKind::Float: {
      static const double step_limits[] = {0, 0.5, 1, 5}, scales[] = {1e-6, 0.05, 0.3, 2, 50};
      if (spec.name == "alpha") value = in.unit();
      else if (spec.name == "newton_step_limit") value = step_limits[in.byte() % 4];
      else if (spec.name == "saliency_scale") value = scales[in.byte() % 5];
      break;
    }
    }
  }
  invalid = false;
  if (in.chance(16)) {
    static const std::pair<const char *, double> bad[] = {
        {"iterations", -1}, {"alpha", 1.5}, {"placement", 9}, {"saliency_scale", 0},
        {"quality", 9}, {"newton_step_limit", std::numeric_limits<double>::quiet_NaN()}};
    const auto &choice = bad[in.byte() % 6];
    if (p.count(choice.first)) p[choice.first] = choice.second, invalid = true;
  }
  return p;
}

inline int g_calls = 0, g_cancel_at = 0;
inline bool progress(int, const char *) { return ++g_calls != g_cancel_at; }

// What the failing input decoded to, for the report.
inline const MeshArrays *g_mesh = nullptr;
inline const saliency_bezier::ParameterValues *g_parameters = nullptr;

[[noreturn]] inline void fail(const char *what, const saliency_bezier::FilterOutcome &o) {
  std::fprintf(stderr, "fuzz check failed: %s (ok=%d, error='%s')\n", what, int(o.ok),
               o.error.c_str());
  for (const std::string &line : o.log) std::fprintf(stderr, "  log: %s\n", line.c_str());
  if (g_parameters)
    for (const auto &[name, value] : *g_parameters)
      std::fprintf(stderr, "  parameter %s = %.17g\n", name.c_str(), value);
  if (g_mesh) {
    for (const Vec3 &p : g_mesh->points)
      std::fprintf(stderr, "  v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    for (const Face &f : g_mesh->faces) std::fprintf(stderr, "  f %d %d %d\n", f[0], f[1], f[2]);
  }
  std::fprintf(stderr, "  cancel at progress call %d (%d calls made)\n", g_cancel_at, g_calls);
  std::abort();
}

template <class MeshType>
void runOne(ByteReader &in) {
  using namespace saliency_bezier;
  using Allocator = vcg::tri::Allocator<MeshType>;
  using Scalar = typename MeshType::ScalarType;
  const MeshArrays arrays = decodeMesh(in);
  MeshType m;
  test_vcg::assign(m, arrays);
  for (auto &v : m.vert) {
    if (in.chance(4)) v.SetS();
    v.Q() = Scalar(in.range(-3, 3));
  }
  const int dead_vertices = in.chance(3) ? in.range(1, 3) : 0;
  for (int k = 0; k < dead_vertices && !m.vert.empty(); ++k) {
    auto &v = m.vert[in.range(0, int(m.vert.size()) - 1)];
    if (!v.IsD()) Allocator::DeleteVertex(m, v);
  }
  const int dead_faces = in.chance(3) ? in.range(1, 3) : 0;
  for (int k = 0; k < dead_faces && !m.face.empty(); ++k) {
    auto &f = m.face[in.range(0, int(m.face.size()) - 1)];
    if (!f.IsD()) Allocator::DeleteFace(m, f);
  }
  if (in.chance(4)) { // stale attributes: same names, other types
    auto a = Allocator::template AddPerVertexAttribute<int>(m, "Saliency");
    auto b = Allocator::template AddPerVertexAttribute<vcg::Point3f>(m, "K1");
    for (size_t i = 0; i < m.vert.size(); ++i) a[i] = int(i), b[i] = vcg::Point3f(1, 2, 3);
  }
  if constexpr (std::is_same_v<MeshType, test_vcg::FloatMesh>)
    if (in.chance(2)) m.vert.EnableCurvatureDir();

  const FilterId id = in.chance(3) ? FilterId::ComputeSaliencyCurvature
                                   : FilterId::SaliencyBezierSmooth;
  bool invalid = false;
  const ParameterValues p = decodeParameters(id, in, invalid);
  g_calls = 0;
  g_cancel_at = in.chance(4) ? in.range(1, 12) : 0;
  g_mesh = &arrays, g_parameters = &p;

  const std::string before = test_vcg::snapshot(m);
  const std::vector<Vec3> positions_before = test_vcg::positions(m);
  const int vn = m.vn, fn = m.fn;
  const FilterOutcome o = applyFilterById(id, m, p, progress);
  const bool cancelled = g_cancel_at > 0 && g_calls >= g_cancel_at;
  if (!o.ok) {
    if (o.error.empty()) fail("refusal without a message", o);
    if (test_vcg::snapshot(m) != before) fail("mesh changed although the filter refused", o);
    return;
  }
  if (invalid) fail("an invalid parameter was accepted", o);
  if (cancelled) fail("a cancel was ignored", o);
  if (m.vn != vn || m.fn != fn) fail("vertex or face count changed", o);
  for (size_t i = 0; i < m.vert.size(); ++i) {
    const auto &v = m.vert[i];
    const Vec3 now(double(v.cP()[0]), double(v.cP()[1]), double(v.cP()[2]));
    if (v.IsD()) {
      if (std::memcmp(&now, &positions_before[i], sizeof now) != 0)
        fail("a deleted vertex moved", o);
      continue;
    }
    if (!now.allFinite()) fail("non-finite output position", o);
    if (!std::isfinite(double(v.cQ()))) fail("non-finite quality", o);
  }
  for (const char *name : {"Saliency", "MeanCurvature", "GaussianCurvature", "K1", "K2", "Alpha",
                           "Displacement"}) {
    const std::vector<double> values = test_vcg::attribute(m, name);
    for (size_t i = 0; i < values.size(); ++i)
      if (!m.vert[i].IsD() && !std::isfinite(values[i])) fail(name, o);
  }
}

// Runs one input; returns 0 (libFuzzer's convention) or aborts on a violated check.
inline int runInput(const uint8_t *data, size_t size) {
  ByteReader in(data, size);
  if (in.byte() & 1) runOne<test_vcg::DoubleMesh>(in);
  else runOne<test_vcg::FloatMesh>(in);
  return 0;
}

} // namespace sbs_fuzz
