#pragma once
// The main() of a study whose ctest entry is one process per tier: it runs
// the tier's cases once, writes the result files the report reads, then lets
// its TESTs check the gates on those numbers (the gates share runs that cost
// minutes, so they are not split into one process per TEST). Used by
// verification/channel and verification/mesh_sensitivity. Header-only: it
// needs GoogleTest, which fdem_study_io does not link.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <string>
#include <string_view>

#include "study_io.hpp"

namespace fdem::study {

/// The value of `--tier=NAME` ("fast" without one); "" with a message on
/// stderr when it is not one of `tiers`.
inline std::string tier_argument(int argc, char** argv, std::initializer_list<std::string_view> tiers) {
  std::string tier = "fast";
  for (int i = 1; i < argc; ++i)
    if (std::strncmp(argv[i], "--tier=", 7) == 0) tier = argv[i] + 7;
  for (const std::string_view t : tiers)
    if (tier == t) return tier;
  std::string names;
  for (const std::string_view t : tiers) names += (names.empty() ? "" : ", ") + std::string(t);
  std::fprintf(stderr, "--tier must be one of: %s\n", names.c_str());
  return "";
}

/// Runs `run_and_write` (the tier's cases and its result files), then every
/// TEST on what it left. meta.json gets `record(wall_s, passed, status)`:
/// status "error" (exit 1) when run_and_write throws, else "done" with the
/// gates' verdict and the whole wall time.
inline int run_tier_then_gates(const std::string& study, const std::function<void()>& run_and_write,
                               const std::function<RunRecord(double, bool, const std::string&)>& record) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    run_and_write();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", study.c_str(), e.what());
    const std::string dir = results_dir(study);
    std::filesystem::create_directories(dir);
    write_meta(dir, study, record(0.0, false, "error"));
    return 1;
  }
  const int status = RUN_ALL_TESTS();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  write_meta(results_dir(study), study, record(wall_s, status == 0, "done"));
  return status;
}

}  // namespace fdem::study
