// libFuzzer entry point: see fuzz_filters.h for what an input decodes to and what is checked.
//   scripts/test_sanitizers.sh builds and runs it for a short budget in CI; a longer run:
//   build-asan/tests/fuzz/fuzz_filters -max_total_time=3600 -jobs=2 tests/fuzz/corpus
#include "fuzz_filters.h"

#ifdef _OPENMP
#include <omp.h>
#endif

extern "C" int LLVMFuzzerInitialize(int *, char ***) {
#ifdef _OPENMP
  omp_set_num_threads(1); // small meshes: thread start-up would dominate
#endif
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  return sbs_fuzz::runInput(data, size);
}
