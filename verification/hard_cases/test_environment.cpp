// Thread count of the hard-case and restart tests: one OpenMP thread unless
// OMP_NUM_THREADS says otherwise. The cases are small (tens of elements,
// hundreds of grains); on the shared 2-core test machine an OpenMP barrier
// per assembly loop cost 30x the work itself (measured: 14 s vs 0.44 s of CPU
// for the CFL cases). Results do not depend on it (the DEM sums in a fixed
// order for any thread count), and the restart tests need one fixed count.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdlib>

namespace {

class SingleThreadUnlessAsked : public ::testing::Environment {
 public:
  void SetUp() override {
    if (std::getenv("OMP_NUM_THREADS") == nullptr) omp_set_num_threads(1);
  }
};

[[maybe_unused]] ::testing::Environment* const kEnvironment =
    ::testing::AddGlobalTestEnvironment(new SingleThreadUnlessAsked);

}  // namespace
