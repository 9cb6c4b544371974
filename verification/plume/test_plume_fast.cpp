// Fast tier: the reduced salt plume (plume_fast.yaml: 4704 grains of 0.6 mm,
// 60 x 60 x 120 mm column, 10 mm cells, 0.4 s) in the three coupling modes.
// One test, because every claim compares the three runs and each run is the
// expensive part; each claim is a separate, named EXPECT (plume_test_support.hpp,
// run_and_check). Thresholds are
// argued in README.md ("Gates") from the physics and the measured runs.
#include <gtest/gtest.h>

#include "plume_test_support.hpp"

namespace fdem::plume {
namespace {

// A one-way run has no lateral force on any grain (fluid to particle: the
// fluid stays at rest and drag only opposes each grain's own vertical motion;
// particle to fluid: no drag at all), and this monodisperse lattice never
// makes contacts, so its radial spread is constant up to round-off.
constexpr double kOneWaySpreadChange = 1e-12;
// Two-way: the spread grows (README.md "Gates": measured ratio 1.031 at
// 0.4 s against exactly 1 one-way); its gate, 1.01 (a third of that growth,
// still 1e10 times the one-way round-off), is the row
// plume.fast.spread_ratio_twoway_over_* of reference_data/plume.csv.
// The cloud's shape changes only in two-way: largest |dome_shape| two-way
// over one-way, gated by plume.fast.dome_ratio_twoway_over_oneway (at least
// 10; measured 148, the argument in that row and README.md "Gates").
// The resting fluid in fluid-to-particle mode (1e-12 m/s), the free fall in
// particle-to-fluid mode (1e-9), the spread ratios (>= 1.01) and the dome ratio (>= 10) are gated by
// their rows of reference_data/plume.csv (plume.fast.*), reasons there.

TEST(PlumeFast, ReducedPlume_DomeSpreadOnlyInTwoWay_FluidAtRestInF2P_FreeFallInP2F) {
  testing::run_and_check({.scene_file = "plume_fast.yaml",
                          .name = "fast",
                          .values_prefix = "plume.fast",
                          .sample_interval_s = 0.05,
                          .snapshot_times_s = {0.0, 0.2, 0.4, 0.6},
                          .verbose = false,
                          .one_way_spread_change = kOneWaySpreadChange,
                          .extra_values = {}});
}

}  // namespace
}  // namespace fdem::plume
