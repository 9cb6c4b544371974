// Nightly: the paper's salt plume (plume.yaml: 28224 grains, 100 x 100 x 250 mm,
// 10 mm cells, fluid step 1e-3 s, 100 DEM subcycles, contacts on, 1 s) in the
// three coupling modes, with the per-phase wall time. Thresholds and the size
// truncation are argued in README.md.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "plume_test_support.hpp"

namespace fdem::plume {
namespace {

// The resting fluid (f2p), the free fall (p2f) and the spread ratios are
// gated by their rows of reference_data/plume.csv, reasons there.
// Polydisperse grains settle at different speeds and touch; a contact's
// force has a horizontal part, so one-way spreads are constant only up to
// these pushes: measured 0 (README.md). 1e-3 is a tenth of the smallest
// two-way growth we accept.
constexpr double kOneWaySpreadChange = 1e-3;
// Largest |dome_shape| two-way over one-way: the row
// plume.dome_ratio_twoway_over_oneway (at least 20; measured 870, the
// argument in that row and README.md "Gates").

TEST(PlumeFull, PaperPlume_DomeSpreadOnlyInTwoWay_FluidAtRestInF2P_FreeFallInP2F) {
  testing::run_and_check(
      {.scene_file = "plume.yaml",
       .name = "full",
       .values_prefix = "plume",
       .sample_interval_s = 0.01,
       .snapshot_times_s = {0.0, 0.2, 0.4, 0.6, 0.8, 1.0},
       .verbose = true,
       .one_way_spread_change = kOneWaySpreadChange,
       // Centre-of-mass height at 0.2 s and 1 s, beside the DPMFoam peer (reference_data/plume.csv).
       .extra_values = [](const testing::StudyOutcome& o) -> std::vector<std::pair<std::string, double>> {
         const double top = o.runs.twoway.geometry.top_z_m;
         return {{"dpmfoam_zcm_0.2s_mm", 1e3 * (top - o.runs.twoway.at(0.2).centroid_depth_m)},
                 {"dpmfoam_zcm_1s_mm", 1e3 * (top - o.runs.twoway.at(1.0).centroid_depth_m)}};
       }});
}

}  // namespace
}  // namespace fdem::plume
