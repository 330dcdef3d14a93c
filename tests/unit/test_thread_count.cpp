// The filters' results do not depend on the thread count: the whole filter (apply_filters.h, as
// the plugin runs it) on one and on two threads must give the same bytes: positions, quality and
// attributes. Every stage through its parallel path (min_parallel_vertices 0), and a mesh between
// the two thresholds at their defaults (the heavy stages parallel, the others serial: rings.h).
// For the default (automatic) method and each mode it chooses between;
// tests/e2e/test_thread_count.py checks the same through meshlabserver with OMP_NUM_THREADS.
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <support/vcg_meshes.h>

#include <filter_saliency_bezier_smooth/apply_filters.h>

#include <omp.h>

using namespace saliency_bezier;

namespace {

// The filter's result (test_vcg::snapshot) on 1 and on 2 threads, per placement.
void expectSameBytesOnOneAndTwoThreads(const vcg_ext::MeshArrays &noisy) {
  const int threads = omp_get_max_threads();
  for (int placement : {5, 3, 4}) {
    std::string result[2];
    for (int t : {1, 2}) {
      omp_set_num_threads(t);
      test_vcg::FloatMesh m;
      test_vcg::assign(m, noisy);
      ParameterValues p = defaultParameters(FilterId::SaliencyBezierSmooth);
      p["placement"] = placement;
      const FilterOutcome o = applySaliencyBezierSmooth(m, p, nullptr);
      ASSERT_TRUE(o.ok) << o.error;
      result[t - 1] = test_vcg::snapshot(m);
    }
    EXPECT_TRUE(result[0] == result[1]) << "placement " << placement;
  }
  omp_set_num_threads(threads);
}

vcg_ext::MeshArrays noisyIcosphere(int subdivisions) {
  vcg_ext::MeshArrays noisy = test_meshes::icosphere(1.0, subdivisions);
  double edge = 0;
  for (const vcg_ext::Face &f : noisy.faces)
    edge += (noisy.points[f[0]] - noisy.points[f[1]]).norm() / noisy.faces.size();
  test_meshes::addNoise(noisy, 0.25 * edge, 11);
  return noisy;
}

} // namespace

TEST(ThreadCount, OneAndTwoThreadsGiveTheSameBytes) {
  const int saved_parallel = vcg_ext::min_parallel_vertices;
  vcg_ext::min_parallel_vertices = 0;
  expectSameBytesOnOneAndTwoThreads(noisyIcosphere(4)); // 2562 vertices
  vcg_ext::min_parallel_vertices = saved_parallel;
}

TEST(ThreadCount, HeavyStagesAloneInParallelGiveTheSameBytes) {
  // The library's thresholds (test_saliency_lattice.cpp sets the first to 0 for this binary).
  const int saved_parallel = vcg_ext::min_parallel_vertices, saved_heavy = vcg_ext::min_parallel_heavy;
  vcg_ext::min_parallel_vertices = 20000;
  vcg_ext::min_parallel_heavy = 5000;
  const vcg_ext::MeshArrays noisy = noisyIcosphere(5); // 10242 vertices, between the thresholds
  EXPECT_TRUE(vcg_ext::parallelHeavy(long(noisy.points.size())));
  EXPECT_FALSE(long(noisy.points.size()) >= vcg_ext::min_parallel_vertices);
  expectSameBytesOnOneAndTwoThreads(noisy);
  vcg_ext::min_parallel_vertices = saved_parallel;
  vcg_ext::min_parallel_heavy = saved_heavy;
}
