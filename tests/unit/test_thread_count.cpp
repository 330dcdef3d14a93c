// The filters' results do not depend on the thread count: the whole filter (apply_filters.h, as
// the plugin runs it) on one and on two threads, every stage through its parallel path
// (min_parallel_vertices 0), must give the same bytes: positions, quality and attributes. For the
// default (automatic) method and each mode it chooses between; tests/e2e/test_thread_count.py
// checks the same through meshlabserver with OMP_NUM_THREADS.
#include <gtest/gtest.h>
#include <support/analytic_meshes.h>
#include <support/vcg_meshes.h>

#include <filter_saliency_bezier_smooth/apply_filters.h>

#include <omp.h>

using namespace saliency_bezier;

TEST(ThreadCount, OneAndTwoThreadsGiveTheSameBytes) {
  vcg_ext::MeshArrays noisy = test_meshes::icosphere(1.0, 4);
  double edge = 0;
  for (const vcg_ext::Face &f : noisy.faces)
    edge += (noisy.points[f[0]] - noisy.points[f[1]]).norm() / noisy.faces.size();
  test_meshes::addNoise(noisy, 0.25 * edge, 11);
  const int saved_parallel = vcg_ext::min_parallel_vertices, threads = omp_get_max_threads();
  vcg_ext::min_parallel_vertices = 0;
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
  vcg_ext::min_parallel_vertices = saved_parallel;
}
