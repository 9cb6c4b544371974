// Nightly: `fdem check`'s memory estimate against the peak RSS (wait4
// ru_maxrss) of `fdem run` on dry, fluid and coupled scenes: within 1.3x
// either way. The estimate counts items (bytes per particle, per non-zero of
// the fluid system and its ILUT factors, per node, per element, the largest
// output buffer); 1.3x leaves room for what it does not follow: the ILUT's
// actual fill (bounded by the fill factor, not known before the solve) and
// allocator slack.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cmath>
#include <string>

#include "memory_scenes.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;

// The "memory     about X MiB peak" line of fdem check, in bytes.
double estimate_from_check(const std::string& out) {
  const std::size_t at = out.find("memory     about ");
  if (at == std::string::npos) return std::nan("");
  std::size_t used = 0;
  const double value = std::stod(out.substr(at + 17), &used);
  const std::string unit = out.substr(at + 17 + used + 1, 3);
  const double scale = unit == "GiB" ? 1024.0 * 1024.0 * 1024.0 : unit == "MiB" ? 1024.0 * 1024.0 : 1024.0;
  return value * scale;
}

void expect_estimate_within_30_percent(const std::string& name, const std::string& yaml) {
  const fs::path dir = hard::scratch_dir("memory_estimate_" + name);
  hard::write_text(dir / "scene.yaml", yaml);
  hard::FdemProcess check({"check", (dir / "scene.yaml").string()}, dir);
  ASSERT_EQ(check.wait(), 0) << check.stderr_text();
  const double estimate = estimate_from_check(check.stdout_text());
  ASSERT_TRUE(std::isfinite(estimate)) << check.stdout_text();
  rusage usage{};
  const int code = hard::run_fdem_limited({"run", (dir / "scene.yaml").string(), "-o", (dir / "out").string(), "-q",
                                           "-t", "1"},
                                          dir, RLIMIT_AS, RLIM_INFINITY, &usage);
  ASSERT_EQ(code, 0) << hard::read_text(dir / "stderr.txt");
  const double measured = static_cast<double>(usage.ru_maxrss) * 1024.0;
  const double ratio = estimate / measured;
  std::printf("%s: estimate %.1f MiB, measured peak RSS %.1f MiB, ratio %.3f\n", name.c_str(), estimate / 1048576.0,
              measured / 1048576.0, ratio);
  EXPECT_GT(ratio, 1.0 / 1.3) << name;
  EXPECT_LT(ratio, 1.3) << name;
}

TEST(MemoryEstimate, DryCloudOfTwoHundredThousandGrains) {
  expect_estimate_within_30_percent("dry", hard::random_grains_yaml(200000, 0.2));
}

TEST(MemoryEstimate, DryCloudWritingSnapshotsAndCheckpoints) {
  expect_estimate_within_30_percent(
      "dry_output", hard::random_grains_yaml(200000, 0.2, ", vtu_interval: 2.0e-5, checkpoint_interval: 2.0e-5"));
}

TEST(MemoryEstimate, FluidOnlyCubeOfTwentyCubedCells) {
  expect_estimate_within_30_percent("fluid", hard::water_cube_yaml(20, 0));
}

TEST(MemoryEstimate, CoupledCubeWithTwentyThousandGrains) {
  expect_estimate_within_30_percent("coupled", hard::water_cube_yaml(20, 20000));
}

}  // namespace
}  // namespace fdem
