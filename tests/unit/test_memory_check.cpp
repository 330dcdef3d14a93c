// Out of memory is a refusal (filter_saliency_bezier_smooth/memory_check.h, apply_filters.h): under
// an address-space limit too small for a run, both filters refuse with a message that says how
// much memory the run needs, before allocating (the estimate) or when an allocation fails (the
// std::bad_alloc path, also from inside the parallel regions), and the mesh is left bit for bit as
// it was. The limit is this process's own RLIMIT_AS, lowered for the test and restored after.
#include <gtest/gtest.h>
#include <omp.h>
#include <support/analytic_meshes.h>
#include <support/vcg_meshes.h>

#include <filter_saliency_bezier_smooth/apply_filters.h>

#include <climits>
#include <cmath>
#include <sys/resource.h>

using namespace saliency_bezier;

namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true; // its shadow memory needs terabytes of address space
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

// Lowers this process's address-space limit to what it maps now plus `extra` bytes while alive.
class AddressSpaceLimit {
public:
  explicit AddressSpaceLimit(double extra) {
    getrlimit(RLIMIT_AS, &saved_);
    rlimit lowered = saved_;
    lowered.rlim_cur = rlim_t(detail::procField("/proc/self/status", "VmSize") + extra);
    ok_ = setrlimit(RLIMIT_AS, &lowered) == 0;
  }
  ~AddressSpaceLimit() { setrlimit(RLIMIT_AS, &saved_); }
  bool ok() const { return ok_; }

private:
  rlimit saved_{};
  bool ok_ = false;
};

vcg_ext::MeshArrays noisySphere(int subdivisions) {
  vcg_ext::MeshArrays m = test_meshes::icosphere(1.0, subdivisions);
  test_meshes::addNoise(m, 0.01, 3);
  return m;
}

} // namespace

TEST(MemoryCheck, RoomIsFiniteUnderAnAddressSpaceLimit) {
  if (kAddressSanitizer) GTEST_SKIP() << "address-space limits do not work under ASan";
  const MemoryRoom unlimited = memoryRoom();
  EXPECT_GT(unlimited.bytes, 0.0);
  AddressSpaceLimit limit(50e6);
  ASSERT_TRUE(limit.ok());
  const MemoryRoom room = memoryRoom();
  EXPECT_LE(room.bytes, 50e6 + 1e6);
  EXPECT_GE(room.bytes, 40e6); // what maps meanwhile (gtest's own allocations) is small
  EXPECT_NE(room.limit.find("ulimit -v"), std::string::npos) << room.limit;
}

TEST(MemoryCheck, BothFiltersRefuseBeforeAllocatingWhenTheEstimateExceedsTheRoom) {
  if (kAddressSanitizer) GTEST_SKIP() << "address-space limits do not work under ASan";
  test_vcg::FloatMesh m;
  test_vcg::assign(m, noisySphere(4)); // 2562 vertices: even the fixed part (64 MB) is over 20 MB
  const std::string before = test_vcg::snapshot(m);
  FilterOutcome smoothed, analysed;
  {
    AddressSpaceLimit limit(20e6);
    ASSERT_TRUE(limit.ok());
    smoothed = applySaliencyBezierSmooth(m, defaultParameters(FilterId::SaliencyBezierSmooth), nullptr);
    analysed = applyComputeSaliency(m, defaultParameters(FilterId::ComputeSaliencyCurvature), nullptr);
  }
  for (const FilterOutcome *o : {&smoothed, &analysed}) {
    EXPECT_FALSE(o->ok);
    EXPECT_NE(o->error.find("Not enough memory"), std::string::npos) << o->error;
    EXPECT_NE(o->error.find("needs about"), std::string::npos) << o->error;
    EXPECT_NE(o->error.find("ulimit -v"), std::string::npos) << o->error;
    EXPECT_NE(o->error.find("unchanged"), std::string::npos) << o->error;
  }
  EXPECT_TRUE(test_vcg::snapshot(m) == before);
  // The same mesh without the limit runs.
  EXPECT_TRUE(applySaliencyBezierSmooth(m, defaultParameters(FilterId::SaliencyBezierSmooth), nullptr).ok);
}

// The parallel sort (spatial order, saliency grid) allocates only outside its parallel regions, so
// a failed allocation reaches the caller as std::bad_alloc (the filter refuses) instead of
// terminating an OpenMP thread; the values are left as they were (the buffer comes first).
TEST(MemoryCheck, ParallelSortPassesAnAllocationFailureToItsCaller) {
  if (kAddressSanitizer) GTEST_SKIP() << "address-space limits do not work under ASan";
  const int saved_parallel = vcg_ext::min_parallel_vertices;
  vcg_ext::min_parallel_vertices = 0;
  const int saved_threads = omp_get_max_threads();
  omp_set_num_threads(2);
  std::vector<std::pair<std::uint64_t, int>> values(4000000); // 64 MB, its buffer as much again
  for (int i = 0; i < int(values.size()); ++i)
    values[i] = {std::uint64_t(values.size() - i) * 2654435761u % 1000003u, i};
  const std::vector<std::pair<std::uint64_t, int>> before = values;
  bool threw = false;
  {
    AddressSpaceLimit limit(16e6);
    ASSERT_TRUE(limit.ok());
    try {
      vcg_ext::detail::parallelSort(values);
    } catch (const std::bad_alloc &) {
      threw = true;
    }
  }
  EXPECT_TRUE(threw);
  EXPECT_TRUE(values == before);
  vcg_ext::detail::parallelSort(values); // without the limit
  EXPECT_TRUE(std::is_sorted(values.begin(), values.end()));
  omp_set_num_threads(saved_threads);
  vcg_ext::min_parallel_vertices = saved_parallel;
}

TEST(MemoryCheck, AllocationFailureAnywhereInARunIsARefusalAndLeavesTheMeshUnchanged) {
  if (kAddressSanitizer) GTEST_SKIP() << "address-space limits do not work under ASan";
  // Past the estimate (scaled away), with limits from a few MB to beyond what the run needs: the
  // allocation that fails is a different one each time, some of them inside parallel regions
  // (min_parallel_vertices 0). Every run must end as a success or as a refusal, never abort.
  const int saved_parallel = vcg_ext::min_parallel_vertices;
  const double saved_scale = memory_room_scale;
  vcg_ext::min_parallel_vertices = 0;
  memory_room_scale = INFINITY;
  // The OpenMP threads and their stacks exist before any limit (an empty region is optimised
  // away, hence the work).
  std::vector<int> warm(64);
#pragma omp parallel for schedule(static, 1)
  for (int i = 0; i < int(warm.size()); ++i) warm[i] = i * i;
  ASSERT_EQ(warm[63], 63 * 63);
  int refused = 0, ran = 0;
  for (int placement : {5, 4, 3, 0}) {
    for (double extra_mb : {1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 12.0, 400.0}) {
      test_vcg::FloatMesh m;
      test_vcg::assign(m, noisySphere(5)); // 10242 vertices
      const std::string before = test_vcg::snapshot(m);
      ParameterValues p = defaultParameters(FilterId::SaliencyBezierSmooth);
      p["placement"] = placement;
      FilterOutcome o;
      {
        AddressSpaceLimit limit(extra_mb * 1e6);
        ASSERT_TRUE(limit.ok());
        o = applySaliencyBezierSmooth(m, p, nullptr);
      }
      if (o.ok) {
        ++ran;
        continue;
      }
      ++refused;
      EXPECT_NE(o.error.find("Out of memory"), std::string::npos) << o.error;
      EXPECT_NE(o.error.find("needs about"), std::string::npos) << o.error;
      EXPECT_TRUE(test_vcg::snapshot(m) == before)
          << "placement " << placement << ", " << extra_mb << " MB";
    }
  }
  vcg_ext::min_parallel_vertices = saved_parallel;
  memory_room_scale = saved_scale;
  EXPECT_GT(refused, 0);
  EXPECT_GT(ran, 0);
  RecordProperty("refused", refused);
  RecordProperty("ran", ran);
}
